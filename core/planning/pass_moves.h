#pragma once
// The program of a plan made of passes (rows of poses, cut at feed) joined
// by proved connections (lead-in, steps or links between passes, lead-out):
// the shape the hub finish and point milling share. connections[0] leads in,
// connections[p + 1] joins pass p to pass p + 1, the last leads out. A
// connection that could not be proved is a Stop with its reason, never a
// motion. A pass's first move is named after how it was reached ("approach"
// after a link or lead, "step" after a step), the rest "cut".
#include <algorithm>
#include <string>
#include <vector>

#include "core/toolpath/move.h"

namespace bliskrun {

// A proved (or refused) join of such a plan: the hub finish and point
// milling both use this one type (HubFinishConnection, PointMillConnection
// name it), so a link or lead is built and checked the same way in both.
struct PassConnection {
  enum class Kind { Step, Link, Departure };
  Kind kind = Kind::Step;
  int from_pass = -1, to_pass = -1;   // -1: the operation's start / end
  std::vector<ToolPose> poses;        // between the passes' own poses
  std::vector<std::string> motion;    // "step", or a link's "retract"/"traverse"/"approach", "start"
  bool clear = false;
  std::string reason;                 // why not clear
};

// `lead_in` / `lead_out` false: that connection is left out (something
// else, e.g. a join between two parts, replaces it).
template <class Pass, class Connection>
Toolpath passes_to_moves(const std::vector<Pass>& passes, const std::vector<Connection>& connections,
                         bool lead_in = true, bool lead_out = true) {
  Toolpath out;
  if (passes.empty()) return out;
  for (size_t p = 0; p <= passes.size(); ++p) {
    const Connection& c = connections[p];
    const int row = passes[std::min(p, passes.size() - 1)].row;
    const char* reach = "approach";
    if ((p == 0 && !lead_in) || (p == passes.size() && !lead_out)) {
      // left to the caller
    } else if (!c.clear) {
      out.push_back(Move{Move::Kind::Stop, ToolPose{}, row, "stop", c.reason});
    } else {
      const bool step = c.kind == Connection::Kind::Step;
      for (size_t i = 0; i < c.poses.size(); ++i)
        out.push_back(Move{step ? Move::Kind::Feed : Move::Kind::Rapid, c.poses[i], row, c.motion[i], ""});
      if (step) reach = "step";
    }
    if (p == passes.size()) break;
    const Pass& pass = passes[p];
    for (size_t i = 0; i < pass.poses.size(); ++i)
      out.push_back(Move{Move::Kind::Feed, pass.poses[i].pose, pass.row, i == 0 ? reach : "cut", ""});
  }
  return out;
}

}  // namespace bliskrun
