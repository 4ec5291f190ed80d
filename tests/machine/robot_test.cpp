#include "core/machine/robot.h"

#include <gtest/gtest.h>

#include <random>

#include "core/common/error.h"

namespace bliskrun {
namespace {

// An arm with every OPW length non-zero (a sideways offset b and a wrist
// offset a2 included), so each term of the closed forms is exercised.
RobotArm test_arm() {
  RobotArm arm;
  arm.name = "test";
  arm.geometry = {.a1_mm = 350, .a2_mm = -41, .b_mm = 30, .c1_mm = 675, .c2_mm = 1150, .c3_mm = 1200, .c4_mm = 215};
  const double lim[6] = {185, 140, 120, 350, 125, 350};
  for (int i = 0; i < 6; ++i) {
    arm.joints[i].min_rad = -deg_to_rad(lim[i]);
    arm.joints[i].max_rad = deg_to_rad(lim[i]);
    arm.joints[i].max_speed_rad_s = deg_to_rad(100);
  }
  // A controller convention unlike OPW's: axis 3 zero with the forearm
  // level, axes 1 and 4 counting the other way.
  arm.joints[2].zero_rad = kPi / 2;
  arm.joints[0].sign = -1;
  arm.joints[3].sign = -1;
  return arm;
}

double frame_distance(const Frame& a, const Frame& b) {
  const double rot = Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
  return (a.translation() - b.translation()).norm() + 1000 * rot;  // 1 mrad ~ 1 µm at 1 m
}

TEST(Robot, StraightUpArmIsTheSumOfItsLengths) {
  RobotArm arm = test_arm();
  // OPW zero: the controller's joint 3 is at -90° (its zero is the forearm level).
  const JointAngles q = {0, 0, -kPi / 2, 0, 0, 0};
  const Frame f = robot_forward(arm, q);
  const OpwGeometry& g = arm.geometry;
  EXPECT_NEAR((f.translation() - Vec3(g.a1_mm + g.a2_mm, g.b_mm, g.c1_mm + g.c2_mm + g.c3_mm + g.c4_mm)).norm(), 0,
              1e-9);
  EXPECT_NEAR((f.linear() - Mat3::Identity()).norm(), 0, 1e-12);
}

TEST(Robot, ForearmLevelReachesForwardByTheForearmAndWrist) {
  // Controller zero of this arm: upper arm up, forearm level forward, flange
  // facing +X: the wrist centre is c3 ahead of axis 3 (a2 below it), the
  // flange c4 further along +X.
  RobotArm arm = test_arm();
  const Frame f = robot_forward(arm, JointAngles{0, 0, 0, 0, 0, 0});
  const OpwGeometry& g = arm.geometry;
  EXPECT_NEAR((f.translation() - Vec3(g.a1_mm + g.c3_mm + g.c4_mm, g.b_mm, g.c1_mm + g.c2_mm - g.a2_mm)).norm(), 0,
              1e-9);
  EXPECT_NEAR((f.linear().col(2) - Vec3::UnitX()).norm(), 0, 1e-12);
  // Axis 1 turns the whole arm about Z; the controller counts it negative.
  const Frame turned = robot_forward(arm, JointAngles{-kPi / 2, 0, 0, 0, 0, 0});
  EXPECT_NEAR((turned.translation() - Vec3(-g.b_mm, g.a1_mm + g.c3_mm + g.c4_mm, g.c1_mm + g.c2_mm - g.a2_mm)).norm(),
              0, 1e-9);
}

TEST(Robot, EveryInverseSolutionReachesThePoseAndOneIsTheOriginalJoints) {
  // Brute force over the whole joint space: random joints (away from the
  // wrist singularity), FK, IK: all 8 solutions must give the same flange,
  // and one of them must be the joints we started from.
  RobotArm arm = test_arm();
  std::mt19937 rng(7);
  int checked = 0;
  for (int n = 0; n < 5000; ++n) {
    JointAngles q;
    for (int i = 0; i < 6; ++i)
      q[i] = std::uniform_real_distribution<double>(arm.joints[i].min_rad, arm.joints[i].max_rad)(rng);
    if (std::abs(std::sin(arm.joints[4].zero_rad + q[4])) < 1e-2) continue;
    const Frame target = robot_forward(arm, q);
    RobotIkOptions options;
    options.previous = q;
    const auto solutions = robot_inverse(arm, target, options);
    // 8 where the arm reaches the wrist centre leaning back over axis 1 too,
    // 4 where only the front branches reach it.
    ASSERT_TRUE(solutions.size() == 8u || solutions.size() == 4u) << "sample " << n << ": " << solutions.size();
    bool found = false;
    for (const RobotSolution& s : solutions) {
      ASSERT_LT(frame_distance(robot_forward(arm, s.joints), target), 1e-7) << "sample " << n << " branch " << s.branch;
      double diff = 0;
      for (int i = 0; i < 6; ++i) diff = std::max(diff, std::abs(s.joints[i] - q[i]));
      found = found || diff < 1e-7;
    }
    EXPECT_TRUE(found) << "sample " << n;
    ++checked;
  }
  EXPECT_GT(checked, 4800);
}

TEST(Robot, AtTheWristSingularityAxisFourStaysAndSixTakesTheRotation) {
  RobotArm arm = test_arm();
  // θ5 = 0 (OPW): axes 4 and 6 in line.
  const JointAngles q = {0.3, 0.2, -0.4, 0.7, 0.0, -0.5};
  const Frame target = robot_forward(arm, q);
  RobotIkOptions options;
  options.previous = JointAngles{0.3, 0.2, -0.4, 1.1, 0.0, 0.0};  // axis 4 was at 1.1 rad
  const auto solutions = robot_inverse(arm, target, options);
  ASSERT_FALSE(solutions.empty());
  const auto chosen = robot_choose(arm, solutions, *options.previous, 0);
  ASSERT_TRUE(chosen);
  EXPECT_TRUE(chosen->wrist_singular);
  EXPECT_NEAR(chosen->joints[3], 1.1, 1e-12);  // kept
  EXPECT_LT(frame_distance(robot_forward(arm, chosen->joints), target), 1e-7);
  // θ4 + θ6 is what the pose fixes. Axis 4 counts backwards on this arm,
  // so θ6 = (θ4 + θ6) - θ4 = (-0.7 - 0.5) - (-1.1).
  EXPECT_NEAR(chosen->joints[5], -0.1, 1e-9);
}

TEST(Robot, APathKeepsItsBranchAndMovesLittleBetweenPoses) {
  // A straight line of flange poses across the front of the arm, orientation
  // turning slowly: the chosen solution keeps its branch and no joint jumps.
  RobotArm arm = test_arm();
  JointAngles previous = {0.1, 0.3, -0.2, 0.2, 0.6, 0.1};
  const Frame start = robot_forward(arm, previous);
  int branch = -1;
  for (int k = 0; k <= 200; ++k) {
    Frame target = start;
    target.translation() += Vec3(0, -600.0 * k / 200, -200.0 * k / 200);
    target.linear() = Eigen::AngleAxisd(0.4 * k / 200, Vec3::UnitZ()).toRotationMatrix() * start.linear();
    RobotIkOptions options;
    options.previous = previous;
    const auto chosen = robot_choose(arm, robot_inverse(arm, target, options), previous, branch);
    ASSERT_TRUE(chosen) << k;
    if (branch >= 0) EXPECT_EQ(chosen->branch, branch) << k;
    for (int i = 0; i < 6; ++i) EXPECT_LT(std::abs(chosen->joints[i] - previous[i]), 0.05) << k << " joint " << i;
    previous = chosen->joints;
    branch = chosen->branch;
  }
}

TEST(Robot, APoseBeyondReachHasNoSolutionAndLimitsAreMarked) {
  RobotArm arm = test_arm();
  Frame far = Frame::Identity();
  far.translation() = Vec3(5000, 0, 1000);
  EXPECT_TRUE(robot_inverse(arm, far).empty());
  // A pose behind the arm needs axis 1 beyond ±185° on the front branches.
  arm.joints[0].min_rad = -deg_to_rad(90);
  arm.joints[0].max_rad = deg_to_rad(90);
  const Frame behind = robot_forward(arm, JointAngles{0, 0, 0, 0, 0.5, 0});
  Frame target = behind;
  target.translation() = Eigen::AngleAxisd(kPi, Vec3::UnitZ()) * behind.translation();
  target.linear() = Eigen::AngleAxisd(kPi, Vec3::UnitZ()).toRotationMatrix() * behind.linear();
  int outside = 0;
  for (const RobotSolution& s : robot_inverse(arm, target))
    if (!s.within_limits) {
      ++outside;
      EXPECT_GE(s.violated_joint, 0);
    }
  EXPECT_GT(outside, 0);
}

TEST(Robot, ArmValidationNamesTheField) {
  RobotArm arm = test_arm();
  arm.geometry.c2_mm = 0;
  try {
    arm.validate();
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("c2"), std::string::npos);
  }
  arm = test_arm();
  arm.joints[4].sign = 2;
  EXPECT_THROW(arm.validate(), ParameterError);
  arm = test_arm();
  EXPECT_NO_THROW(arm.validate());
}

}  // namespace
}  // namespace bliskrun
