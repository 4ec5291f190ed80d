// The motion a controller makes between two blocks, and the program swept
// as it makes it (core/machine/motion.h, verify.h): splitting to the whole
// tool under each interpolation, the sweep of the program read back, the
// way in and out at the safe height, rotary display resets and the feed at
// the cutter.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <sstream>

#include "core/common/error.h"
#include "core/machine/motion.h"
#include "core/machine/verify.h"
#include "machine/test_machines.h"
#include "test_support.h"

namespace bliskrun {
namespace {

const ToolReach kReach{5.0, 120.0};  // a cutter reaching 5 mm from its tip, holder top 120 mm


// The whole tool's departure from the planned motion a -> b while the
// controller moves from block `from` to block `to`, by brute force: dense
// samples, each compared with the planned pose where its tip projects onto
// the planned segment (the segment is uniform in t, so that is the planned
// pose's own parameter).
double dense_tool_deviation(const Kinematics& kin, ControllerMotion motion, const MachineAxes& from,
                            const MachineAxes& to, const Vec3& tip_from, const Vec3& tip_to, const ToolPose& a,
                            const ToolPose& b, double reach, int samples = 4000) {
  const Vec3 seg = b.tip - a.tip;
  double worst = 0;
  for (int i = 0; i <= samples; ++i) {
    const ToolPose c = controller_pose(kin, motion, from, to, tip_from, tip_to, double(i) / samples);
    const double t = std::clamp((c.tip - a.tip).dot(seg) / seg.squaredNorm(), 0.0, 1.0);
    const ToolPose p = interpolate_pose(a, b, t);
    worst = std::max(worst, (c.tip - p.tip).norm() + reach * (c.axis.normalized() - p.axis).norm());
  }
  return worst;
}

// A row near the C pole: the tool axis 5 deg off the table axis swings
// round by 150 deg while the tip moves 2 mm — one block turns C by ~150 deg.
std::vector<PlannedMove> pole_swing() {
  std::vector<PlannedMove> path(2);
  path[0].kind = MoveKind::Rapid;
  path[0].pose = test::tilted_pose(Vec3(30, 0, 5), 5 * kDeg, 0);
  path[1].feed_mm_per_min = 600;
  path[1].pose = test::tilted_pose(Vec3(30, 2, 5), 5 * kDeg, 150 * kDeg);
  return path;
}

MotionOptions tcp_options(bool vector) {
  MotionOptions o;
  o.tcp = true;
  o.tcp_vector = vector;
  o.chord_tol_mm = 0.002;
  o.body_tol_mm = 0.05;
  o.start.rotary_rad = {-5 * kDeg, 0};
  return o;
}

// Under TCP with linear rotaries the axis leaves the great circle by
// degrees; the planner splits until the whole tool is within tolerance,
// measured densely against the planned motion.
TEST(ControllerMotion, TcpWithLinearRotariesIsSplitToTheWholeTool) {
  const Kinematics kin(test::table_table_ac(), 80.0);
  const std::vector<PlannedMove> path = pole_swing();
  const MotionOptions o = tcp_options(false);
  const MachineProgram program = plan_machine_motion(kin, path, o, Progress::none(), kReach);
  ASSERT_GT(program.moves.size(), 10u);
  EXPECT_EQ(program.controller, ControllerMotion::TcpRotaryLinear);
  // Unsplit, the one block would put the cutter a third of a millimetre off
  // the planned motion (the axis ~4 deg off the great circle).
  const MachineAxes a = program.moves.front().axes, b = program.moves.back().axes;
  EXPECT_GT(dense_tool_deviation(kin, ControllerMotion::TcpRotaryLinear, a, b, path[0].pose.tip, path[1].pose.tip,
                                 path[0].pose, path[1].pose, kReach.cutter_mm),
            0.1);
  for (size_t i = 1; i < program.moves.size(); ++i) {
    const MachineMove& p = program.moves[i - 1];
    const MachineMove& q = program.moves[i];
    for (const auto& [reach, tol] : {std::pair<double, double>{kReach.cutter_mm, o.chord_tol_mm},
                                     {kReach.body_mm, o.body_tol_mm}}) {
      EXPECT_LE(dense_tool_deviation(kin, ControllerMotion::TcpRotaryLinear, p.axes, q.axes, p.pose.tip, q.pose.tip,
                                     path[0].pose, path[1].pose, reach),
                tol + 1e-9)
          << "block " << i;
    }
  }
  EXPECT_LE(program.max_deviation_mm, o.chord_tol_mm);
}

// With vector orientation the controller follows the planned motion: no split.
TEST(ControllerMotion, TcpWithVectorOrientationIsNotSplit) {
  const Kinematics kin(test::table_table_ac(), 80.0);
  const MachineProgram program = plan_machine_motion(kin, pole_swing(), tcp_options(true), Progress::none(), kReach);
  EXPECT_EQ(program.moves.size(), 2u);
}

// The bound tool_deviation reports is never below the truth (brute force),
// the sampled value never above it, for every machine and interpolation.
TEST(ControllerMotion, DeviationBoundHoldsForRandomBlocks) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coord(-50, 50), turn(-0.4, 0.4);
  for (const MachineDefinition& m : test::all_machines()) {
    const Kinematics kin(m, 80.0);
    for (ControllerMotion motion :
         {ControllerMotion::JointLinear, ControllerMotion::TcpRotaryLinear, ControllerMotion::TcpVector}) {
      for (int i = 0; i < 12; ++i) {
        MachineAxes a, b;
        a.rotary_rad = test::random_rotary(m, rng);
        b.rotary_rad = {a.rotary_rad[0] + turn(rng), a.rotary_rad[1] + turn(rng)};
        a.linear_mm = Vec3(coord(rng), coord(rng), coord(rng));
        b.linear_mm = a.linear_mm + 0.2 * Vec3(coord(rng), coord(rng), coord(rng));
        // The planned motion between the blocks' own poses.
        const ToolPose pa = kin.forward(a), pb = kin.forward(b);
        const ToolDeviation dev = tool_deviation(kin, motion, a, b, pa.tip, pb.tip, pa, pb, kReach, 0.001, 0.01);
        const double truth_cutter = dense_tool_deviation(kin, motion, a, b, pa.tip, pb.tip, pa, pb, kReach.cutter_mm);
        EXPECT_LE(truth_cutter, dev.cutter_bound_mm + 1e-9) << m.name << " " << to_string(motion) << " " << i;
        EXPECT_LE(dev.cutter_mm, truth_cutter + 1e-9);  // both sampled: the dense one sees at least as much
        if (motion == ControllerMotion::TcpVector) EXPECT_LT(dev.cutter_mm, 1e-9);  // the planned motion itself
      }
    }
  }
}

// A writer of ISO programs for these tests: TCP on with G43.4 (rotaries
// linear) or, `vector`, Heidenhain's FUNCTION TCPM ... PATHCTRL VECTOR; M94
// before a move that resets the display. What a post does, without Lua.
std::string write_program(const MachineProgram& program, const MachineDefinition& m, bool vector = false) {
  std::ostringstream out;
  out << "%\nG90 G17 G21 " << (program.feed_mode == FeedMode::InverseTime ? "G93" : "G94") << "\nT1 M6\n";
  if (program.tcp) out << (vector ? "FUNCTION TCPM F TCP AXIS POS PATHCTRL VECTOR\n" : "G43.4 H1\n");
  char buf[64];
  for (const MachineMove& move : program.moves) {
    for (int r = 0; r < 2; ++r)
      if (move.rotary_reset[r] != 0) out << "M94 " << m.rotary[r].name << "\n";
    const Vec3 xyz = program.tcp ? move.pose.tip : move.axes.linear_mm;
    out << (move.kind == MoveKind::Rapid ? "G0" : "G1");
    for (int i = 0; i < 3; ++i) {
      std::snprintf(buf, sizeof buf, " %c%.4f", "XYZ"[i], xyz[i]);
      out << buf;
    }
    for (int i = 0; i < 2; ++i) {
      std::snprintf(buf, sizeof buf, " %s%.4f", m.rotary[i].name.c_str(), rad_to_deg(move.axes.rotary_rad[i]));
      out << buf;
    }
    if (move.kind == MoveKind::Feed) {
      std::snprintf(buf, sizeof buf, " F%.4f", move.feed);
      out << buf;
    }
    out << "\n";
  }
  out << "M30\n%\n";
  return out.str();
}

VerifyOptions sweep_options(double chord_tol) {
  VerifyOptions o;
  o.read.file_name = "swing.nc";
  o.reaches = {kReach};
  o.chord_tol_mm = chord_tol;
  o.body_tol_mm = 0.05;
  return o;
}

// A program whose 150 deg C block was planned for vector orientation but
// runs with linear rotaries (G43.4) gouges between its blocks: the sweep
// refuses it at that block's line, though both block ends are exact. Read as
// PATHCTRL VECTOR the same blocks pass; split for linear rotaries, they pass.
TEST(ControllerMotion, SweepRefusesABlockTheControllerMovesOffThePlan) {
  MachineDefinition m = test::table_table_ac();
  m.linear_resolution_mm = 1e-4;
  m.rotary_resolution_rad = deg_to_rad(1e-4);
  const Kinematics kin(m, 80.0);
  const std::vector<PlannedMove> path = pole_swing();
  const MachineProgram for_vector = plan_machine_motion(kin, path, tcp_options(true), Progress::none(), kReach);
  try {
    verify_program(write_program(for_vector, m), kin, for_vector, sweep_options(0.002));
    FAIL() << "expected the sweep to refuse the block";
  } catch (const DataError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("swing.nc:6"), std::string::npos) << what;  // the G1 block
    EXPECT_NE(what.find("TCP, rotaries linear"), std::string::npos) << what;
  }
  const VerifyReport vector = verify_program(write_program(for_vector, m, true), kin, for_vector, sweep_options(0.002));
  EXPECT_EQ(vector.swept_moves, 1);
  EXPECT_LT(vector.max_cutter_mm, 0.002);
  const MachineProgram split = plan_machine_motion(kin, path, tcp_options(false), Progress::none(), kReach);
  const VerifyReport r = verify_program(write_program(split, m), kin, split, sweep_options(0.002));
  EXPECT_EQ(r.swept_moves, static_cast<long>(split.moves.size()) - 1);
  EXPECT_LE(r.max_cutter_mm, 0.002 + 1e-3);
  EXPECT_GT(r.max_cutter_mm, 0.0);
}

