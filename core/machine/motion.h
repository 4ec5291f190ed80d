#pragma once
// From planned tool poses to machine-axis moves, and the motion a controller
// makes between two blocks.
//
// The planner proved every move with the tool on the *planned motion*: tip
// on the straight segment, tool axis turning along the great circle
// (interpolate_pose). A controller moves otherwise (ControllerMotion):
//   - without tool-centre-point control every machine axis is interpolated
//     linearly (joint-linear): the tip leaves the segment and the axis the
//     great circle wherever a rotary axis turns;
//   - with TCP and linear rotaries (Heidenhain FUNCTION TCPM ... PATHCTRL
//     AXIS, Fanuc G43.4, Siemens TRAORI with ORIAXES, LinuxCNC trt) the tip
//     stays on the segment but the axis follows the rotary axes' straight
//     line, not the great circle — tens of degrees off where one block turns
//     C by 90 deg or more near the pole;
//   - with TCP and vector orientation (PATHCTRL VECTOR, ORIVECT) the axis
//     follows the great circle: the planned motion itself.
// Each move is measured with the *whole tool* (tool_deviation: the tip's
// departure plus the reach of the tool times the axis' departure) and split
// by inserting poses of the planned motion until the cutter stays within
// the chord tolerance and the rest of the tool (shank, holder) within the
// body tolerance of the proved motion. The same model sweeps the program
// read back (verify.h).
//
// Rapids. On a rapid each axis runs at its own rate along a path the program
// does not define, yet the planner proved every link clear along the same
// straight segment (tip linear, axis along the great circle) as a feed move.
// So a rapid stays a rapid only where the machine follows that segment anyway
// (one linear axis, or linear axes on a controller that interpolates rapids
// linearly — MachineDefinition::rapid); every other planned rapid becomes a
// *positioning* feed move at the machine's rapid feed, split like a cutting
// move. A positioning move that would have to change the rotary branch (the
// same tool axis reached by other rotary angles) cannot follow the segment at
// all and is refused: the plan must retract to where any motion is safe.
#include <array>
#include <limits>
#include <string>
#include <vector>

#include "core/common/progress.h"
#include "core/machine/kinematics.h"

