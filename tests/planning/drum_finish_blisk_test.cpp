// Issue 11, on the built-in blisk: every emitted move of the drum-finish
// plan of blade 1's concave pressure flank - rows, retracts, traverses,
// approaches - is clear of the machined flank beyond the tolerance, checked
// independently of the planner's gouge guard and of the simulation: the
// tool's exact signed distance at points of the exact design flank (not the
// trimmed B-spline reconstruction the planner works on), at every position
// of every link swept finely and at every cutting pose, brute force over the
// flank points near the tool.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/geometry/mesh.h"
#include "core/parts/builtin_blisk.h"
#include "core/planning/drum_finish.h"

namespace bliskrun {
namespace {

struct Flank {
  std::vector<Vec3> points;
};

// The exact flank sampled about every 0.2 mm.
Flank sample_flank(const Surface& s, int nu, int nv) {
  Flank f;
  f.points.reserve(static_cast<size_t>(nu) * nv);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) f.points.push_back(s.point(static_cast<double>(i) / (nu - 1), static_cast<double>(j) / (nv - 1)));
  return f;
}

// Smallest signed distance from the cutter to any flank point (negative:
// the point is inside the cutter) at the given pose.
double clearance(const Tool& tool, const ToolPose& pose, const Flank& f) {
  const Eigen::Isometry3d to_tool = tool_to_part(pose).inverse();
  const double reach = tool.cutter().reach() + 0.5;
  double worst = std::numeric_limits<double>::infinity();
  for (const Vec3& p : f.points) {
    if ((p - pose.tip).squaredNorm() > reach * reach) continue;
    worst = std::min(worst, tool.cutter().signed_distance(Vec3(to_tool * p)));
  }
  return worst;
}

TEST(DrumFinishBlisk, EveryEmittedMoveOfThePressureFlankPlanClearsTheMachinedFlank) {
  const BuiltinBlisk blisk;
  const SurfaceOfRevolution hub(blisk.hub_meridian()), casing(blisk.casing_meridian());
  const Tool wheel = Tool::drum_wheel({8, 50, 4, {6, 96}, {}});
  const int n = blisk.blade_count();
  // As scripts/lib/blisk_world.lua: the neighbours' flanks and the hub for
  // every tool part, the blade itself for the shank and holder.
  CollisionWorld world;
  for (int nb : {n - 1, 1})
    for (FlankSide side : {FlankSide::kPressure, FlankSide::kSuction})
      world.add("blade " + std::to_string(nb) + (side == FlankSide::kPressure ? " pressure" : " suction"),
                tessellate(*blisk.flank_surface(nb, side), 0.01));
  world.add("hub", tessellate(hub, 0.01));
  PartMask shank_only;
  shank_only.cutter = false;
  for (FlankSide side : {FlankSide::kPressure, FlankSide::kSuction})
    world.add(side == FlankSide::kPressure ? "own pressure" : "own suction",
              tessellate(*blisk.flank_surface(0, side), 0.05), {shank_only, 0.05});

  DrumFinishRequest rq;
  rq.flank = blisk.flank_surface(0, FlankSide::kPressure);
  rq.hub = &hub;
  rq.casing = &casing;
  rq.tool = &wheel;
  rq.world = &world;
  rq.tilt.clearances = {0, 0.1, 1};
  const DrumFinishResult plan = plan_drum_finish(rq);
  ASSERT_EQ(plan.total_refusals, 0);
  ASSERT_EQ(plan.refused_links, 0);

  const Flank flank = sample_flank(*rq.flank, 200, 250);
  // The flank points are about 0.2 mm apart: between them the wheel (radius
  // 4 mm about its axis) can dip up to 0.2^2 / (8 * 4) = 1.3 um more.
  const double allowed = rq.links.allowed_overcut_mm + 0.0013;
  const Toolpath moves = drum_finish_moves(plan);
  int link_positions = 0, cutting_poses = 0;
  double worst_link = std::numeric_limits<double>::infinity(), worst_cut = worst_link;
  for (size_t i = 1; i < moves.size(); ++i) {
    const Move& m = moves[i];
    ASSERT_NE(m.kind, Move::Kind::Stop);
    if (m.motion == "cut") {
      worst_cut = std::min(worst_cut, clearance(wheel, m.pose, flank));
      ++cutting_poses;
      continue;
    }
    // A link leg, swept: no cutter point moves more than 0.02 mm between
    // the positions checked.
    const PoseMotion motion(moves[i - 1].pose, m.pose);
    const int steps = std::max(1, static_cast<int>(std::ceil(motion.max_point_speed(wheel.cutter().reach()) / 0.02)));
    const int last = m.kind == Move::Kind::Rapid ? steps : steps - 1;  // the next row's pose is a cut
    for (int s = 1; s <= last; ++s) {
      const double c = clearance(wheel, motion.pose_at(static_cast<double>(s) / steps), flank);
      worst_link = std::min(worst_link, c);
      ++link_positions;
      EXPECT_GE(c, -allowed) << "move " << i << " (" << m.motion << ", row " << m.row << ") at t = "
                             << static_cast<double>(s) / steps;
    }
  }
  EXPECT_GT(link_positions, 1000);
  EXPECT_EQ(cutting_poses + static_cast<int>(plan.rows.size()), plan.total_poses);
  // The cutting poses touch the flank (within the chord and the sampling).
  EXPECT_GE(worst_cut, -allowed);
  EXPECT_LT(worst_cut, 0.01);
  // And the links leave it: nothing within the allowance below the flank.
  EXPECT_GE(worst_link, -allowed);
}

}  // namespace
}  // namespace bliskrun