// One tool's moves with the way in and out: Retract (Z alone), Rotate (the
// rotaries alone), Position (X, Y at the safe height), the first planned
// move reached down its own tool axis, and the Lift up the last one's.
TEST(ControllerMotion, WayInAndOutRunAlongTheToolAxisFromTheSafeHeight) {
  MachineDefinition m = test::table_table_ac();
  m.linear[2].max_mm = 300;  // the Z slide's top: the safe height
  const Kinematics kin(m, 80.0);
  std::vector<PlannedMove> path(3);
  path[0].kind = MoveKind::Rapid;
  path[0].pose = test::tilted_pose(Vec3(40, 0, 20), 30 * kDeg, 0);
  path[1].feed_mm_per_min = 500;
  path[1].pose = test::tilted_pose(Vec3(40, 5, 20), 30 * kDeg, 10 * kDeg);
  path[2] = path[1];
  path[2].pose = test::tilted_pose(Vec3(40, 10, 20), 30 * kDeg, 20 * kDeg);
  MotionOptions o;
  o.start.linear_mm = Vec3(100, -50, 120);
  o.approach.enabled = true;
  o.approach.proved_mm = 2000;
  o.approach.proved_up_mm = 0;  // on the trunnion the Z slide moves the tip along the tool axis
  const MachineProgram program = plan_machine_motion_tools({{&kin, kReach}}, path, {0, 0, 0}, o);
  ASSERT_GE(program.moves.size(), 6u);
  const std::vector<MachineMove>& mv = program.moves;
  EXPECT_EQ(mv[0].safe, SafeMove::Retract);
  EXPECT_EQ(mv[1].safe, SafeMove::Rotate);
  EXPECT_EQ(mv[2].safe, SafeMove::Position);
  EXPECT_EQ(mv[3].safe, SafeMove::Descend);
  EXPECT_EQ(mv.back().safe, SafeMove::Lift);
  const double safe_z = kin.safe_z_mm();
  EXPECT_NEAR(safe_z, 300 - 80, 1e-9);  // the top of the slide less the tool (tip words)
  // Retract: Z alone from where the machine was.
  EXPECT_EQ(mv[0].axes.linear_mm.head<2>(), o.start.linear_mm.head<2>());
  EXPECT_EQ(mv[0].axes.linear_mm.z(), safe_z);
  EXPECT_EQ(mv[0].axes.rotary_rad, o.start.rotary_rad);
  // Rotate: the rotaries alone, to the first pose's.
  EXPECT_EQ(mv[1].axes.linear_mm, mv[0].axes.linear_mm);
  EXPECT_EQ(mv[1].axes.rotary_rad, mv[3].axes.rotary_rad);
  // Position at the safe height over the first pose (X, Y of the first
  // pose's axes): on the trunnion that is on the first pose's axis line.
  EXPECT_EQ(mv[2].axes.linear_mm.z(), safe_z);
  EXPECT_EQ(mv[2].axes.linear_mm.head<2>(), mv[3].axes.linear_mm.head<2>());
  const Vec3 out = mv[2].pose.tip - path[0].pose.tip;
  EXPECT_LT(out.cross(path[0].pose.axis).norm(), 1e-9);
  EXPECT_GT(out.dot(path[0].pose.axis), 0);
  EXPECT_LT((kin.forward(mv[2].axes).tip - mv[2].pose.tip).norm(), 1e-9);
  EXPECT_EQ(mv[3].kind, MoveKind::Rapid);  // Z alone: a defined path
  // Lift: up the last pose's axis to the safe height.
  const Vec3 up = mv.back().pose.tip - path[2].pose.tip;
  EXPECT_LT(up.cross(path[2].pose.axis).norm(), 1e-9);
  EXPECT_NEAR(mv.back().axes.linear_mm.z(), safe_z, 1e-9);
  // Read back: the descent and lift are swept, the moves at the safe height
  // checked by their words.
  const VerifyReport r = verify_program(write_program(program, m), kin, program, [&] {
    VerifyOptions v = sweep_options(0.005);
    v.read.start = o.start;
    return v;
  }());
  EXPECT_EQ(r.safe_moves, 3);
  EXPECT_EQ(r.unswept_moves, 0);
  // A way longer than the plan proved is refused.
  o.approach.proved_mm = 50;
  try {
    plan_machine_motion_tools({{&kin, kReach}}, path, {0, 0, 0}, o);
    FAIL() << "expected the way in to be refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("proved 50 mm"), std::string::npos) << e.what();
  }
  // Under a B head over a C table the Z slide moves the tip up the part's
  // +Z: that line must have been proved, not the tool axis.
  MachineDefinition head = test::head_table_bc();
  head.linear[2].max_mm = 400;
  const Kinematics head_kin(head, 80.0);
  o.approach.proved_mm = 2000;
  EXPECT_THROW(plan_machine_motion_tools({{&head_kin, kReach}}, path, {0, 0, 0}, o), Error);
  o.approach.proved_up_mm = 2000;
  const MachineProgram on_head = plan_machine_motion_tools({{&head_kin, kReach}}, path, {0, 0, 0}, o);
  const Vec3 up_head = on_head.moves[2].pose.tip - path[0].pose.tip;
  EXPECT_LT(up_head.cross(Vec3::UnitZ()).norm(), 1e-9);
  EXPECT_GT(up_head.z(), 0);
}

