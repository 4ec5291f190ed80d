#pragma once
// One toolpath type for every operation (issue 35): each planner turns its
// plan into a Toolpath — the drum finish (drum_finish_moves), the edge
// finish, the hub finish, the repair paths and the channel roughing — and
// every consumer takes that one shape: the undercut simulation through
// toolpath_passes, the APT writer (core/toolpath/apt.h), the Lua binding's
// plan:moves() that the posts, VTK and the job read. None of them needs to
// know which strategy made the moves.
//
// Above core/tools (a move is a ToolPose), below core/planning (which fills
// it); core/sim takes plain pose passes and does not need it.
#include <string>
#include <vector>

#include "core/tools/pose.h"

namespace bliskrun {

// A move ends at `pose`. Feed: the cutter moves there at the cutting feed
// (along a row, a step-over, a proved feed connection); Rapid: at rapid
// (a link's or a lead's proved leg). Stop: the planner could not prove the
// motion that would come here (a refused link, lead-in or lead-out); the
// program stops with `reason` rather than imply an unchecked move, and the
// pose is unset.
//
// `motion` names the motion that ends at the move. It stays a string, not
// an enum: every consumer uses it as a name (Lua's plan:moves(), the job's
// JSON and report, the simulation's "the overcut was cut by a <motion>"),
// and the planners' connections (links.h's link_leg_name, the hub's and the
// repair's connection motion lists) already carry it as a name. The names
// in use:
//   "start"     the first pose of a program, or a row's first after a Stop
//   "cut"       along a row or pass
//   "approach"  a link's last leg, or a row's first pose reached by one
//   "retract", "traverse"   a link's legs (LinkLeg), a lead-out
//   "step"      a direct step-over or step-down at the feed between rows
//   "link"      the hub finish's join from the root part to the channel part
//   "lead-in", "lead-out", "bridge"   the repair paths' arc connections
//   "stop"      a Stop
//
// Provenance: the issue names tool, feed, operation, blade and contact as
// per-move fields. No C++ planner fills them and no C++ consumer reads them
// today — each plan is one operation with one tool on one surface, and the
// whole-part job (scripts/lib/job.lua) attaches tool, operation and blade
// when it strings plans into programs — so they are not fields here yet. A
// field is added, with its default, when a planner or consumer first needs it.
struct Move {
  enum class Kind { Feed, Rapid, Stop };
  Kind kind = Kind::Feed;
  ToolPose pose;       // Feed, Rapid
  int row = 0;         // the plan's row (pass) the move cuts or leads into, 0-based
  std::string motion;  // see above
  std::string reason;  // Stop: why the motion here was refused
};

// "feed", "rapid", "stop": the kind as the Lua binding's plan:moves() and
// the reports name it.
const char* to_string(Move::Kind kind);

// A program in cutting order. Nothing more than its moves: the APT writer
// takes the planner's row header and stop label as arguments, and the
// simulation's passes are derived (toolpath_passes).
using Toolpath = std::vector<Move>;

// The program's motion for the undercut simulation (core/sim): every move —
// rows and links — as passes, one per stretch of continuous motion (a Stop
// ends one). `first_move[p]` is the index in the toolpath of pass p's first
// pose, so a simulation result (pass, pose) names its move:
// first_move[pass] + pose.
struct ToolpathPasses {
  std::vector<std::vector<ToolPose>> passes;  // core/sim's ToolPass each
  std::vector<long> first_move;
};
ToolpathPasses toolpath_passes(const Toolpath& moves);

}  // namespace bliskrun
