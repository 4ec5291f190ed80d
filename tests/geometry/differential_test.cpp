#include "core/geometry/differential.h"

#include <gtest/gtest.h>

#include "core/common/error.h"
#include "geometry/analytic_surfaces.h"

namespace bliskrun {
namespace {

using test::Cylinder;
using test::Sphere;
using test::Torus;

TEST(Curvature, SphereIsUmbilicWithCurvatureOneOverR) {
  const Sphere s(12.5);
  for (double u : {0.1, 0.5, 0.9})
    for (double v : {0.0, 0.3, 0.77}) {
      const SurfaceCurvature c = curvature(s.eval(u, v));
      EXPECT_NEAR(c.K, 1 / (12.5 * 12.5), 1e-12);
      EXPECT_NEAR(c.H, -1 / 12.5, 1e-12);
      // k1,2 = H +- sqrt(H^2 - K): at an umbilic the square root turns
      // rounding of 1e-18 into 1e-9, so they are good to about 1e-8.
      EXPECT_NEAR(c.k1, -1 / 12.5, 1e-8);
      EXPECT_NEAR(c.k2, -1 / 12.5, 1e-8);
      // Outward unit normal for this parametrisation.
      EXPECT_NEAR((c.normal - s.point(u, v) / 12.5).norm(), 0, 1e-12);
    }
}

TEST(Curvature, CylinderPrincipalCurvaturesAndDirections) {
  const double r = 23.0;
  const Cylinder s(r, 30);
  const SurfaceCurvature c = curvature(s.eval(0.4, 0.6));
  EXPECT_NEAR(c.K, 0, 1e-14);
  EXPECT_NEAR(c.k1, 1 / r, 1e-12);  // around (normal points to the axis)
  EXPECT_NEAR(c.k2, 0, 1e-12);      // along the axis
  EXPECT_NEAR(std::abs(c.dir1.z()), 0, 1e-12);
  EXPECT_NEAR(std::abs(c.dir2.dot(Vec3::UnitZ())), 1, 1e-12);
  EXPECT_NEAR(c.dir1.dot(c.dir2), 0, 1e-12);
}

TEST(Curvature, TorusGaussianCurvatureClosedForm) {
  const Torus t(40, 8);
  for (double u : {0.0, 0.1, 0.25, 0.4, 0.5, 0.85})
    for (double v : {0.2, 0.7}) {
      const double phi = t.phi(u);
      const SurfaceCurvature c = curvature(t.eval(u, v));
      EXPECT_NEAR(c.K, std::cos(phi) / (8 * (40 + 8 * std::cos(phi))), 1e-12) << u;
      const double a = 1.0 / 8, b = std::cos(phi) / (40 + 8 * std::cos(phi));
      EXPECT_NEAR(c.k1, std::max(a, b), 1e-12);
      EXPECT_NEAR(c.k2, std::min(a, b), 1e-12);
      // The tube direction (pu) is principal with curvature 1/r.
      const Vec3 tube = t.eval(u, v).pu.normalized();
      const Vec3 dir_a = (a >= b) ? c.dir1 : c.dir2;
      EXPECT_NEAR(std::abs(dir_a.dot(tube)), 1, 1e-9);
    }
}

TEST(Curvature, EulerFormulaForNormalCurvature) {
  const Torus t(40, 8);
  const SurfaceDerivs d = t.eval(0.13, 0.4);
  const SurfaceCurvature c = curvature(d);
  for (double deg = 0; deg < 360; deg += 15) {
    const double a = deg_to_rad(deg);
    const Vec3 dir = std::cos(a) * c.dir1 + std::sin(a) * c.dir2;
    const double euler = c.k1 * std::cos(a) * std::cos(a) + c.k2 * std::sin(a) * std::sin(a);
    EXPECT_NEAR(normal_curvature(d, dir), euler, 1e-12) << deg;
    // Any scale and any normal component of the direction give the same k_n.
    EXPECT_NEAR(normal_curvature(d, 3.7 * dir + 2.0 * c.normal), euler, 1e-12);
  }
}

TEST(Curvature, SingularPointIsAnError) {
  SurfaceDerivs d;
  d.pu = Vec3(1, 0, 0);
  d.pv = Vec3(2, 0, 0);
  EXPECT_THROW(curvature(d), Error);
}

}  // namespace
}  // namespace bliskrun
