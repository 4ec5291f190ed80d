// CollisionWorld: per-part clearances against analytic distances, and the
// swept check between poses (blisk paper Fig. 9).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>  // the test counts the meshes' triangles

#include "collision/test_meshes.h"
#include "core/collision/collision_world.h"
#include "core/common/error.h"
#include "core/geometry/mesh.h"
#include "test_support.h"

namespace bliskrun {
namespace {

using test::box_mesh;
using test::grid_mesh;

// FCL's triangle distances are exact to rounding.
constexpr double kFclTolMm = 1e-9;

// The FCL body encloses the tool within its overestimate: a distance it
// reports lies in [true - overestimate, true].
void expect_enclosing_distance(double fcl_mm, double true_mm, const ToolBody& body, const std::string& what) {
  EXPECT_LE(fcl_mm, true_mm + kFclTolMm) << what;
  EXPECT_GE(fcl_mm, true_mm - body.overestimate_mm() - kFclTolMm) << what;
}

TEST(CollisionWorld, BallEndAbovePlaneMatchesAnalyticDistance) {
  CollisionWorld world;
  world.add("floor", grid_mesh(Vec3(-100, -100, 0), Vec3(200, 0, 0), Vec3(0, 200, 0), 10, 10));
  const ToolBody body(Tool::ball_end_mill({3, 15, {6, 30}, {}}), 1e-3);
  const double R = 3;
  for (double alpha_deg : {0.0, 10.0, 35.0, 60.0}) {
    for (double d0 : {0.5, 2.0, 7.3}) {
      const double a = deg_to_rad(alpha_deg);
      // Tip raised so the ball's lowest point (centre.z - R) stays d0 above the floor.
      const double tip_z = d0 + R * (1 - std::cos(a));
      const ToolPose pose{Vec3(1.7, -2.2, tip_z), Vec3(std::sin(a), 0, std::cos(a))};
      const PoseCheck c = world.check(body, pose, Clearances{});
      ASSERT_EQ(c.parts.size(), 2u);
      const std::string at = "alpha " + std::to_string(alpha_deg) + " d0 " + std::to_string(d0);
      expect_enclosing_distance(c.parts[0].distance_mm, d0, body, "cutter " + at);
      // Shank: lowest point of its bottom rim.
      const double shank = tip_z + 15 * std::cos(a) - 3 * std::sin(a);
      expect_enclosing_distance(c.parts[1].distance_mm, shank, body, "shank " + at);
      EXPECT_TRUE(c.parts[0].resolved);
      EXPECT_EQ(c.parts[0].object, 0);
      EXPECT_TRUE(c.clear);
      EXPECT_NEAR(c.parts[1].on_object.z(), 0, 1e-9);
      EXPECT_NEAR(c.parts[1].on_tool.z(), c.parts[1].distance_mm, 1e-9);
    }
  }
  // Below the plane: collision, never clear even with clearance 0.
  const PoseCheck dipped = world.check(body, ToolPose{Vec3(0, 0, -0.1), Vec3::UnitZ()}, Clearances{});
  EXPECT_TRUE(dipped.parts[0].collides);
  EXPECT_EQ(dipped.parts[0].distance_mm, 0);
  EXPECT_FALSE(dipped.clear);
}

// The blade being machined is a check surface for the shank and holder
// only, and a coarse mesh carries its chord tolerance as a margin.
TEST(CollisionWorld, PartMaskAndMarginPerCheckSurface) {
  const ToolBody body(Tool::ball_end_mill({3, 15, {6, 30}, {}}), 1e-3);
  const ToolPose pose{Vec3(0, 0, 0.5), Vec3::UnitZ()};  // ball 0.5 above the floor, shank 15.5
  CollisionWorld shank_only;
  PartMask mask;
  mask.cutter = false;
  shank_only.add("own blade", grid_mesh(Vec3(-100, -100, 0), Vec3(200, 0, 0), Vec3(0, 200, 0), 10, 10), {mask, 0.0});
  const PoseCheck c = shank_only.check(body, pose, Clearances{});
  ASSERT_EQ(c.parts.size(), 2u);
  EXPECT_EQ(c.parts[0].object, -1);  // the cutter does not see it
  EXPECT_FALSE(c.parts[0].resolved);
  expect_enclosing_distance(c.parts[1].distance_mm, 15.5, body, "shank");
  // Dipping the ball into it is no collision for a shank-only surface.
  EXPECT_TRUE(shank_only.check(body, ToolPose{Vec3(0, 0, -1), Vec3::UnitZ()}, Clearances{}).clear);

  CollisionWorld margined;
  margined.add("coarse", grid_mesh(Vec3(-100, -100, 0), Vec3(200, 0, 0), Vec3(0, 200, 0), 10, 10), {{}, 0.2});
  const PoseCheck m = margined.check(body, pose, Clearances{});
  expect_enclosing_distance(m.parts[0].distance_mm, 0.5 - 0.2, body, "cutter with margin");
  // Clear/not-clear at exactly the clearance: a surface the query does not
  // reach must not turn "not clear" through (d + margin) - margin rounding.
  const ToolPose far{Vec3(0, 0, 5), Vec3::UnitZ()};
  const PoseCheck at_bound = margined.check(body, far, Clearances{0.5, 0.5, 0}, 0.0);
  EXPECT_TRUE(at_bound.clear);
  EXPECT_EQ(at_bound.parts[0].object, -1);
  CheckSurfaceOptions none;
  none.parts.cutter = none.parts.shank = none.parts.holder = false;
  EXPECT_THROW(margined.add("nothing", grid_mesh(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 1, 1), none),
               ParameterError);
}

// The pairs a world leaves out, as a world of their own: the own blade
// (shank and holder only) for the cutter alone; a surface checked against
// every part drops out.
TEST(CollisionWorld, UncheckedPairsAreTheMaskedOutPartsAlone) {
  const ToolBody body(Tool::ball_end_mill({3, 15, {6, 30}, {}}), 1e-3);
  CollisionWorld world;
  PartMask mask;
  mask.cutter = false;
  world.add("own blade", grid_mesh(Vec3(-100, -100, 0), Vec3(200, 0, 0), Vec3(0, 200, 0), 10, 10), {mask, 0.0});
  world.add("hub", box_mesh(Vec3(200, 200, -50), Vec3(210, 210, 50)));
  const std::shared_ptr<const CollisionWorld> pairs = world.unchecked_pairs();
  ASSERT_NE(pairs, nullptr);
  const CollisionWorld& left = *pairs;
  ASSERT_EQ(left.size(), 1);
  EXPECT_EQ(left.name(0), "own blade");
  // The ball dipped 1 mm into the blade: clear for the world, not for the
  // pairs it left out.
  const ToolPose dipped{Vec3(0, 0, -1), Vec3::UnitZ()};
  EXPECT_TRUE(world.check(body, dipped, Clearances{}).clear);
  const PoseCheck c = left.check(body, dipped, Clearances{});
  EXPECT_FALSE(c.clear);
  EXPECT_TRUE(c.parts[0].collides);
  // The shank through the blade, the cutter 5 mm under it: the world's
  // pair, not the left-out one's.
  const ToolPose through{Vec3(0, 0, -20), Vec3::UnitZ()};
  EXPECT_FALSE(world.check(body, through, Clearances{}).clear);
  const PoseCheck s = left.check(body, through, Clearances{});
  EXPECT_TRUE(s.clear);
  EXPECT_EQ(s.parts[1].object, -1);  // the shank sees nothing
  EXPECT_NEAR(s.parts[0].distance_mm, 5, body.overestimate_mm() + 1e-9);
  // A world that checks every pair leaves none.
  CollisionWorld full;
  full.add("hub", box_mesh(Vec3(200, 200, -50), Vec3(210, 210, 50)));
  EXPECT_EQ(full.unchecked_pairs(), nullptr);
}

// A world less the triangles a filter picks: the plate's x < 0 half gone,
// the x > 0 half and the box as they were (with their margin, the box
// shared); a filter taking everything leaves nothing.
TEST(CollisionWorld, WithoutTrianglesKeepsTheRestAsItWas) {
  const ToolBody body(Tool::ball_end_mill({3, 15, {6, 30}, {}}), 1e-3);
  CollisionWorld world;
  world.add("plate", grid_mesh(Vec3(-100, -100, 0), Vec3(200, 0, 0), Vec3(0, 200, 0), 10, 10), {PartMask{}, 0.5});
  world.add("box", box_mesh(Vec3(200, 200, -50), Vec3(210, 210, 50)));
  const std::shared_ptr<const CollisionWorld> half =
      world.without_triangles([](const Vec3& a, const Vec3& b, const Vec3& c) {
        return a.x() <= 0 && b.x() <= 0 && c.x() <= 0;  // the plate's x < 0 half
      });
  ASSERT_NE(half, nullptr);
  ASSERT_EQ(half->size(), 2);
  EXPECT_EQ(half->name(0), "plate");
  EXPECT_EQ(half->triangle_count(0), 100);
  EXPECT_EQ(half->triangle_count(1), world.triangle_count(1));
  // The ball's tip 2 mm over the plate at x = -50: 1.5 mm off it with its
  // margin before, nothing near now; at x = +50 as before.
  const ToolPose left{Vec3(-50, 0, 2), Vec3::UnitZ()}, right{Vec3(50, 0, 2), Vec3::UnitZ()};
  EXPECT_NEAR(world.check(body, left, Clearances{}).parts[0].distance_mm, 1.5, body.overestimate_mm() + 1e-6);
  EXPECT_GT(half->check(body, left, Clearances{}).parts[0].distance_mm, 40);
  EXPECT_NEAR(half->check(body, right, Clearances{}).parts[0].distance_mm, 1.5, body.overestimate_mm() + 1e-6);
  // Dipped 1 mm into the kept half: the containment test still sees it.
  EXPECT_TRUE(half->check(body, {Vec3(50, 0, -1), Vec3::UnitZ()}, Clearances{}).parts[0].collides);
  EXPECT_EQ(world.without_triangles([](const Vec3&, const Vec3&, const Vec3&) { return true; }), nullptr);
}

TEST(CollisionWorld, SeparateClearancesForCutterShankAndHolder) {
  // Flat-end mill R 5 (corner r 1, flutes 20), shank d 8 up to z 50, holder d 30 up to z 70.
  const ToolBody body(Tool::flat_end_mill({5, 1, 20, {8, 30}, {30, 20}}), 1e-3);
  CollisionWorld world;
  world.add("wall", box_mesh(Vec3(10, -20, 25), Vec3(20, 20, 45)));
  const ToolPose pose{Vec3::Zero(), Vec3::UnitZ()};
  const PoseCheck c = world.check(body, pose, Clearances{});
  ASSERT_EQ(c.parts.size(), 3u);
  EXPECT_EQ(c.parts[0].part, ToolPartId::Cutter);
  EXPECT_EQ(c.parts[1].part, ToolPartId::Shank);
  EXPECT_EQ(c.parts[2].part, ToolPartId::Holder);
  // Cutter's top rim (5, 20) to the wall's lower edge (10, 25).
  expect_enclosing_distance(c.parts[0].distance_mm, std::hypot(5.0, 5.0), body, "cutter");
  expect_enclosing_distance(c.parts[1].distance_mm, 6, body, "shank");   // radius 4, wall at x 10
  expect_enclosing_distance(c.parts[2].distance_mm, 5, body, "holder");  // from z 50, wall top 45
  EXPECT_TRUE(c.clear);

  // Each part against its own clearance.
  EXPECT_TRUE(world.check(body, pose, Clearances{7.0, 5.9, 4.9}).clear);
  const PoseCheck shank_close = world.check(body, pose, Clearances{1.0, 6.5, 1.0});
  EXPECT_FALSE(shank_close.clear);
  EXPECT_EQ(shank_close.parts[shank_close.worst].part, ToolPartId::Shank);
  EXPECT_NEAR(shank_close.min_margin_mm, -0.5, body.overestimate_mm() + kFclTolMm);
  const PoseCheck holder_close = world.check(body, pose, Clearances{1.0, 1.0, 5.5});
  EXPECT_FALSE(holder_close.clear);
  EXPECT_EQ(holder_close.parts[holder_close.worst].part, ToolPartId::Holder);

  // Lower the tool 10 mm: the holder overlaps the wall.
  const PoseCheck low = world.check(body, ToolPose{Vec3(0, 0, -10), Vec3::UnitZ()}, Clearances{});
  EXPECT_TRUE(low.parts[2].collides);
  EXPECT_FALSE(low.parts[1].collides);
  EXPECT_FALSE(low.clear);
}

// check_bounded asks first the object that was nearest a piece at its last
// query (it prunes the others by that distance). The order must change the
// cost only: the tool hops over five blocks, each nearest in turn and in
// every order (down the row, up it, skipping), and every part's distance
// and nearest object equal the minimum over worlds holding one block each.
TEST(CollisionWorld, NearestFirstOrderGivesTheMinimumOverTheObjects) {
  const ToolBody body(Tool::flat_end_mill({3, 0.5, 9, {6, 30}, {12, 20}}), 1e-3);
  constexpr int kBlocks = 5;
  CollisionWorld all;
  std::vector<CollisionWorld> one(kBlocks);
  for (int b = 0; b < kBlocks; ++b) {
    const TriangleMesh block = box_mesh(Vec3(30 * b - 5, -5, -10), Vec3(30 * b + 5, 5, 0));
    all.add("block " + std::to_string(b), block);
    one[b].add("block " + std::to_string(b), block);
  }
  const std::vector<int> hops = {4, 3, 2, 1, 0, 0, 2, 4, 1, 3, 0, 4};
  for (size_t k = 0; k < hops.size(); ++k) {
    const double tilt = 0.1 * static_cast<double>(k % 4);
    const ToolPose pose{Vec3(30 * hops[k] + 0.5 * static_cast<double>(k % 3), 0, 0.5 + 0.2 * static_cast<double>(k % 5)),
                        Vec3(std::sin(tilt), 0, std::cos(tilt))};
    const PoseCheck c = all.check(body, pose, Clearances{});
    for (size_t p = 0; p < c.parts.size(); ++p) {
      double best = std::numeric_limits<double>::infinity();
      int best_block = -1;
      for (int b = 0; b < kBlocks; ++b) {
        const double d = one[b].check(body, pose, Clearances{}).parts[p].distance_mm;
        if (d < best) {
          best = d;
          best_block = b;
        }
      }
      EXPECT_EQ(c.parts[p].distance_mm, best) << "hop " << k << " part " << p;
      ASSERT_GE(c.parts[p].object, 0);
      EXPECT_EQ(all.name(c.parts[p].object), "block " + std::to_string(best_block)) << "hop " << k << " part " << p;
    }
    EXPECT_EQ(all.name(c.parts[0].object), "block " + std::to_string(hops[k]));  // the cutter's is the one below it
  }
}

TEST(CollisionWorld, NamesObjectsAndRejectsBadMeshes) {
  CollisionWorld world;
  world.add("blade k-1", box_mesh(Vec3(-30, -1, 0), Vec3(-20, 1, 30)));
  world.add("blade k+1", box_mesh(Vec3(20, -1, 0), Vec3(30, 1, 30)));
  EXPECT_EQ(world.size(), 2);
  EXPECT_EQ(world.name(1), "blade k+1");
  const ToolBody body(Tool::ball_end_mill({3, 15, {}, {}}));
  const PoseCheck c = world.check(body, ToolPose{Vec3(10, 0, 5), Vec3::UnitZ()}, Clearances{});
  EXPECT_EQ(c.parts[0].object, 1);  // nearer the +x blade
  EXPECT_NEAR(c.parts[0].distance_mm, 7, body.overestimate_mm() + kFclTolMm);
  EXPECT_THROW(world.add("blade k+1", box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1))), ParameterError);
  EXPECT_THROW(world.add("empty", TriangleMesh{}), ParameterError);
  TriangleMesh bad = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  bad.triangles[3] = Eigen::Vector3i(0, 1, 8);
  EXPECT_THROW(world.add("bad", bad), ParameterError);
}

