#pragma once
// Closed (periodic) C2 cubic B-spline curves: a measured blade section, a
// profile loop. interpolate_cubic (interpolation.h) is for open curves and
// needs end tangents; a loop has no ends, and clamping it at a chosen point
// would leave a curvature kink there that the curvature profile of a section
// (repair paper §1.3) would show as a false peak.
#include <vector>

#include "core/geometry/curve.h"

namespace bliskrun {

// A closed C2 curve whose parameter is the cumulative chord length of the
// points it was made from (mm, close to arc length). It runs over one period
// [start, start + period); eval wraps any t into that period, so the same
// shape can start anywhere (started_at) without re-fitting.
class ClosedCurve : public Curve {
 public:
  ClosedCurve() = default;
  // `periodic`: a cubic B-spline whose knots repeat with the period and whose
  // first three control points equal its last three (C2 across the seam).
  ClosedCurve(BSplineCurve periodic, double start);

  CurveDerivs eval(double t) const override;
  double t_min() const override { return start_; }
  double t_max() const override { return start_ + period(); }
  double period() const { return spline_.t_max() - spline_.t_min(); }

  // The same curve starting at parameter t (any real: taken modulo the period).
  ClosedCurve started_at(double t) const;
  const BSplineCurve& spline() const { return spline_; }

 private:
  BSplineCurve spline_;
  double start_ = 0;
};

// The closed C2 cubic through `loop` in order (first point not repeated),
// knots at the cumulative chord-length parameters, t = 0 at loop[0] — the
// cyclic tridiagonal analogue of eq. 6–7. O(n). Throws ParameterError
// ("loop") for fewer than 4 points, a non-finite point, or two consecutive
// points (the closing pair included) that coincide.
ClosedCurve interpolate_closed_cubic(const std::vector<Vec3>& loop);

// The same at given knots: loop[k] at knots[k], knots[n] closing the loop
// (n + 1 knots, strictly increasing, period knots[n] - knots[0]). Loops
// interpolated at one knot vector share their basis, so their control points
// can be the rows of a surface closed around them (a loft through sections,
// core/geometry/section_loft.h). Returns the periodic spline itself: control
// points c_{-3} .. c_{n-1}, the first three repeating as the last three,
// domain [knots[0], knots[n]]. Throws ParameterError as above, and
// ("knots") for a wrong count or knots that are not finite and increasing.
BSplineCurve interpolate_closed_cubic(const std::vector<Vec3>& loop, const std::vector<double>& knots);

}  // namespace bliskrun
