#pragma once
// Analytic surfaces with closed-form derivatives and curvatures, shared by
// the geometry tests.
#include <cmath>

#include "core/geometry/surface.h"

namespace bliskrun::test {

// Sphere of radius R: u -> polar angle in [0.2, pi - 0.2], v -> azimuth
// [0, 2 pi). Normal pu x pv points outwards, so the normal curvature is
// -1/R in every direction (the surface bends away from the normal).
class Sphere : public Surface {
 public:
  explicit Sphere(double r) : r_(r) {}
  SurfaceDerivs eval(double u, double v) const override {
    const double a0 = 0.2, da = kPi - 0.4, db = 2 * kPi;
    const double a = a0 + da * u, b = db * v;
    const double sa = std::sin(a), ca = std::cos(a), sb = std::sin(b), cb = std::cos(b);
    SurfaceDerivs d;
    d.p = r_ * Vec3(sa * cb, sa * sb, ca);
    d.pu = r_ * da * Vec3(ca * cb, ca * sb, -sa);
    d.pv = r_ * db * Vec3(-sa * sb, sa * cb, 0);
    d.puu = -r_ * da * da * Vec3(sa * cb, sa * sb, ca);
    d.puv = r_ * da * db * Vec3(-ca * sb, ca * cb, 0);
    d.pvv = -r_ * db * db * Vec3(sa * cb, sa * sb, 0);
    return d;
  }
  double r_;
};

// Cylinder of radius R about Z: u -> z in [0, H], v -> angle [0, 1 rad].
// pu x pv points to the axis: normal curvature +1/R around, 0 along it.
class Cylinder : public Surface {
 public:
  Cylinder(double r, double h) : r_(r), h_(h) {}
  SurfaceDerivs eval(double u, double v) const override {
    const double c = std::cos(v), s = std::sin(v);
    SurfaceDerivs d;
    d.p = Vec3(r_ * c, r_ * s, h_ * u);
    d.pu = Vec3(0, 0, h_);
    d.pv = Vec3(-r_ * s, r_ * c, 0);
    d.pvv = Vec3(-r_ * c, -r_ * s, 0);
    return d;
  }
  double r_, h_;
};

// Torus: tube radius r around a circle of radius R in the XY plane.
// u -> tube angle phi in [0, 2 pi), v -> ring angle theta in [0, pi/2].
// pu x pv points to the tube's centre circle. Principal curvatures 1/r
// (around the tube) and cos(phi) / (R + r cos(phi)) (around the ring);
// Gaussian curvature K = cos(phi) / (r (R + r cos(phi))).
class Torus : public Surface {
 public:
  Torus(double big_r, double r) : R_(big_r), r_(r) {}
  SurfaceDerivs eval(double u, double v) const override {
    const double du = 2 * kPi, dv = kPi / 2;
    const double ph = du * u, th = dv * v;
    const double cp = std::cos(ph), sp = std::sin(ph), ct = std::cos(th), st = std::sin(th);
    const double w = R_ + r_ * cp;
    SurfaceDerivs d;
    d.p = Vec3(w * ct, w * st, r_ * sp);
    d.pu = du * Vec3(-r_ * sp * ct, -r_ * sp * st, r_ * cp);
    d.pv = dv * Vec3(-w * st, w * ct, 0);
    d.puu = du * du * Vec3(-r_ * cp * ct, -r_ * cp * st, -r_ * sp);
    d.puv = du * dv * Vec3(r_ * sp * st, -r_ * sp * ct, 0);
    d.pvv = dv * dv * Vec3(-w * ct, -w * st, 0);
    return d;
  }
  double phi(double u) const { return 2 * kPi * u; }
  double R_, r_;
};

}  // namespace bliskrun::test