// prepare + add(prepared) is add in two steps: prepared on two threads, the
// world answers as the one built by add; the name is checked on adding,
// the mesh on preparing, and a surface is added once.
TEST(CollisionWorld, PreparedOnThreadsThenAddedInOrderIsTheSameWorld) {
  const std::vector<std::pair<std::string, TriangleMesh>> meshes = {
      {"blade k-1", box_mesh(Vec3(-30, -1, 0), Vec3(-20, 1, 30))},
      {"blade k+1", box_mesh(Vec3(20, -1, 0), Vec3(30, 1, 30))},
      {"floor", grid_mesh(Vec3(-50, -50, -3), Vec3(100, 0, 0), Vec3(0, 100, 0), 8, 8)}};
  CollisionWorld direct, prepared;
  std::vector<CollisionWorld::PreparedSurface> built(meshes.size());
  std::vector<std::thread> workers;
  for (size_t k = 0; k < meshes.size(); ++k)
    workers.emplace_back([&, k] { built[k] = CollisionWorld::prepare(meshes[k].first, meshes[k].second); });
  for (std::thread& t : workers) t.join();
  for (size_t k = 0; k < meshes.size(); ++k) {
    direct.add(meshes[k].first, meshes[k].second);
    prepared.add(built[k]);
    EXPECT_EQ(prepared.name(static_cast<int>(k)), meshes[k].first);
  }
  const ToolBody body(Tool::ball_end_mill({3, 15, {6, 30}, {}}));
  for (const Vec3& tip : {Vec3(10, 0, 5), Vec3(-12, 0, 2), Vec3(0, 0, 1)}) {
    const PoseCheck a = direct.check(body, ToolPose{tip, Vec3::UnitZ()}, Clearances{});
    const PoseCheck b = prepared.check(body, ToolPose{tip, Vec3::UnitZ()}, Clearances{});
    ASSERT_EQ(a.parts.size(), b.parts.size());
    for (size_t p = 0; p < a.parts.size(); ++p) {
      EXPECT_EQ(a.parts[p].distance_mm, b.parts[p].distance_mm);
      EXPECT_EQ(a.parts[p].object, b.parts[p].object);
    }
  }
  EXPECT_THROW(prepared.add(CollisionWorld::prepare("floor", meshes[2].second)), ParameterError);  // name taken
  EXPECT_THROW(CollisionWorld::prepare("empty", TriangleMesh{}), ParameterError);
  EXPECT_THROW(prepared.add(built[0]), ParameterError);  // already added: it was moved into the world
  EXPECT_THROW(prepared.add(CollisionWorld::PreparedSurface{}), ParameterError);
}

