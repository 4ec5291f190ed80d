#include "core/geometry/revolution_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/common/error.h"

namespace bliskrun {

namespace {

// Distance from p to the segment ab and the foot on it.
double segment_distance(const Vec2& p, const Vec2& a, const Vec2& b, Vec2& foot) {
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  foot = a + t * d;
  return (p - foot).norm();
}

double box_distance(const Vec2& p, const Vec2& lo, const Vec2& hi) {
  const double dz = std::max({lo.x() - p.x(), 0.0, p.x() - hi.x()});
  const double dr = std::max({lo.y() - p.y(), 0.0, p.y() - hi.y()});
  return std::hypot(dz, dr);
}

constexpr int kLeafSegments = 4;

// The meridian of `surface` as (z, r) points, doubled until the curve
// between every two of them, measured at three points, stays within
// chord_tol_mm of their chord.
std::vector<Vec2> meridian_polyline(const SurfaceOfRevolution& surface, double chord_tol_mm) {
  if (!(chord_tol_mm > 0) || !std::isfinite(chord_tol_mm))
    throw ParameterError("chord_tol", "must be a positive length in mm");
  // The meridian is u along the surface at v = 0, where (x, y, z) = (r, 0, z).
  auto at = [&](double u) {
    const Vec3 p = surface.eval(u, 0).p;
    return Vec2(p.z(), p.x());
  };
  for (int n = 64; n <= (1 << 20); n *= 2) {
    std::vector<Vec2> pts;
    for (int i = 0; i <= n; ++i) pts.push_back(at(static_cast<double>(i) / n));
    double worst = 0;
    for (int i = 0; i < n && worst <= chord_tol_mm; ++i) {
      for (int k = 1; k <= 3; ++k) {
        Vec2 foot;
        worst = std::max(worst, segment_distance(at((i + k / 4.0) / n), pts[i], pts[i + 1], foot));
      }
    }
    if (worst <= chord_tol_mm) return pts;
  }
  throw Error("RevolutionDistance: the meridian is not within " + std::to_string(chord_tol_mm) +
              " mm of 2^20 chords");
}

}  // namespace

RevolutionDistance::RevolutionDistance(const SurfaceOfRevolution& surface, double chord_tol_mm)
    : RevolutionDistance(meridian_polyline(surface, chord_tol_mm), chord_tol_mm) {}

RevolutionDistance::RevolutionDistance(std::vector<Vec2> meridian_zr, double chord_tol_mm)
    : zr_(std::move(meridian_zr)), chord_tol_mm_(chord_tol_mm) {
  if (zr_.size() < 2) throw ParameterError("meridian", "needs at least 2 (z, r) points");
  if (!(chord_tol_mm >= 0) || !std::isfinite(chord_tol_mm))
    throw ParameterError("chord_tol", "must be a non-negative length in mm");
  for (size_t i = 0; i < zr_.size(); ++i) {
    if (!zr_[i].allFinite() || zr_[i].y() < 0)
      throw ParameterError("meridian", "point " + std::to_string(i) + " must be finite with r >= 0");
  }
  nodes_.reserve(2 * zr_.size() / kLeafSegments + 2);
  build(0, segment_count());
}

int RevolutionDistance::build(int first, int count) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back({});
  Node node;
  node.first = first;
  node.count = count;
  node.lo = node.hi = zr_[first];
  for (int i = first; i <= first + count; ++i) {
    node.lo = node.lo.cwiseMin(zr_[i]);
    node.hi = node.hi.cwiseMax(zr_[i]);
  }
  if (count > kLeafSegments) {
    const int half = count / 2;
    node.left = build(first, half);
    node.right = build(first + half, count - half);
  }
  nodes_[index] = node;
  return index;
}

double RevolutionDistance::distance(const Vec3& q, double bound, Vec3* nearest) const {
  const double rho = std::hypot(q.x(), q.y());
  const Vec2 p(q.z(), rho);
  // Polyline distances below bound + tol matter; the tolerance comes off after.
  double best = bound + chord_tol_mm_;
  Vec2 best_foot = Vec2::Zero();
  bool found = false;
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (box_distance(p, node.lo, node.hi) >= best) continue;
    if (node.left < 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        Vec2 foot;
        const double d = segment_distance(p, zr_[i], zr_[i + 1], foot);
        if (d < best) {
          best = d;
          best_foot = foot;
          found = true;
        }
      }
      continue;
    }
    // The nearer child last, so it is taken first.
    const Node& l = nodes_[node.left];
    const Node& r = nodes_[node.right];
    const bool left_nearer = box_distance(p, l.lo, l.hi) <= box_distance(p, r.lo, r.hi);
    stack[top++] = left_nearer ? node.right : node.left;
    stack[top++] = left_nearer ? node.left : node.right;
  }
  if (!found) return bound;
  if (nearest) {
    const double c = rho > 0 ? q.x() / rho : 1.0, s = rho > 0 ? q.y() / rho : 0.0;
    *nearest = Vec3(best_foot.y() * c, best_foot.y() * s, best_foot.x());
  }
  return std::max(0.0, best - chord_tol_mm_);
}

}  // namespace bliskrun
