// The robot program's cycle-time estimate against closed forms: a straight
// path at its feed with one ramp, a step a joint slows, the home moves'
// trapezoid and a short link's triangle.
#include "core/machine/robot_cycle_time.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"

namespace bliskrun {
namespace {

RobotMove move_at(double x, int path, double feed, bool link = false, double offset = 0) {
  RobotMove m;
  m.contact.point = Vec3(x, 0, 0);
  m.contact.normal = Vec3::UnitZ();
  m.path = path;
  m.link = link;
  m.offset_mm = offset;
  m.feed_mm_s = feed;
  return m;
}

RobotCycleTimeOptions no_home() {
  RobotCycleTimeOptions o;
  o.from_home = o.to_home = false;
  return o;
}

TEST(RobotCycleTime, AStraightPathTakesItsLengthOverTheFeedPlusOneRamp) {
  RobotCell cell;  // joints at 1 rad/s, home all zero
  RobotGrindingPlan plan;
  for (int i = 0; i <= 100; ++i) plan.moves.push_back(move_at(0.5 * i, 0, 20));
  const RobotCycleTime c = estimate_robot_cycle_time(cell, plan, no_home());
  // L = 50 mm at v = 20 mm/s, a = 1000 mm/s^2: L/v + v/a.
  EXPECT_NEAR(c.grinding_s, 50.0 / 20 + 20.0 / 1000, 1e-12);
  EXPECT_NEAR(c.grinding_mm, 50.0, 1e-12);
  EXPECT_EQ(c.paths, 1);
  EXPECT_EQ(c.link_s, 0);
  EXPECT_EQ(c.joint_limited_steps, 0);
  EXPECT_DOUBLE_EQ(c.total_s, c.grinding_s);
}

TEST(RobotCycleTime, AStepAJointCannotFollowTakesTheJointsTime) {
  RobotCell cell;
  RobotGrindingPlan plan;
  for (int i = 0; i <= 10; ++i) plan.moves.push_back(move_at(1.0 * i, 0, 20));
  // Joint 4 turns 0.5 rad on the step 5 -> 6: 0.5 s at 1 rad/s against
  // 0.05 s at the feed.
  for (size_t i = 6; i < plan.moves.size(); ++i) plan.moves[i].joints[3] = 0.5;
  const RobotCycleTime c = estimate_robot_cycle_time(cell, plan, no_home());
  EXPECT_EQ(c.joint_limited_steps, 1);
  EXPECT_NEAR(c.grinding_s, 9 * (1.0 / 20) + 0.5 + 20.0 / 1000, 1e-12);
}

TEST(RobotCycleTime, HomeMovesAreTheSlowestJointsTrapezoidAndLinksRunRestToRest) {
  RobotCell cell;
  cell.home = {0, 0, 0, 0, 0, 0};
  RobotGrindingPlan plan;
  plan.moves.push_back(move_at(0, 0, 20));
  plan.moves.push_back(move_at(10, 0, 20));
  // Lift off 10 mm along the normal at 200 mm/s: a short move (v^2/a =
  // 40 mm > 10 mm) takes the triangle's 2 sqrt(L/a) = 0.2 s.
  plan.moves.push_back(move_at(10, -1, 200, true, 10));
  for (RobotMove& m : plan.moves) m.joints[0] = 1.0;  // 1 rad from home
  RobotCycleTimeOptions o;
  o.joint_accel_rad_s2 = 2;
  const RobotCycleTime c = estimate_robot_cycle_time(cell, plan, o);
  // 1 rad at 1 rad/s, 2 rad/s^2: d/v + v/a = 1.5 s, there and back.
  EXPECT_NEAR(c.home_s, 3.0, 1e-12);
  EXPECT_NEAR(c.link_s, 2 * std::sqrt(10.0 / 1000), 1e-12);
  EXPECT_NEAR(c.link_mm, 10.0, 1e-12);
  EXPECT_NEAR(c.grinding_s, 10.0 / 20 + 20.0 / 1000, 1e-12);
  EXPECT_NEAR(c.total_s, c.home_s + c.link_s + c.grinding_s, 1e-12);
}

TEST(RobotCycleTime, RefusesANonPositiveAcceleration) {
  RobotCell cell;
  RobotGrindingPlan plan;
  RobotCycleTimeOptions o;
  o.tcp_accel_mm_s2 = 0;
  EXPECT_THROW(estimate_robot_cycle_time(cell, plan, o), ParameterError);
}

}  // namespace
}  // namespace bliskrun
