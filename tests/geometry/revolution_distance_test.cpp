// Distance to a surface of revolution in the meridian plane: exact on a
// cylinder and at the ends of its meridian, a lower bound within the
// polyline's tolerance of brute force on a curved meridian, and cut short
// at the bound it is asked for.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/common/error.h"
#include "core/geometry/revolution.h"
#include "core/geometry/revolution_distance.h"

namespace bliskrun {
namespace {

TEST(RevolutionDistance, CylinderAndItsEndCircles) {
  // r = 20 from z = 0 to z = 50, given as its own polyline (exact).
  const RevolutionDistance cyl({Vec2(0, 20), Vec2(25, 20), Vec2(50, 20)}, 0.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(0, 2 * kPi), rho(0, 40), z(-20, 70);
  for (int i = 0; i < 500; ++i) {
    const double a = angle(rng), r = rho(rng), h = z(rng);
    const Vec3 q(r * std::cos(a), r * std::sin(a), h);
    const double zc = std::clamp(h, 0.0, 50.0);
    const double expected = std::hypot(h - zc, r - 20);
    Vec3 foot;
    EXPECT_NEAR(cyl.distance(q, 1e9, &foot), expected, 1e-9);
    EXPECT_NEAR((foot - q).norm(), expected, 1e-9);
    EXPECT_NEAR(std::hypot(foot.x(), foot.y()), 20, 1e-9);
  }
}

TEST(RevolutionDistance, BoundCutsTheSearchShort) {
  const RevolutionDistance cyl({Vec2(0, 20), Vec2(50, 20)}, 0.0);
  EXPECT_EQ(cyl.distance(Vec3(35, 0, 10), 5.0), 5.0);    // 15 away
  EXPECT_NEAR(cyl.distance(Vec3(23, 0, 10), 5.0), 3.0, 1e-12);
  EXPECT_EQ(cyl.distance(Vec3(0, 0, 10), 5.0), 5.0);     // on the axis, 20 away
}

TEST(RevolutionDistance, CurvedMeridianIsALowerBoundWithinItsTolerance) {
  // A hub-like profile: a quarter of a 40 mm circle from axial to radial.
  std::vector<Vec2> zr;
  for (int i = 0; i <= 40; ++i) {
    const double t = 0.5 * kPi * i / 40;
    zr.emplace_back(40 * std::sin(t), 60 - 40 * std::cos(t));
  }
  const SurfaceOfRevolution hub(zr);
  const double tol = 1e-3;
  const RevolutionDistance d(hub, tol);
  EXPECT_GT(d.segment_count(), 64);
  // Brute force: the meridian sampled 400 000 times in q's plane (chord
  // error below 1e-8 mm on this radius).
  std::vector<Vec2> dense;
  for (int i = 0; i <= 400000; ++i) {
    const Vec3 p = hub.eval(i / 400000.0, 0).p;
    dense.emplace_back(p.z(), p.x());
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(0, 2 * kPi), rho(10, 90), z(-10, 50);
  for (int i = 0; i < 60; ++i) {
    const double a = angle(rng), r = rho(rng), h = z(rng);
    const Vec3 q(r * std::cos(a), r * std::sin(a), h);
    double brute = 1e300;
    for (const Vec2& p : dense) brute = std::min(brute, std::hypot(p.x() - h, p.y() - r));
    const double got = d.distance(q, 1e9);
    EXPECT_LE(got, brute + 1e-9);
    EXPECT_GE(got, brute - 2 * tol - 1e-9);
  }
}

TEST(RevolutionDistance, RefusesBadInput) {
  EXPECT_THROW(RevolutionDistance({Vec2(0, 1)}, 0.0), ParameterError);
  EXPECT_THROW(RevolutionDistance({Vec2(0, 1), Vec2(1, -1)}, 0.0), ParameterError);
  EXPECT_THROW(RevolutionDistance({Vec2(0, 1), Vec2(1, 1)}, -1.0), ParameterError);
  const SurfaceOfRevolution s({Vec2(0, 10), Vec2(10, 12), Vec2(20, 15)});
  EXPECT_THROW(RevolutionDistance(s, 0.0), ParameterError);
}

}  // namespace
}  // namespace bliskrun
