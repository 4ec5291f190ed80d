#pragma once
// From planned tool poses to machine-axis moves.
//
// Between two blocks a controller without tool-centre-point control moves all
// axes linearly; with a rotary axis in the move the tip then leaves the
// planned straight segment (blisk paper §3.4 assumes it does not). Each feed
// move is measured and, where the departure exceeds the chord tolerance,
// split by inserting poses on the planned segment (tip linear, axis along the
// great circle) until every piece is within tolerance. With TCP control
// (G43.4, TRAORI, M128) the controller keeps the tip on the segment and no
// move is split.
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
#include <string>
#include <vector>

#include "core/common/progress.h"
#include "core/machine/kinematics.h"

namespace bliskrun {

enum class MoveKind { Rapid, Feed };

struct PlannedMove {
  MoveKind kind = MoveKind::Feed;
  ToolPose pose;
  double feed_mm_per_min = 0;  // feed moves: tip speed along the path
  long row = -1;               // provenance for messages; -1 when not in a row
};

struct MotionOptions {
  double chord_tol_mm = 0.005;  // allowed departure of the tip from the planned segment
  bool tcp = false;             // the controller interpolates the tip (no splitting)
  int max_depth = 10;           // split rounds per move before giving up
  MachineAxes start;            // axes before the first move: continuity reference
  // At each rapid move the rotary branch is chosen by following the next feed
  // moves (up to this many) on each branch: see plan_machine_motion.
  size_t branch_lookahead = 20000;
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
};

struct MachineProgram {
  std::vector<MachineMove> moves;
  FeedMode feed_mode = FeedMode::PerMinute;
  bool tcp = false;
  double max_deviation_mm = 0;  // bound on the tip departure over all feed moves, after splitting
  long inserted_moves = 0;
  long skipped_moves = 0;       // planned moves that did not move any axis
  long positioning_moves = 0;   // planned rapids posted as feed moves at the rapid feed
};

// The departure of the tip from the straight segment tip_from -> tip_to (part
// frame) while the machine moves its axes linearly from `from` to `to`.
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
                                   Progress& progress = Progress::none());

// One program, several tools: `path` is cut in segments where `tool_of`
// changes (tool_of[i] indexes `kins`, one Kinematics per tool — its length
// moves the tip on head axes and in gauge mode). Each segment is planned as a
// program of its own, its first move a rapid from the tool change position;
// the moves carry their tool index and `source` counts in the whole path.
MachineProgram plan_machine_motion_tools(const std::vector<const Kinematics*>& kins,
                                         const std::vector<PlannedMove>& path, const std::vector<int>& tool_of,
                                         const MotionOptions& options, Progress& progress = Progress::none());

// The pose at t in [0, 1] of the planned motion from a to b: tip linear, axis
// along the great circle. Throws ParameterError("axis") when the axes are
// opposite (no unique great circle).
ToolPose interpolate_pose(const ToolPose& a, const ToolPose& b, double t);

}  // namespace bliskrun
