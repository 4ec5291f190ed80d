#include "core/geometry/revolution.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/common/error.h"
#include "core/common/progress.h"
#include "core/geometry/interpolation.h"
#include "core/geometry/projection.h"
#include "core/geometry/root_find.h"

namespace bliskrun {

namespace {

BSplineCurve fit_meridian(const std::vector<Vec2>& meridian) {
  if (meridian.size() < 2)
    throw ParameterError("meridian", "needs at least 2 (z, r) points, got " +
                                         std::to_string(meridian.size()));
  std::vector<Vec3> pts;
  for (size_t i = 0; i < meridian.size(); ++i) {
    if (!std::isfinite(meridian[i].x()) || !std::isfinite(meridian[i].y()) || meridian[i].y() < 0)
      throw ParameterError("meridian", "point " + std::to_string(i) +
                                           " must be finite with r >= 0");
    pts.emplace_back(meridian[i].x(), meridian[i].y(), 0.0);
  }
  return interpolate_cubic(pts);
}

}  // namespace

SurfaceOfRevolution::SurfaceOfRevolution(const std::vector<Vec2>& meridian)
    : SurfaceOfRevolution(std::make_shared<const BSplineCurve>(fit_meridian(meridian)),
                          static_cast<int>(meridian.size())) {}

SurfaceOfRevolution::SurfaceOfRevolution(std::shared_ptr<const Curve> meridian_zr, int seed_samples)
    : meridian_(std::move(meridian_zr)) {
  if (!meridian_) throw ParameterError("meridian", "expected a profile curve, got none");
  foot_options_.seed_samples_u = std::max(16, seed_samples);
  foot_seeds_ = curve_seed_samples(*meridian_, foot_options_);
}

SurfaceDerivs SurfaceOfRevolution::eval(double u, double v) const {
  const CurveDerivs m = meridian_->eval(u);  // (z, r, 0)
  const double w = 2 * kPi;
  const double c = std::cos(w * v), s = std::sin(w * v);
  const double z = m.p.x(), r = m.p.y();
  SurfaceDerivs d;
  d.p = Vec3(r * c, r * s, z);
  d.pu = Vec3(m.dt.y() * c, m.dt.y() * s, m.dt.x());
  d.pv = Vec3(-r * s, r * c, 0) * w;
  d.puu = Vec3(m.dtt.y() * c, m.dtt.y() * s, m.dtt.x());
  d.puv = Vec3(-m.dt.y() * s, m.dt.y() * c, 0) * w;
  d.pvv = Vec3(-r * c, -r * s, 0) * (w * w);
  return d;
}

SurfaceOfRevolution SurfaceOfRevolution::offset(double d, int samples) const {
  if (!std::isfinite(d)) throw ParameterError("offset", "expected a finite distance in mm");
  if (samples < 8) throw ParameterError("samples", "expected at least 8 profile samples");
  std::vector<Vec2> m;
  m.reserve(static_cast<size_t>(samples));
  for (int i = 0; i < samples; ++i) {
    const double f = static_cast<double>(i) / (samples - 1);
    const CurveDerivs c = meridian_->eval(meridian_->t_min() + f * (meridian_->t_max() - meridian_->t_min()));  // (z, r, 0)
    const Vec2 t(c.dt.x(), c.dt.y());
    const double speed = t.norm();
    if (!(speed > 0)) throw Error("offset: the hub profile has a zero tangent");
    // eval's pu x pv at angle 0 is 2 pi r (-z', 0, r'): in (z, r), (r', -z').
    const Vec2 n = Vec2(t.y(), -t.x()) / speed;
    // Signed curvature of the profile towards n; the offset folds where
    // 1 - d * kappa <= 0.
    const double kappa = (c.dtt.x() * n.x() + c.dtt.y() * n.y()) / (speed * speed);
    if (1 - d * kappa <= 0)
      throw ParameterError("offset", "the profile turns tighter than " + std::to_string(std::abs(d)) +
                                         " mm on that side: the offset surface would fold");
    m.emplace_back(Vec2(c.p.x(), c.p.y()) + d * n);
  }
  return SurfaceOfRevolution(m);
}

double SurfaceOfRevolution::offset_in_meridian(const Vec3& q, Vec3* direction_zr) const {
  // Work in q's meridian plane: (z, r) of q against the profile curve.
  const Vec3 qzr(q.z(), std::hypot(q.x(), q.y()), 0.0);
  const CurveProjection foot = project_to_curve(*meridian_, qzr, foot_options_, foot_seeds_);
  if (!foot.ok)
    throw Error("radial_offset: no foot on the meridian for (z, r) = (" + std::to_string(qzr.x()) +
                ", " + std::to_string(qzr.y()) + "): " + foot.failure);
  const CurveDerivs d = meridian_->eval(foot.t);
  // Left normal of the profile direction (z', r'): (-r', z'). For a profile
  // running towards +z this points away from the axis.
  Vec3 normal(-d.dt.y(), d.dt.x(), 0.0);
  normal.normalize();
  const Vec3 e = qzr - foot.point;
  // Beyond an end of the profile the foot is the end point; the offset is
  // still signed by the side of the profile's normal.
  const bool out = e.dot(normal) >= 0;
  if (direction_zr) *direction_zr = e.norm() > 1e-9 ? Vec3((out ? 1.0 : -1.0) * e.normalized()) : normal;
  return out ? e.norm() : -e.norm();
}

double SurfaceOfRevolution::radial_offset(const Vec3& q) const { return offset_in_meridian(q, nullptr); }

Vec3 SurfaceOfRevolution::offset_direction(const Vec3& q) const {
  Vec3 zr;
  offset_in_meridian(q, &zr);
  const double rxy = std::hypot(q.x(), q.y());
  // On the axis every half-plane is q's: take the one through +X.
  const Vec3 radial = rxy > 1e-12 ? Vec3(q.x() / rxy, q.y() / rxy, 0.0) : Vec3::UnitX();
  return Vec3(zr.x() * Vec3::UnitZ() + zr.y() * radial);
}

double SurfaceOfRevolution::radius_at(double z) const {
  const double t0 = meridian_->t_min(), t1 = meridian_->t_max();
  const double z0 = meridian_->point(t0).x(), z1 = meridian_->point(t1).x();
  if (z < std::min(z0, z1) - 1e-12 || z > std::max(z0, z1) + 1e-12)
    throw Error("radius_at: z = " + std::to_string(z) + " mm is outside the profile [" +
                std::to_string(std::min(z0, z1)) + ", " + std::to_string(std::max(z0, z1)) + "]");
  // Bisection on z(u): the profile is single-valued in z where this is used.
  double lo = t0, hi = t1;
  const bool rising = z1 > z0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    const double zm = meridian_->point(mid).x();
    if ((zm < z) == rising) lo = mid; else hi = mid;
  }
  return meridian_->point(0.5 * (lo + hi)).y();
}

