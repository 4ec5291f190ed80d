#pragma once
// The blank a part is machined from: a solid of revolution about the part's
// Z axis (a forged or turned disc), given by its meridian — a closed
// polygon in the (r, z) half-plane, r >= 0, in either orientation. A bore
// or a stepped hub is a polygon that does not touch the axis, or touches it
// only along part of its height.
#include <utility>
#include <vector>

#include "core/common/types.h"

namespace bliskrun {

class BlankProfile {
 public:
  // Throws ParameterError("profile", why): fewer than 3 points, a point not
  // finite or at r < 0, zero area, or edges that cross or touch other than
  // at their shared vertex. A last point equal to the first is dropped.
  // At most kMaxPoints points (the simple-polygon check is quadratic).
  explicit BlankProfile(std::vector<Vec2> rz);
  static constexpr int kMaxPoints = 5000;

  const std::vector<Vec2>& points() const { return points_; }
  double r_max() const { return r_max_; }
  double z_min() const { return z_min_; }
  double z_max() const { return z_max_; }
  // The solid's exact volume, mm³ (Pappus: ∮ π r² dz).
  double volume() const { return volume_; }

  // The solid's material along the line of radius r parallel to the axis:
  // z spans, sorted, disjoint (even-odd rule on the polygon).
  std::vector<std::pair<double, double>> z_spans_at_radius(double r) const;
  // The meridian's material along the line of height z: r spans, sorted.
  std::vector<std::pair<double, double>> r_spans_at_height(double z) const;

 private:
  std::vector<Vec2> points_;
  double r_max_ = 0, z_min_ = 0, z_max_ = 0, volume_ = 0;
};

}  // namespace bliskrun
