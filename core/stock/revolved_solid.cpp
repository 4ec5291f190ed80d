#include "core/stock/revolved_solid.h"

#include <algorithm>
#include <cmath>

#include "core/common/error.h"

namespace bliskrun {

namespace {

constexpr double kSolidThinMm = 1e-12;  // a slab thinner than this adds nothing

// The span where a·s² + 2·b·s + c <= 0 within [lo, hi]; false if empty.
// The set is one span there for every piece the solids are made of (the
// slab of a convex frustum or sphere zone), so a two-span answer of a
// concave quadratic is closed to its hull.
bool solid_quadratic_span(double a, double b, double c, double& lo, double& hi) {
  if (std::abs(a) < 1e-12) {
    if (std::abs(b) < 1e-15) return c <= 0 && lo <= hi;
    const double root = -c / (2 * b);
    if (b > 0) {
      hi = std::min(hi, root);
    } else {
      lo = std::max(lo, root);
    }
    return lo <= hi;
  }
  const double disc = b * b - a * c;
  if (a > 0) {
    if (disc < 0) return false;
    // The stable pair of roots.
    const double q = -(b + std::copysign(std::sqrt(disc), b));
    double r1 = q / a, r2 = q != 0 ? c / q : r1;
    if (r1 > r2) std::swap(r1, r2);
    lo = std::max(lo, r1);
    hi = std::min(hi, r2);
    return lo <= hi;
  }
  if (disc <= 0) return lo <= hi;  // <= 0 everywhere
  const double q = -(b + std::copysign(std::sqrt(disc), b));
  double r1 = q / a, r2 = q != 0 ? c / q : r1;
  if (r1 > r2) std::swap(r1, r2);
  // (-inf, r1] and [r2, inf) within [lo, hi].
  const bool below = lo <= std::min(r1, hi), above = std::max(r2, lo) <= hi;
  if (below && above) return true;  // both: the hull is [lo, hi]
  if (below) {
    hi = std::min(r1, hi);
    return true;
  }
  if (above) {
    lo = std::max(r2, lo);
    return true;
  }
  return false;
}

double solid_arc_start(const ProfileElement& e) { return std::atan2(e.start.y() - e.centre.y(), e.start.x() - e.centre.x()); }

double solid_arc_sweep(const ProfileElement& e) {
  const double a0 = solid_arc_start(e);
  const double a1 = std::atan2(e.end.y() - e.centre.y(), e.end.x() - e.centre.x());
  double s = a1 - a0;
  while (s <= 0) s += 2 * kPi;
  return s;
}

RevolvedSolid::Piece solid_frustum(const Vec2& a, const Vec2& b) {
  RevolvedSolid::Piece p;
  p.z0 = a.y();
  p.z1 = b.y();
  p.r0 = std::max(0.0, a.x());
  p.slope = (std::max(0.0, b.x()) - p.r0) / (b.y() - a.y());
  return p;
}

}  // namespace

double RevolvedSolid::Piece::radius_at(double z) const {
  if (!sphere) return r0 + slope * (z - z0);
  const double d = z - centre_z;
  return std::sqrt(std::max(0.0, radius * radius - d * d));
}

RevolvedSolid::RevolvedSolid(const Profile& profile, double torus_tol_mm) {
  if (!(torus_tol_mm > 0)) throw ParameterError("torus_tol_mm", "expected a positive tolerance, mm");
  for (const ProfileElement& e : profile.elements()) {
    if (e.end.y() - e.start.y() < kSolidThinMm) continue;  // a flat face: the slabs beside it hold it
    if (e.kind == ProfileElement::Kind::Segment) {
      pieces_.push_back(solid_frustum(e.start, e.end));
      continue;
    }
    if (std::abs(e.centre.x()) < 1e-9) {
      Piece p;
      p.sphere = true;
      p.z0 = e.start.y();
      p.z1 = e.end.y();
      p.centre_z = e.centre.y();
      p.radius = e.radius;
      pieces_.push_back(p);
      continue;
    }
    // A torus: its tangent polygon (corners at radius rho / cos(step/2)).
    const double max_step = 2 * std::acos(1.0 / (1.0 + torus_tol_mm / e.radius));
    const double sweep = solid_arc_sweep(e);
    const int n = std::max(1, static_cast<int>(std::ceil(sweep / max_step)));
    const double step = sweep / n, a0 = solid_arc_start(e), corner = e.radius / std::cos(step / 2);
    Vec2 last = e.start;
    for (int k = 0; k <= n; ++k) {
      const Vec2 next = k < n ? Vec2(e.centre + corner * Vec2(std::cos(a0 + (k + 0.5) * step),
                                                                std::sin(a0 + (k + 0.5) * step)))
                              : e.end;
      if (next.y() - last.y() >= kSolidThinMm) pieces_.push_back(solid_frustum(last, next));
      if (next.y() >= last.y()) last = next;
    }
  }
  finish();
}

void RevolvedSolid::finish() {
  z_min_ = kInf;
  z_max_ = -kInf;
  max_radius_ = 0;
  for (const Piece& p : pieces_) {
    z_min_ = std::min(z_min_, p.z0);
    z_max_ = std::max(z_max_, p.z1);
    max_radius_ = std::max({max_radius_, p.radius_at(p.z0), p.radius_at(p.z1)});
    if (p.sphere && p.centre_z > p.z0 && p.centre_z < p.z1) max_radius_ = std::max(max_radius_, p.radius);
  }
  if (pieces_.empty()) z_min_ = z_max_ = 0;
}

RevolvedSolid RevolvedSolid::swept_along_axis(double shift) const {
  RevolvedSolid from = *this;
  if (shift < 0) {
    // Moving down by |shift| sweeps what moving up from the end does.
    for (Piece& p : from.pieces_) {
      p.z0 += shift;
      p.z1 += shift;
      p.centre_z += shift;
    }
    shift = -shift;
  }
  // The lowest height of the widest section: below it R(z) rises, above it
  // falls (a convex profile), so the sweep keeps the lower part, the upper
  // part shifted, and the widest radius between.
  double widest = -1, at = 0;
  for (const Piece& p : from.pieces_) {
    const auto consider = [&](double z) {
      const double r = p.radius_at(z);
      if (r > widest + 1e-12 || (r > widest - 1e-12 && z < at)) widest = std::max(widest, r), at = z;
    };
    consider(p.z0);
    consider(p.z1);
    if (p.sphere && p.centre_z > p.z0 && p.centre_z < p.z1) consider(p.centre_z);
  }
  RevolvedSolid out;
  for (const Piece& p : from.pieces_) {
    if (p.z0 < at - kSolidThinMm) {
      Piece lower = p;
      lower.z1 = std::min(p.z1, at);
      out.pieces_.push_back(lower);
    }
  }
  if (shift > kSolidThinMm) {
    Piece band;
    band.z0 = at;
    band.z1 = at + shift;
    band.r0 = widest;
    out.pieces_.push_back(band);
  }
  for (const Piece& p : from.pieces_) {
    if (p.z1 > at + kSolidThinMm) {
      Piece upper = p;
      upper.z0 = std::max(p.z0, at);
      if (!p.sphere) upper.r0 = p.radius_at(upper.z0);
      upper.z0 += shift;
      upper.z1 += shift;
      upper.centre_z += shift;
      out.pieces_.push_back(upper);
    }
  }
  out.finish();
  return out;
}

bool RevolvedSolid::bound(const FrameRay& ray, double& lo, double& hi) const {
  if (pieces_.empty()) return false;
  lo = -kInf;
  hi = kInf;
  if (std::abs(ray.dz) < 1e-12) {
    if (ray.z0 < z_min_ || ray.z0 > z_max_) return false;
  } else {
    lo = (z_min_ - ray.z0) / ray.dz;
    hi = (z_max_ - ray.z0) / ray.dz;
    if (lo > hi) std::swap(lo, hi);
  }
  return solid_quadratic_span(ray.a, ray.b, ray.c - max_radius_ * max_radius_, lo, hi);
}

namespace {

// The ray's span in one piece (its slab and its quadric); false if none.
bool solid_piece_span(const RevolvedSolid::Piece& p, const FrameRay& ray, double& l, double& h) {
  l = -kInf;
  h = kInf;
  if (std::abs(ray.dz) < 1e-12) {
    if (ray.z0 < p.z0 || ray.z0 > p.z1) return false;
  } else {
    l = (p.z0 - ray.z0) / ray.dz;
    h = (p.z1 - ray.z0) / ray.dz;
    if (l > h) std::swap(l, h);
  }
  double qa, qb, qc;
  if (p.sphere) {
    const double g = ray.z0 - p.centre_z;
    qa = ray.a + ray.dz * ray.dz;
    qb = ray.b + g * ray.dz;
    qc = ray.c + g * g - p.radius * p.radius;
  } else {
    const double e = p.r0 + p.slope * (ray.z0 - p.z0), f = p.slope * ray.dz;
    qa = ray.a - f * f;
    qb = ray.b - e * f;
    qc = ray.c - e * e;
  }
  return solid_quadratic_span(qa, qb, qc, l, h);
}

}  // namespace

bool RevolvedSolid::intersect(const FrameRay& ray, double bound_lo, double bound_hi, double& lo, double& hi) const {
  const int n = static_cast<int>(pieces_.size());
  double l, h;
  if (std::abs(ray.dz) < 1e-12) {
    // Across the axis: the one or two slabs at the ray's height.
    bool hit = false;
    for (const Piece& p : pieces_) {
      if (ray.z0 < p.z0 || ray.z0 > p.z1 || !solid_piece_span(p, ray, l, h)) continue;
      lo = hit ? std::min(lo, l) : l;
      hi = hit ? std::max(hi, h) : h;
      hit = true;
    }
    return hit;
  }
  // The slabs are in z order, so in order along the ray (reversed when it
  // runs down the axis). The solid is convex: the first slab the ray meets
  // it in holds the span's start, the last its end, and only slabs within
  // the bounding span's heights can.
  const double za = ray.z0 + ray.dz * bound_lo, zb = ray.z0 + ray.dz * bound_hi;
  const double z_lo = std::min(za, zb) - 1e-9, z_hi = std::max(za, zb) + 1e-9;
  const bool up = ray.dz > 0;
  int first = -1;
  for (int k = 0; k < n; ++k) {
    const Piece& p = pieces_[static_cast<size_t>(up ? k : n - 1 - k)];
    if (p.z1 < z_lo || p.z0 > z_hi) continue;
    if (solid_piece_span(p, ray, l, h)) {
      first = k;
      lo = l;
      hi = h;
      break;
    }
  }
  if (first < 0) return false;
  for (int k = n - 1; k > first; --k) {
    const Piece& p = pieces_[static_cast<size_t>(up ? k : n - 1 - k)];
    if (p.z1 < z_lo || p.z0 > z_hi) continue;
    if (solid_piece_span(p, ray, l, h)) {
      hi = std::max(hi, h);
      break;
    }
  }
  return true;
}

}  // namespace bliskrun
