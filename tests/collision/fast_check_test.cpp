// The blisk paper's point check (§3.4, eq. 20) against FCL: where they agree
// and the three ways the point check misses what FCL sees.
#include <gtest/gtest.h>

#include <cmath>

#include "collision/test_meshes.h"
#include "core/collision/collision_world.h"
#include "core/collision/fast_check.h"
#include "test_support.h"

namespace bliskrun {
namespace {

using test::grid_mesh;

TEST(FastCheck, ComparesRadiusWithRofZInHeadAndShankAbove) {
  const Tool t = test::paper_drum_wheel();
  const ToolPose pose{Vec3(10, 0, 0), Vec3::UnitX()};  // tool lying along +x
  const Clearances c{0.1, 0.2, 0};
  // In the head at Z = 2 (R = 4): a point 4.05 from the axis conflicts with
  // clearance 0.1, one at 4.15 does not.
  EXPECT_FALSE(fast_check(t, pose, {Vec3(12, 0, 4.05)}, c).clear);
  EXPECT_TRUE(fast_check(t, pose, {Vec3(12, 4.15, 0)}, c).clear);
  // Above L_c the shank radius 3 counts, with the shank's clearance.
  const FastCheck shank = fast_check(t, pose, {Vec3(40, 0, 3.3), Vec3(60, 0, 3.15)}, c);
  EXPECT_FALSE(shank.clear);
  EXPECT_EQ(shank.conflicts, 1);
  EXPECT_EQ(shank.first_conflict, 1);
  EXPECT_EQ(shank.part, ToolPartId::Shank);
  EXPECT_NEAR(shank.min_margin_mm, 3.15 - 3 - 0.2, 1e-12);
  // Eq. (20) is invariant to the pose: the same point in the tool frame.
  const double a = deg_to_rad(37);
  const Vec3 axis(std::cos(a), std::sin(a), 0);
  const Vec3 radial(-std::sin(a), std::cos(a), 0);
  const ToolPose turned{Vec3(1, 2, 3), axis};
  EXPECT_NEAR(fast_check(t, turned, {Vec3(1, 2, 3) + 2 * axis + 4.3 * radial}, c).min_margin_mm, 0.2, 1e-12);
}

TEST(FastCheck, AgreesWithFclOnADenseWallBesideTheTool) {
  // A wall sampled every 0.1 mm beside a ball-end's straight side, where
  // the radial gap is the distance: both see the dip and the clearance.
  const Tool tool = Tool::ball_end_mill({3, 15, {}, {}});
  const ToolBody body(tool);
  for (double gap : {-0.2, 0.05, 0.3}) {
    const TriangleMesh wall = grid_mesh(Vec3(3 + gap, -5, 4), Vec3(0, 10, 0), Vec3(0, 0, 10), 100, 100);
    CollisionWorld world;
    world.add("wall", wall);
    const ToolPose pose{Vec3(0, 0.013, 0), Vec3::UnitZ()};
    const Clearances c{0.1, 0, 0};
    const bool fast = fast_check(tool, pose, wall.vertices, c).clear;
    const bool fcl = world.check(body, pose, c).clear;
    EXPECT_EQ(fast, fcl) << "gap " << gap;
    EXPECT_EQ(fcl, gap > 0.1) << "gap " << gap;
  }
}

TEST(FastCheck, MissesAThinFeatureBetweenItsPoints) {
  // One large triangle cutting through the head; its vertices are far away.
  TriangleMesh sheet;
  sheet.vertices = {Vec3(-50, -50, 2), Vec3(50, -50, 2), Vec3(0, 80, 2)};
  sheet.triangles = {Eigen::Vector3i(0, 1, 2)};
  CollisionWorld world;
  world.add("sheet", sheet);
  const Tool tool = test::paper_drum_wheel();
  const ToolPose pose{Vec3::Zero(), Vec3::UnitZ()};
  EXPECT_TRUE(fast_check(tool, pose, sheet.vertices, Clearances{}).clear);
  const PoseCheck fcl = world.check(ToolBody(tool), pose, Clearances{});
  EXPECT_FALSE(fcl.clear);
  EXPECT_TRUE(fcl.parts[0].collides);
}

TEST(FastCheck, ComparesRadiallySoItIgnoresPointsBelowTheTip) {
  // A point 0.1 mm below the tip, required clearance 0.5: FCL's distance sees
  // it, the radial comparison cannot (no part spans that height).
  TriangleMesh speck = grid_mesh(Vec3(-0.5, -0.5, -0.1), Vec3(1, 0, 0), Vec3(0, 1, 0));
  CollisionWorld world;
  world.add("speck", speck);
  const Tool tool = test::paper_drum_wheel();
  const ToolPose pose{Vec3::Zero(), Vec3::UnitZ()};
  const Clearances c{0.5, 0.5, 0};
  EXPECT_TRUE(fast_check(tool, pose, speck.vertices, c).clear);
  const PoseCheck fcl = world.check(ToolBody(tool), pose, c);
  EXPECT_FALSE(fcl.clear);
  EXPECT_NEAR(fcl.parts[0].distance_mm, 0.1, 2e-6);
}

TEST(FastCheck, PassesBothPosesOfFig9WhileTheMotionCollides) {
  // The fin of the Fig. 9 case, densely sampled: the point check clears both
  // poses; only the swept check sees the motion cut the blade.
  const TriangleMesh fin = grid_mesh(Vec3(0, -20, -10), Vec3(0, 40, 0), Vec3(0, 0, 13), 200, 130);
  CollisionWorld world;
  world.add("blade", fin);
  const Tool tool = test::paper_drum_wheel();
  const ToolBody body(tool);
  const Clearances c{0.5, 0.5, 0};
  const ToolPose from{Vec3(-6, 0, 1), Vec3::UnitZ()}, to{Vec3(6, 0, 1), Vec3::UnitZ()};
  EXPECT_TRUE(fast_check(tool, from, fin.vertices, c).clear);
  EXPECT_TRUE(fast_check(tool, to, fin.vertices, c).clear);
  EXPECT_FALSE(world.check_motion(body, from, to, c).clear);
  // Halfway, both agree it cuts.
  const ToolPose mid{Vec3(0, 0, 1), Vec3::UnitZ()};
  EXPECT_FALSE(fast_check(tool, mid, fin.vertices, c).clear);
  EXPECT_FALSE(world.check(body, mid, c).clear);
}

}  // namespace
}  // namespace bliskrun
