// Sphere covers of tool solids: every point of the solid inside a sphere,
// the ball of a ball end one sphere as it is, and the cover no wider than
// the solid by more than its overestimate, sideways and from below.
#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"
#include "core/common/types.h"
#include "core/tools/sphere_cover.h"
#include "core/tools/tool.h"

namespace bliskrun {
namespace {

// Distance of a plane with unit normal n through the origin... measured as
// the support: the largest n . p over the cover, and over the profile.
double cover_support(const SphereCover& c, const Vec3& n) {
  double s = -1e300;
  for (const AxisSphere& a : c.spheres) s = std::max(s, n.z() * a.z + a.radius);
  return s;
}

double solid_support(const Profile& p, const Vec3& n) {
  // sup over (r, z) of r * |n_xy| + z * n_z, sampled finely along z.
  const double nr = std::hypot(n.x(), n.y());
  double s = -1e300;
  const int k = 200000;
  for (int i = 0; i <= k; ++i) {
    const double z = p.z_min() + (p.z_max() - p.z_min()) * i / k;
    s = std::max(s, p.radius_at(z) * nr + z * n.z());
  }
  return s;
}

void expect_covers(const Profile& profile, const SphereCover& cover) {
  // Boundary points of the solid (the interior is nearer every centre).
  const int k = 20000;
  for (int i = 0; i <= k; ++i) {
    const double z = profile.z_min() + (profile.z_max() - profile.z_min()) * i / k;
    const double r = profile.radius_at(z);
    bool inside = false;
    for (const AxisSphere& a : cover.spheres) {
      if (std::hypot(r, z - a.z) <= a.radius + 1e-9) {
        inside = true;
        break;
      }
    }
    ASSERT_TRUE(inside) << "solid point (r " << r << ", z " << z << ") outside every sphere";
  }
  // Every sphere inside its group's bound.
  for (const SphereCover::Group& g : cover.groups) {
    for (int j = g.first; j < g.first + g.count; ++j) {
      const AxisSphere& a = cover.spheres[static_cast<size_t>(j)];
      EXPECT_LE(std::abs(a.z - g.bound.z) + a.radius, g.bound.radius + 1e-12);
    }
  }
}

TEST(SphereCover, BallEndIsItsBallAndCoversTheFlute) {
  const Tool tool = Tool::ball_end_mill({3, 20, {6, 30}, {}});
  const Profile& cutter = tool.cutter();
  const SphereCover cover = sphere_cover(cutter, 0.01, 1e-3);
  ASSERT_FALSE(cover.spheres.empty());
  // The ball: one sphere at its centre, its radius within the polygon's
  // tolerance and the excess.
  EXPECT_NEAR(cover.spheres[0].z, 3.0, 0.02);
  EXPECT_GE(cover.spheres[0].radius, 3.0);
  EXPECT_LE(cover.spheres[0].radius, 3.0 + cover.overestimate_mm);
  expect_covers(cutter, cover);
  // A cylinder of radius 3 in slabs of 2 sqrt((3.01)^2 - 9) = 0.49 mm.
  EXPECT_GT(static_cast<int>(cover.spheres.size()), 30);
  EXPECT_LT(static_cast<int>(cover.spheres.size()), 50);
}

TEST(SphereCover, NoWiderThanTheSolidSidewaysAndBelow) {
  const Tool tool = Tool::tapered_ball_end_mill({3, deg_to_rad(2), 90, {16, 60}, {}});
  const Profile& cutter = tool.cutter();
  const SphereCover cover = sphere_cover(cutter, 0.01, 1e-3);
  expect_covers(cutter, cover);
  for (double deg : {0.0, 15.0, 45.0, 80.0, 90.0}) {
    // Directions from straight down to sideways (the top cap, a flat end,
    // is where spheres on the axis stand out; nothing runs on it). Straight
    // down (the ball) and square to the axis the cover is within its
    // overestimate; between, a sphere's slab leans out by up to
    // R (1 - sin a) more.
    const double a = deg_to_rad(deg);
    const Vec3 n(std::sin(a), 0, -std::cos(a));
    const double exact = solid_support(cutter, n);
    const double covered = cover_support(cover, n);
    const double slack = deg == 0 || deg == 90 ? 0 : cutter.max_radius() * (1 - std::sin(a));
    EXPECT_GE(covered, exact - 1e-6) << deg << " deg";
    EXPECT_LE(covered, exact + cover.overestimate_mm + slack + 1e-6) << deg << " deg";
  }
}

TEST(SphereCover, RefusesBadArguments) {
  const Tool tool = Tool::ball_end_mill({3, 20, {6, 30}, {}});
  EXPECT_THROW(sphere_cover(tool.cutter(), 0), ParameterError);
  EXPECT_THROW(sphere_cover(tool.cutter(), 0.01, -1), ParameterError);
}

}  // namespace
}  // namespace bliskrun
