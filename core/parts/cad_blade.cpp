#include "core/parts/cad_blade.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/common/error.h"
#include "core/geometry/differential.h"

namespace bliskrun {

// ---- the cylindrical wrap ----------------------------------------------------

UnwrappedSurface::UnwrappedSurface(std::shared_ptr<const Surface> unwrapped, double axial_origin_mm)
    : s_(std::move(unwrapped)), origin_(axial_origin_mm) {}

SurfaceDerivs UnwrappedSurface::eval(double u, double v) const {
  // F(a, s, R) = (R cos(s/R), R sin(s/R), a - origin). With th = s/R:
  // dth/ds = 1/R, dth/dR = -th/R; first and second partials of X, Y in (s, R)
  // below; Z = a is linear.
  const SurfaceDerivs q = s_->eval(u, v);
  const double s = q.p.y(), R = q.p.z();
  if (!(R > 0)) throw Error("unwrapped surface: radius (z) must be > 0, got " + std::to_string(R));
  const double th = s / R, c = std::cos(th), sn = std::sin(th);
  // Jacobian rows for X and Y as d/ds, d/dR.
  const double Xs = -sn, XR = c + th * sn, Ys = c, YR = sn - th * c;
  const double Xss = -c / R, XsR = th * c / R, XRR = -th * th * c / R;
  const double Yss = -sn / R, YsR = th * sn / R, YRR = -th * th * sn / R;
  auto first = [&](const Vec3& d) {  // J d
    return Vec3(Xs * d.y() + XR * d.z(), Ys * d.y() + YR * d.z(), d.x());
  };
  auto second = [&](const Vec3& d, const Vec3& e) {  // H(d, e)
    return Vec3(Xss * d.y() * e.y() + XsR * (d.y() * e.z() + d.z() * e.y()) + XRR * d.z() * e.z(),
                Yss * d.y() * e.y() + YsR * (d.y() * e.z() + d.z() * e.y()) + YRR * d.z() * e.z(), 0);
  };
  SurfaceDerivs out;
  out.p = Vec3(R * c, R * sn, q.p.x() - origin_);
  out.pu = first(q.pu);
  out.pv = first(q.pv);
  out.puu = first(q.puu) + second(q.pu, q.pu);
  out.puv = first(q.puv) + second(q.pu, q.pv);
  out.pvv = first(q.pvv) + second(q.pv, q.pv);
  return out;
}

// ---- flanks --------------------------------------------------------------------

namespace {

// p'(u', v') = closed(c, t) with t = u' (span) and c = c0 + dir L v' taken
// modulo 1 (the arc may run over the seam of a closed surface).
class FlankWindow : public Surface {
 public:
  FlankWindow(std::shared_ptr<const Surface> closed, bool closed_in_u, double c0, double length, double dir)
      : s_(std::move(closed)), in_u_(closed_in_u), c0_(c0), k_(dir * length) {}

  SurfaceDerivs eval(double u, double v) const override {
    double c = c0_ + k_ * std::clamp(v, 0.0, 1.0);
    c -= std::floor(c);
    const double t = std::clamp(u, 0.0, 1.0);
    const SurfaceDerivs q = in_u_ ? s_->eval(c, t) : s_->eval(t, c);
    // Partials of the closed surface along the chord (c) and span (t).
    const Vec3& qc = in_u_ ? q.pu : q.pv;
    const Vec3& qt = in_u_ ? q.pv : q.pu;
    const Vec3& qcc = in_u_ ? q.puu : q.pvv;
    const Vec3& qtt = in_u_ ? q.pvv : q.puu;
    SurfaceDerivs out;
    out.p = q.p;
    out.pu = qt;
    out.pv = k_ * qc;
    out.puu = qtt;
    out.puv = k_ * q.puv;
    out.pvv = k_ * k_ * qcc;
    return out;
  }

