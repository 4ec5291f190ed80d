#include "core/machine/kinematics.h"

#include <gtest/gtest.h>

#include <random>

#include "core/common/error.h"
#include "machine/test_machines.h"

namespace bliskrun {
namespace {

using test::angle_between;


class EveryConfiguration : public ::testing::TestWithParam<int> {
 protected:
  MachineDefinition machine() const { return test::all_machines()[GetParam()]; }
};

// FK(IK(pose)) = pose for poses the machine reaches, from a previous position
// anywhere within travel.
TEST_P(EveryConfiguration, InverseThenForwardReturnsThePose) {
  const Kinematics kin(machine(), 95.0);
  std::mt19937 rng(1234 + GetParam());
  std::uniform_real_distribution<double> coord(-150, 150);
  for (int i = 0; i < 3000; ++i) {
    MachineAxes q;
    q.rotary_rad = test::random_rotary(kin.machine(), rng);
    q.linear_mm = Vec3(coord(rng), coord(rng), coord(rng));
    const ToolPose pose = kin.forward(q);
    MachineAxes previous;
    previous.rotary_rad = test::random_rotary(kin.machine(), rng);
    const MachineAxes solved = kin.inverse(pose, previous);
    const ToolPose back = kin.forward(solved);
    ASSERT_LT((back.tip - pose.tip).norm(), 1e-9) << "pose " << i;
    ASSERT_LT(angle_between(back.axis, pose.axis), 1e-9) << "pose " << i;
    for (int r = 0; r < 2; ++r) {
      const RotaryAxis& a = kin.machine().rotary[r];
      ASSERT_GE(solved.rotary_rad[r], a.min_rad - 1e-9);
      ASSERT_LE(solved.rotary_rad[r], a.max_rad + 1e-9);
    }
  }
}

// Away from the singularity there are two rotary solutions, both giving the
// axis, and the one the pose came from is among them (mod 2 pi).
TEST_P(EveryConfiguration, BothRotarySolutionsAreFound) {
  const Kinematics kin(machine(), 60.0);
  std::mt19937 rng(99 + GetParam());
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const std::array<double, 2> r = test::random_rotary(kin.machine(), rng);
    const Vec3 k = kin.tool_axis(r);
    const Vec3 d1 = kin.machine().rotary[kin.primary_axis()].direction;
    if (d1.cross(k).norm() < 1e-3) continue;
    const auto solutions = kin.rotary_solutions(k, {0.0, 0.0});
    ASSERT_EQ(solutions.size(), 2u);
    bool found = false;
    for (const RotarySolution& s : solutions) {
      ASSERT_LT(angle_between(kin.tool_axis(s.rotary_rad), k), 1e-10);
      found |= std::abs(std::remainder(s.rotary_rad[0] - r[0], 2 * kPi)) < 1e-9 &&
               std::abs(std::remainder(s.rotary_rad[1] - r[1], 2 * kPi)) < 1e-9;
    }
    ASSERT_TRUE(found) << "pose " << i;
    ++checked;
  }
  EXPECT_GT(checked, 1500);
}

INSTANTIATE_TEST_SUITE_P(Machine, EveryConfiguration, ::testing::Range(0, 4));

// Hand computation: the part axis (0, -sin 30, cos 30) is z turned +30 deg
// about X. The table must turn the part the other way: A = -30, C = 0, or
// A = +30 with the table turned over, C = 180.
TEST(MachineKinematics, TrunnionTiltAboutXGivesA30) {
  const Kinematics kin(test::table_table_ac(), 50.0);
  const Vec3 k(0, -std::sin(30 * kDeg), std::cos(30 * kDeg));
  const auto solutions = kin.rotary_solutions(k, {0.0, 0.0});
  ASSERT_EQ(solutions.size(), 2u);
  bool minus = false, plus = false;
  for (const RotarySolution& s : solutions) {
    const double a = s.rotary_rad[0] / kDeg, c = s.rotary_rad[1] / kDeg;
    if (std::abs(a + 30) < 1e-9 && std::abs(c) < 1e-9) minus = true;
    if (std::abs(a - 30) < 1e-9 && std::abs(std::abs(c) - 180) < 1e-9) plus = true;
  }
  EXPECT_TRUE(minus);
  EXPECT_TRUE(plus);
  // With no previous motion the smaller total rotation wins.
  const MachineAxes q = kin.inverse({Vec3(10, 0, 0), k}, MachineAxes{});
  EXPECT_NEAR(q.rotary_rad[0] / kDeg, -30, 1e-9);
  EXPECT_NEAR(q.rotary_rad[1] / kDeg, 0, 1e-9);
}

// Head-table: the B head tilts the spindle towards +X for B = +30.
TEST(MachineKinematics, HeadTiltAboutYGivesB30) {
  const Kinematics kin(test::head_table_bc(), 50.0);
  const Vec3 k(std::sin(30 * kDeg), 0, std::cos(30 * kDeg));
  const MachineAxes q = kin.inverse({Vec3(0, 0, 0), k}, MachineAxes{});
  EXPECT_NEAR(q.rotary_rad[1] / kDeg, 30, 1e-9);
  EXPECT_NEAR(q.rotary_rad[0] / kDeg, 0, 1e-9);
  // Tip at the part origin (15 mm above the table centre), head pivot 180 mm
  // above the gauge point, tool 50 mm: the tip swings on a 230 mm radius to
  // -X and up, so X brings it back by +230 sin 30 and Z down by
  // 230 (1 - cos 30).
  EXPECT_NEAR(q.linear_mm.x(), 230 * std::sin(30 * kDeg), 1e-9);
  EXPECT_NEAR(q.linear_mm.y(), 0, 1e-9);
  EXPECT_NEAR(q.linear_mm.z(), 15 - 230 * (1 - std::cos(30 * kDeg)), 1e-9);
}

// Turning the tool axis round the C axis at a fixed tilt: C winds on past
// +-180 deg without jumps, two whole turns.
TEST(MachineKinematics, PrimaryAxisUnwrapsAcrossHalfTurns) {
  const Kinematics kin(test::table_table_ac(), 50.0);
  MachineAxes q;
  const int steps = 720;
  const double first_c = kin.inverse({Vec3(5, 5, 0), Vec3(0, -std::sin(0.5), std::cos(0.5))}, q).rotary_rad[1];
  for (int i = 0; i <= steps; ++i) {
    const double phi = -kPi / 2 + 4 * kPi * i / steps;
    const Vec3 k(std::sin(0.5) * std::cos(phi), std::sin(0.5) * std::sin(phi), std::cos(0.5));
    const MachineAxes next = kin.inverse({Vec3(5, 5, 0), k}, q);
    if (i > 0) ASSERT_LT(std::abs(next.rotary_rad[1] - q.rotary_rad[1]), 4 * kPi / steps + 1e-9) << i;
    q = next;
  }
  EXPECT_NEAR(std::abs(q.rotary_rad[1] - first_c), 4 * kPi, 1e-9);
  EXPECT_NEAR(q.rotary_rad[0], -0.5, 1e-9);
}

// At the pole (tool axis along C) C is free: it keeps its previous value.
// Passing straight through the pole, A changes sign and C does not flip.
TEST(MachineKinematics, SingularityKeepsThePreviousPrimaryAngle) {
  const Kinematics kin(test::table_table_ac(), 50.0);
  MachineAxes previous;
  previous.rotary_rad = {-0.2, 1.234};
  const MachineAxes at_pole = kin.inverse({Vec3(1, 2, 3), Vec3::UnitZ()}, previous);
  EXPECT_EQ(at_pole.rotary_rad[1], 1.234);
  EXPECT_NEAR(at_pole.rotary_rad[0], 0, 1e-12);
  EXPECT_LT((kin.forward(at_pole).tip - Vec3(1, 2, 3)).norm(), 1e-9);

  // Great circle through the pole in the plane the tilt is in at C = 0.
  MachineAxes q;
  double last_a = -1;
  for (int i = 0; i <= 40; ++i) {
    const double t = (20 - i) * kDeg;
    const MachineAxes next = kin.inverse({Vec3(4, 0, 0), Vec3(0, -std::sin(t), std::cos(t))}, q);
    EXPECT_NEAR(next.rotary_rad[1], 0, 1e-12) << i;
    EXPECT_NEAR(next.rotary_rad[0], -t, 1e-12) << i;
    EXPECT_GT(next.rotary_rad[0], last_a);
    last_a = next.rotary_rad[0];
    q = next;
  }
}

// Travel decides before continuity: the A/C trunnion's A stops at +30 deg, so
// a 60 deg tilt must be A = -60 even coming from A = +25, C = 180.
TEST(MachineKinematics, TravelLimitsChooseTheBranch) {
  const Kinematics kin(test::table_table_ac(), 50.0);
  MachineAxes previous;
  previous.rotary_rad = {25 * kDeg, kPi};
  const Vec3 k(0, std::sin(60 * kDeg), std::cos(60 * kDeg));
  const MachineAxes q = kin.inverse({Vec3::Zero(), k}, previous);
  EXPECT_NEAR(q.rotary_rad[0] / kDeg, -60, 1e-9);
  EXPECT_NEAR(std::remainder(q.rotary_rad[1] - kPi, 2 * kPi), 0, 1e-9);
  EXPECT_NEAR(q.rotary_rad[1], kPi, 1e-9);  // unwrapped next to the previous C
}

// The blisk paper's machine (§2.2): C in [-30, +30] deg turns the tool
// direction. An axis that needs C = 20 deg is reachable, one that needs 45 is
// not, and solving it is an error naming C.
TEST(MachineKinematics, RotaryTravelAnswersReachability) {
  MachineDefinition m = test::head_table_bc();
  m.rotary[0] = test::rotary("C", AxisCarrier::Part, Vec3::UnitZ(), Vec3::Zero(), -30, 30);
  const Kinematics kin(m, 50.0);
  auto axis_for = [&](double c_deg) { return kin.tool_axis({c_deg * kDeg, 40 * kDeg}); };
  EXPECT_TRUE(kin.reachable(axis_for(20)));
  EXPECT_TRUE(kin.reachable(axis_for(-29.9)));
  EXPECT_FALSE(kin.reachable(axis_for(45)));
  EXPECT_FALSE(kin.reachable(axis_for(-100)));
  try {
    kin.inverse({Vec3::Zero(), axis_for(45)}, MachineAxes{});
    FAIL() << "expected an error";
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.name(), "C");
    EXPECT_NE(std::string(e.what()).find("outside travel"), std::string::npos) << e.what();
  }
}

