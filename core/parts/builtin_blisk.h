#pragma once
// A built-in parametric blisk at the scale of the blisk paper (§4: 22 blades,
// 30 mm blade height, narrowest passage about 10.5 mm, flank curvature of the
// order of Table 1) so that recipes and tests run without CAD data (SPEC §11).
//
// Frame: Z is the rotor axis, flow towards +Z; lengths mm, angles rad.
//
// Blade section at radius r (a cylinder section unrolled to the (z, s = r θ)
// plane, then wrapped back onto the cylinder):
//   - camber line: a circular arc of chord `chord_mm` and turning angle
//     camber(r), chord midpoint on the stacking line (z = 0, θ = 0),
//     chord at stagger(r) to the Z axis;
//   - half thickness h(ξ) along the camber arc length ξ between the edge
//     circles: h = r_le at the LE end and r_te at the TE end, both with zero
//     slope, and max_thickness(r)/2 at mid-chord
//       h(ξ) = r_le (1 - S(ξ)) + r_te S(ξ) + (t/2 - (r_le + r_te)/2) sin²(π ξ)
//     with S the cubic smoothstep. Because h' = 0 at the ends, the LE circle
//     of radius r_le centred on the camber line where the flanks start is
//     tangent to both flanks (G1), and likewise at the TE;
//   - flanks: camber ∓ h along the camber normal. The suction flank is the
//     convex side (facing +θ), the pressure flank the concave side.
// Stagger, camber and max thickness vary linearly with r from their hub
// values (at the mean hub radius) to their tip values (at the mean casing
// radius): the blade twists from hub to tip.
//
// Flank grids, as a CAD user extracts them: the flank faces between the edge
// rounds (the LE/TE circles are separate faces, machined by the edge
// strategy), rows at constant radius from `span_extension_mm` below the
// lowest hub radius to `span_extension_mm` above the highest casing radius,
// so the hub and casing cones cut the grid obliquely (their intersections are
// not iso-u lines, trimming matters).
//   u (rows): span, hub -> tip.
//   v (cols): along the chord. Pressure flank: LE -> TE. Suction flank:
//   TE -> LE. With u hub -> tip, only this choice makes pu x pv point out of
//   the material on both flanks (SPEC §2); a flank with v LE -> TE on the
//   suction side would have its normal into the blade.
#include <memory>
#include <string>
#include <vector>

#include "core/geometry/point_grid.h"
#include "core/geometry/surface.h"
#include "core/parts/blisk_part.h"

namespace bliskrun {

// The defaults give (measured, see tests/parts/builtin_blisk_test.cpp): blade
// height 30 mm, narrowest passage ~10.5 mm, and on the pressure flank's
// 100 x 500 reconstruction k1 max ~0.043, k2 max ~0.008, k_e max (C ±30°)
// ~0.020 mm^-1 over K < 0 - the order of the paper's Table 1 (0.0435,
// 0.0089, 0.0195).
struct BliskParams {
  int blade_count = 22;
  // Meridian: hub and casing are cones, straight in (z, r) between the inlet
  // and outlet planes.
  double z_inlet_mm = -22.0;
  double z_outlet_mm = 22.0;
  double hub_radius_inlet_mm = 60.0;
  double hub_radius_outlet_mm = 66.0;
  double casing_radius_inlet_mm = 90.0;
  double casing_radius_outlet_mm = 96.0;
  // Section.
  double chord_mm = 36.0;
  double stagger_hub_rad = 32.3 * kPi / 180.0;  // chord to Z axis
  double stagger_tip_rad = 48.0 * kPi / 180.0;
  double camber_hub_rad = 46.0 * kPi / 180.0;   // turning of the camber arc
  double camber_tip_rad = 40.0 * kPi / 180.0;
  double max_thickness_hub_mm = 3.0;
  double max_thickness_tip_mm = 2.2;
  double le_radius_mm = 0.4;
  double te_radius_mm = 0.3;
  // Grid.
  int grid_rows = 100;
  int grid_cols = 500;
  double span_extension_mm = 1.5;
};

// Throws ParameterError naming the first invalid parameter.
void validate(const BliskParams& p);

class BuiltinBlisk : public BliskPart {
 public:
  explicit BuiltinBlisk(const BliskParams& params = {});

  const BliskParams& params() const { return params_; }
  int blade_count() const override { return params_.blade_count; }

  // The flank of blade k as the analytic surface the grid samples (u, v as
  // in the grid, u over the grid's radial range). Derivatives by central
  // differences of the closed-form point (accurate to ~1e-7 relative).
  std::shared_ptr<const Surface> flank_surface(int blade, FlankSide side) const override;
  // grid_rows x grid_cols samples of flank_surface at u = i/(rows-1),
  // v = j/(cols-1).
  PointGrid flank_grid(int blade, FlankSide side) const override;

  // The closed section of blade k at radius r (on the cylinder of that
  // radius), edge circles included: the pressure flank LE -> TE at
  // `points_per_flank` chord fractions, the TE half circle, the suction flank
  // TE -> LE, the LE half circle (edge points about as far apart as the
  // flanks', at least 8 per half circle); first point not repeated. The exact
  // blade a repair measures (core/repair/damaged_blade.h). Throws
  // ParameterError ("blade", "radius", "points").
  std::vector<Vec3> section_loop(int blade, double r, int points_per_flank = 400) const;

  // Meridian lines (z, r) from inlet to outlet, for SurfaceOfRevolution.
  std::vector<Vec2> hub_meridian() const override;
  std::vector<Vec2> casing_meridian() const override;
  double hub_radius_at(double z_mm) const override;
  double casing_radius_at(double z_mm) const override;
  std::shared_ptr<const SurfaceOfRevolution> hub() const override;
  std::shared_ptr<const SurfaceOfRevolution> casing() const override;
  std::string description() const override;
  // Radii of grid rows 0 and rows-1.
  double grid_radius_min_mm() const { return r_lo_; }
  double grid_radius_max_mm() const { return r_hi_; }

  // Minimum distance between the suction flank of blade k and the pressure
  // flank of blade k+1 (all passages are equal), over points between hub and
  // casing on both flanks (narrowest_span_passage on the analytic flanks).
  double narrowest_passage_mm() const override;

 private:
  struct Section;
  Vec3 flank_point(FlankSide side, double r, double t) const;

  BliskParams params_;
  double r_lo_ = 0, r_hi_ = 0;
  friend class FlankSurface;
};

}  // namespace bliskrun