TEST(CollisionWorld, HorizonBoundsWhatIsResolved) {
  CollisionWorld world;
  world.add("floor", grid_mesh(Vec3(-100, -100, 0), Vec3(200, 0, 0), Vec3(0, 200, 0), 10, 10));
  const ToolBody body(Tool::ball_end_mill({3, 15, {6, 30}, {}}));
  const ToolPose pose{Vec3(0, 0, 2), Vec3::UnitZ()};
  const Clearances c{0.5, 0.5, 0};
  // Horizon 0: only "at least the clearance" is established.
  const PoseCheck quick = world.check(body, pose, c, 0);
  EXPECT_TRUE(quick.clear);
  EXPECT_FALSE(quick.parts[0].resolved);
  EXPECT_EQ(quick.parts[0].distance_mm, 0.5);
  EXPECT_EQ(quick.parts[0].object, -1);
  // Horizon 2: the cutter's 2 mm is within 0.5 + 2, the shank's 17 is not.
  const PoseCheck mid = world.check(body, pose, c, 2);
  EXPECT_TRUE(mid.parts[0].resolved);
  expect_enclosing_distance(mid.parts[0].distance_mm, 2, body, "cutter");
  EXPECT_FALSE(mid.parts[1].resolved);
  EXPECT_EQ(mid.parts[1].distance_mm, 2.5);
  // Too close: resolved whatever the horizon, so the refusal can say how close.
  const PoseCheck near = world.check(body, ToolPose{Vec3(0, 0, 0.2), Vec3::UnitZ()}, c, 0);
  EXPECT_FALSE(near.clear);
  EXPECT_TRUE(near.parts[0].resolved);
  expect_enclosing_distance(near.parts[0].distance_mm, 0.2, body, "cutter");
}