// Rows that each turn the C table by 200 deg, linked by rapids: the display
// of C is reset at the links (M94) so it never passes one turn and a half;
// without a reset a controller limit of 1000 deg is refused by name. The
// program with its resets reads back and sweeps clean.
TEST(ControllerMotion, ContinuousRotaryIsResetAtLinksWithinTheInputRange) {
  MachineDefinition m = test::head_table_bc();
  m.linear_resolution_mm = 1e-4;
  m.rotary_resolution_rad = deg_to_rad(1e-4);
  const Kinematics kin(m, 60.0);
  std::vector<PlannedMove> path;
  double azimuth = 0;
  for (int row = 0; row < 8; ++row) {
    for (int k = 0; k <= 10; ++k) {
      PlannedMove p;
      p.kind = k == 0 ? MoveKind::Rapid : MoveKind::Feed;
      p.feed_mm_per_min = 800;
      p.pose = test::tilted_pose(Vec3(20 + 0.2 * k, 0, 10 + row), 40 * kDeg, azimuth);
      if (k < 10) azimuth += 20 * kDeg;
      path.push_back(p);
    }
  }
  MotionOptions o;
  o.rotary_reset = true;
  o.rotary_input_limit_rad = 1000 * kDeg;
  const MachineProgram program = plan_machine_motion(kin, path, o, Progress::none(), kReach);
  EXPECT_GT(program.rotary_resets, 0);
  for (const MachineMove& mm : program.moves) EXPECT_LE(std::abs(mm.axes.rotary_rad[0]), (360 + 210) * kDeg);
  const VerifyReport r = verify_program(write_program(program, m), kin, program, sweep_options(0.005));
  EXPECT_GT(r.swept_moves, 70);
  o.rotary_reset = false;
  try {
    plan_machine_motion(kin, path, o, Progress::none(), kReach);
    FAIL() << "expected C beyond the input range";
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.name(), "C");
    EXPECT_NE(std::string(e.what()).find("input range"), std::string::npos) << e.what();
  }
}

