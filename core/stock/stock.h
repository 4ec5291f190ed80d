#pragma once
// The stock: the material still on the part, from the blank of revolution
// through every operation's moves (issue 41 item 1).
//
// Tri-dexel (docs/architecture.md, "The stock model"): three grids of rays
// along X, Y and Z at one spacing, each ray the sorted spans of material it
// passes through. A cut intersects each ray near the tool with the tool's
// solid of revolution in closed form (core/stock/revolved_solid.h), so a
// ray's material is exact along it; the grids' spacing is the lateral
// resolution. Volumes are the mean of the three grids' (each a midpoint rule
// over its plane); the depth of material above a surface point is read on
// the grid whose rays run closest to the surface normal, which is never
// more than 54.7° from it.
//
// The motion between two poses (PoseMotion, the machine's interpolation) is
// sampled so that no cutter point moves more than `step_mm` between samples:
// the union of the sampled tools lies inside the true sweep and every point
// of the sweep lies within step_mm / 2 of it, so the material a cut leaves
// that the real motion removes is at most step_mm / 2 thick — at most
// rho - sqrt(rho² - step²/4) where the sweep's surface is made by a round
// part of the cutter of radius rho (a ball of R 4 at 0.5 mm steps: 8 µm).
// A move along the tool's own axis (a plunge, a retract) is swept exactly.
#include <array>
#include <cstddef>
#include <vector>

#include "core/common/progress.h"
#include "core/stock/blank_profile.h"
#include "core/stock/dexel_grid.h"
#include "core/tools/tool.h"
#include "core/toolpath/move.h"

namespace bliskrun {

struct StockOptions {
  double resolution_mm = 0.5;  // ray spacing of the three grids
};

struct CutOptions {
  // Largest motion of any cutter point between samples, mm; 0 = the
  // stock's resolution. Bounds the material left by sampling (above).
  double step_mm = 0;
  // Tangent-polygon tolerance of a torus (bull-nose corner, barrel), mm:
  // the cut removes at most this much more than the tool.
  double torus_tol_mm = 0.002;
  // A stretch of a feed move (one sample step) that removes less than this
  // per mm of tip path (mm³/mm = mm² of cross-section) is cutting air.
  double air_mm2 = 1e-3;
  // Measure the shank and holder against the stock at every sample (they
  // never cut: material inside them is a collision), on the one grid whose
  // rays run closest to the tool axis.
  bool check_body = true;
  // Up to three: the grids are cut side by side (the result does not
  // depend on it).
  int threads = 1;
};

// What one move did to the stock.
struct MoveCut {
  double removed_mm3 = 0;
  double length_mm = 0;  // tip path
  double air_mm = 0;     // tip path of its sample steps that cut air (feed moves only)
  // Engagement: removed volume per mm of tip path (mm²), the largest over
  // the move's sample steps; the axial extent of one step's removed
  // material along the tool axis (ap) and its radial extent across the
  // feed, perpendicular to the axis (ae; 0 for a motion along the axis).
  double rate_max_mm2 = 0;
  double axial_mm = 0;
  double radial_mm = 0;
  // The largest volume of stock inside the shank or holder at one sample.
  double body_mm3 = 0;
};

struct CutResult {
  std::vector<MoveCut> moves;  // one per move, in order
  double removed_mm3 = 0;
  double cut_mm = 0;           // tip path of the feed moves
  double air_cut_mm = 0;       // of which cutting air
  double rapid_mm = 0;         // tip path of the rapid moves
  double rapid_removed_mm3 = 0;  // material a rapid went through (a crash)
  long rapid_cut_moves = 0;
  long body_contact_moves = 0;  // moves whose shank or holder met the stock
  double body_contact_max_mm3 = 0;
  double rate_max_mm2 = 0, axial_max_mm = 0, radial_max_mm = 0;
  long samples = 0;  // tool positions applied
};

class Stock {
 public:
  // Throws ParameterError("profile", ...) (BlankProfile) or
  // ParameterError("resolution_mm", ...): at least 0.01 mm and at most a
  // quarter of the blank's height and radius. Refuses a grid the memory
  // budget cannot hold before allocating it.
  Stock(const BlankProfile& blank, const StockOptions& options);

  // Removes what `tool`'s cutter sweeps along `moves` (a Stop breaks the
  // motion: the next pose is placed, as is the first one unless `from`
  // gives the pose the motion starts at). Throws ParameterError for bad
  // options, for two consecutive poses with opposite axes.
  CutResult cut(const Toolpath& moves, const Tool& tool, const CutOptions& options, const ToolPose* from = nullptr,
                Progress& progress = Progress::none());

  double resolution() const { return spacing_; }
  // Material now and in the blank as the grids hold it (mean of the three),
  // and the blank's exact volume, mm³.
  double volume() const;
  double blank_volume() const { return blank_volume_; }
  double blank_exact_volume() const { return blank_exact_volume_; }
  double volume_of_grid(int axis) const;

  // Depth of material above a point of a surface along its unit outward
  // normal (mm): on the grid whose rays run closest to `normal`, the top of
  // the material under the point on the four rays around it, interpolated
  // bilinearly, times the cosine between ray and normal — exact for a layer
  // of even thickness over a plane. Negative where the material ends below
  // the point (an overcut); searched within ±max_mm along the ray; NaN when
  // none of the four rays has material there.
  double material_above(const Vec3& point, const Vec3& normal, double max_mm = 10) const;

  const DexelGrid& grid(int axis) const { return grids_[static_cast<size_t>(axis)]; }
  long ray_count() const;
  long span_count() const;
  std::size_t memory_bytes() const;

 private:
  std::array<DexelGrid, 3> grids_;
  std::array<double, 3> material_mm_{};  // per grid, sum of span lengths
  double spacing_ = 0.5;
  double blank_volume_ = 0, blank_exact_volume_ = 0;
};

}  // namespace bliskrun