TEST(CollisionWorld, CheckSurfaceWhollyInsideAPartCollides) {
  // A small closed box inside the shank crosses none of its faces.
  const ToolBody body(Tool::ball_end_mill({3, 15, {6, 30}, {}}));
  CollisionWorld world;
  world.add("chip", box_mesh(Vec3(-1, -1, 20), Vec3(1, 1, 22)));
  const PoseCheck c = world.check(body, ToolPose{Vec3::Zero(), Vec3::UnitZ()}, Clearances{});
  EXPECT_FALSE(c.clear);
  EXPECT_FALSE(c.parts[0].collides);
  EXPECT_TRUE(c.parts[1].collides);
  EXPECT_EQ(c.parts[1].distance_mm, 0);
  // Moved off the axis by 10 mm it is 6 mm clear of the shank's side.
  const PoseCheck off = world.check(body, ToolPose{Vec3(-10, 0, 0), Vec3::UnitZ()}, Clearances{});
  EXPECT_TRUE(off.clear);
  expect_enclosing_distance(off.parts[1].distance_mm, 6, body, "shank");
}

// A hub-like cylinder of radius 50 about z, as a Surface on [0,1]^2.
class HubCylinder : public Surface {
 public:
  SurfaceDerivs eval(double u, double v) const override {
    const double a = kPi / 2 * (v - 0.5), z = 40 * u;
    SurfaceDerivs d;
    d.p = Vec3(50 * std::cos(a), 50 * std::sin(a), z);
    d.pu = Vec3(0, 0, 40);
    d.pv = kPi / 2 * Vec3(-50 * std::sin(a), 50 * std::cos(a), 0);
    d.pvv = kPi * kPi / 4 * Vec3(-50 * std::cos(a), -50 * std::sin(a), 0);
    return d;
  }
};

