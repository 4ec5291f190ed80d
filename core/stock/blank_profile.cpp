#include "core/stock/blank_profile.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/common/error.h"

namespace bliskrun {

namespace {

double blank_cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Whether segments [p, q] and [r, s] meet (touching included).
bool blank_segments_meet(const Vec2& p, const Vec2& q, const Vec2& r, const Vec2& s) {
  const auto side = [](const Vec2& a, const Vec2& b, const Vec2& c) {
    const double v = blank_cross(b - a, c - a);
    return v > 0 ? 1 : (v < 0 ? -1 : 0);
  };
  const auto on = [](const Vec2& a, const Vec2& b, const Vec2& c) {  // c on [a, b], given collinear
    return std::min(a.x(), b.x()) <= c.x() && c.x() <= std::max(a.x(), b.x()) && std::min(a.y(), b.y()) <= c.y() &&
           c.y() <= std::max(a.y(), b.y());
  };
  const int d1 = side(r, s, p), d2 = side(r, s, q), d3 = side(p, q, r), d4 = side(p, q, s);
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  return (d1 == 0 && on(r, s, p)) || (d2 == 0 && on(r, s, q)) || (d3 == 0 && on(p, q, r)) ||
         (d4 == 0 && on(p, q, s));
}

// Crossings of the polygon's edges with the line coord[axis] = value, as
// the other coordinate, sorted. Half-open rule: an edge counts when one end
// is below the value and the other at or above it, so a vertex on the line
// counts once (or twice, or not at all, for a touching vertex) and the spans
// pair up.
std::vector<std::pair<double, double>> blank_spans_on_line(const std::vector<Vec2>& pts, int axis, double value) {
  std::vector<double> at;
  const int other = 1 - axis;
  const size_t n = pts.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2& a = pts[i];
    const Vec2& b = pts[(i + 1) % n];
    if ((a[axis] < value) != (b[axis] < value)) {
      const double t = (value - a[axis]) / (b[axis] - a[axis]);
      at.push_back(a[other] + t * (b[other] - a[other]));
    }
  }
  std::sort(at.begin(), at.end());
  std::vector<std::pair<double, double>> out;
  for (size_t k = 0; k + 1 < at.size(); k += 2) {
    if (at[k + 1] > at[k]) out.emplace_back(at[k], at[k + 1]);
  }
  return out;
}

}  // namespace

BlankProfile::BlankProfile(std::vector<Vec2> rz) : points_(std::move(rz)) {
  if (points_.size() >= 2 && (points_.front() - points_.back()).norm() == 0) points_.pop_back();
  const int n = static_cast<int>(points_.size());
  if (n < 3) throw ParameterError("profile", "expected a closed polygon of at least 3 (r, z) points, got " +
                                                 std::to_string(n));
  if (n > kMaxPoints) {
    throw ParameterError("profile", "expected at most " + std::to_string(kMaxPoints) + " points, got " +
                                        std::to_string(n));
  }
  r_max_ = 0;
  z_min_ = kInf;
  z_max_ = -kInf;
  double area2 = 0, volume = 0;
  for (int i = 0; i < n; ++i) {
    const Vec2& a = points_[i];
    const Vec2& b = points_[(i + 1) % n];
    if (!std::isfinite(a.x()) || !std::isfinite(a.y())) {
      throw ParameterError("profile", "point " + std::to_string(i + 1) + " is not finite");
    }
    if (a.x() < 0) {
      throw ParameterError("profile", "point " + std::to_string(i + 1) + " has r = " + std::to_string(a.x()) +
                                          " < 0 (r is the distance from the part's axis)");
    }
    if ((b - a).norm() == 0) {
      throw ParameterError("profile", "points " + std::to_string(i + 1) + " and " + std::to_string((i + 1) % n + 1) +
                                          " coincide");
    }
    r_max_ = std::max(r_max_, a.x());
    z_min_ = std::min(z_min_, a.y());
    z_max_ = std::max(z_max_, a.y());
    area2 += blank_cross(a, b);
    // Green: the volume swept about the axis is ∮ π r² dz.
    volume += (b.y() - a.y()) * (a.x() * a.x() + a.x() * b.x() + b.x() * b.x()) / 3;
  }
  if (!(std::abs(area2) > 1e-12)) throw ParameterError("profile", "the polygon encloses no area");
  // Only edges that are not neighbours may not meet at all.
  for (int i = 0; i < n; ++i) {
    for (int j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;
      if (blank_segments_meet(points_[i], points_[i + 1], points_[j], points_[(j + 1) % n])) {
        throw ParameterError("profile", "edges " + std::to_string(i + 1) + "-" + std::to_string(i + 2) + " and " +
                                            std::to_string(j + 1) + "-" + std::to_string((j + 1) % n + 1) +
                                            " cross: expected a simple polygon");
      }
    }
  }
  volume_ = std::abs(kPi * volume);
}

std::vector<std::pair<double, double>> BlankProfile::z_spans_at_radius(double r) const {
  return blank_spans_on_line(points_, 0, r);
}

std::vector<std::pair<double, double>> BlankProfile::r_spans_at_height(double z) const {
  return blank_spans_on_line(points_, 1, z);
}

}  // namespace bliskrun
