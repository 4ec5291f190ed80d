#include "core/geometry/revolution.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/common/error.h"
#include "core/geometry/differential.h"

namespace bliskrun {
namespace {

// A cone: r = 100 + 0.25 z over z in [0, 40] (a conical hub).
SurfaceOfRevolution cone() {
  std::vector<Vec2> m;
  for (int i = 0; i <= 8; ++i) m.emplace_back(5.0 * i, 100 + 0.25 * 5.0 * i);
  return SurfaceOfRevolution(m);
}

TEST(SurfaceOfRevolution, ConeRadiusNormalAndCurvature) {
  const SurfaceOfRevolution s = cone();
  for (double z : {0.0, 7.3, 20.0, 40.0}) EXPECT_NEAR(s.radius_at(z), 100 + 0.25 * z, 1e-12);
  const SurfaceDerivs d = s.eval(0.5, 0.1);
  const double r = std::hypot(d.p.x(), d.p.y());
  EXPECT_NEAR(r, 100 + 0.25 * d.p.z(), 1e-12);
  // Cone curvature: 0 along the generator, cos(alpha)/r around, alpha the
  // half-angle's complement: slope dr/dz = 0.25.
  const SurfaceCurvature c = curvature(d);
  const double around = 1.0 / (r * std::sqrt(1 + 0.25 * 0.25));
  EXPECT_NEAR(std::max(std::abs(c.k1), std::abs(c.k2)), around, 1e-9);
  EXPECT_NEAR(std::min(std::abs(c.k1), std::abs(c.k2)), 0, 1e-9);
}

TEST(SurfaceOfRevolution, RadialOffsetIsSignedMeridianDistance) {
  const SurfaceOfRevolution s = cone();
  // Point at z = 20 radius 110 + 2: the cone's radius there is 105; the
  // distance to the line r = 100 + z/4 in the meridian plane is (r - 100 -
  // z/4) / sqrt(1 + 1/16).
  const double theta = 0.7;
  const Vec3 q(112 * std::cos(theta), 112 * std::sin(theta), 20);
  EXPECT_NEAR(s.radial_offset(q), (112 - 105) / std::sqrt(1 + 1.0 / 16), 1e-9);
  const Vec3 inside(98 * std::cos(theta), 98 * std::sin(theta), 20);
  EXPECT_NEAR(s.radial_offset(inside), (98 - 105) / std::sqrt(1 + 1.0 / 16), 1e-9);
  EXPECT_THROW(s.radius_at(50), Error);
}

TEST(SurfaceOfRevolution, OffsetDirectionIsTheConesNormalOnEitherSide) {
  const SurfaceOfRevolution s = cone();
  // The gradient of the signed offset: the cone's outward normal in q's
  // meridian half-plane, (radial, z) ~ (1, -1/4), inside as outside.
  for (const double rq : {112.0, 98.0}) {
    const double theta = 2.1;
    const Vec3 q(rq * std::cos(theta), rq * std::sin(theta), 20);
    const Vec3 n = Vec3(std::cos(theta), std::sin(theta), -0.25).normalized();
    EXPECT_NEAR((s.offset_direction(q) - n).norm(), 0, 1e-9) << rq;
  }
}

// Issue 38: a hub profile through dense data rounded as Rotor 67's (1e-5 in
// on points 10 um apart near its trailing edge, 5-13 mm apart elsewhere)
// wiggles at the um scale; 2 mm off it the difference quotient of
// radial_offset points anywhere (into the hub: the root rows' axes did),
// the direction from the foot stays on the line's normal.
TEST(SurfaceOfRevolution, OffsetDirectionHoldsOverAProfileThroughRoundedDenseData) {
  const double q = 1e-5 * 25.4;
  auto rounded = [&](double x) { return q * std::round(x / q); };
  std::vector<double> zs;
  for (double z = 40; z < 85; z += 5) zs.push_back(z);
  double z = 85, step = 1.0;
  for (; z < 89.5; z += step, step = std::max(0.01, 0.75 * step)) zs.push_back(z);
  for (step = 0.01; z < 140; z += step, step *= 1.6) zs.push_back(z);
  std::vector<Vec2> m;
  for (const double zz : zs) m.emplace_back(rounded(zz), rounded(118 + 0.12 * (zz - 89)));
  const SurfaceOfRevolution s(m);
  const Vec3 n = Vec3(0, 1, -0.12).normalized();  // the line's normal at theta = 90 deg
  double worst = 0, worst_difference = 0;
  for (int i = 0; i <= 400; ++i) {
    const double zc = 86 + 4.0 * i / 400;
    const Vec3 p = Vec3(0, 118 + 0.12 * (zc - 89), zc) + 2.0 * n;
    const Vec3 d = s.offset_direction(p);
    EXPECT_NEAR(d.norm(), 1, 1e-12);
    worst = std::max(worst, std::acos(std::clamp(d.dot(n), -1.0, 1.0)));
    Vec3 g;
    for (int k = 0; k < 3; ++k) {
      Vec3 e = Vec3::Zero();
      e[k] = 1e-4;
      g[k] = (s.radial_offset(p + e) - s.radial_offset(p - e)) / 2e-4;
    }
    worst_difference = std::max(worst_difference, std::acos(std::clamp(g.normalized().dot(n), -1.0, 1.0)));
  }
  EXPECT_LT(worst, 3 * kPi / 180);
  EXPECT_GT(worst_difference, kPi / 2);  // the case the difference quotient fails
}

// A radial plane sheet: points (r cos t0, r sin t0, z) for r in [90, 130],
// z in [0, 40]; u -> r, v -> z. Its intersection with the cone is the line
// r = 100 + z/4.
class RadialSheet : public Surface {
 public:
  SurfaceDerivs eval(double u, double v) const override {
    const double t0 = 0.3, r = 90 + 40 * u, z = 40 * v;
    SurfaceDerivs d;
    d.p = Vec3(r * std::cos(t0), r * std::sin(t0), z);
    d.pu = Vec3(40 * std::cos(t0), 40 * std::sin(t0), 0);
    d.pv = Vec3(0, 0, 40);
    return d;
  }
};

TEST(SurfaceOfRevolution, OffsetOfATorusIsTheConcentricTorus) {
  // A quarter circle of radius 20 about (z, r) = (0, 100) swept about Z
  // (a torus' inner quarter, like an impeller hub's bend). Offset along
  // eval's normal by +-2: points of the offset lie 20 -+ 2 from the
  // circle's centre in their meridian plane — or 20 +- 2, whichever side
  // the normal points; both offsets together must give both.
  std::vector<Vec2> m;
  for (int i = 0; i <= 96; ++i) {  // dense: the interpolated profile within 1e-7 of the circle
    const double a = 0.5 * kPi * i / 96;
    m.emplace_back(20 * std::sin(a), 100 - 20 * std::cos(a));
  }
  const SurfaceOfRevolution torus(m);
  const SurfaceDerivs d = torus.eval(0.5, 0);
  const Vec3 n = d.pu.cross(d.pv).normalized();
  const Vec3 centre(100, 0, 0);  // the profile circle's centre in the plane at angle 0
  const double toward = n.dot(centre - d.p) > 0 ? 1 : -1;  // +1: the normal points at the centre
  for (const double off : {2.0, -2.0}) {
    const SurfaceOfRevolution o = torus.offset(off);
    double worst = 0;
    for (int i = 0; i <= 50; ++i) {
      const Vec3 p = o.point(i / 50.0, 0.0);
      const double rho = std::hypot(p.x() - 100, p.z());
      worst = std::max(worst, std::abs(rho - (20 - toward * off)));
      EXPECT_NEAR(p.y(), 0, 1e-12);
    }
    EXPECT_LT(worst, 1e-6) << off;
  }
  // Towards the centre by more than the radius the offset would fold.
  EXPECT_THROW(torus.offset(toward * 21), ParameterError);
  EXPECT_NO_THROW(torus.offset(toward * 19));
  EXPECT_THROW(torus.offset(std::nan("")), ParameterError);
}

TEST(IntersectWithRevolution, SheetMeetsConeOnTheAnalyticLine) {
  const SurfaceCurveOnSurface curve = intersect_with_revolution(RadialSheet(), cone(), 50);
  ASSERT_EQ(curve.u.size(), 50u);
  for (size_t k = 0; k < curve.u.size(); ++k) {
    const double z = 40 * curve.v[k];
    const double r_expected = 100 + 0.25 * z;
    EXPECT_NEAR(90 + 40 * curve.u[k], r_expected, 1e-8) << k;
    EXPECT_NEAR(std::hypot(curve.points[k].x(), curve.points[k].y()), r_expected, 1e-8);
  }
}

TEST(IntersectWithRevolution, MissingCrossingIsAnError) {
  std::vector<Vec2> far;
  for (int i = 0; i <= 4; ++i) far.emplace_back(10.0 * i, 300.0);
  EXPECT_THROW(intersect_with_revolution(RadialSheet(), SurfaceOfRevolution(far), 10), Error);
}

}  // namespace
}  // namespace bliskrun
