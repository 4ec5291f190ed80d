#pragma once
// Curvature analysis of a blade flank (blisk paper §2.2 and Table 1).
//
// The surface is sampled on an nu x nv grid of parameters u_i = i/(nu-1),
// v_j = j/(nv-1). At each sample: K, H, k1 >= k2, signed by the surface normal
// pu x pv. For a flank whose normal points out of the material (SPEC §2),
// concave directions have k > 0 and convex ones k < 0.
//
// Table 1 quantities, all over the samples with K < 0 (the paper ignores the
// locally convex region, §2.2):
//   k1_max  max k1: the concave principal curvature that bounds the wheel
//           (eq. 12). Reported as |max k1|.
//   k2_max  max |k2|: the largest convex principal curvature in the K < 0
//           region. (Table 1 gives it without saying which sign is meant; we
//           report the magnitude.)
//   ke_max  max over samples of the largest normal curvature along a
//           tool-axis direction the rotary axis can reach (eq. 14, 15).
//
// Our reading of the C-axis limit of §2.2 ("rotate the tool axis to the
// horizontal plane; its angle to Y must stay within C in [-30°, +30°]"): the
// drum wheel's axis lies in the tangent plane; its nominal direction is the
// flank's span direction pu/|pu| (hub -> tip), which for a blisk on the
// machine of Fig. 4 maps to Y; the C limit lets the axis turn within
// ±c_range_rad of it inside the tangent plane. With a the angle from pu
// (positive towards n x pu) and k_n(a) = k1 cos²(a - a1) + k2 sin²(a - a1)
// (Euler, eq. 14, a1 the angle of the k1 direction), k_e at a sample is
// max over |a| <= c_range_rad of k_n(a), found in closed form (the maximum is
// at a1 modulo pi when that is in range, otherwise at an end). With
// c_range_rad >= pi/2 every direction is allowed and ke_max == k1_max.
#include <vector>

#include "core/common/progress.h"
#include "core/geometry/surface.h"

namespace bliskrun {

struct CurvatureStatsOptions {
  int samples_u = 100;
  int samples_v = 500;
  double c_range_rad = 30.0 * kPi / 180.0;  // half-width of the allowed axis range
  bool keep_map = true;                     // store per-sample values (for pictures)
};

struct CurvatureSample {
  double K = 0, H = 0, k1 = 0, k2 = 0;
  double ke = 0;  // max normal curvature within the C range
};

// Where a maximum occurs.
struct CurvatureExtreme {
  double value = 0;        // the reported magnitude (mm^-1)
  double u = 0, v = 0;
  double angle_rad = 0;    // direction angle from pu in the tangent plane
                           // (k1: of dir1; ke: of the maximising axis)
  bool found = false;      // false when no sample has K < 0
};

struct CurvatureStats {
  int samples_u = 0, samples_v = 0;
  long negative_K_count = 0;
  double negative_K_fraction = 0;  // share of samples with K < 0
  CurvatureExtreme k1_max;         // |max k1| over K < 0
  CurvatureExtreme k2_max;         // max |k2| over K < 0
  CurvatureExtreme ke_max;         // max k_e over K < 0 within the C range
  double K_min = 0, K_max = 0;     // over all samples
  // Per-sample values, sample (i, j) at map[i * samples_v + j]; empty unless
  // keep_map.
  std::vector<CurvatureSample> map;
  const CurvatureSample& at(int i, int j) const {
    return map[static_cast<size_t>(i) * samples_v + j];
  }
};

// Throws ParameterError on fewer than 2 samples per direction or a negative
// C range, Error at a singular surface point, Cancelled via progress.
// Deterministic: samples are visited in a fixed order, ties keep the first.
CurvatureStats curvature_stats(const Surface& s, const CurvatureStatsOptions& opts = {},
                               Progress& progress = Progress::none());

// The closed-form maximum of k1 cos²(a - a1) + k2 sin²(a - a1) over
// a in [-c, c] (k1 >= k2). Returns the maximum and sets *arg to where it is.
double max_normal_curvature_in_range(double k1, double k2, double a1_rad, double c_rad,
                                     double* arg_rad);

}  // namespace bliskrun