SurfaceCurveOnSurface intersect_with_revolution(const Surface& s, const SurfaceOfRevolution& rev,
                                                int samples_v) {
  if (samples_v < 2) throw ParameterError("samples_v", "must be at least 2");
  constexpr int kBracket = 64;
  SurfaceCurveOnSurface out;
  for (int j = 0; j < samples_v; ++j) {
    cancellation_point();
    const double v = static_cast<double>(j) / (samples_v - 1);
    auto g = [&](double u) { return rev.radial_offset(s.point(u, v)); };
    double prev_u = 0, prev_g = g(0);
    bool found = false;
    for (int i = 1; i <= kBracket && !found; ++i) {
      const double u = static_cast<double>(i) / kBracket;
      const double gu = g(u);
      if ((prev_g <= 0) != (gu <= 0)) {
        const double root = illinois_root(g, prev_u, u, prev_g, gu, 1e-13, 100);
        out.u.push_back(root);
        out.v.push_back(v);
        out.points.push_back(s.point(root, v));
        found = true;
      }
      prev_u = u;
      prev_g = gu;
    }
    if (!found)
      throw Error("intersect_with_revolution: the iso-v line v = " + std::to_string(v) +
                  " does not cross the surface of revolution");
  }
  return out;
}

}  // namespace bliskrun