TEST(MachineKinematics, LinearTravelIsChecked) {
  MachineDefinition m = test::table_table_ac();
  m.linear[0].max_mm = 100;
  const Kinematics kin(m, 50.0);
  EXPECT_NO_THROW(kin.inverse({Vec3(90, 0, 0), Vec3::UnitZ()}, MachineAxes{}));
  try {
    kin.inverse({Vec3(120, 0, 0), Vec3::UnitZ()}, MachineAxes{});
    FAIL() << "expected an error";
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.name(), "X");
  }
}

TEST(MachineKinematics, InvalidDefinitionsAreRefused) {
  MachineDefinition parallel = test::table_table_ac();
  parallel.rotary[1].direction = Vec3::UnitX();
  EXPECT_THROW(Kinematics(parallel, 10), ParameterError);
  MachineDefinition spins = test::head_table_bc();
  spins.rotary[1].direction = Vec3::UnitZ();  // the head axis along the spindle
  spins.rotary[0].direction = Vec3::UnitX();
  EXPECT_THROW(Kinematics(spins, 10), ParameterError);
  MachineDefinition same = test::table_table_ac();
  same.rotary[1].name = "A";
  EXPECT_THROW(Kinematics(same, 10), ParameterError);
  MachineDefinition one = test::table_table_ac();
  one.rotary.pop_back();
  EXPECT_THROW(Kinematics(one, 10), ParameterError);
  MachineDefinition bad_unit = test::table_table_ac();
  bad_unit.spindle = Vec3(0, 0, 2);
  EXPECT_THROW(Kinematics(bad_unit, 10), ParameterError);
  EXPECT_THROW(Kinematics(test::table_table_ac(), -1), ParameterError);
}

TEST(MachineKinematics, LeverArmIsTheDistanceToTheFarthestAxis) {
  const Kinematics kin(test::table_table_ac(), 50.0);
  MachineAxes q;
  q.linear_mm = Vec3(30, 3, 0);  // tip at x = 30 on the C line's y, z = 0
  // A axis: line y = 0, z = -80 -> distance hypot(3, 80); C axis: x = 0,
  // y = 3 -> distance 30.
  EXPECT_NEAR(kin.lever_arm_mm(q), std::hypot(3.0, 80.0), 1e-12);
}

}  // namespace
}  // namespace bliskrun