TEST(CollisionWorld, TessellatedSurfaceAtChordTolerance) {
  const double chord_tol = 1e-3;
  CollisionWorld world;
  world.add("hub", tessellate(HubCylinder(), chord_tol));
  const ToolBody body(Tool::ball_end_mill({3, 15, {}, {}}));
  for (double gap : {0.05, 0.5, 2.0}) {
    for (double angle_deg : {-20.0, 0.0, 33.0}) {
      // Ball end pointing away from the axis, its tip `gap` outside the cylinder.
      const Vec3 radial(std::cos(deg_to_rad(angle_deg)), std::sin(deg_to_rad(angle_deg)), 0);
      const PoseCheck c = world.check(body, ToolPose{(50 + gap) * radial + Vec3(0, 0, 20), radial}, Clearances{});
      // The chords lie inside the true cylinder by at most chord_tol.
      EXPECT_LE(c.parts[0].distance_mm, gap + chord_tol + kFclTolMm) << gap << " " << angle_deg;
      EXPECT_GE(c.parts[0].distance_mm, gap - body.overestimate_mm() - kFclTolMm) << gap << " " << angle_deg;
    }
  }
}

// Blisk paper Fig. 9: two poses that are clear, and the motion between them
// cuts through the blade. The "blade" is a thin fin between the poses.
TEST(CollisionWorld, MotionBetweenTwoClearPosesThroughAFinIsCaught) {
  CollisionWorld world;
  world.add("blade", grid_mesh(Vec3(0, -20, -10), Vec3(0, 40, 0), Vec3(0, 0, 13), 4, 4));  // x = 0, z up to 3
  const ToolBody body(test::paper_drum_wheel(), 1e-3);
  const Clearances clearances{0.5, 0.5, 0};
  const ToolPose from{Vec3(-6, 0, 1), Vec3::UnitZ()}, to{Vec3(6, 0, 1), Vec3::UnitZ()};
  // Each pose alone: the head (radius 4) is 2 mm from the fin.
  const PoseCheck a = world.check(body, from, clearances), b = world.check(body, to, clearances);
  EXPECT_TRUE(a.clear);
  EXPECT_TRUE(b.clear);
  EXPECT_NEAR(a.parts[0].distance_mm, 2, body.overestimate_mm() + kFclTolMm);
  // The motion: the widest ring (z 3, at the fin's top) comes within 0.5 mm
  // of the fin when the tip is at x = -4.5, i.e. t = 1.5 / 12.
  const MotionCheck m = world.check_motion(body, from, to, clearances, 1e-3);
  EXPECT_FALSE(m.clear);
  EXPECT_FALSE(m.undecided);
  EXPECT_NEAR(m.t, 0.125, 1e-4);
  EXPECT_EQ(m.at.parts[m.at.worst].part, ToolPartId::Cutter);
  EXPECT_EQ(world.name(m.at.parts[m.at.worst].object), "blade");

  // Lift the tool 2.6 mm: the motion passes over the fin (tip at 3.6 > 3 + 0.5).
  const ToolPose from_high{Vec3(-6, 0, 3.6), Vec3::UnitZ()}, to_high{Vec3(6, 0, 3.6), Vec3::UnitZ()};
  const MotionCheck clear = world.check_motion(body, from_high, to_high, clearances, 1e-3);
  EXPECT_TRUE(clear.clear);
  EXPECT_GE(clear.min_margin_mm, 0);
  // Every step advances at least (margin + tol) / V = (0.1 - overestimate + 0.001) / 12.
  EXPECT_LE(clear.samples, static_cast<int>(12 / (0.1 - body.overestimate_mm())) + 1);
}

