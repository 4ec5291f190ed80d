#pragma once
// Drum-wheel sizing from flank curvature and the blade passage (blisk paper
// §2.2 eq. 12, 13, 15 and Table 2).
//
//   D_t < 2 / |max k1|   over K < 0          (eq. 12)
//   D_t < d_min - passage clearance           (eq. 13, with the safety
//                                              distance §4 mentions but does
//                                              not quantify)
//   R_c < 1 / |max k1|   traditional rule
//   R_c < 1 / |max k_e|  extended rule, k_e within the C-axis range (eq. 15)
//
// Every bound is strict; a chosen size is the largest multiple of its step
// strictly below the bound (1 mm for D_t, 10 mm for R_c by default), which
// reproduces Table 2: 1/k1 23.0 -> R_c 20, 1/k_e 51.3 -> R_c 50,
// d_min 10.5 -> D_t 8.0.

namespace bliskrun {

struct WheelDesignInput {
  double k1_max_per_mm = 0;   // |max k1| over K < 0 (CurvatureStats::k1_max)
  double ke_max_per_mm = 0;   // |max k_e| within the C range (CurvatureStats::ke_max)
  double d_min_mm = 0;        // narrowest blade passage
};

struct WheelDesignOptions {
  // Safety distance between the wheel and the passage walls, subtracted from
  // d_min. 2 mm turns the paper's 10.5 mm passage into D_t 8.0 as in Table 2.
  double passage_clearance_mm = 2.0;
  double diameter_step_mm = 1.0;     // D_t is a multiple of this
  double drum_radius_step_mm = 10.0; // R_c is a multiple of this
};

// One row of Table 2.
struct WheelChoice {
  double radius_limit_mm = 0;    // 1/|k| the rule bounds R_c by
  double drum_radius_mm = 0;     // R_c
  double diameter_limit_mm = 0;  // min(2/|k1max|, d_min - clearance)
  double diameter_mm = 0;        // D_t
};

struct WheelDesign {
  WheelChoice traditional;  // R_c from k1 max (eq. 12)
  WheelChoice extended;     // R_c from k_e max within the C range (eq. 15)
};

// Throws ParameterError naming the input when a curvature is not positive and
// finite, d_min or a step is not positive, or no positive size fits a bound
// (e.g. the clearance eats the whole passage).
WheelDesign design_drum_wheel(const WheelDesignInput& in, const WheelDesignOptions& opts = {});

// Largest positive multiple of `step` strictly below `limit`; 0 if none.
double largest_multiple_below(double limit, double step);

}  // namespace bliskrun
