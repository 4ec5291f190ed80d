#include "core/machine/robot_cell.h"

#include <gtest/gtest.h>

#include "core/common/error.h"
#include "core/machine/wheel_clearance.h"

#include <cstdio>

namespace bliskrun {
namespace {

// A KR 120-class arm, one wheel 1.7 m in front of it at table height, its
// normal facing the robot and its axis horizontal; the blade held 150 mm out
// along the flange's z axis.
RobotCell reach_cell() {
  RobotCell cell;
  cell.name = "test cell";
  RobotArm& arm = cell.arm;
  arm.geometry = {.a1_mm = 350, .a2_mm = -41, .b_mm = 0, .c1_mm = 675, .c2_mm = 1150, .c3_mm = 1200, .c4_mm = 215};
  const double lo[6] = {-185, -140, -120, -350, -125, -350}, hi[6] = {185, -5, 168, 350, 125, 350};
  for (int i = 0; i < 6; ++i) {
    arm.joints[i].min_rad = deg_to_rad(lo[i]);
    arm.joints[i].max_rad = deg_to_rad(hi[i]);
    arm.joints[i].max_speed_rad_s = deg_to_rad(120);
  }
  arm.joints[1].zero_rad = kPi / 2;  // KUKA: A2 = -90 deg stands the upper arm up
  for (int i : {0, 3, 5}) arm.joints[i].sign = -1;
  cell.home = {0, deg_to_rad(-90), deg_to_rad(90), 0, deg_to_rad(30), 0};
  cell.grip.translation() = Vec3(0, 0, 150);
  BeltStation s;
  s.name = "fine";
  s.contact.linear().col(0) = Vec3(0, 1, 0);   // wheel axis
  s.contact.linear().col(1) = Vec3(0, 0, -1);  // normal x axis: right-handed
  s.contact.linear().col(2) = Vec3(-1, 0, 0);  // outward normal, towards the robot
  s.contact.translation() = Vec3(1700, 0, 900);
  s.wheel_radius_mm = 20;
  s.wheel_width_mm = 10;
  cell.stations.push_back(s);
  cell.validate();
  return cell;
}

// A row of contacts on a flat 60 mm strip of the blade, normal +Y (blade frame).
std::vector<BladeContact> strip(double z) {
  std::vector<BladeContact> path;
  for (int i = 0; i <= 30; ++i) path.push_back({Vec3(-30 + 2.0 * i, 0, z), Vec3(0, 1, 0), Vec3(1, 0, 0)});
  return path;
}

TEST(RobotCell, TheContactLiesOnTheWheelWithItsNormalIntoIt) {
  const RobotCell cell = reach_cell();
  const BeltStation& st = cell.station("fine");
  const BladeContact c{Vec3(12, -3, 40), Vec3(0.3, 1, 0.1).normalized(), Vec3(1, -0.3, 0).normalized()};
  for (bool turned : {false, true}) {
    const BladeContact at = contact_in_base(cell, flange_for_contact(cell, st, c, turned), c);
    EXPECT_NEAR((at.point - st.contact.translation()).norm(), 0, 1e-9);
    EXPECT_NEAR(at.normal.dot(st.contact.linear().col(2)), -1, 1e-12);            // into the wheel
    const Vec3 t = (at.tangent - at.tangent.dot(at.normal) * at.normal).normalized();
    EXPECT_NEAR(t.dot(st.contact.linear().col(0)), turned ? -1 : 1, 1e-12);       // along the wheel axis
  }
  EXPECT_THROW(cell.station("coarse"), ParameterError);
}

TEST(RobotCell, EveryGrindingMovePutsItsContactOnTheWheelThroughTheArmsKinematics) {
  const RobotCell cell = reach_cell();
  const BeltStation& st = cell.station("fine");
  RobotGrindingOptions o;
  o.start = cell.home;
  const RobotGrindingPlan plan = plan_robot_grinding(cell, st, {strip(20), strip(21), strip(22)}, o);
  ASSERT_TRUE(plan.refusals.empty()) << plan.refusals.front();
  EXPECT_EQ(plan.paths, 3);
  // Per path: approach, 31 points, lift-off; between paths the traverse
  // back along the last path every 10 mm (points 25, 20, ..., 0 of 0..30).
  ASSERT_EQ(plan.moves.size(), 3u * (31 + 2) + 2u * 6);
  EXPECT_EQ(plan.branch_changes, 0);
  for (const RobotMove& m : plan.moves) {
    // Forward kinematics of the planned joints, then the blade's contact:
    // on the wheel for grinding moves, `retract` off it along the normal on
    // the lift-offs and approaches.
    const BladeContact at = contact_in_base(cell, robot_forward(cell.arm, m.joints), m.contact);
    const Vec3 off = at.point - st.contact.translation();
    EXPECT_NEAR(off.norm(), m.link ? o.retract_mm : 0, 1e-6);
    if (m.link) EXPECT_NEAR(off.normalized().dot(st.contact.linear().col(2)), 1, 1e-9);
    for (int j = 0; j < 6; ++j) {
      EXPECT_GE(m.joints[j], cell.arm.joints[j].min_rad);
      EXPECT_LE(m.joints[j], cell.arm.joints[j].max_rad);
    }
  }
  // 2 mm steps at 20 mm/s on a flat strip: the arm moves slowly.
  EXPECT_LT(plan.max_joint_speed_ratio, 1.0);
}

TEST(RobotCell, AStationOutOfReachRefusesThePathsAndEmitsNothing) {
  RobotCell cell = reach_cell();
  cell.stations[0].contact.translation() = Vec3(4000, 0, 900);  // beyond 2.7 m
  RobotGrindingOptions o;
  o.start = cell.home;
  const RobotGrindingPlan plan = plan_robot_grinding(cell, cell.stations[0], {strip(20)}, o);
  EXPECT_TRUE(plan.moves.empty());
  ASSERT_EQ(plan.refusals.size(), 1u);
  EXPECT_NE(plan.refusals[0].find("out of the arm's reach"), std::string::npos) << plan.refusals[0];
}

// The strip's face, blade frame: the plane y = 0 (normal +y), x in
// [-40, 40], z in [0, 40]; and optionally a wall across it at z = 30
// standing 30 mm towards the wheel (a root platform beside the paths).
class CellPlane : public Surface {
 public:
  CellPlane(Vec3 o, Vec3 a, Vec3 b) : o_(o), a_(a), b_(b) {}
  SurfaceDerivs eval(double u, double v) const override {
    SurfaceDerivs d;
    d.p = o_ + u * a_ + v * b_;
    d.pu = a_;
    d.pv = b_;
    return d;
  }