TEST(CollisionWorld, MotionThatOnlyTurnsTheAxisIsChecked) {
  // Tip fixed, axis swings from -30 to +30 degrees about Y: the shank's top
  // end (z 100 when upright) sweeps an arc through a block at the top.
  const ToolBody body(test::paper_drum_wheel(), 1e-3);
  const Clearances clearances{0.5, 0.5, 0};
  const auto axis = [](double deg) { return Vec3(std::sin(deg_to_rad(deg)), 0, std::cos(deg_to_rad(deg))); };
  const ToolPose from{Vec3::Zero(), axis(-30)}, to{Vec3::Zero(), axis(30)};
  CollisionWorld blocked;
  blocked.add("casing", box_mesh(Vec3(-2, -2, 99), Vec3(2, 2, 103)));
  EXPECT_TRUE(blocked.check(body, from, clearances).clear);
  EXPECT_TRUE(blocked.check(body, to, clearances).clear);
  const MotionCheck m = blocked.check_motion(body, from, to, clearances);
  EXPECT_FALSE(m.clear);
  EXPECT_GT(m.t, 0.40);
  EXPECT_LT(m.t, 0.50);
  EXPECT_EQ(m.at.parts[m.at.worst].part, ToolPartId::Shank);

  // Block 2 mm above the shank: the rim rises at most to sqrt(100² + 3²) < 100.05.
  CollisionWorld above;
  above.add("casing", box_mesh(Vec3(-2, -2, 102), Vec3(2, 2, 106)));
  const MotionCheck ok = above.check_motion(body, from, to, clearances);
  EXPECT_TRUE(ok.clear);
  EXPECT_GE(ok.min_margin_mm, 0);
}

TEST(CollisionWorld, ALongCutterGlidingOverAPlaneStepsByItsBottomPiece) {
  // The impeller's tapered ball end (r 3, 90 mm flute) 0.1 mm over a plane,
  // moving 10 mm while its axis tilts 5 deg about the tip: the ball's lowest
  // point dips to 0.1 - r (1 - cos 5 deg) = 0.0886 mm, the rest stays far.
  // Every step advances (margin + tol) / V of the piece nearest the plane —
  // the bottom piece, V = 10 + theta * its reach — where one body would step
  // by the whole cutter's reach (~96 mm: over 180 samples).
  const Tool tool = Tool::tapered_ball_end_mill({3, deg_to_rad(2), 90, {16, 60}, {}});
  const ToolBody body(tool, 1e-3);
  CollisionWorld world;
  world.add("hub", grid_mesh(Vec3(-100, -100, 0), Vec3(200, 0, 0), Vec3(0, 200, 0), 4, 4));
  const double theta = deg_to_rad(5);
  const ToolPose from{Vec3(-5, 0, 0.1), Vec3::UnitZ()}, to{Vec3(5, 0, 0.1), Vec3(std::sin(theta), 0, std::cos(theta))};
  const MotionCheck m = world.check_motion(body, from, to, Clearances{}, 1e-3);
  EXPECT_TRUE(m.clear);
  const double oe = body.parts().front().pieces.front().overestimate_mm;  // the bottom piece's
  EXPECT_GE(m.min_margin_mm, 0);
  const double v_bottom = 10 + theta * body.parts().front().pieces.front().reach_mm;
  const double v_whole = 10 + theta * body.parts().front().reach_mm;
  const double least = 0.1 - 3 * (1 - std::cos(theta)) - oe;
  EXPECT_LE(m.samples, static_cast<int>(v_bottom / least) + 2);
  EXPECT_LT(static_cast<int>(v_bottom / least) + 2, static_cast<int>(v_whole / 0.101));
  // Through a fin standing at x = 0 (z up to 3) the ball is caught: the
  // bottom piece's larger steps still stop where it comes too close.
  world.add("fin", grid_mesh(Vec3(0, -20, -10), Vec3(0, 40, 0), Vec3(0, 0, 13), 4, 4));
  const MotionCheck fin = world.check_motion(body, {Vec3(-6, 0, 1), Vec3::UnitZ()}, {Vec3(6, 0, 1), Vec3::UnitZ()},
                                             Clearances{0.2, 0, 0}, 1e-3);
  EXPECT_FALSE(fin.clear);
  EXPECT_GT(fin.t, 0.1);
  EXPECT_LT(fin.t, 0.5);
  EXPECT_EQ(world.name(fin.at.parts[fin.at.worst].object), "fin");
}