 private:
  std::shared_ptr<const Surface> s_;
  bool in_u_;
  double c0_, k_;
};

double size_of(const Surface& s) {
  Vec3 lo = s.point(0, 0), hi = lo;
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j) {
      const Vec3 p = s.point(i / 8.0, j / 8.0);
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  return (hi - lo).norm();
}

double closing_gap(const Surface& s, bool in_u) {
  double gap = 0;
  for (int k = 0; k <= 20; ++k) {
    const double t = k / 20.0;
    gap = std::max(gap, in_u ? (s.point(0, t) - s.point(1, t)).norm() : (s.point(t, 0) - s.point(t, 1)).norm());
  }
  return gap;
}

}  // namespace

CadBlade cad_blade(std::shared_ptr<const Surface> closed, const CadBladeOptions& options) {
  if (!closed) throw ParameterError("cad_blade", "no surface given");
  if (options.samples < 16) throw ParameterError("samples", "must be >= 16");
  CadBlade out;
  out.airfoil = options.coordinates == CadCoordinates::kAxialRthetaR
                    ? std::make_shared<UnwrappedSurface>(closed, options.axial_origin_mm)
                    : closed;
  const Surface& s = *out.airfoil;
  const double size = size_of(s), gu = closing_gap(s, true), gv = closing_gap(s, false);
  const double tol = 1e-6 * std::max(1.0, size);
  if (gu > tol && gv > tol)
    throw ParameterError("cad_blade", "the surface does not close around the airfoil: its u = 0 and u = 1 edges are " +
                                          std::to_string(gu) + " mm apart, its v = 0 and v = 1 edges " +
                                          std::to_string(gv) + " mm (a closed airfoil surface is expected)");
  out.closed_in_u = gu <= gv;
  const bool in_u = out.closed_in_u;
  auto at = [&](double c, double t) { return in_u ? s.point(c, t) : s.point(t, c); };
  // Edges at mid-span: lowest and highest axial position (z).
  const int n = options.samples;
  double zmin = 1e300, zmax = -1e300;
  std::vector<Vec3> section;
  for (int k = 0; k < n; ++k) {
    const double c = double(k) / n;
    const Vec3 p = at(c, 0.5);
    section.push_back(p);
    if (p.z() < zmin) zmin = p.z(), out.le = c;
    if (p.z() > zmax) zmax = p.z(), out.te = c;
  }
  if (!(zmax - zmin > tol)) throw ParameterError("cad_blade", "the airfoil has no axial extent at mid-span");
  // Whether q lies inside the mid-span section, seen along the span
  // direction `span` (even-odd rule on the section projected on the plane
  // across it): a crescent-shaped section's centroid may lie outside it.
  auto inside = [&](const Vec3& q, const Vec3& span) {
    const Vec3 e = span.normalized();
    const Vec3 a = e.unitOrthogonal(), b = e.cross(a);
    bool in = false;
    for (size_t i = 0, j = section.size() - 1; i < section.size(); j = i++) {
      const double xi = (section[i] - q).dot(a), yi = (section[i] - q).dot(b);
      const double xj = (section[j] - q).dot(a), yj = (section[j] - q).dot(b);
      if ((yi > 0) != (yj > 0) && xi + (0 - yi) * (xj - xi) / (yj - yi) > 0) in = !in;
    }
    return in;
  };
  // The two arcs from LE to TE, each oriented so pu x pv points out of the
  // material (a step along it leaves the section).
  const double fwd = out.te - out.le - std::floor(out.te - out.le);  // LE -> TE going forward
  std::shared_ptr<const Surface> arcs[2];
  double bend[2];
  for (int a = 0; a < 2; ++a) {
    // Arc 0 forward from LE over fwd, arc 1 forward from TE over 1 - fwd.
    const double c0 = a == 0 ? out.le : out.te, len = a == 0 ? fwd : 1 - fwd;
    auto w = std::make_shared<FlankWindow>(out.airfoil, in_u, c0, len, 1.0);
    const SurfaceDerivs d = w->eval(0.5, 0.5);
    if (inside(d.p + 1e-3 * size * d.pu.cross(d.pv).normalized(), d.pu))
      w = std::make_shared<FlankWindow>(out.airfoil, in_u, c0 + len, len, -1.0);
    arcs[a] = w;
    bend[a] = 0;
    for (double v : {0.3, 0.5, 0.7}) {
      const SurfaceDerivs e = w->eval(0.5, v);
      bend[a] += normal_curvature(e, e.pv);
    }
  }
  // Convex (bending away from the outward normal): the more negative one.
  const int suction = bend[0] < bend[1] ? 0 : 1;
  out.suction = arcs[suction];
  out.pressure = arcs[1 - suction];
  return out;
}

SurfaceOfRevolution revolution_from_curve(const Curve& meridian, const CadBladeOptions& options, int samples) {
  if (samples < 2) throw ParameterError("samples", "must be >= 2");
  std::vector<Vec2> zr;
  for (int k = 0; k < samples; ++k) {
    const Vec3 p = meridian.point(meridian.t_min() + (meridian.t_max() - meridian.t_min()) * k / (samples - 1));
    zr.push_back(options.coordinates == CadCoordinates::kAxialRthetaR
                     ? Vec2(p.x() - options.axial_origin_mm, std::hypot(p.y(), p.z()))
                     : Vec2(p.z(), std::hypot(p.x(), p.y())));
  }
  if (zr.back().x() < zr.front().x()) std::reverse(zr.begin(), zr.end());
  for (size_t k = 1; k < zr.size(); ++k)
    if (!(zr[k].x() > zr[k - 1].x()))
      throw ParameterError("meridian", "the curve's axial position must increase along it (sample " +
                                           std::to_string(k) + " of " + std::to_string(samples) + " at " +
                                           std::to_string(zr[k].x()) + " mm does not)");
  return SurfaceOfRevolution(zr);
}

}  // namespace bliskrun
