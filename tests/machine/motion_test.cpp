#include "core/machine/motion.h"

#include <gtest/gtest.h>

#include <random>

#include "core/common/error.h"
#include "machine/test_machines.h"
#include "test_support.h"

namespace bliskrun {
namespace {


double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// The departure of the tip from the planned segment, by brute force: the
// machine's linear axis interpolation sampled densely.
double dense_deviation(const Kinematics& kin, const MachineAxes& a, const MachineAxes& b,
                       const Vec3& tip_a, const Vec3& tip_b, int samples = 4000) {
  double worst = 0;
  for (int i = 0; i <= samples; ++i) {
    const double t = double(i) / samples;
    MachineAxes q;
    q.linear_mm = a.linear_mm + t * (b.linear_mm - a.linear_mm);
    for (int r = 0; r < 2; ++r) q.rotary_rad[r] = a.rotary_rad[r] + t * (b.rotary_rad[r] - a.rotary_rad[r]);
    worst = std::max(worst, distance_to_segment(kin.forward(q).tip, tip_a, tip_b));
  }
  return worst;
}


// The bound move_deviation reports is never below the true departure, and
// the sampled value never above it.
TEST(MachineMotion, DeviationBoundHoldsForRandomMoves) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-60, 60);
  for (const MachineDefinition& m : test::all_machines()) {
    const Kinematics kin(m, 80.0);
    for (int i = 0; i < 40; ++i) {
      MachineAxes a, b;
      a.rotary_rad = test::random_rotary(m, rng);
      b.rotary_rad = a.rotary_rad;
      b.rotary_rad[0] += std::uniform_real_distribution<double>(-0.3, 0.3)(rng);
      b.rotary_rad[1] += std::uniform_real_distribution<double>(-0.3, 0.3)(rng);
      a.linear_mm = Vec3(coord(rng), coord(rng), coord(rng));
      b.linear_mm = a.linear_mm + Vec3(coord(rng), coord(rng), coord(rng)) * 0.2;
      const Vec3 tip_a = kin.forward(a).tip, tip_b = kin.forward(b).tip;
      const MoveDeviation dev = move_deviation(kin, a, b, tip_a, tip_b, 0.001);
      const double truth = dense_deviation(kin, a, b, tip_a, tip_b);
      EXPECT_LE(truth, dev.bound_mm + 1e-12) << m.name << " move " << i;
      EXPECT_LE(dev.sampled_mm, truth + 1e-6) << m.name << " move " << i;  // both sampled
      EXPECT_LE(dev.bound_mm - dev.sampled_mm, 0.001 + 1e-12);
    }
  }
}

// A feed move that swings C by 90 deg at a 30 deg tilt with the tip 40 mm
// off the C axis: linear axis interpolation leaves the segment by
// millimetres; after splitting every piece stays within the chord tolerance,
// measured densely.
TEST(MachineMotion, SplittingKeepsANinetyDegreeSwingWithinTolerance) {
  const Kinematics kin(test::table_table_ac(), 80.0);
  const double tol = 0.002;
  std::vector<PlannedMove> path(2);
  path[0].kind = MoveKind::Rapid;
  path[0].pose = test::tilted_pose(Vec3(40, 0, 5), 30 * kDeg, 0);
  path[1].kind = MoveKind::Feed;
  path[1].feed_mm_per_min = 1000;
  path[1].pose = test::tilted_pose(Vec3(0, 40, 5), 30 * kDeg, 90 * kDeg);

  MachineAxes start;
  const MachineAxes a = kin.inverse(path[0].pose, start), b = kin.inverse(path[1].pose, a);
  ASSERT_NEAR(std::abs(b.rotary_rad[1] - a.rotary_rad[1]), 90 * kDeg, 1e-9);
  const double unsplit = dense_deviation(kin, a, b, path[0].pose.tip, path[1].pose.tip);
  EXPECT_GT(unsplit, 1.0);  // the test means something

  MotionOptions options;
  options.chord_tol_mm = tol;
  const MachineProgram program = plan_machine_motion(kin, path, options);
  EXPECT_GT(program.inserted_moves, 10);
  EXPECT_LE(program.max_deviation_mm, tol);
  ASSERT_EQ(program.moves.front().kind, MoveKind::Rapid);
  for (size_t i = 1; i < program.moves.size(); ++i) {
    const MachineMove& from = program.moves[i - 1];
    const MachineMove& to = program.moves[i];
    // Each piece ends on the planned segment, its pose reached by the axes.
    EXPECT_LT(distance_to_segment(to.pose.tip, path[0].pose.tip, path[1].pose.tip), 1e-9);
    EXPECT_LT((kin.forward(to.axes).tip - to.pose.tip).norm(), 1e-9);
    EXPECT_LE(dense_deviation(kin, from.axes, to.axes, from.pose.tip, to.pose.tip, 400), tol) << i;
    EXPECT_EQ(to.source, 1);
  }
  EXPECT_FALSE(program.moves.back().inserted);
  EXPECT_LT((program.moves.back().pose.tip - path[1].pose.tip).norm(), 1e-12);
}