// A motion proof asks the cutter's coarse body (0.01 mm mesh) first and
// keeps its distance only far from the clearance; near it, the fine body's
// answer decides. A wall beside the flat end's side, the tool gliding
// along it at a constant distance D, for walls all round the axis (so some
// face a corner of the coarse polygon, up to ~0.02 mm nearer than the
// side): 5 um more clearance than D is refused everywhere, 5 um less
// proved everywhere — which the coarse body alone would refuse.
TEST(CollisionWorld, AMotionProofKeepsTheCoarseBodysDistanceOnlyFarFromTheClearance) {
  const ToolBody body(Tool::flat_end_mill({3, 0.5, 9, {6, 50}, {12, 40}}), 1e-3);
  const FclPiece& cutter = body.parts().front().pieces.front();
  ASSERT_TRUE(cutter.coarse);
  EXPECT_GT(cutter.coarse_overestimate_mm, cutter.overestimate_mm);
  EXPECT_LE(cutter.coarse_overestimate_mm, 2 * kCoarsePieceTolMm + 1e-9);
  EXPECT_LT(cutter.coarse->num_tris, cutter.geometry->num_tris / 4);
  const double D = 0.3;
  int proved = 0, refused = 0;
  for (int k = 0; k < 36; ++k) {
    const double a = deg_to_rad(10.0 * k + 1.3);
    const Vec3 out(std::cos(a), std::sin(a), 0), along(-std::sin(a), std::cos(a), 0);
    CollisionWorld world;
    // The wall's plane at 3 + D from the axis, from below the cutter's
    // bottom to 4 mm up its 9 mm side: the shank above is not beside it.
    world.add("wall", grid_mesh(Vec3((3 + D) * out - 50 * along + Vec3(0, 0, -2)), Vec3(100 * along),
                                Vec3(0, 0, 6), 4, 4));
    // 4 mm of travel: long enough for many samples near the clearance, short
    // enough that 36 walls x 3 proofs stay a unit test.
    const double travel = 4;
    const ToolPose from{Vec3(-travel / 2 * along), Vec3::UnitZ()}, to{Vec3(travel / 2 * along), Vec3::UnitZ()};
    const MotionCheck near_out = world.check_motion(body, from, to, Clearances{D - 0.005, 0, 0}, 1e-3);
    const MotionCheck near_in = world.check_motion(body, from, to, Clearances{D + 0.005, 0, 0}, 1e-3);
    proved += near_out.clear;
    refused += !near_in.clear;
    EXPECT_TRUE(near_out.clear) << "wall at " << 10 * k + 1.3 << " deg";
    EXPECT_FALSE(near_in.clear) << "wall at " << 10 * k + 1.3 << " deg";
    // Far from it: proved, in the few samples the coarse distance allows.
    const MotionCheck far = world.check_motion(body, from, to, Clearances{D - 0.25, 0, 0}, 1e-3);
    EXPECT_TRUE(far.clear);
    EXPECT_LE(far.samples, static_cast<int>(std::ceil(travel / (0.25 - 2 * kCoarsePieceTolMm))) + 1);
  }
  EXPECT_EQ(proved, 36);
  EXPECT_EQ(refused, 36);
}

TEST(CollisionWorld, MotionRejectsBadSettings) {
  CollisionWorld world;
  world.add("floor", grid_mesh(Vec3(-10, -10, 0), Vec3(20, 0, 0), Vec3(0, 20, 0)));
  const ToolBody body(Tool::ball_end_mill({3, 15, {}, {}}));
  const ToolPose p{Vec3(0, 0, 5), Vec3::UnitZ()};
  EXPECT_THROW(world.check_motion(body, p, p, Clearances{}, 0.0), ParameterError);
  EXPECT_THROW(world.check(body, p, Clearances{-1, 0, 0}), ParameterError);
  EXPECT_THROW(world.check(body, ToolPose{Vec3::Zero(), Vec3::Zero()}, Clearances{}), ParameterError);
  // No motion at all: one sample.
  EXPECT_EQ(world.check_motion(body, p, p, Clearances{}).samples, 1);
}

}  // namespace
}  // namespace bliskrun

namespace bliskrun {
namespace {

TEST(CollisionWorld, OverlapIsNotClearWithZeroClearanceAndHorizon) {
  // The tilt loop asks with horizon 0; with clearance 0 too, an overlap must
  // still come out as a collision (distance 0 is not "beyond the bound").
  CollisionWorld world;
  world.add("floor", test::grid_mesh(Vec3(-100, -100, 0), Vec3(200, 0, 0), Vec3(0, 200, 0), 10, 10));
  const ToolBody body(Tool::ball_end_mill({3, 15, {6, 30}, {}}), 1e-3);
  const ToolPose sunk{Vec3(0.3, 0.2, -1.0), Vec3::UnitZ()};  // the ball 1 mm into the floor
  const PoseCheck c = world.check(body, sunk, Clearances{}, 0.0);
  EXPECT_FALSE(c.clear);
  EXPECT_TRUE(c.parts.front().collides);
  const ToolPose above{Vec3(0.3, 0.2, 0.5), Vec3::UnitZ()};
  EXPECT_TRUE(world.check(body, above, Clearances{}, 0.0).clear);
}

}  // namespace
}  // namespace bliskrun

