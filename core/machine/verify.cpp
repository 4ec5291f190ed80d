#include "core/machine/verify.h"

#include <cmath>
#include <sstream>

#include "core/common/error.h"

namespace bliskrun {

ToolPose replay(const Kinematics& kin, const ProgramMove& move) {
  if (!move.tcp) return kin.forward(move.axes);
  ToolPose pose;
  pose.tip = move.axes.linear_mm;
  pose.axis = kin.tool_axis(move.axes.rotary_rad);
  return pose;
}

namespace {

// A read-back block in both forms: machine axes and the tool tip in the
// part frame (a TCP block gives the tip; the other follows from the
// kinematics).
struct BlockState {
  MachineAxes axes;  // machine axes (linear: the slides' words)
  Vec3 tip = Vec3::Zero();
};

BlockState state_of(const Kinematics& kin, const ProgramMove& m) {
  BlockState s;
  s.axes = m.axes;
  if (m.tcp) {
    s.tip = m.axes.linear_mm;
    s.axes.linear_mm = kin.linear_for(s.tip, m.axes.rotary_rad);
  } else {
    s.tip = kin.forward(m.axes).tip;
  }
  return s;
}

ControllerMotion motion_of(const ProgramMove& m) {
  if (!m.tcp) return ControllerMotion::JointLinear;
  return m.vector ? ControllerMotion::TcpVector : ControllerMotion::TcpRotaryLinear;
}

bool same(double a, double b) { return std::abs(a - b) < 1e-9; }

// A move at the safe height may change only its own axis words (motion.h
// SafeMove): Retract Z, Rotate the rotaries (both written with TCP off, in
// machine axes), Position X and Y. `before` is the block read before it, in
// the reader's own (modal) words.
void check_safe_move(const std::string& file, const ProgramMove& got, const ProgramMove& before,
                     const MachineMove& want) {
  const MachineAxes& a = before.axes;
  const MachineAxes& b = got.axes;
  const bool x = same(a.linear_mm.x(), b.linear_mm.x()), y = same(a.linear_mm.y(), b.linear_mm.y());
  const bool z = same(a.linear_mm.z(), b.linear_mm.z());
  const bool r = same(a.rotary_rad[0], b.rotary_rad[0]) && same(a.rotary_rad[1], b.rotary_rad[1]);
  bool ok = true;
  const char* rule = "";
  switch (want.safe) {
    case SafeMove::Retract:
      rule = "Z alone, with TCP control off";
      ok = x && y && r && !got.tcp;
      break;
    case SafeMove::Rotate:
      rule = "the rotary axes alone, with TCP control off";
      ok = x && y && z && !got.tcp;
      break;
    case SafeMove::Position:
      rule = "X and Y alone";
      ok = got.tcp || (z && r);  // under TCP every word is written again (tip coordinates)
      break;
    default:
      return;
  }
  if (!ok)
    throw DataError(file, got.line,
                    std::string("this block at the safe height (") + to_string(want.safe) + ") must move " + rule);
}

}  // namespace

VerifyReport verify_program(const std::string& text, const Kinematics& kin,
                            const MachineProgram& plan, const VerifyOptions& options) {
  return verify_program(text, std::vector<const Kinematics*>{&kin}, plan, options);
}

VerifyReport verify_program(const std::string& text, const std::vector<const Kinematics*>& kins,
                            const MachineProgram& plan, const VerifyOptions& options) {
  if (kins.empty()) throw ParameterError("tools", "need at least one tool's kinematics");
  const std::string& file = options.read.file_name;
  const std::vector<ProgramMove> moves = read_program(text, kins.front()->machine(), options.read);
  const int last_line = moves.empty() ? 1 : moves.back().line;
  if (moves.size() != plan.moves.size())
    throw DataError(file, last_line,
                    "the program commands " + std::to_string(moves.size()) +
                        " moves, the plan has " + std::to_string(plan.moves.size()));
  const MachineDefinition& m = kins.front()->machine();
  const double linear_slack = 0.5 * m.linear_resolution_mm * std::sqrt(3.0);
  const double rotary_step = 0.5 * m.rotary_resolution_rad;
  VerifyReport report;
  report.moves = static_cast<long>(moves.size());
  BlockState previous;
  for (size_t i = 0; i < moves.size(); ++i) {
    const ProgramMove& got = moves[i];
    const MachineMove& want = plan.moves[i];
    if (got.kind != want.kind)
      throw DataError(file, got.line,
                      std::string("expected a ") + (want.kind == MoveKind::Rapid ? "rapid" : "feed") +
                          " move (plan move " + std::to_string(want.source + 1) + ")");
    if (want.tool < 0 || want.tool >= static_cast<int>(kins.size()))
      throw ParameterError("tools", "plan move " + std::to_string(want.source + 1) + " uses a tool without kinematics");
    if (!options.tool_numbers.empty() && got.tool != options.tool_numbers.at(static_cast<size_t>(want.tool)))
      throw DataError(file, got.line,
                      "expected tool " + std::to_string(options.tool_numbers.at(static_cast<size_t>(want.tool))) +
                          " here (plan move " + std::to_string(want.source + 1) + "), the program has tool " +
                          std::to_string(got.tool));
    const Kinematics& kin = *kins[static_cast<size_t>(want.tool)];
    if (i > 0) check_safe_move(file, got, moves[i - 1], want);
    if (want.safe == SafeMove::Retract || want.safe == SafeMove::Rotate) {
      // Machine words only (the others are what the last block left, in
      // whatever frame it wrote them): the written ones must be the plan's.
      const bool retract = want.safe == SafeMove::Retract;
      const double off = retract ? std::abs(got.axes.linear_mm.z() - want.axes.linear_mm.z())
                                 : std::max(std::abs(got.axes.rotary_rad[0] - want.axes.rotary_rad[0]),
                                            std::abs(got.axes.rotary_rad[1] - want.axes.rotary_rad[1]));
      if (got.tcp || off > (retract ? linear_slack + options.tol_mm : 2 * rotary_step + options.angle_tol_rad)) {
        std::ostringstream msg;
        msg.precision(6);
        msg << "expected the " << to_string(want.safe) << " block of the way in (plan move " << want.source + 1
            << "), with TCP control off, at " << (retract ? "Z " : "the first pose's rotary axes ")
            << (retract ? want.axes.linear_mm.z() : rad_to_deg(want.axes.rotary_rad[0])) << "; off by "
            << (retract ? off : rad_to_deg(off)) << (retract ? " mm" : " deg");
        throw DataError(file, got.line, msg.str());
      }
      previous.axes = want.axes;
      previous.tip = kin.forward(want.axes).tip;
      ++report.safe_moves;
      continue;
    }
    const ToolPose pose = replay(kin, got);
    const double position = (pose.tip - want.pose.tip).norm();
    const double angle = std::atan2(pose.axis.cross(want.pose.axis).norm(), pose.axis.dot(want.pose.axis));
    const double tip_rounding = linear_slack + (got.tcp ? 0.0 : 2 * rotary_step * kin.lever_arm_mm(got.axes));
    const double allowed_position = options.tol_mm + tip_rounding;
    const double allowed_angle = options.angle_tol_rad + 2 * rotary_step;
    if (position > report.max_position_mm) {
      report.max_position_mm = position;
      report.worst_position_line = got.line;
    }
    if (angle > report.max_angle_rad) {
      report.max_angle_rad = angle;
      report.worst_angle_line = got.line;
    }
    if (position > allowed_position || angle > allowed_angle) {
      std::ostringstream msg;
      msg.precision(6);
      msg << "the replayed tool is " << position << " mm and " << rad_to_deg(angle)
          << " deg from the plan (allowed " << allowed_position << " mm, " << rad_to_deg(allowed_angle)
          << " deg) at plan move " << want.source + 1;
      if (want.row >= 0) msg << " (row " << want.row << ")";
      throw DataError(file, got.line, msg.str());
    }

    // Between the blocks: the tool as this controller moves it, against the
    // planned motion. The block starts where the last one ended, less the
    // turns an M94 took off the display.
    BlockState from = previous;
    for (int r = 0; r < 2; ++r) from.axes.rotary_rad[r] -= 2 * kPi * got.rotary_reset[r];
    const BlockState to = state_of(kin, got);
    previous = to;
    if (want.safe == SafeMove::Position) {
      ++report.safe_moves;
      continue;
    }
    if (i == 0 || (plan.moves[i - 1].tool != want.tool && want.safe != SafeMove::Descend)) {
      ++report.unswept_moves;  // from wherever the tool change left the machine
      continue;
    }
    const ToolReach reach = options.reaches.empty() ? ToolReach{} : options.reaches.at(static_cast<size_t>(want.tool));
    const ControllerMotion motion = motion_of(got);
    // What the output resolution explains: the rounded tip, and the rounded
    // rotaries turning the axis (each by half a step) over the tool's reach.
    // Plus, as at the block ends, the read-back's own tolerance.
    const double cutter_allowed = options.chord_tol_mm + options.tol_mm + tip_rounding +
                                  (2 * rotary_step + options.angle_tol_rad) * reach.cutter_mm;
    const double body_allowed = options.body_tol_mm + options.tol_mm + tip_rounding +
                                (2 * rotary_step + options.angle_tol_rad) * reach.body_mm;
    ToolDeviation dev;
    try {
      dev = tool_deviation(kin, motion, from.axes, to.axes, from.tip, to.tip, plan.moves[i - 1].pose, want.pose, reach,
                           0.1 * options.chord_tol_mm, 0.1 * options.body_tol_mm);
      // The bound stands up to its resolution above the departure itself:
      // a block it puts beyond the allowance is measured again ten times
      // finer before it is refused (a block the split left at its
      // tolerance, its rotaries rounded the worst way, came out 10 nm over
      // with the coarse bound).
      if (dev.cutter_bound_mm > cutter_allowed || dev.body_bound_mm > body_allowed)
        dev = tool_deviation(kin, motion, from.axes, to.axes, from.tip, to.tip, plan.moves[i - 1].pose, want.pose,
                             reach, 0.01 * options.chord_tol_mm, 0.01 * options.body_tol_mm);
    } catch (const ParameterError& e) {
      throw DataError(file, got.line, std::string("this block cannot be swept: ") + e.what());
    }
    ++report.swept_moves;
    report.controller = motion;
    if (dev.cutter_bound_mm > report.max_cutter_mm) {
      report.max_cutter_mm = dev.cutter_bound_mm;
      report.worst_cutter_line = got.line;
    }
    report.max_body_mm = std::max(report.max_body_mm, dev.body_bound_mm);
    // The block nearest its allowance, for a verdict that states the limit.
    if (dev.cutter_bound_mm / cutter_allowed > report.tightest_cutter_mm / report.tightest_cutter_allowed_mm) {
      report.tightest_cutter_mm = dev.cutter_bound_mm;
      report.tightest_cutter_allowed_mm = cutter_allowed;
    }
    if (dev.body_bound_mm / body_allowed > report.tightest_body_mm / report.tightest_body_allowed_mm) {
      report.tightest_body_mm = dev.body_bound_mm;
      report.tightest_body_allowed_mm = body_allowed;
    }
    if (dev.cutter_bound_mm > cutter_allowed || dev.body_bound_mm > body_allowed) {
      std::ostringstream msg;
      msg.precision(4);
      msg << "swept as the controller moves (" << to_string(motion) << "), the "
          << (dev.cutter_bound_mm > cutter_allowed ? "cutter" : "tool") << " leaves the planned motion by "
          << (dev.cutter_bound_mm > cutter_allowed ? dev.cutter_bound_mm : dev.body_bound_mm) << " mm (allowed "
          << (dev.cutter_bound_mm > cutter_allowed ? cutter_allowed : body_allowed) << " mm; tool axis "
          << rad_to_deg(dev.axis_rad) << " deg off) at t = " << dev.worst_t << " of the block, plan move "
          << want.source + 1;
      if (want.row >= 0) msg << " (row " << want.row << ")";
      throw DataError(file, got.line, msg.str());
    }
  }
  return report;
}

}  // namespace bliskrun