// A planned rapid that turns a rotary axis is posted as positioning feed
// moves at the machine's rapid feed, split like a cutting move: the machine
// then follows the segment the link checks proved (within the chord
// tolerance, measured densely), where a G0 would swing the tip off it.
TEST(MachineMotion, RapidsThatTurnARotaryAreSplitPositioningMoves) {
  MachineDefinition m = test::table_table_ac();
  m.rapid.feed_mm_per_min = 12000;
  const Kinematics kin(m, 80.0);
  const double tol = 0.005;
  std::vector<PlannedMove> path(3);
  path[0].kind = MoveKind::Rapid;
  path[0].pose = test::tilted_pose(Vec3(40, 0, 5), 30 * kDeg, 0);
  path[1].kind = MoveKind::Rapid;  // C turns 60 deg: a link between rows
  path[1].pose = test::tilted_pose(Vec3(20, 35, 8), 30 * kDeg, 60 * kDeg);
  path[2].kind = MoveKind::Rapid;  // two linear axes, rotaries fixed
  path[2].pose = test::tilted_pose(Vec3(25, 40, 8), 30 * kDeg, 60 * kDeg);
  MotionOptions options;
  options.chord_tol_mm = tol;
  const MachineProgram program = plan_machine_motion(kin, path, options);
  EXPECT_EQ(program.positioning_moves, 2);
  ASSERT_EQ(program.moves.front().kind, MoveKind::Rapid);
  EXPECT_GT(program.moves.size(), 5u);  // the 60 deg turn is split
  const MachineAxes a = kin.inverse(path[0].pose, MachineAxes{});
  const MachineAxes b = kin.inverse(path[1].pose, a);
  EXPECT_GT(dense_deviation(kin, a, b, path[0].pose.tip, path[1].pose.tip), 1.0);  // as one G0: mm off
  for (size_t i = 1; i < program.moves.size(); ++i) {
    const MachineMove& from = program.moves[i - 1];
    const MachineMove& to = program.moves[i];
    EXPECT_EQ(to.kind, MoveKind::Feed) << i;
    EXPECT_TRUE(to.positioning) << i;
    EXPECT_DOUBLE_EQ(to.feed, 12000) << i;
    const PlannedMove& planned_from = path[to.source - 1];
    const PlannedMove& planned_to = path[to.source];
    EXPECT_LE(dense_deviation(kin, from.axes, to.axes, planned_from.pose.tip, planned_to.pose.tip, 400), tol) << i;
  }
  // A controller that interpolates rapids linearly keeps the linear-only one a rapid.
  MachineDefinition linear = m;
  linear.rapid.linear = true;
  const MachineProgram with_linear = plan_machine_motion(Kinematics(linear, 80.0), path, options);
  EXPECT_EQ(with_linear.positioning_moves, 1);
  EXPECT_EQ(with_linear.moves.back().kind, MoveKind::Rapid);
  EXPECT_FALSE(with_linear.moves.back().positioning);
}

// With TCP control the controller keeps the tip on the segment: measured at
// the tip alone (no tool reach given) there is nothing to split. (With a
// reach the axis' departure counts: controller_motion_test.cpp.)
TEST(MachineMotion, TcpOutputIsNotSplitAtTheTip) {
  const Kinematics kin(test::table_table_ac(), 80.0);
  std::vector<PlannedMove> path(2);
  path[0].kind = MoveKind::Rapid;
  path[0].pose = test::tilted_pose(Vec3(40, 0, 5), 30 * kDeg, 0);
  path[1].feed_mm_per_min = 1000;
  path[1].pose = test::tilted_pose(Vec3(0, 40, 5), 30 * kDeg, 90 * kDeg);
  MotionOptions options;
  options.tcp = true;
  EXPECT_EQ(plan_machine_motion(kin, path, options).moves.size(), 2u);
}

