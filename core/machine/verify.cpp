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
    const ToolPose pose = replay(kin, got);
    const double position = (pose.tip - want.pose.tip).norm();
    const double angle = std::atan2(pose.axis.cross(want.pose.axis).norm(), pose.axis.dot(want.pose.axis));
    const double allowed_position = options.tol_mm + linear_slack +
                                    (got.tcp ? 0.0 : 2 * rotary_step * kin.lever_arm_mm(got.axes));
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
  }
  return report;
}

}  // namespace bliskrun
