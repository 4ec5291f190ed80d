#include "core/geometry/projection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/geometry/interpolation.h"

namespace bliskrun {
namespace {

BSplineSurface wavy_patch() {
  PointGrid g(12, 15);
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 15; ++j) {
      const double x = j * 2.0, y = i * 2.5;
      g.at(i, j) = Vec3(x, y, 4 * std::sin(0.2 * x) * std::cos(0.15 * y) + 0.02 * x * y);
    }
  return interpolate_grid(g);
}

// Brute force: dense sampling, then a fine local sampling around the best.
SurfaceProjection brute_force(const Surface& s, const Vec3& q) {
  double bu = 0, bv = 0, best = 1e300;
  const int n = 400;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double d = (s.point(i / double(n), j / double(n)) - q).squaredNorm();
      if (d < best) { best = d; bu = i / double(n); bv = j / double(n); }
    }
  double h = 1.0 / n;
  for (int round = 0; round < 12; ++round) {
    double cu = bu, cv = bv;
    for (int i = -4; i <= 4; ++i)
      for (int j = -4; j <= 4; ++j) {
        const double u = std::clamp(cu + i * h / 4, 0.0, 1.0), v = std::clamp(cv + j * h / 4, 0.0, 1.0);
        const double d = (s.point(u, v) - q).squaredNorm();
        if (d < best) { best = d; bu = u; bv = v; }
      }
    h /= 4;
  }
  SurfaceProjection r;
  r.ok = true;
  r.u = bu;
  r.v = bv;
  r.point = s.point(bu, bv);
  r.distance = std::sqrt(best);
  return r;
}

TEST(ProjectToSurface, AgreesWithBruteForceInsideAndOnTheBoundary) {
  const BSplineSurface s = wavy_patch();
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> x(-6, 34), y(-6, 34), z(-8, 8);
  int boundary_feet = 0;
  for (int k = 0; k < 40; ++k) {
    const Vec3 q(x(rng), y(rng), z(rng));
    const SurfaceProjection p = project_to_surface(s, q);
    ASSERT_TRUE(p.ok) << p.failure;
    const SurfaceProjection b = brute_force(s, q);
    EXPECT_NEAR(p.distance, b.distance, 1e-7) << q.transpose();
    EXPECT_LT((p.point - b.point).norm(), 1e-4) << q.transpose();
    boundary_feet += p.on_boundary;
  }
  EXPECT_GT(boundary_feet, 5) << "the sample must exercise feet on edges and corners";
}

TEST(ProjectToSurface, CornerFootIsTheCorner) {
  const BSplineSurface s = wavy_patch();
  const Vec3 corner = s.point(0, 0);
  const SurfaceProjection p = project_to_surface(s, corner + Vec3(-3, -3, 0.5));
  ASSERT_TRUE(p.ok);
  EXPECT_DOUBLE_EQ(p.u, 0);
  EXPECT_DOUBLE_EQ(p.v, 0);
  EXPECT_TRUE(p.on_boundary);
}

TEST(ProjectToSurface, OnSurfacePointsProjectToThemselves) {
  const BSplineSurface s = wavy_patch();
  for (double u : {0.13, 0.5, 0.91})
    for (double v : {0.07, 0.62}) {
      const SurfaceProjection p = project_to_surface(s, s.point(u, v));
      ASSERT_TRUE(p.ok);
      EXPECT_NEAR(p.u, u, 1e-9);
      EXPECT_NEAR(p.v, v, 1e-9);
      EXPECT_LT(p.distance, 1e-9);
    }
}

TEST(ProjectToSurface, ReportsFailureInsteadOfAWrongAnswer) {
  const BSplineSurface s = wavy_patch();
  ProjectionOptions o;
  o.max_iterations = 1;  // cannot converge from a coarse seed in one step
  o.seed_samples_u = o.seed_samples_v = 2;
  const SurfaceProjection p = project_to_surface(s, Vec3(13.3, 17.1, 9));
  const SurfaceProjection f = project_to_surface(s, Vec3(13.3, 17.1, 9), o);
  ASSERT_TRUE(p.ok);
  EXPECT_FALSE(f.ok);
  EXPECT_FALSE(f.failure.empty());
}

TEST(ProjectToCurve, AgreesWithBruteForce) {
  std::vector<Vec3> pts;
  for (int i = 0; i < 20; ++i) pts.emplace_back(i, 3 * std::sin(0.5 * i), 0.1 * i * i);
  const BSplineCurve c = interpolate_cubic(pts);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(-5, 25);
  for (int k = 0; k < 30; ++k) {
    const Vec3 q(d(rng), d(rng) / 4, d(rng));
    const CurveProjection p = project_to_curve(c, q);
    ASSERT_TRUE(p.ok) << p.failure;
    double best = 1e300;
    for (int i = 0; i <= 200000; ++i) best = std::min(best, (c.point(i / 200000.0) - q).norm());
    EXPECT_NEAR(p.distance, best, 1e-6);
  }
}

// Where Newton does not converge (here: forced, one iteration allowed) the
// golden-section fallback inside the seed's bracket still finds the foot.
TEST(ProjectToCurve, FallsBackWhenNewtonDoesNotConverge) {
  std::vector<Vec3> pts;
  for (int i = 0; i < 20; ++i) pts.emplace_back(i, 3 * std::sin(0.5 * i), 0.1 * i * i);
  const BSplineCurve c = interpolate_cubic(pts);
  ProjectionOptions o;
  o.max_iterations = 1;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(-5, 25);
  for (int k = 0; k < 20; ++k) {
    const Vec3 q(d(rng), d(rng) / 4, d(rng));
    const CurveProjection p = project_to_curve(c, q, o);
    ASSERT_TRUE(p.ok) << p.failure;
    double best = 1e300;
    for (int i = 0; i <= 200000; ++i) best = std::min(best, (c.point(i / 200000.0) - q).norm());
    EXPECT_NEAR(p.distance, best, 1e-6);
  }
}

}  // namespace
}  // namespace bliskrun