 private:
  Vec3 o_, a_, b_;
};

BladeBody strip_body(bool wall) {
  std::vector<std::pair<std::string, std::shared_ptr<const Surface>>> faces{
      {"flank", std::make_shared<CellPlane>(Vec3(-40, 0, 0), Vec3(80, 0, 0), Vec3(0, 0, 40))}};
  if (wall) faces.push_back({"platform", std::make_shared<CellPlane>(Vec3(-40, 0, 30), Vec3(80, 0, 0), Vec3(0, 30, 0))});
  return BladeBody::sample(faces, 0.5);
}

TEST(RobotCell, TheWheelAndBeltAreCheckedAgainstTheWholeBladeOnEveryMoveAndBetween) {
  const RobotCell cell = reach_cell();
  RobotGrindingOptions o;
  o.start = cell.home;
  const BladeBody clear = strip_body(false);
  o.blade = &clear;
  const RobotGrindingPlan plan = plan_robot_grinding(cell, cell.stations[0], {strip(20), strip(21), strip(22)}, o);
  ASSERT_TRUE(plan.refusals.empty()) << plan.refusals.front();
  EXPECT_TRUE(plan.wheel.checked);
  // Every move and the motion between them: 2 mm steps and the 10 mm
  // lift-offs sampled at 1 mm, so more poses than moves.
  EXPECT_GT(plan.wheel.poses, static_cast<long>(plan.moves.size()) + 3 * 2 * 9);
  EXPECT_EQ(plan.wheel.collisions, 0);
  EXPECT_LT(plan.wheel.max_conformity_mm, 1e-6);  // a flat face: line contact

  // A platform 8-10 mm beside the paths: the wheel (r = 20) reaches it, and
  // turned the part is beyond axis 5, so every path is refused, each naming
  // the face, and nothing is emitted.
  const BladeBody walled = strip_body(true);
  o.blade = &walled;
  const RobotGrindingPlan refused = plan_robot_grinding(cell, cell.stations[0], {strip(20), strip(21), strip(22)}, o);
  EXPECT_TRUE(refused.moves.empty());
  ASSERT_EQ(refused.refusals.size(), 3u);
  for (const std::string& why : refused.refusals) {
    EXPECT_NE(why.find("as is: at the first approach: platform face point"), std::string::npos) << why;
    EXPECT_NE(why.find("turned: joint 5"), std::string::npos) << why;
  }
  // The depth is the least way out of the wheel: 10 mm radially for the
  // platform's edge on path 1 (z = 20, the wheel's centre 20 mm off the
  // face), 5 mm sideways (half the width) — less the samples' offset from
  // the wheel's mid-plane.
  EXPECT_NEAR(refused.wheel.max_collision_depth_mm, 5, 0.5);
}

// The program's first motion is a joint move from home to the first
// approach, and its last one back home; they are checked too. In this cell
// the direct joint move from home clips the belt behind the wheel (0.07 mm,
// found by the check): the plan reaches a staging pose further out along
// the first contact's normal and links in straight, and leaves the same
// way. Home 15 mm into the wheel: no staging pose helps, both ends are
// refused, named, and nothing of the plan may be posted.
TEST(RobotCell, TheJointMovesFromAndBackToHomeAreCheckedAgainstTheWheel) {
  const RobotCell cell = reach_cell();
  const BeltStation& st = cell.stations[0];
  const BladeBody body = strip_body(false);
  RobotGrindingOptions o;
  o.blade = &body;
  o.start = cell.home;
  const RobotGrindingPlan clear = plan_robot_grinding(cell, st, {strip(20)}, o);
  ASSERT_TRUE(clear.refusals.empty()) << clear.refusals.front();
  // Staged at both ends: a link move more than the lift-off out along the
  // normal, first and last, clear of the wheel.
  ASSERT_GE(clear.moves.size(), 3u);
  for (const RobotMove* m : {&clear.moves.front(), &clear.moves.back()}) {
    EXPECT_TRUE(m->link);
    EXPECT_GE(m->offset_mm, 50.0 + 10.0 - 1e-9);
  }
  EXPECT_EQ(clear.wheel.collisions, 0);
  // A point 15 mm under the face (against its normal) put on the wheel's
  // surface: the face is 15 mm into the wheel.
  const BladeContact inside{Vec3(0, -15, 20), Vec3(0, 1, 0), Vec3(1, 0, 0)};
  const auto solution = robot_choose(cell.arm, robot_inverse(cell.arm, flange_for_contact(cell, st, inside, false)),
                                     cell.home);
  ASSERT_TRUE(solution.has_value());
  o.start = solution->joints;
  const RobotGrindingPlan plan = plan_robot_grinding(cell, st, {strip(20)}, o);
  ASSERT_EQ(plan.refusals.size(), 2u);
  EXPECT_NE(plan.refusals[0].find("the joint move from home to the first approach: the blade meets the wheel"),
            std::string::npos) << plan.refusals[0];
  EXPECT_NE(plan.refusals[0].find("no staging pose up to 400 mm"), std::string::npos) << plan.refusals[0];
  EXPECT_NE(plan.refusals[1].find("the joint move from the last lift-off back home"), std::string::npos)
      << plan.refusals[1];
  EXPECT_NEAR(plan.wheel.max_collision_depth_mm, 5, 0.6);  // sideways out of the 10 mm wide wheel
}

}  // namespace
}  // namespace bliskrun
