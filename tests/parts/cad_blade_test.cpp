#include "core/parts/cad_blade.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"
#include "core/geometry/differential.h"

namespace bliskrun {
namespace {

// A flat patch in unwrapped (x axial, y = R theta, z = R) coordinates at
// R = 100: wrapped, a piece of the cylinder of radius 100 about Z.
class UnwrappedPatch : public Surface {
 public:
  SurfaceDerivs eval(double u, double v) const override {
    SurfaceDerivs d;
    d.p = Vec3(250 + 30 * u, -20 + 40 * v + 5 * u * v, 100 + 3 * u * u);
    d.pu = Vec3(30, 5 * v, 6 * u);
    d.pv = Vec3(0, 40 + 5 * u, 0);
    d.puu = Vec3(0, 0, 6);
    d.puv = Vec3(0, 5, 0);
    return d;
  }
};

TEST(UnwrappedSurface, WrapsRThetaOntoTheCylinderWithExactDerivatives) {
  const UnwrappedSurface s(std::make_shared<UnwrappedPatch>(), 260);
  const UnwrappedPatch q;
  for (double u : {0.0, 0.3, 1.0})
    for (double v : {0.0, 0.45, 1.0}) {
      const Vec3 p = s.point(u, v), a = q.point(u, v);
      EXPECT_NEAR(std::hypot(p.x(), p.y()), a.z(), 1e-12);              // R
      EXPECT_NEAR(std::atan2(p.y(), p.x()), a.y() / a.z(), 1e-12);      // theta = s / R
      EXPECT_NEAR(p.z(), a.x() - 260, 1e-12);                           // axial
    }
  const double e = 1e-5;
  for (double u : {0.2, 0.7})
    for (double v : {0.3, 0.8}) {
      const SurfaceDerivs d = s.eval(u, v), a = s.eval(u + e, v), b = s.eval(u - e, v);
      const SurfaceDerivs c = s.eval(u, v + e), f = s.eval(u, v - e);
      EXPECT_NEAR(((a.p - b.p) / (2 * e) - d.pu).norm(), 0, 1e-6);
      EXPECT_NEAR(((c.p - f.p) / (2 * e) - d.pv).norm(), 0, 1e-6);
      EXPECT_NEAR(((a.pu - b.pu) / (2 * e) - d.puu).norm(), 0, 1e-6);
      EXPECT_NEAR(((c.pv - f.pv) / (2 * e) - d.pvv).norm(), 0, 1e-6);
      EXPECT_NEAR(((c.pu - f.pu) / (2 * e) - d.puv).norm(), 0, 1e-6);
    }
  // At u = 0 the patch is a constant-radius cylinder piece: curvature 1/R
  // around, 0 along the axis.
  const SurfaceCurvature k = curvature(s.eval(0, 0.5));
  EXPECT_NEAR(std::max(std::abs(k.k1), std::abs(k.k2)), 1 / 100.0, 1e-9);
}

// A cambered airfoil, span along X from r = 100 to 120, chord along Z
// (LE at z = -15, TE at z = +15), closed around in u; the camber bulges to
// +y, so the +y side is the convex (suction) one.
class Airfoil : public Surface {
 public:
  explicit Airfoil(bool swap = false) : swap_(swap) {}
  SurfaceDerivs eval(double a, double b) const override {
    const double u = swap_ ? b : a, v = swap_ ? a : b;
    const double w = 2 * kPi, s = std::sin(w * u), c = std::cos(w * u);
    // z = 15 cos, y = 3 sin + 0.02 (225 - z^2) = 3 s + 4.5 s^2
    SurfaceDerivs d;
    d.p = Vec3(100 + 20 * v, 3 * s + 4.5 * s * s, 15 * c);
    const Vec3 du(0, 3 * w * c + 9 * w * s * c, -15 * w * s);
    const Vec3 duu(0, -3 * w * w * s + 9 * w * w * (c * c - s * s), -15 * w * w * c);
    const Vec3 dv(20, 0, 0);
    d.pu = swap_ ? dv : du;
    d.pv = swap_ ? du : dv;
    d.puu = swap_ ? Vec3::Zero() : duu;
    d.pvv = swap_ ? duu : Vec3::Zero();
    return d;
  }
  bool swap_;
};

void expect_flanks(const CadBlade& b) {
  for (const auto& [name, f] : {std::pair{"pressure", b.pressure}, {"suction", b.suction}}) {
    // u hub -> tip.
    EXPECT_NEAR(f->point(0, 0.5).x(), 100, 1e-9) << name;
    EXPECT_NEAR(f->point(1, 0.5).x(), 120, 1e-9) << name;
    // The ends of v are the edges, z = -15 and +15 (found on 2000 samples).
    const double z0 = f->point(0.5, 0).z(), z1 = f->point(0.5, 1).z();
    EXPECT_NEAR(std::min(z0, z1), -15, 1e-3) << name;
    EXPECT_NEAR(std::max(z0, z1), 15, 1e-3) << name;
  }
  // Outward normals: the suction flank's to +y, the pressure flank's to -y.
  for (double v : {0.25, 0.5, 0.75}) {
    const SurfaceDerivs s = b.suction->eval(0.5, v), p = b.pressure->eval(0.5, v);
    EXPECT_GT(s.pu.cross(s.pv).y(), 0) << v;
    EXPECT_LT(p.pu.cross(p.pv).y(), 0) << v;
    EXPECT_GT(s.p.y(), p.p.y());
  }
  // Derivatives of the window match finite differences.
  const double e = 1e-6;
  const SurfaceDerivs d = b.pressure->eval(0.4, 0.3), a = b.pressure->eval(0.4, 0.3 + e),
                      c = b.pressure->eval(0.4, 0.3 - e);
  EXPECT_NEAR(((a.p - c.p) / (2 * e) - d.pv).norm(), 0, 1e-5 * d.pv.norm());
  EXPECT_NEAR(((a.pv - c.pv) / (2 * e) - d.pvv).norm(), 0, 1e-4 * (d.pvv.norm() + 1));
}

TEST(CadBlade, SplitsAClosedAirfoilIntoOutwardFacingFlanks) {
  const CadBlade b = cad_blade(std::make_shared<Airfoil>());
  EXPECT_TRUE(b.closed_in_u);
  EXPECT_NEAR(b.le, 0.5, 1e-3);
  EXPECT_NEAR(b.te, 0.0, 1e-3);
  expect_flanks(b);
}

TEST(CadBlade, AcceptsASurfaceClosedInV) {
  const CadBlade b = cad_blade(std::make_shared<Airfoil>(true));
  EXPECT_FALSE(b.closed_in_u);
  expect_flanks(b);
}

class OpenPatch : public Surface {
 public:
  SurfaceDerivs eval(double u, double v) const override {
    SurfaceDerivs d;
    d.p = Vec3(u, v, 0);
    d.pu = Vec3(1, 0, 0);
    d.pv = Vec3(0, 1, 0);
    return d;
  }
};

TEST(CadBlade, RefusesASurfaceThatDoesNotClose) {
  try {
    cad_blade(std::make_shared<OpenPatch>());
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("does not close"), std::string::npos) << e.what();
  }
}

class Line : public Curve {
 public:
  explicit Line(Vec3 a, Vec3 b) : a_(a), b_(b) {}
  CurveDerivs eval(double t) const override { return {a_ + t * (b_ - a_), b_ - a_, Vec3::Zero()}; }
  Vec3 a_, b_;
};

TEST(CadBlade, HubOfRevolutionFromAMeridianCurve) {
  CadBladeOptions o;
  o.coordinates = CadCoordinates::kAxialRthetaR;
  o.axial_origin_mm = 50;
  // E3's hub.igs: x axial, y radius, in the plane z = 0; given backwards.
  const SurfaceOfRevolution hub = revolution_from_curve(Line({100, 60, 0}, {0, 50, 0}), o);
  EXPECT_NEAR(hub.radius_at(-50), 50, 1e-9);
  EXPECT_NEAR(hub.radius_at(0), 55, 1e-9);
  EXPECT_NEAR(hub.radius_at(50), 60, 1e-9);
  EXPECT_THROW(revolution_from_curve(Line({0, 50, 0}, {0, 60, 0}), o), ParameterError);
}

}  // namespace
}  // namespace bliskrun
