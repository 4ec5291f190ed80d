// Robot programs read back by the controllers' own rules (issue 39): status
// and configuration bits against hand-worked poses, the frames' roles of an
// external TCP, and programs written here from the manuals' grammar —
// independent of the Lua posts — that the read-back must pass or fail.
#include "core/machine/robot_program.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/common/error.h"

namespace bliskrun {
namespace {

// KUKA KR 120 R2700-2 (scripts/machines/kuka_kr120_belt_cell.lua): ψ3 =
// atan2(-115, 1220) = -5.385°, so the wrist root point is on the A2-A3 line
// at A3 = φ = +5.385°.
RobotArm kuka_arm() {
  RobotArm arm;
  arm.geometry = {.a1_mm = 330, .a2_mm = -115, .b_mm = 0, .c1_mm = 645, .c2_mm = 1150, .c3_mm = 1220, .c4_mm = 215};
  const double lo[6] = {-185, -140, -120, -350, -125, -350}, hi[6] = {185, -5, 168, 350, 125, 350};
  for (int i = 0; i < 6; ++i) {
    arm.joints[i].min_rad = deg_to_rad(lo[i]);
    arm.joints[i].max_rad = deg_to_rad(hi[i]);
    arm.joints[i].max_speed_rad_s = deg_to_rad(120);
  }
  arm.joints[1].zero_rad = kPi / 2;  // A2 = -90° stands the upper arm up
  for (int i : {0, 3, 5}) arm.joints[i].sign = -1;
  return arm;
}

// ABB IRB 6650S-125/3.5: ψ3 = atan2(-200, 1592) = -7.160°; axis 3 zero with
// the forearm level (θ3 = 90° + q3).
RobotArm abb_arm() {
  RobotArm arm;
  arm.geometry = {.a1_mm = 600, .a2_mm = -200, .b_mm = 0, .c1_mm = 630, .c2_mm = 1280, .c3_mm = 1592, .c4_mm = 200};
  const double lo[6] = {-180, -40, -180, -300, -120, -360}, hi[6] = {180, 160, 70, 300, 120, 360};
  for (int i = 0; i < 6; ++i) {
    arm.joints[i].min_rad = deg_to_rad(lo[i]);
    arm.joints[i].max_rad = deg_to_rad(hi[i]);
    arm.joints[i].max_speed_rad_s = deg_to_rad(120);
  }
  arm.joints[2].zero_rad = kPi / 2;
  return arm;
}

JointAngles deg(double a, double b, double c, double d, double e, double f) {
  return {deg_to_rad(a), deg_to_rad(b), deg_to_rad(c), deg_to_rad(d), deg_to_rad(e), deg_to_rad(f)};
}

TEST(KukaStatus, EachBitAgainstHandWorkedPoses) {
  const RobotArm arm = kuka_arm();
  // Home {0, -90, 90, 0, 30, 0}: wrist root point x = a1 + c3 = 1550 mm > 0
  // (basic area), A3 = 90° >= φ, A5 > 0: S = 'B010' = 2; only A2 < 0: T = 2.
  EXPECT_EQ(kuka_status(arm, deg(0, -90, 90, 0, 30, 0)), 2);
  EXPECT_EQ(kuka_turn_bits(deg(0, -90, 90, 0, 30, 0)), 2);
  // Leaning back, forearm in line: A2 = -140 (θ2 = -50°), A3 = 0: x = 330 -
  // 1150 sin 50° + 1225.4 sin(-55.385°) = -1559 mm < 0 (overhead, bit 0);
  // A3 = 0 < φ (bit 1 clear); A5 = -30 (bit 2). S = 5; T: A2, A4, A5 < 0 =
  // 2 + 8 + 16 = 26.
  EXPECT_EQ(kuka_status(arm, deg(10, -140, 0, -20, -30, 5)), 5);
  EXPECT_EQ(kuka_turn_bits(deg(10, -140, 0, -20, -30, 5)), 26);
  // The offset between A3 and A4 moves bit 1's switch to φ = 5.385°, not 0.
  EXPECT_EQ(kuka_status(arm, deg(0, -90, 5.3, 0, 30, 0)) & 2, 0);
  EXPECT_EQ(kuka_status(arm, deg(0, -90, 5.5, 0, 30, 0)) & 2, 2);
  // Bit 2: 0 for 0° <= A5 < 180°, 1 for -180° <= A5 < 0°.
  EXPECT_EQ(kuka_status(arm, deg(0, -90, 90, 0, 0, 0)) & 4, 0);
  EXPECT_EQ(kuka_status(arm, deg(0, -90, 90, 0, -0.001, 0)) & 4, 4);
  // Bit 0 turns with A1: the same arm pose at A1 = 120° stays in the basic area.
  EXPECT_EQ(kuka_status(arm, deg(120, -90, 90, 0, 30, 0)) & 1, 0);
  // T: bit i for axis i+1 < 0, all six.
  EXPECT_EQ(kuka_turn_bits(deg(-1, -1, -1, -1, -1, -1)), 63);
}

TEST(AbbConfiguration, CfxAndQuadrantsAgainstHandWorkedPoses) {
  const RobotArm arm = abb_arm();
  // Home: forearm level ahead of the upright lower arm, axis 5 positive.
  EXPECT_EQ(abb_cfx(arm, deg(0, 0, 0, 0, 30, 0)), 0);
  // q3 = -100: θ3 + ψ3 = -10° - 7.16° < 0, wrist centre behind the lower arm (+2);
  // q2 = -40: x = 600 - 1280 sin 40° + 1604.5 sin(-57.16°) = -1571 mm, behind axis 1 (+4);
  // q5 < 0 (+1).
  EXPECT_EQ(abb_cfx(arm, deg(0, -40, -100, 0, -30, 0)), 7);
  EXPECT_EQ(abb_cfx(arm, deg(0, 0, -100, 0, 30, 0)), 2);
  // The switch of +2 at θ3 + ψ3 = 0: q3 = -90 + 7.16 = -82.84°.
  EXPECT_EQ(abb_cfx(arm, deg(0, 0, -82.7, 0, 30, 0)) & 2, 0);
  EXPECT_EQ(abb_cfx(arm, deg(0, 0, -83.0, 0, 30, 0)) & 2, 2);
  // Quadrants: floor(angle / 90°) of axes 1, 4, 6.
  const auto q = abb_quadrants(deg(-10, 0, 0, 185, 0, -270));
  EXPECT_EQ(q[0], -1);
  EXPECT_EQ(q[1], 2);
  EXPECT_EQ(q[2], -3);
}

// Brute force: every inverse-kinematics branch's status, by the definition,
// is the branch the solver built it on (shoulder behind -> bit 0, elbow
// "down" (forearm turned back off the upper arm) -> bit 1 clear, wrist flip
// -> A5 negative) — on both arms, over many poses.
TEST(KukaStatus, EveryBranchOfTheInverseHasTheStatusOfItsGeometry) {
  for (const RobotArm& arm : {kuka_arm(), abb_arm()}) {
    int checked = 0;
    for (int i = 0; i < 60; ++i) {
      const JointAngles q = deg(-150 + 5 * i, -100 + 1.5 * i, -60 + 3 * i, -170 + 6 * i, -100 + 3.3 * i, 40 - i);
      for (const RobotSolution& s : robot_inverse(arm, robot_forward(arm, q))) {
        if (s.wrist_singular) continue;
        const bool shoulder = s.branch & 4, elbow_down = s.branch & 2, flip = s.branch & 1;
        if (arm.joints[1].zero_rad != 0) {  // the KUKA arm (A2 zero at -90°)
          EXPECT_EQ(kuka_status(arm, s.joints), (shoulder ? 1 : 0) | (elbow_down ? 0 : 2) | (flip ? 4 : 0));
        } else {
          EXPECT_EQ(abb_cfx(arm, s.joints), s.branch);
        }
        ++checked;
      }
    }
    EXPECT_GT(checked, 200);
  }
}

// A cell with the KR 120 R2700-2 and one wheel 1.7 m ahead at 900 mm.
RobotCell program_cell(const RobotArm& arm, const JointAngles& home) {
  RobotCell cell;
  cell.name = "test cell";
  cell.arm = arm;
  cell.home = home;
  cell.grip.translation() = Vec3(0, 0, 150);
  BeltStation s;
  s.name = "fine";
  s.contact.linear().col(0) = Vec3(0, 1, 0);
  s.contact.linear().col(1) = Vec3(0, 0, -1);
  s.contact.linear().col(2) = Vec3(-1, 0, 0);
  s.contact.translation() = Vec3(1700, 0, 900);
  s.wheel_radius_mm = 20;
  s.wheel_width_mm = 10;
  cell.stations.push_back(s);
  cell.validate();
  return cell;
}

// Contacts on a cylinder of radius 100 about the blade's z axis: the normal
// turns 1.15° per 2 mm step.
std::vector<BladeContact> contact_arc(double z) {
  std::vector<BladeContact> path;
  for (int i = 0; i <= 20; ++i) {
    const double a = -0.2 + 0.02 * i;
    path.push_back({Vec3(100 * std::sin(a), 100 * std::cos(a), z), Vec3(std::sin(a), std::cos(a), 0),
                    Vec3(std::cos(a), -std::sin(a), 0)});
  }
  return path;
}

struct Variant {
  double shift = 0;          // every target moved along the blade's x, mm
  bool swap_frames = false;  // the wheel and the blade in each other's roles
  int first_status_xor = 0;  // S of the first (PTP / MoveJ) target
  int lin_status_xor = 0;    // S of every LIN target (KRL ignores it, but it is wrong)
  bool home = true;          // an axis move first
  double ori_speed = 500;    // deg/s
};

std::string xyzabc(const Frame& f) {
  const Vec3 e = f.linear().eulerAngles(2, 1, 0);
  char b[200];
  std::snprintf(b, sizeof b, "X %.4f,Y %.4f,Z %.4f,A %.6f,B %.6f,C %.6f", f.translation().x(), f.translation().y(),
                f.translation().z(), rad_to_deg(e[0]), rad_to_deg(e[1]), rad_to_deg(e[2]));
  return b;
}

std::string pose(const Frame& f) {
  const Eigen::Quaterniond q(f.linear());
  char b[200];
  std::snprintf(b, sizeof b, "[[%.4f,%.4f,%.4f],[%.9f,%.9f,%.9f,%.9f]]", f.translation().x(), f.translation().y(),
                f.translation().z(), q.w(), q.x(), q.y(), q.z());
  return b;
}

// KRL as KSS 8.x reads it: external TCP with $BASE the wheel, $TOOL the blade.
std::string krl(const RobotCell& cell, const RobotGrindingPlan& plan, const Variant& v) {
  const BeltStation& st = cell.stations[0];
  const JointAngles& h = cell.home;
  char b[400];
  std::string text = "DEF T( )\n";
  if (v.home) {
    std::snprintf(b, sizeof b, "PTP {A1 %.4f,A2 %.4f,A3 %.4f,A4 %.4f,A5 %.4f,A6 %.4f}\n", rad_to_deg(h[0]),
                  rad_to_deg(h[1]), rad_to_deg(h[2]), rad_to_deg(h[3]), rad_to_deg(h[4]), rad_to_deg(h[5]));
    text += b;
  }
  text += "$BASE = {" + xyzabc(v.swap_frames ? cell.grip : st.contact) + "}\n";
  text += "$TOOL = {" + xyzabc(v.swap_frames ? st.contact : cell.grip) + "}\n";
  std::snprintf(b, sizeof b, "$IPO_MODE = #TCP\n$VEL.CP = 0.02\n$VEL.ORI1 = %g\n$VEL.ORI2 = %g\n", v.ori_speed,
                v.ori_speed);
  text += b;
  for (size_t k = 0; k < plan.moves.size(); ++k) {
    const RobotMove& m = plan.moves[k];
    Frame t = robot_target_frame(cell, st, m);
    t.translation() += Vec3(v.shift, 0, 0);
    const int s = kuka_status(cell.arm, m.joints) ^ (k == 0 ? v.first_status_xor : v.lin_status_xor);
    std::snprintf(b, sizeof b, "%s {E6POS: %s,S %d,T %d}\n", k == 0 ? "PTP" : "LIN", xyzabc(t).c_str(), s,
                  kuka_turn_bits(m.joints));
    text += b;
  }
  return text + "$IPO_MODE = #BASE\nEND\n";
}

// RAPID as the controller reads it: a stationary tool and a work object held by the robot.
std::string robot_rapid(const RobotCell& cell, const RobotGrindingPlan& plan, const Variant& v, const std::string& name = "T") {
  const BeltStation& st = cell.stations[0];
  const JointAngles& h = cell.home;
  char b[600];
  std::string text = "MODULE " + name + "\n";
  text += std::string("  PERS tooldata tw_") + name + " := [" + (v.swap_frames ? "TRUE," + pose(cell.grip) : "FALSE," + pose(st.contact)) +
          ",[1,[0,0,0],[1,0,0,0],0,0,0]];\n";
  text += std::string("  PERS wobjdata wb_") + name + " := [" + (v.swap_frames ? "FALSE" : "TRUE") + ",TRUE,\"\"," +
          (v.swap_frames ? pose(st.contact) : pose(cell.grip)) + ",[[0,0,0],[1,0,0,0]]];\n";
  text += "  PROC " + name + "()\n";
  if (v.home) {
    std::snprintf(b, sizeof b, "    MoveAbsJ [[%.4f,%.4f,%.4f,%.4f,%.4f,%.4f],[9E9,9E9,9E9,9E9,9E9,9E9]],v200,fine,tool0;\n",
                  rad_to_deg(h[0]), rad_to_deg(h[1]), rad_to_deg(h[2]), rad_to_deg(h[3]), rad_to_deg(h[4]),
                  rad_to_deg(h[5]));
    text += b;
  }
  for (size_t k = 0; k < plan.moves.size(); ++k) {
    const RobotMove& m = plan.moves[k];
    Frame t = robot_target_frame(cell, st, m);
    t.translation() += Vec3(v.shift, 0, 0);
    const auto cf = abb_quadrants(m.joints);
    const int cfx = abb_cfx(cell.arm, m.joints) ^ (k == 0 ? v.first_status_xor : v.lin_status_xor);
    const std::string p = pose(t);
    std::snprintf(b, sizeof b, "    %s [%s,[%d,%d,%d,%d],[9E9,9E9,9E9,9E9,9E9,9E9]],[20,%g,5000,1000],z1,tw_%s\\WObj:=wb_%s;\n",
                  k == 0 ? "MoveJ" : "MoveL", p.substr(1, p.size() - 2).c_str(), cf[0], cf[1], cf[2], cfx,
                  v.ori_speed, name.c_str(), name.c_str());
    text += b;
  }
  return text + "  ENDPROC\nENDMODULE\n";
}

struct ProgramFixture {
  RobotCell kuka = program_cell(kuka_arm(), deg(0, -90, 90, 0, 30, 0));
  RobotCell abb = program_cell(abb_arm(), deg(0, 0, 0, 0, 30, 0));
  RobotGrindingPlan plan_for(const RobotCell& cell) const {
    RobotGrindingOptions o;
    o.start = cell.home;
    const RobotGrindingPlan p = plan_robot_grinding(cell, cell.stations[0], {contact_arc(20), contact_arc(22)}, o);
    EXPECT_TRUE(p.refusals.empty());
    return p;
  }
};

RobotVerifyReport replay(const RobotCell& cell, const RobotGrindingPlan& plan, RobotDialect d, const Variant& v) {
  const std::string text = d == RobotDialect::KukaKrl ? krl(cell, plan, v) : robot_rapid(cell, plan, v);
  return verify_robot_program(cell, cell.stations[0], plan, read_robot_program({{"T", text}}, "T", d), d);
}

TEST(RobotProgram, WrittenByTheManualsItReplaysThePlan) {
  const ProgramFixture f;
  for (RobotDialect d : {RobotDialect::KukaKrl, RobotDialect::AbbRapid}) {
    const RobotCell& cell = d == RobotDialect::KukaKrl ? f.kuka : f.abb;
    const RobotGrindingPlan plan = f.plan_for(cell);
    const RobotVerifyReport ok = replay(cell, plan, d, {});
    EXPECT_TRUE(ok.problems.empty()) << ok.problems.front();
    EXPECT_EQ(ok.moves, static_cast<int>(plan.moves.size()));
    EXPECT_LT(ok.max_position_mm, 1e-4);  // 4 decimals written
    EXPECT_LT(ok.max_joint_deg, 1e-3);
    // 10 um moved: every target lands off the plan by 10 um.
    Variant moved;
    moved.shift = 0.01;
    const RobotVerifyReport off = replay(cell, plan, d, moved);
    EXPECT_NEAR(off.max_position_mm, 0.01, 1e-4);
    EXPECT_EQ(off.problems.size(), plan.moves.size());
  }
}

// The frames' roles: with the wheel and the blade in each other's places the
// targets put the blade nowhere near the wheel — the read-back fails.
TEST(RobotProgram, SwappedFramesFailTheReadBack) {
  const ProgramFixture f;
  for (RobotDialect d : {RobotDialect::KukaKrl, RobotDialect::AbbRapid}) {
    const RobotCell& cell = d == RobotDialect::KukaKrl ? f.kuka : f.abb;
    const RobotGrindingPlan plan = f.plan_for(cell);
    Variant swapped;
    swapped.swap_frames = true;
    const RobotVerifyReport r = replay(cell, plan, d, swapped);
    EXPECT_FALSE(r.problems.empty());
    EXPECT_TRUE(r.unreachable == r.moves || r.max_position_mm > 100) << r.max_position_mm << " " << r.unreachable;
  }
}

// A wrong status bit: on the first (PTP / MoveJ) target it chooses another
// solution, or none; on LINs KUKA ignores S, but a written S the arm does
// not stand in is reported; ABB's MoveL with ConfL on goes to the written
// cfx or stops.
TEST(RobotProgram, AWrongStatusBitFailsTheReadBack) {
  const ProgramFixture f;
  for (int bit : {1, 2, 4}) {
    Variant first;
    first.first_status_xor = bit;
    const RobotGrindingPlan kplan = f.plan_for(f.kuka);
    const RobotVerifyReport k = replay(f.kuka, kplan, RobotDialect::KukaKrl, first);
    EXPECT_FALSE(k.problems.empty()) << "S bit " << bit;
    EXPECT_GT(k.unreachable + k.configuration_flips, 0) << "S bit " << bit;
    Variant lin;
    lin.lin_status_xor = bit;
    const RobotVerifyReport kl = replay(f.kuka, kplan, RobotDialect::KukaKrl, lin);
    EXPECT_EQ(kl.configuration_disagreements, static_cast<int>(kplan.moves.size()) - 1) << "S bit " << bit;
    EXPECT_LT(kl.max_position_mm, 1e-4);  // the motion itself is unchanged
    const RobotGrindingPlan aplan = f.plan_for(f.abb);
    const RobotVerifyReport a = replay(f.abb, aplan, RobotDialect::AbbRapid, lin);
    EXPECT_FALSE(a.problems.empty()) << "cfx bit " << bit;
  }
}

TEST(RobotProgram, NoAxisMoveFirstOrAFeedTheOrientationSpeedCapsFails) {
  const ProgramFixture f;
  const RobotGrindingPlan plan = f.plan_for(f.abb);
  Variant no_home;
  no_home.home = false;
  EXPECT_FALSE(replay(f.abb, plan, RobotDialect::AbbRapid, no_home).problems.empty());
  // 1.15° per 2 mm at 20 mm/s needs 11.5 deg/s; 5 deg/s slows every grinding move.
  Variant slow;
  slow.ori_speed = 5;
  const RobotVerifyReport r = replay(f.abb, plan, RobotDialect::AbbRapid, slow);
  EXPECT_EQ(r.feed_capped, 2 * 20);
  slow.ori_speed = 12;
  EXPECT_EQ(replay(f.abb, plan, RobotDialect::AbbRapid, slow).feed_capped, 0);
}

// Module structure: a main module calling station procedures loads; two
// modules declaring `PROC main`, or one PERS name with two values, do not.
TEST(RobotProgram, RapidModulesShareOneTaskAndAreRefusedWhenTheyClash) {
  const ProgramFixture f;
  const RobotGrindingPlan plan = f.plan_for(f.abb);
  const std::map<std::string, std::string> ok = {
      {"MAIN", "MODULE MAIN\n  PROC main()\n    A;\n    B;\n  ENDPROC\nENDMODULE\n"},
      {"A", robot_rapid(f.abb, plan, {}, "A")},
      {"B", robot_rapid(f.abb, plan, {}, "B")}};
  const auto targets = read_robot_program(ok, "MAIN", RobotDialect::AbbRapid);
  EXPECT_EQ(targets.size(), 2 * (plan.moves.size() + 1));
  std::map<std::string, std::string> two_mains = ok;
  two_mains["A"].replace(two_mains["A"].find("PROC A()"), 8, "PROC main()");
  EXPECT_THROW(read_robot_program(two_mains, "MAIN", RobotDialect::AbbRapid), Error);
  std::map<std::string, std::string> shared = ok;
  std::string b = robot_rapid(f.abb, plan, {}, "B");
  b.replace(b.find("tw_B :="), 4, "tw_A");  // B declares A's tool, at another place
  b.replace(b.find("[[1700.0000"), 11, "[[1701.0000");
  shared["B"] = b;
  try {
    read_robot_program(shared, "MAIN", RobotDialect::AbbRapid);
    FAIL() << "a PERS name with two values loaded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("PERS tw_A"), std::string::npos) << e.what();
  }
}

// A station program calling its parts replays as the one program it was cut from.
TEST(RobotProgram, SplitProgramsReplayAsOne) {
  const ProgramFixture f;
  const RobotGrindingPlan plan = f.plan_for(f.kuka);
  const std::string whole = krl(f.kuka, plan, {});
  // Cut after the first path's lift-off: the part programs hold the moves.
  size_t cut = 0;
  for (size_t i = 1; i < plan.moves.size(); ++i)
    if (plan.moves[i].path != plan.moves[i - 1].path) cut = i;
  ASSERT_GT(cut, 0u);
  std::string head, p1 = "DEF T_P1( )\n", p2 = "DEF T_P2( )\n", tail;
  size_t target = 0, pos = 0;
  while (pos < whole.size()) {
    const size_t end = whole.find('\n', pos) + 1;
    const std::string line = whole.substr(pos, end - pos);
    pos = end;
    const bool cartesian = line.find("E6POS") != std::string::npos;
    if (cartesian) (target++ < cut ? p1 : p2) += line;
    else if (target == 0) head += line;
    else tail += line;
  }
  const std::map<std::string, std::string> programs = {
      {"T", head + "T_P1()\nT_P2()\n" + tail}, {"T_P1", p1 + "END\n"}, {"T_P2", p2 + "END\n"}};
  const auto targets = read_robot_program(programs, "T", RobotDialect::KukaKrl);
  const RobotVerifyReport r = verify_robot_program(f.kuka, f.kuka.stations[0], plan, targets, RobotDialect::KukaKrl);
  EXPECT_TRUE(r.problems.empty()) << r.problems.front();
  EXPECT_EQ(r.moves, static_cast<int>(plan.moves.size()));
  // KSS selects a program by its file: a DEF that names another file is refused.
  std::map<std::string, std::string> misnamed = programs;
  misnamed["T_P2"] = "DEF OTHER( )\nEND\n";
  EXPECT_THROW(read_robot_program(misnamed, "T", RobotDialect::KukaKrl), Error);
}

// The load, read as the controllers add it up (issue 39 item 2): KUKA's
// $LOAD is the whole load on the flange — centre of gravity and principal
// axes in FLANGE, principal moments in kg·m²; ABB's tooldata tload is the
// gripper in the wrist frame and, with a stationary tool, the GripLoad
// payload is in the object frame of the work object the robot holds (the
// RAPID reference's loaddata). A program that states the blade's load in the
// flange frame, or as a point mass, fails the read-back.
std::string load_text(const MassProperties& m, bool krl) {
  const PrincipalInertia p = principal_inertia(m.inertia_kg_mm2);
  char b[400];
  if (krl) {
    const Vec3 e = p.axes.eulerAngles(2, 1, 0);
    std::snprintf(b, sizeof b, "{M %.3f,CM {X %.3f,Y %.3f,Z %.3f,A %.5f,B %.5f,C %.5f},J {X %.7f,Y %.7f,Z %.7f}}",
                  m.mass_kg, m.cog_mm.x(), m.cog_mm.y(), m.cog_mm.z(), rad_to_deg(e[0]), rad_to_deg(e[1]),
                  rad_to_deg(e[2]), 1e-6 * p.moments_kg_mm2.x(), 1e-6 * p.moments_kg_mm2.y(), 1e-6 * p.moments_kg_mm2.z());
  } else {
    const Eigen::Quaterniond q(p.axes);
    std::snprintf(b, sizeof b, "[%.3f,[%.3f,%.3f,%.3f],[%.9f,%.9f,%.9f,%.9f],%.7f,%.7f,%.7f]", m.mass_kg, m.cog_mm.x(),
                  m.cog_mm.y(), m.cog_mm.z(), q.w(), q.x(), q.y(), q.z(), 1e-6 * p.moments_kg_mm2.x(),
                  1e-6 * p.moments_kg_mm2.y(), 1e-6 * p.moments_kg_mm2.z());
  }
  return b;
}

std::string replaced(std::string text, const std::string& what, const std::string& with) {
  const size_t at = text.find(what);
  EXPECT_NE(at, std::string::npos) << what;
  return at == std::string::npos ? text : text.replace(at, what.size(), with);
}

TEST(RobotProgram, TheLoadIsReadAsTheControllerAddsItUp) {
  const ProgramFixture f;
  // A 15 kg gripper (a cylinder Ø 160 x 180 mm, 90 mm out on the flange
  // axis) and a 0.43 kg titanium plate in the blade frame, off its origin and
  // turned, so the blade's tensor is full and the frames matter.
  const MassProperties gripper = cylinder_mass_properties(15, 80, 180, [] {
    Frame g = Frame::Identity();
    g.translation() = Vec3(0, 0, 90);
    return g;
  }());
  Frame plate = Frame::Identity();
  plate.linear() = Eigen::AngleAxisd(deg_to_rad(30), Vec3(1, 1, 0).normalized()).toRotationMatrix();
  plate.translation() = Vec3(10, -20, 40);
  const MassProperties blade = box_mass_properties(0.43, Vec3(120, 40, 20), plate);  // blade frame
  for (RobotDialect d : {RobotDialect::KukaKrl, RobotDialect::AbbRapid}) {
    const bool krl_dialect = d == RobotDialect::KukaKrl;
    const RobotCell& cell = krl_dialect ? f.kuka : f.abb;
    const RobotGrindingPlan plan = f.plan_for(cell);
    const MassProperties payload = combined(gripper, transformed(blade, cell.grip));  // on the flange
    const std::string base = krl_dialect ? krl(cell, plan, {}) : robot_rapid(cell, plan, {});
    auto with_load = [&](const MassProperties& flange_or_gripper, const MassProperties& grip_load) {
      if (krl_dialect) return replaced(base, "$IPO_MODE = #TCP\n", "$LOAD = " + load_text(flange_or_gripper, true) +
                                                                     "\n$IPO_MODE = #TCP\n");
      const std::string with_tool = replaced(base, ",[1,[0,0,0],[1,0,0,0],0,0,0]];", "," + load_text(flange_or_gripper, false) + "];");
      return replaced(replaced(with_tool, "  PROC T()\n",
                               "  PERS loaddata ld_T := " + load_text(grip_load, false) + ";\n  PROC T()\n"),
                      "    MoveJ", "    GripLoad ld_T;\n    MoveJ");
    };
    auto check = [&](const std::string& text) {
      return verify_robot_program(cell, cell.stations[0], plan, read_robot_program({{"T", text}}, "T", d), d, 0.002,
                                  0.001, &payload);
    };
    // By the manuals: KRL the whole load on the flange; RAPID the gripper as
    // tload and the blade in the object frame.
    const RobotVerifyReport ok = check(with_load(krl_dialect ? payload : gripper, blade));
    EXPECT_EQ(ok.load_disagreements, 0) << (ok.problems.empty() ? "" : ok.problems.front());
    EXPECT_TRUE(ok.problems.empty());
    // The previous posts: KRL a point mass (J and the axes zero); RAPID the
    // blade's centre of gravity in the flange frame, no inertia.
    MassProperties point = payload;
    point.inertia_kg_mm2.setZero();
    MassProperties blade_on_flange = transformed(blade, cell.grip);
    blade_on_flange.inertia_kg_mm2.setZero();
    const RobotVerifyReport old = check(with_load(krl_dialect ? point : gripper, blade_on_flange));
    EXPECT_EQ(old.load_disagreements, old.moves) << (krl_dialect ? "KRL" : "RAPID");
    EXPECT_NE(old.problems.front().find("load in force"), std::string::npos) << old.problems.front();
    // No load at all is a disagreement too.
    EXPECT_EQ(check(base).load_disagreements, ok.moves);
  }
}

TEST(RobotProgram, UnreadableStatementsNameTheirLine) {
  EXPECT_THROW(read_robot_program("MODULE T\n  MoveL [[1,2,3],[1,0,0,0]],v20,z1,t;\n", RobotDialect::AbbRapid), Error);
  try {
    read_robot_program("DEF T()\n$BASE = {X 0,Y 0,Z 0,A 0,B 0,C 0}\n$TOOL = {X 0,Y 0,Z 0,A 0,B 0,C 0}\n"
                       "LIN {X 1,Y 2,Z 3,A 0,B 0,C 0}\n",
                       RobotDialect::KukaKrl);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("line 4"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("S or T"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace bliskrun