namespace bliskrun {
namespace {

// A hub-like cylinder r = 40 about Z, measured analytically (no mesh).
CollisionWorld cylinder_hub_world() {
  CollisionWorld world;
  CheckSurfaceOptions cutter_only;
  cutter_only.parts = {true, false, false};
  world.add("hub", std::make_shared<RevolutionDistance>(std::vector<Vec2>{Vec2(-50, 40), Vec2(50, 40)}, 0.0),
            cutter_only);
  return world;
}

TEST(CollisionWorld, RevolutionMeasuresTheBallAsItIs) {
  const CollisionWorld world = cylinder_hub_world();
  const ToolBody body(Tool::ball_end_mill({3, 15, {6, 30}, {}}), 1e-3);
  for (double deg : {0.0, 20.0, 50.0}) {
    for (double d : {0.05, 0.5, 2.0}) {
      // Axis leaning away from the radial direction by `deg`, the ball's
      // centre 43 + d from the axis: the ball d from the hub, the flute
      // farther.
      const double a = deg_to_rad(deg);
      const Vec3 axis(std::cos(a), 0, std::sin(a));
      const ToolPose pose{Vec3(43 + d, 0, 0) - 3 * axis, axis};
      const double expected = d;
      const PoseCheck c = world.check(body, pose, Clearances{});
      ASSERT_EQ(c.parts.size(), 2u);
      EXPECT_LE(c.parts[0].distance_mm, expected + 1e-9) << deg << " " << d;
      EXPECT_GE(c.parts[0].distance_mm, expected - body.parts()[0].pieces[0].cover.overestimate_mm - 1e-9)
          << deg << " " << d;
      EXPECT_EQ(c.parts[0].object, 0);
      EXPECT_NEAR(std::hypot(c.parts[0].on_object.x(), c.parts[0].on_object.y()), 40, 1e-9);
      // The shank is not checked against it.
      EXPECT_FALSE(c.parts[1].resolved);
    }
  }
  // Sunk 0.2 mm into the hub: a collision.
  const PoseCheck sunk = world.check(body, ToolPose{Vec3(39.8, 0, 0), Vec3::UnitX()}, Clearances{});
  EXPECT_FALSE(sunk.clear);
  EXPECT_TRUE(sunk.parts[0].collides);
}

// A plate nearer the ball than the hub (the plate listed first): the part's
// nearest surface is the plate at every pose. An unresolved hub query
// returns its bound, best + r, and (best + r) - r rounds one unit below
// best for some values — that passed as a nearer hub with an unset nearest
// point (a helper saw "cutter against hub" beside a blade flank).
TEST(CollisionWorld, AFartherRevolutionNeverTakesTheNearestSurfacesName) {
  CollisionWorld world;
  CheckSurfaceOptions cutter_only;
  cutter_only.parts = {true, false, false};
  // The plate x = 60 (normal -X), the hub r = 40 about Z; the tool upright
  // beside the plate, its ball `gap` from it and 14 mm or more from the hub.
  world.add("plate", test::grid_mesh(Vec3(60, -50, -50), Vec3(0, 100, 0), Vec3(0, 0, 100), 4, 4), cutter_only);
  world.add("hub", std::make_shared<RevolutionDistance>(std::vector<Vec2>{Vec2(-50, 40), Vec2(50, 40)}, 0.0),
            cutter_only);
  const ToolBody body(Tool::ball_end_mill({3, 15, {6, 30}, {}}), 1e-3);
  int poses = 0;
  for (int i = 0; i < 400; ++i) {
    const double gap = 0.013 + 0.0173 * i;  // ball 0.013 .. 6.9 mm off the plate
    const ToolPose pose{Vec3(60 - 3 - gap, 0.01 * i, 0.5), Vec3::UnitZ()};
    const PoseCheck c = world.check(body, pose, Clearances{}, 20.0);
    ASSERT_TRUE(c.parts[0].resolved);
    EXPECT_EQ(world.name(c.parts[0].object), "plate") << "gap " << gap;
    EXPECT_NEAR(c.parts[0].on_object.x(), 60, 1e-9) << "gap " << gap;
    ++poses;
  }
  EXPECT_EQ(poses, 400);
}

TEST(CollisionWorld, RevolutionProvesAMotionAlongTheHubOrFindsItsDip) {
  // The tip 0.5 mm off the hub at -phi and +phi, the axis radial at both:
  // the straight move's middle puts the ball centre (40.5) cos(phi) + 3 from
  // the axis, into the hub when (40.5) cos(phi) < 40, i.e. phi > 8.99 deg.
  const CollisionWorld world = cylinder_hub_world();
  const ToolBody body(Tool::ball_end_mill({3, 15, {6, 30}, {}}), 1e-3);
  auto radial = [](double deg) {
    const double a = deg_to_rad(deg);
    const Vec3 n(std::cos(a), std::sin(a), 0);
    return ToolPose{40.5 * n, n};
  };
  Clearances c;
  c.cutter_mm = 0.05;
  const MotionCheck shallow = world.check_motion(body, radial(-8), radial(8), c, 1e-3);
  EXPECT_TRUE(shallow.clear);  // dips to 40.5 cos 8 deg - 40 = 0.106 mm
  // The proof's smallest margin is what it resolved: no more than the truth.
  EXPECT_GT(shallow.min_margin_mm, 0);
  EXPECT_LE(shallow.min_margin_mm, 40.5 * std::cos(deg_to_rad(8)) - 40 - 0.05 + 1e-9);
  const MotionCheck deep = world.check_motion(body, radial(-10), radial(10), c, 1e-3);
  EXPECT_FALSE(deep.clear);  // would reach 40.5 cos 10 deg - 40 = -0.115 mm
  EXPECT_GT(deep.t, 0.2);
  EXPECT_LT(deep.t, 0.5);
  EXPECT_EQ(world.name(deep.at.parts[deep.at.worst].object), "hub");
}

}  // namespace
}  // namespace bliskrun