namespace bliskrun {

enum class MoveKind { Rapid, Feed };

// How the controller interpolates the tool between two blocks (see above).
enum class ControllerMotion { JointLinear, TcpRotaryLinear, TcpVector };
// "joint-linear", "TCP, rotaries linear", "TCP, vector orientation".
const char* to_string(ControllerMotion motion);

// How far a tool reaches from its tip: what turns a departure of the tool
// axis into a departure of tool points, and a rotation into cutter speed.
struct ToolReach {
  double cutter_mm = 0;  // farthest point of the cutting part (Tool::cutter) from the tip
  double body_mm = 0;    // farthest point of the whole tool (cutter, shank, holder)
  // Farthest point of the part of the cutter that cuts in this program
  // (e.g. a flat-end mill's bottom and corner in edge finishing): what
  // the feed at the cutter is measured on; <= 0: cutter_mm.
  double active_mm = 0;
  double active() const { return active_mm > 0 ? active_mm : cutter_mm; }
};

struct PlannedMove {
  MoveKind kind = MoveKind::Feed;
  ToolPose pose;
  double feed_mm_per_min = 0;  // feed moves: tip speed along the path
  long row = -1;               // provenance for messages; -1 when not in a row
};

// The moves a program makes besides the plan: the way from the tool change
// position to the first planned pose of a tool, and from its last pose
// back up (plan_machine_motion_tools with MotionOptions::approach).
//   Retract  Z alone to the safe height, from wherever the tool change left
//            the machine (one axis: a defined path);
//   Rotate   the rotary axes alone, to those of the first pose, at the safe
//            height;
//   Position X and Y alone, at the safe height, over the first pose;
//   Descend  Z alone, down to the first pose: in the part frame along the
//            tool axis on a table-table machine (the spindle is the Z), along
//            the part's +Z under a head over a C table — the plan proved
//            that line clear (MotionOptions::approach);
//   Lift     Z alone, up from the last pose to the safe height.
// Retract, Rotate and Position run at the safe height, above the part by the
// machine file's statement; the machine's own bodies are not modelled here.
enum class SafeMove { None, Retract, Rotate, Position, Descend, Lift };
const char* to_string(SafeMove move);  // "", "retract", "rotate", "position", "descend", "lift"

struct ApproachOptions {
  bool enabled = false;
  // How far from each tool's first and last planned pose the plan proved
  // the line clear (mm), out along the tool axis and up the part frame's
  // +Z: a descent or lift longer than that (or along another line) is
  // refused.
  double proved_mm = 0;
  double proved_up_mm = 0;
  // The safe height as the machine's Z word (program zero frame); NaN: the
  // top of the Z slide's travel (Kinematics::safe_z_mm).
  double safe_z_mm = std::numeric_limits<double>::quiet_NaN();
};

struct MotionOptions {
  double chord_tol_mm = 0.005;  // allowed departure of the cutter from the planned motion
  double body_tol_mm = 0.05;    // allowed departure of the shank and holder
  bool tcp = false;             // the controller interpolates the tip
  bool tcp_vector = false;      // ... and the tool axis along the great circle (PATHCTRL VECTOR)
  int max_depth = 10;           // split rounds per move before giving up
  MachineAxes start;            // axes before the first move: continuity reference
  // At each rapid move the rotary branch is chosen by following the next feed
  // moves (up to this many) on each branch: see plan_machine_motion.
  size_t branch_lookahead = 20000;
  // Feed at the cutter: no point of the cutter moves faster than this times
  // the planned feed (rotation-heavy blocks get a lower F), and no rotary
  // axis faster than its RotaryAxis::max_speed_rad_per_min.
  double cutter_feed_factor = 1.5;
  // Continuous rotary axes: the largest value the controller takes (e.g.
  // 99 999.9999 deg on a TNC). Where an axis would leave it, or wind past one
  // turn, at a rapid move, the program resets the axis' display to [0, 360)
  // deg (MachineMove::rotary_reset) when `rotary_reset` allows; otherwise a
  // value beyond the limit is refused.
  double rotary_input_limit_rad = std::numeric_limits<double>::infinity();
  bool rotary_reset = false;
  ApproachOptions approach;
  ControllerMotion controller() const {
    return !tcp ? ControllerMotion::JointLinear
                : (tcp_vector ? ControllerMotion::TcpVector : ControllerMotion::TcpRotaryLinear);
  }
};

struct MachineMove {
  MoveKind kind = MoveKind::Feed;
  MachineAxes axes;
  ToolPose pose;       // planned pose at the end of this move (part frame)
  double feed = 0;     // F word: mm/min (per minute) or 1/min (inverse time); 0 for rapids
  long source = 0;     // index of the planned move this one ends or belongs to
  long row = -1;
  bool inserted = false;  // added by splitting; ends inside the planned move
  bool positioning = false;  // a planned rapid posted as a feed move (see above)
  int tool = 0;              // index of the tool (plan_machine_motion_tools); 0 with one tool
  SafeMove safe = SafeMove::None;
  // Before this move the controller resets the display of rotary axis i by
  // this many turns (2*pi each, subtracted); 0 for none.
  std::array<int, 2> rotary_reset{0, 0};
  // Feed at the cutter (feed moves): the fastest cutter point over the
  // block relative to the planned feed, after the F word's choice.
  double cutter_speed_ratio = 0;
};

struct MachineProgram {
  std::vector<MachineMove> moves;
  FeedMode feed_mode = FeedMode::PerMinute;
  bool tcp = false;
  ControllerMotion controller = ControllerMotion::JointLinear;
  double max_deviation_mm = 0;  // bound on the cutter's departure over all moves, after splitting
  double max_body_deviation_mm = 0;  // the same for the whole tool
  long inserted_moves = 0;
  long skipped_moves = 0;       // planned moves that did not move any axis
  long positioning_moves = 0;   // planned rapids posted as feed moves at the rapid feed
  long slowed_moves = 0;        // feed moves whose F was lowered for the cutter or a rotary axis
  // TCP feed moves that hardly move the tip: F (the tip's speed) cannot time
  // them; the controller's rotary speed limits do.
  long untimed_moves = 0;
  double max_cutter_speed_ratio = 0;   // over the feed moves, after slowing
  std::array<double, 2> max_rotary_speed_rad_per_min{0.0, 0.0};  // over the feed moves
  long rotary_resets = 0;
  // Time of the feed moves (cutting and positioning) as the F words ask
  // it, and as the tip alone at the planned feeds would take: what the
  // slowing for the cutter and the rotary axes costs. Rapids not counted.
  double minutes = 0, tip_feed_minutes = 0;
};

// The tool's departure from the planned motion while the controller moves
// from one block to the next. For TCP modes tip_from/tip_to are the blocks'
// tips (the controller's straight line); joint-linear moves use the axes
// only. The planned motion runs from plan_from to plan_to (interpolate_pose).
// At each sample the controller's tool is compared with the planned pose at
// the same place along the segment (the projection of its tip, less the
// offset of the blocks' ends from the planned ones shared linearly along the
// block — a rounded end is still the planned end; the same t where the
// segment is shorter than 0.05 mm): tip distance + reach * |axis
// difference| bounds the distance of every tool point within that reach
// (a body of revolution about its axis). `*_bound_mm` add what can happen
// between samples (second derivatives of tip and axis: see the .cpp);
// samples are added until that margin is at most margin_mm for the cutter
// and body_margin_mm (<= 0: margin_mm) for the whole tool, or 4096 samples.
struct ToolDeviation {
  double cutter_mm = 0, body_mm = 0;              // largest sampled
  double cutter_bound_mm = 0, body_bound_mm = 0;  // never below the truth
  double axis_rad = 0;                            // largest sampled axis departure
  double worst_t = 0;                             // where the cutter's was largest
  int samples = 0;
};
ToolDeviation tool_deviation(const Kinematics& kin, ControllerMotion motion, const MachineAxes& from,
                             const MachineAxes& to, const Vec3& tip_from, const Vec3& tip_to,
                             const ToolPose& plan_from, const ToolPose& plan_to, const ToolReach& reach,
                             double margin_mm, double body_margin_mm = 0);

// The tool at t in [0, 1] of a block, as the controller moves it.
ToolPose controller_pose(const Kinematics& kin, ControllerMotion motion, const MachineAxes& from,
                         const MachineAxes& to, const Vec3& tip_from, const Vec3& tip_to, double t);

// The machine axes at t in [0, 1] of a block as the controller moves them
// (the motion of controller_pose, in machine axes, for placing the machine's
// own bodies — machine_sim.h): joint-linear, the axes' straight line; TCP,
// the rotaries linear (vector orientation: the rotary solution of the great
// circle's axis nearest the linear one) and the slides where they put the
// tip on tip_from -> tip_to (Kinematics::linear_for).
MachineAxes controller_axes(const Kinematics& kin, ControllerMotion motion, const MachineAxes& from,
                            const MachineAxes& to, const Vec3& tip_from, const Vec3& tip_to, double t);

// The departure of the tip alone from the straight segment tip_from -> tip_to
// (part frame) while the machine moves its axes linearly from `from` to `to`
// (the planner and the sweep measure the whole tool: tool_deviation).
// `sampled_mm` is the largest distance seen at evenly spaced samples;
// `bound_mm` adds the most the tip can stray between two samples, from a bound
// on its acceleration (rotations at constant rates summing to W about pivots
// within rho of the tip, linear axes at speed v: |tip''| <= 2 W^2 rho + 2 W v),
// so the true maximum never exceeds `bound_mm`. Samples are added until that
// margin is at most `margin_mm` (or 4096 samples).
struct MoveDeviation {
  double sampled_mm = 0;
  double bound_mm = 0;
  int samples = 0;
};
MoveDeviation move_deviation(const Kinematics& kin, const MachineAxes& from, const MachineAxes& to,
                             const Vec3& tip_from, const Vec3& tip_to, double margin_mm);

// Inverse kinematics along the path (continuity from move to move; at a rapid
// move, or the first, the branch that carries furthest through the following
// feed moves without a jump or a travel limit), splitting of feed moves to the
// chord tolerance, feed words per the machine's feed mode (per minute under
// TCP control, where F is the tip's speed). A pose out of reach throws
// ParameterError naming the machine axis, with the move (counted from 1), its
// row and pose in the message.
MachineProgram plan_machine_motion(const Kinematics& kin, const std::vector<PlannedMove>& path,
                                   const MotionOptions& options,
                                   Progress& progress = Progress::none(), const ToolReach& reach = {});

// One tool of a program: its kinematics (its length moves the tip on head
// axes and in gauge mode) and its reach.
struct MotionTool {
  const Kinematics* kin = nullptr;
  ToolReach reach;
};

// One program, several tools: `path` is cut in segments where `tool_of`
// changes (tool_of[i] indexes `tools`). Each segment is planned as a program
// of its own; with options.approach each starts with the safe way in from
// the tool change position (Retract, Rotate, Position, Descend) and the
// program ends with a Lift; without, a segment's first move is a move from
// wherever the tool change left the machine. The moves carry their tool
// index and `source` counts in the whole path.
MachineProgram plan_machine_motion_tools(const std::vector<MotionTool>& tools, const std::vector<PlannedMove>& path,
                                         const std::vector<int>& tool_of, const MotionOptions& options,
                                         Progress& progress = Progress::none());

// The pose at t in [0, 1] of the planned motion from a to b: tip linear, axis
// along the great circle. Throws ParameterError("axis") when the axes are
// opposite (no unique great circle).
ToolPose interpolate_pose(const ToolPose& a, const ToolPose& b, double t);

}  // namespace bliskrun
