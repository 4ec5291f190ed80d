#pragma once
// Proving a program: read it back, replay every move through the machine's
// kinematics and compare with the plan it was written from — at every block
// end, and swept between blocks as the controller interpolates them.
//
// Move i of the program must be move i of the plan (posts add no motion of
// their own) and of the same kind. For each the replayed tip and axis (full
// forward kinematics, or with TCP control the programmed tip and the axis of
// the programmed rotaries) are compared with the planned pose. A move may
// deviate by the tolerance plus what the output resolution explains: half a
// linear step per axis, and half a rotary step per rotary axis times the lever
// arm from that axis to the tip (zero with TCP control, where the controller
// places the tip itself).
//
// Between blocks. Each block is swept as its controller moves it
// (ControllerMotion, from what the program says: TCP on or off, PATHCTRL
// AXIS or VECTOR) and the whole tool compared with the planned motion
// between the plan's poses (motion.h tool_deviation): the cutter must stay
// within chord_tol_mm and the rest of the tool within body_tol_mm, plus what
// the output resolution explains. This is the proof that what the machine
// does is what the planner proved. Not swept, and counted: the first block
// of a tool without a planned way in (it starts from wherever the tool
// change left the machine), and the moves at the safe height (Retract,
// Rotate, Position — each checked to move only its own axes).
#include <string>
#include <vector>

#include "core/machine/kinematics.h"
#include "core/machine/motion.h"
#include "core/machine/program_reader.h"

namespace bliskrun {

struct VerifyOptions {
  double tol_mm = 0.001;                       // beyond output resolution
  double angle_tol_rad = deg_to_rad(0.001);    // beyond output resolution
  ProgramReadOptions read;                     // file name for messages, TCP from the start
  // With several tools: the tool number each plan tool index must be read
  // back as (T word, TOOL CALL); empty = not checked.
  std::vector<int> tool_numbers;
  // The sweep: per plan tool index the tool's reach (empty: tip only) and
  // the tolerances (the post's split tolerances).
  std::vector<ToolReach> reaches;
  double chord_tol_mm = 0.005;
  double body_tol_mm = 0.05;
};

struct VerifyReport {
  long moves = 0;
  double max_position_mm = 0;   // largest tip deviation from the plan
  double max_angle_rad = 0;     // largest tool-axis deviation from the plan
  int worst_position_line = 0;  // program line of the largest tip deviation
  int worst_angle_line = 0;
  // The sweep between blocks: the largest departure of the cutter and of
  // the whole tool from the planned motion, where.
  double max_cutter_mm = 0;
  double max_body_mm = 0;
  int worst_cutter_line = 0;
  // The swept block nearest its allowance (the tolerance plus what the
  // output resolution explains there), cutter and whole tool: its deviation
  // and that allowance (0 / 1 when nothing was swept).
  double tightest_cutter_mm = 0, tightest_cutter_allowed_mm = 1;
  double tightest_body_mm = 0, tightest_body_allowed_mm = 1;
  long swept_moves = 0;
  long unswept_moves = 0;   // from a tool change without a way in
  long safe_moves = 0;      // Retract, Rotate, Position (checked by their axes)
  ControllerMotion controller = ControllerMotion::JointLinear;  // of the last swept block
};

// Throws DataError at the program line of the first move beyond tolerance or
// not matching the plan (count, kind). Feed words are not compared: they do
// not place the tool. Returns the report when every move is within.
VerifyReport verify_program(const std::string& text, const Kinematics& kin,
                            const MachineProgram& plan, const VerifyOptions& options);
// The same for a program of several tools: move i is replayed with
// kins[plan.moves[i].tool].
VerifyReport verify_program(const std::string& text, const std::vector<const Kinematics*>& kins,
                            const MachineProgram& plan, const VerifyOptions& options);

// Replays one read-back move: the tool pose it puts in the part frame.
ToolPose replay(const Kinematics& kin, const ProgramMove& move);

}  // namespace bliskrun