// The feed at the cutter: a block that turns the tool 10 deg about its
// tip while the tip moves 0.1 mm is timed by the cutter's fastest point
// (tip length + reach x turn, at 1.5 x the feed), and by C's top speed when
// that is slower; inverse time F is 1 / duration.
TEST(ControllerMotion, FeedKeepsTheCutterAndTheRotariesWithinTheirLimits) {
  MachineDefinition m = test::table_table_ac();
  m.feed = FeedMode::InverseTime;
  const Kinematics kin(m, 80.0);
  std::vector<PlannedMove> path(2);
  path[0].kind = MoveKind::Rapid;
  path[0].pose = test::tilted_pose(Vec3(0, 0, 5), 30 * kDeg, 0);
  path[1].feed_mm_per_min = 600;
  path[1].pose = test::tilted_pose(Vec3(0.1, 0, 5), 30 * kDeg, 10 * kDeg);
  MotionOptions o;
  o.tcp = false;
  o.chord_tol_mm = 10;  // one block, as planned (the timing is the point here)
  o.body_tol_mm = 10;
  o.start.rotary_rad = {-30 * kDeg, 0};
  const ToolReach reach{5.0, 5.0};
  const MachineProgram program = plan_machine_motion(kin, path, o, Progress::none(), reach);
  ASSERT_EQ(program.moves.size(), 2u);
  const MachineMove& b = program.moves[1];
  const MachineAxes& a = program.moves[0].axes;
  const double dA = b.axes.rotary_rad[0] - a.rotary_rad[0], dC = b.axes.rotary_rad[1] - a.rotary_rad[1];
  const double turn = std::hypot(dA, dC);  // A and C perpendicular
  const double cutter = 0.1 + 5 * turn;
  EXPECT_NEAR(b.feed, 1 / std::max(0.1 / 600, cutter / (1.5 * 600)), 1e-9);
  EXPECT_NEAR(b.cutter_speed_ratio, 1.5, 1e-9);
  EXPECT_EQ(program.slowed_moves, 1);
  // A slow C: 5 deg/s.
  m.rotary[1].max_speed_rad_per_min = 300 * kDeg;
  const MachineProgram slow = plan_machine_motion(Kinematics(m, 80.0), path, o, Progress::none(), reach);
  EXPECT_NEAR(slow.moves[1].feed, 1 / (std::abs(dC) / (300 * kDeg)), 1e-9);
  EXPECT_NEAR(slow.max_rotary_speed_rad_per_min[1], 300 * kDeg, 1e-9);
  EXPECT_LT(slow.max_cutter_speed_ratio, 1.5);
}

