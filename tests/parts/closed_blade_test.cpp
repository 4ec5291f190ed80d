// A blade closed around its section (core/parts/closed_blade.h) on faces
// with a closed form: the two halves of an elliptic cylinder x²/a² + y²/b²
// = 1 extruded along z, split at the ends of the major axis (the edges).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "core/common/types.h"
#include "core/geometry/interpolation.h"
#include "core/parts/builtin_blisk.h"
#include "core/parts/closed_blade.h"

namespace bliskrun {
namespace {

constexpr double kA = 20, kB = 3, kHeight = 10;  // semi-axes and span, mm
constexpr int kRows = 9, kCols = 121;

// One half of the ellipse, theta from theta0 to theta1 over v, at z = height
// times the row's fraction; rows at parameters u_k (u_k = k / (rows - 1)
// unless warped: a face lofted at its own span parameters, as a blade
// model lofts each face at its own averaged chord lengths).
std::shared_ptr<const BSplineSurface> half_ellipse(double theta0, double theta1, bool warped) {
  PointGrid g(kRows, kCols);
  GridParameters params;
  for (int i = 0; i < kRows; ++i) {
    const double f = static_cast<double>(i) / (kRows - 1);
    params.u.push_back(warped ? f + 0.08 * std::sin(kPi * f) : f);
    for (int j = 0; j < kCols; ++j) {
      const double t = theta0 + (theta1 - theta0) * j / (kCols - 1);
      g.at(i, j) = Vec3(kA * std::cos(t), kB * std::sin(t), kHeight * f);
    }
  }
  for (int j = 0; j < kCols; ++j) params.v.push_back(static_cast<double>(j) / (kCols - 1));
  return std::make_shared<const BSplineSurface>(interpolate_grid(g, params));
}

// Distance of q from the ellipse in its plane, to first order: |f| / |grad f|.
double off_ellipse(const Vec3& q) {
  const double f = q.x() * q.x() / (kA * kA) + q.y() * q.y() / (kB * kB) - 1;
  const Vec2 grad(2 * q.x() / (kA * kA), 2 * q.y() / (kB * kB));
  return std::abs(f) / grad.norm();
}

// Pressure LE (x = -a) -> TE (x = a) under the axis; suction TE -> LE over it.
TEST(ClosedBlade, FacesThatMeetAtTheirEdgesAreJoinedThereEvenAtTheirOwnSpanParameters) {
  const auto pressure = half_ellipse(kPi, 2 * kPi, false);
  const auto suction = half_ellipse(0, kPi, true);
  // The same u is a different height on each face (up to 0.8 mm here).
  EXPECT_GT(std::abs(pressure->point(0.5, 0).z() - suction->point(0.5, 1).z()), 0.7);
  ClosedBladeOptions o;
  o.u0 = 0.05;
  o.u1 = 0.95;
  o.loft.samples = 2048;  // 36 µm apart: the round's curvature to ~1 %
  const ClosedBlade b = close_blade(*pressure, *suction, o);
  EXPECT_LT(b.edge_kink_deg, 0.5);
  // Every point on the ellipse: no half circle, no step at the edges.
  double worst = 0;
  for (int i = 0; i <= 10; ++i)
    for (int j = 0; j < 400; ++j) worst = std::max(worst, off_ellipse(b.loft.surface.point(i / 10.0, j / 400.0)));
  EXPECT_LT(worst, 0.001);
  // The perimeter and the edges' curvature are the ellipse's: Ramanujan's
  // perimeter, and a / b² at the ends of the major axis.
  const double h = std::pow((kA - kB) / (kA + kB), 2);
  EXPECT_NEAR(b.perimeter_mm, kPi * (kA + kB) * (1 + 3 * h / (10 + std::sqrt(4 - 3 * h))), 1e-3);
  for (double v : {b.le_v, b.te_v}) {
    const SurfaceDerivs d = b.loft.surface.eval(0.5, v);
    const double kappa = d.pv.cross(d.pvv).norm() / std::pow(d.pv.norm(), 3);
    EXPECT_NEAR(kappa, kA / (kB * kB), 0.01 * kA / (kB * kB)) << "at v " << v;
    EXPECT_NEAR(std::abs(d.p.x()), kA, 1e-3);
  }
}

// Faces cut off short of the edges, where they still converge: the half
// circle meets them at the angle between the face's end tangent and the
// chord's normal — reported, since the closed surface is not the blade there.
TEST(ClosedBlade, HalfCircleOnConvergingFacesReportsItsKink) {
  const double cut = 0.15;  // rad of the ellipse left out at each edge
  const auto pressure = half_ellipse(kPi + cut, 2 * kPi - cut, false);
  const auto suction = half_ellipse(cut, kPi - cut, false);
  const ClosedBlade b = close_blade(*pressure, *suction);
  // The tangent at theta = cut is (a sin, b cos) up to sign; the half circle
  // leaves along the major axis: the kink is the tangent's angle to it.
  const double expected = std::atan2(kB * std::cos(cut), kA * std::sin(cut)) * 180 / kPi;
  EXPECT_NEAR(b.edge_kink_deg, expected, 0.1);
  EXPECT_GT(b.edge_kink_deg, 40);
}

// The built-in blisk's faces end tangent to its edge circles: the half
// circles close them without a kink.
TEST(ClosedBlade, BuiltinBliskClosesWithoutAKink) {
  const BuiltinBlisk blisk;
  const ClosedBlade b = close_blade(*blisk.flank_surface(0, FlankSide::kPressure),
                                    *blisk.flank_surface(0, FlankSide::kSuction));
  EXPECT_LT(b.edge_kink_deg, 0.5);
}

}  // namespace
}  // namespace bliskrun
