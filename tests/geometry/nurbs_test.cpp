#include "core/geometry/nurbs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/common/error.h"
#include "core/geometry/differential.h"
#include "core/geometry/mesh.h"
#include "core/geometry/projection.h"

namespace bliskrun {
namespace {

const double kArcWeight = std::sqrt(0.5);  // weight of a 90-degree arc's middle point

// Full circle of radius r in XY as a rational quadratic: four 90-degree arcs
// (Piegl & Tiller, Ex. 7.2). Control points and weights.
struct Conic {
  std::vector<double> knots;
  std::vector<Vec3> ctrl;
  std::vector<double> w;
};
Conic conic_circle(double r) {
  return {{0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1},
          {{r, 0, 0}, {r, r, 0}, {0, r, 0}, {-r, r, 0}, {-r, 0, 0},
           {-r, -r, 0}, {0, -r, 0}, {r, -r, 0}, {r, 0, 0}},
          {1, kArcWeight, 1, kArcWeight, 1, kArcWeight, 1, kArcWeight, 1}};
}

// Sphere of radius r about the origin: the meridian half circle (in XZ, from
// the south pole to the north pole) swept by the full circle about Z.
NurbsSurface sphere(double r) {
  const std::vector<Vec3> mer = {{0, 0, -r}, {r, 0, -r}, {r, 0, 0}, {r, 0, r}, {0, 0, r}};
  const std::vector<double> mw = {1, kArcWeight, 1, kArcWeight, 1};
  const Conic c = conic_circle(1.0);
  std::vector<Vec3> ctrl;
  std::vector<double> w;
  for (size_t i = 0; i < mer.size(); ++i)
    for (size_t j = 0; j < c.ctrl.size(); ++j) {
      ctrl.emplace_back(mer[i].x() * c.ctrl[j].x(), mer[i].x() * c.ctrl[j].y(), mer[i].z());
      w.push_back(mw[i] * c.w[j]);
    }
  return NurbsSurface(2, 2, {0, 0, 0, 0.5, 0.5, 1, 1, 1}, c.knots, 5, 9, ctrl, w);
}

// Cylinder of radius r about Z, height h: u along Z (linear), v around.
NurbsSurface nurbs_cylinder(double r, double h, std::vector<double> knots_u = {0, 0, 1, 1}) {
  const Conic c = conic_circle(r);
  std::vector<Vec3> ctrl;
  std::vector<double> w;
  for (double z : {0.0, h})
    for (size_t j = 0; j < c.ctrl.size(); ++j) {
      ctrl.push_back(c.ctrl[j] + Vec3(0, 0, z));
      w.push_back(c.w[j]);
    }
  return NurbsSurface(1, 2, std::move(knots_u), c.knots, 2, 9, ctrl, w);
}

TEST(NurbsCurve, RationalQuadraticCircleIsExactWithCurvatureOneOverR) {
  const double r = 37.5;
  const Conic c = conic_circle(r);
  const NurbsCurve curve(2, c.knots, c.ctrl, c.w);
  for (int k = 0; k <= 400; ++k) {
    const CurveDerivs d = curve.eval(k / 400.0);
    EXPECT_NEAR(d.p.norm(), r, 1e-9) << k;
    EXPECT_NEAR(d.p.z(), 0, 1e-12);
    // Curvature |C' x C''| / |C'|^3 of a circle: 1/R everywhere.
    EXPECT_NEAR(d.dt.cross(d.dtt).norm() / std::pow(d.dt.norm(), 3), 1 / r, 1e-12) << k;
  }
  // Each arc is symmetric in its span, so a span's middle is its angle's.
  EXPECT_NEAR((curve.point(0.25) - Vec3(0, r, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((curve.point(0.625) - r * Vec3(-kArcWeight, -kArcWeight, 0)).norm(), 0.0, 1e-12);
}

TEST(NurbsSurface, CylinderOnExactRadiusWithPrincipalCurvatures) {
  const double r = 20, h = 55;
  const NurbsSurface s = nurbs_cylinder(r, h);
  EXPECT_FALSE(s.is_polynomial());
  for (int i = 0; i <= 10; ++i)
    for (int j = 0; j <= 40; ++j) {
      const double u = i / 10.0, v = j / 40.0;
      const SurfaceDerivs d = s.eval(u, v);
      EXPECT_NEAR(std::hypot(d.p.x(), d.p.y()), r, 1e-9);
      EXPECT_NEAR(d.p.z(), h * u, 1e-12);
      const SurfaceCurvature c = curvature(d);
      // pu (along Z) x pv (counter-clockwise) points to the axis: the
      // surface bends towards the normal, +1/R around, 0 along the axis.
      EXPECT_NEAR(c.k1, 1 / r, 1e-9);
      EXPECT_NEAR(c.k2, 0, 1e-9);
      EXPECT_NEAR(std::abs(c.dir2.z()), 1, 1e-9);
      EXPECT_NEAR(c.K, 0, 1e-12);
    }
}

TEST(NurbsSurface, SpherePatchOnExactRadiusIsUmbilic) {
  const double r = 12.5;
  const NurbsSurface s = sphere(r);
  // Away from the poles, where the net collapses to a point (pu x pv = 0).
  for (int i = 1; i < 20; ++i)
    for (int j = 0; j <= 40; ++j) {
      const double u = i / 20.0, v = j / 40.0;
      const SurfaceDerivs d = s.eval(u, v);
      EXPECT_NEAR(d.p.norm(), r, 1e-9);
      const SurfaceCurvature c = curvature(d);
      EXPECT_NEAR(c.K, 1 / (r * r), 1e-10);
      EXPECT_NEAR(std::abs(c.H), 1 / r, 1e-10);
      // At an umbilic the square root of H^2 - K amplifies rounding (see
      // the analytic sphere's test): good to about 1e-7.
      EXPECT_NEAR(std::abs(c.k1), 1 / r, 1e-7);
      EXPECT_NEAR(std::abs(c.k2), 1 / r, 1e-7);
      EXPECT_NEAR(std::abs(c.normal.dot(d.p / r)), 1, 1e-12);
    }
}

// Central differences of a random rational net (weights 0.3..3) against the
// analytic first and second derivatives.
TEST(NurbsSurface, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(-10, 10), wt(0.3, 3);
  const int rows = 6, cols = 5;
  std::vector<Vec3> ctrl;
  std::vector<double> w;
  for (int k = 0; k < rows * cols; ++k) {
    ctrl.emplace_back(pos(rng), pos(rng), pos(rng));
    w.push_back(wt(rng));
  }
  // Knots on [2, 7] and [-1, 3]: the surface is rescaled to [0, 1]^2.
  const NurbsSurface s(3, 2, {2, 2, 2, 2, 4, 5.5, 7, 7, 7, 7}, {-1, -1, -1, 0.5, 2, 3, 3, 3},
                       rows, cols, ctrl, w);
  EXPECT_DOUBLE_EQ(s.knots_u().front(), 0.0);
  EXPECT_DOUBLE_EQ(s.knots_u().back(), 1.0);
  const double e = 1e-5;
  for (double u : {0.13, 0.41, 0.77})
    for (double v : {0.21, 0.5, 0.88}) {
      const SurfaceDerivs d = s.eval(u, v);
      const SurfaceDerivs a = s.eval(u + e, v), b = s.eval(u - e, v);
      const SurfaceDerivs c = s.eval(u, v + e), f = s.eval(u, v - e);
      const double scale = d.pu.norm() + d.pv.norm() + 1;
      EXPECT_NEAR(((a.p - b.p) / (2 * e) - d.pu).norm(), 0, 1e-6 * scale);
      EXPECT_NEAR(((c.p - f.p) / (2 * e) - d.pv).norm(), 0, 1e-6 * scale);
      const double scale2 = d.puu.norm() + d.pvv.norm() + d.puv.norm() + 1;
      EXPECT_NEAR(((a.pu - b.pu) / (2 * e) - d.puu).norm(), 0, 1e-6 * scale2);
      EXPECT_NEAR(((c.pv - f.pv) / (2 * e) - d.pvv).norm(), 0, 1e-6 * scale2);
      EXPECT_NEAR(((c.pu - f.pu) / (2 * e) - d.puv).norm(), 0, 1e-6 * scale2);
      EXPECT_NEAR(((a.pv - b.pv) / (2 * e) - d.puv).norm(), 0, 1e-6 * scale2);
    }
}

TEST(NurbsCurve, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pos(-10, 10), wt(0.3, 3);
  std::vector<Vec3> ctrl;
  std::vector<double> w;
  for (int k = 0; k < 7; ++k) {
    ctrl.emplace_back(pos(rng), pos(rng), pos(rng));
    w.push_back(wt(rng));
  }
  const NurbsCurve c(3, {1, 1, 1, 1, 1.5, 2.5, 3, 4, 4, 4, 4}, ctrl, w);
  EXPECT_EQ(c.t_min(), 1.0);
  EXPECT_EQ(c.t_max(), 4.0);
  const double e = 1e-5;
  for (double t : {1.1, 1.7, 2.6, 3.9}) {
    const CurveDerivs d = c.eval(t), a = c.eval(t + e), b = c.eval(t - e);
    EXPECT_NEAR(((a.p - b.p) / (2 * e) - d.dt).norm(), 0, 1e-6 * (d.dt.norm() + 1));
    EXPECT_NEAR(((a.dt - b.dt) / (2 * e) - d.dtt).norm(), 0, 1e-6 * (d.dtt.norm() + 1));
  }
}

TEST(NurbsSurface, UnitWeightsReproduceTheBSpline) {
  std::vector<Vec3> ctrl;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j) ctrl.emplace_back(i, j, std::sin(i + 2.0 * j));
  const BSplineSurface b(3, 2, {0, 0, 0, 0, 0.4, 1, 1, 1, 1}, {0, 0, 0, 0.5, 1, 1, 1}, 5, 4, ctrl);
  const NurbsSurface n(b);
  EXPECT_TRUE(n.is_polynomial());
  for (double u : {0.0, 0.2, 0.4, 0.9, 1.0})
    for (double v : {0.0, 0.3, 0.5, 1.0}) {
      const SurfaceDerivs x = b.eval(u, v), y = n.eval(u, v);
      EXPECT_NEAR((x.p - y.p).norm(), 0, 1e-12);
      EXPECT_NEAR((x.pu - y.pu).norm(), 0, 1e-11);
      EXPECT_NEAR((x.puv - y.puv).norm(), 0, 1e-10);
      EXPECT_NEAR((x.pvv - y.pvv).norm(), 0, 1e-10);
    }
}

// Projection and tessellation see a NURBS as any Surface.
TEST(NurbsSurface, ProjectionAndTessellationWorkOnIt) {
  const double r = 20;
  const NurbsSurface s = nurbs_cylinder(r, 30);
  const Vec3 q(25 * std::cos(0.7), 25 * std::sin(0.7), 12);
  const SurfaceProjection pr = project_to_surface(s, q);
  ASSERT_TRUE(pr.ok) << pr.failure;
  EXPECT_NEAR(pr.distance, 5, 1e-9);
  EXPECT_NEAR((pr.point - Vec3(r * std::cos(0.7), r * std::sin(0.7), 12)).norm(), 0, 1e-8);
  const TriangleMesh m = tessellate(s, 0.01);
  ASSERT_FALSE(m.vertices.empty());
  for (const Vec3& p : m.vertices) EXPECT_NEAR(std::hypot(p.x(), p.y()), r, 1e-9);
}

TEST(NurbsSurface, RejectsBadWeightsAndSizes) {
  const Conic c = conic_circle(1);
  std::vector<double> w = c.w;
  w[3] = 0;
  EXPECT_THROW(NurbsCurve(2, c.knots, c.ctrl, w), ParameterError);
  w[3] = -1;
  EXPECT_THROW(NurbsCurve(2, c.knots, c.ctrl, w), ParameterError);
  w.pop_back();
  EXPECT_THROW(NurbsCurve(2, c.knots, c.ctrl, w), ParameterError);
  EXPECT_THROW(NurbsSurface(1, 2, {0, 0, 1, 1}, c.knots, 2, 9, c.ctrl, c.w), ParameterError);
  EXPECT_THROW(NurbsCurve(9, c.knots, c.ctrl, c.w), ParameterError);
  try {
    NurbsCurve(2, c.knots, c.ctrl, std::vector<double>(9, std::nan("")));
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("weight 0"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace bliskrun