// The reader: PATHCTRL VECTOR / AXIS, and M94 reducing the display.
TEST(ControllerMotion, ReaderKnowsPathControlAndDisplayResets) {
  const MachineDefinition m = test::head_table_bc();
  const std::string text =
      "0 BEGIN PGM T MM\n"
      "1 FUNCTION TCPM F TCP AXIS POS PATHCTRL VECTOR\n"
      "2 L X+1 Y+0 Z+5 C+725 B+10 R0 FMAX\n"
      "3 M94 C\n"
      "4 L X+2 C+10 F500\n"
      "5 FUNCTION TCPM F TCP AXIS POS PATHCTRL AXIS\n"
      "6 L X+3 F500\n"
      "7 END PGM T MM\n";
  ProgramReadOptions o;
  const std::vector<ProgramMove> moves = read_program(text, m, o);
  ASSERT_EQ(moves.size(), 3u);
  EXPECT_TRUE(moves[0].vector);
  EXPECT_EQ(moves[1].rotary_reset[0], 2);
  EXPECT_NEAR(rad_to_deg(moves[1].axes.rotary_rad[0]), 10, 1e-9);
  EXPECT_FALSE(moves[2].vector);
  EXPECT_THROW(read_program("1 FUNCTION TCPM F TCP AXIS POS PATHCTRL SIDEWAYS\n", m, o), DataError);
  EXPECT_THROW(read_program("1 M94 A\n", m, o), DataError);
}

}  // namespace
}  // namespace bliskrun