// Inverse time: F = feed / tip length of each move (1/min).
TEST(MachineMotion, InverseTimeFeedIsTheReciprocalOfTheDuration) {
  MachineDefinition m = test::table_table_ac();
  m.feed = FeedMode::InverseTime;
  const Kinematics kin(m, 80.0);
  std::vector<PlannedMove> path(3);
  path[0].kind = MoveKind::Rapid;
  path[0].pose = {Vec3(0, 0, 10), Vec3::UnitZ()};
  path[1].feed_mm_per_min = 600;
  path[1].pose = {Vec3(30, 0, 10), Vec3::UnitZ()};
  path[2].feed_mm_per_min = 600;
  path[2].pose = {Vec3(30, 40, 10), Vec3::UnitZ()};
  const MachineProgram program = plan_machine_motion(kin, path, MotionOptions{});
  ASSERT_EQ(program.moves.size(), 3u);
  EXPECT_EQ(program.feed_mode, FeedMode::InverseTime);
  EXPECT_EQ(program.moves[0].feed, 0);
  EXPECT_NEAR(program.moves[1].feed, 600.0 / 30, 1e-12);
  EXPECT_NEAR(program.moves[2].feed, 600.0 / 40, 1e-12);
}

// An unreachable pose names the move, its row and the axis.
TEST(MachineMotion, UnreachablePoseNamesTheMoveAndAxis) {
  MachineDefinition m = test::head_table_bc();
  m.rotary[0] = test::rotary("C", AxisCarrier::Part, Vec3::UnitZ(), Vec3::Zero(), -30, 30);
  const Kinematics kin(m, 50.0);
  std::vector<PlannedMove> path(3);
  const double c_deg[] = {10, 20, 45};
  for (int i = 0; i < 3; ++i) {
    path[i].feed_mm_per_min = 500;
    path[i].row = 7;
    path[i].pose = {Vec3(i, 0, 0), kin.tool_axis({c_deg[i] * kDeg, 40 * kDeg})};
  }
  try {
    plan_machine_motion(kin, path, MotionOptions{});
    FAIL() << "expected an error";
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.name(), "C");
    const std::string what = e.what();
    EXPECT_NE(what.find("move 3 (row 7)"), std::string::npos) << what;
    EXPECT_NE(what.find("outside travel"), std::string::npos) << what;
  }
}

TEST(MachineMotion, InterpolatedPoseFollowsTheGreatCircle) {
  const ToolPose a{Vec3(0, 0, 0), Vec3::UnitZ()}, b{Vec3(10, 0, 0), Vec3::UnitX()};
  const ToolPose mid = interpolate_pose(a, b, 0.5);
  EXPECT_LT((mid.tip - Vec3(5, 0, 0)).norm(), 1e-12);
  EXPECT_LT((mid.axis - Vec3(1, 0, 1).normalized()).norm(), 1e-12);
  EXPECT_THROW(interpolate_pose(a, {Vec3::Zero(), -Vec3::UnitZ()}, 0.5), ParameterError);
}

}  // namespace
}  // namespace bliskrun

namespace bliskrun {
namespace {

// Past A = +30 deg the A/C trunnion must change branch (A -> -A, C + 180).
// At a rapid move the branch is free: the planner takes the one that lasts
// the row, even when continuity with the previous row points the other way.
TEST(MachineMotion, BranchIsChosenAtTheRapidToLastTheRow) {
  const Kinematics kin(test::table_table_ac(), 80.0);
  std::vector<PlannedMove> path;
  for (int i = 0; i < 4; ++i) {
    PlannedMove m;
    m.kind = i == 0 ? MoveKind::Rapid : MoveKind::Feed;
    m.feed_mm_per_min = 500;
    const double tilt = (28 + i) * kDeg;
    m.pose = {Vec3(20, 0, 0), Vec3(0, -std::sin(tilt), std::cos(tilt))};  // A = -tilt, or +tilt with C = 180
    path.push_back(m);
  }
  MotionOptions options;
  options.start.rotary_rad = {25 * kDeg, kPi};  // continuity alone would take A = +28
  const MachineProgram program = plan_machine_motion(kin, path, options);
  EXPECT_NEAR(program.moves.front().axes.rotary_rad[0], -28 * kDeg, 1e-9);
  EXPECT_NEAR(program.moves.back().axes.rotary_rad[0], -31 * kDeg, 1e-9);
}

// A feed row through the pole from a 40 deg tilt on one side to 40 deg on the
// other needs A from -40 to +40 (or +40 to -40) on either branch: no branch
// lasts, and the move where the change would happen is refused, by name.
TEST(MachineMotion, BranchChangeInsideAFeedRowIsRefused) {
  const Kinematics kin(test::table_table_ac(), 80.0);
  std::vector<PlannedMove> path;
  for (int i = 0; i <= 16; ++i) {
    PlannedMove m;
    m.kind = i == 0 ? MoveKind::Rapid : MoveKind::Feed;
    m.feed_mm_per_min = 500;
    m.row = 4;
    const double t = (-40 + 5 * i) * kDeg;
    m.pose = {Vec3(0, 0, 0), Vec3(0, -std::sin(t), std::cos(t))};
    path.push_back(m);
  }
  try {
    plan_machine_motion(kin, path, MotionOptions{});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("(row 4)"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace bliskrun
