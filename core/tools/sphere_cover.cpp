#include "core/tools/sphere_cover.h"

#include <algorithm>
#include <cmath>

#include "core/common/error.h"

namespace bliskrun {

namespace {

// The circumscribed polygon as a chain in (r, z), z never decreasing: its
// radius at height z and its vertices within a slab.
class MeridianChain {
 public:
  explicit MeridianChain(std::vector<Vec2> points) : points_(std::move(points)) {}
  double z_min() const { return points_.front().y(); }
  double z_max() const { return points_.back().y(); }

  // Largest r of the polygon at height z (a horizontal edge at z counts
  // with its outer end).
  double radius_at(double z) const {
    double r = 0;
    for (size_t i = 1; i < points_.size(); ++i) {
      const Vec2& a = points_[i - 1];
      const Vec2& b = points_[i];
      if (z < a.y() || z > b.y()) continue;
      if (b.y() - a.y() <= 0) {
        r = std::max({r, a.x(), b.x()});
      } else {
        const double f = (z - a.y()) / (b.y() - a.y());
        r = std::max(r, a.x() + f * (b.x() - a.x()));
      }
    }
    return r;
  }

  // The points that bound the polygon's slice between heights lo and hi:
  // its vertices there and its outline at both planes. The slice is convex,
  // so the farthest point from any centre on the axis is one of them (or on
  // the axis, nearer).
  std::vector<Vec2> slice(double lo, double hi) const {
    std::vector<Vec2> out{Vec2(radius_at(lo), lo), Vec2(radius_at(hi), hi)};
    for (const Vec2& p : points_)
      if (p.y() > lo && p.y() < hi) out.push_back(p);
    return out;
  }

 private:
  std::vector<Vec2> points_;
};

double covering_radius(const std::vector<Vec2>& pts, double z) {
  double r = 0;
  for (const Vec2& p : pts) r = std::max(r, std::hypot(p.x(), p.y() - z));
  return r;
}

// The smallest sphere centred on the axis that covers the slice: the
// farthest-point distance is convex in the centre's height.
AxisSphere smallest_cover(const std::vector<Vec2>& pts, double lo, double hi) {
  double a = lo, b = hi;
  for (int k = 0; k < 80 && b - a > 1e-9; ++k) {
    const double m1 = a + (b - a) / 3, m2 = b - (b - a) / 3;
    if (covering_radius(pts, m1) <= covering_radius(pts, m2)) b = m2; else a = m1;
  }
  const double z = 0.5 * (a + b);
  return {z, covering_radius(pts, z)};
}

double largest_radius(const std::vector<Vec2>& pts) {
  double r = 0;
  for (const Vec2& p : pts) r = std::max(r, p.x());
  return r;
}

}  // namespace

SphereCover sphere_cover(const Profile& profile, double excess_mm, double tol_mm) {
  if (!(excess_mm > 0) || !std::isfinite(excess_mm))
    throw ParameterError("excess_mm", "must be a positive length");
  if (!(tol_mm > 0) || !std::isfinite(tol_mm)) throw ParameterError("tol_mm", "must be a positive length");
  const MeridianChain chain(profile.circumscribed_polyline(tol_mm));
  SphereCover cover;
  cover.overestimate_mm = tol_mm + excess_mm;
  const double top = chain.z_max();
  double lo = chain.z_min();
  while (lo < top) {
    // The longest slab from lo whose cover stays within the excess: a
    // longer slab never fits better, so bisect on its top.
    auto fits = [&](double hi) {
      const std::vector<Vec2> pts = chain.slice(lo, hi);
      return smallest_cover(pts, lo, hi).radius <= largest_radius(pts) + excess_mm;
    };
    double hi = top;
    if (!fits(hi)) {
      double good = lo, bad = top;
      for (int k = 0; k < 60 && bad - good > 1e-6; ++k) {
        const double mid = 0.5 * (good + bad);
        if (fits(mid)) good = mid; else bad = mid;
      }
      // A slab at least 1 um long, whatever the profile (a cover slightly
      // fatter than asked beats an endless one).
      hi = std::max(good, std::min(top, lo + 1e-3));
    }
    cover.spheres.push_back(smallest_cover(chain.slice(lo, hi), lo, hi));
    lo = hi;
  }
  // Groups of eight: a query tests a group's bound before its spheres.
  constexpr int kGroup = 8;
  for (int first = 0; first < static_cast<int>(cover.spheres.size()); first += kGroup) {
    SphereCover::Group g;
    g.first = first;
    g.count = std::min(kGroup, static_cast<int>(cover.spheres.size()) - first);
    const double z0 = cover.spheres[first].z, z1 = cover.spheres[first + g.count - 1].z;
    g.bound.z = 0.5 * (z0 + z1);
    for (int k = first; k < first + g.count; ++k)
      g.bound.radius = std::max(g.bound.radius, std::abs(cover.spheres[k].z - g.bound.z) + cover.spheres[k].radius);
    cover.groups.push_back(g);
  }
  return cover;
}

}  // namespace bliskrun
