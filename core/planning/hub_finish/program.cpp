// The hub finish as a program: the root part, the join (its rapids, or a
// Stop where it is refused) and the channel part, each part's passes with
// its steps, links and leads; and the APT text written from them.
#include <algorithm>
#include <cstdio>
#include <sstream>
#include <string>
#include <utility>

#include "core/planning/hub_finish/internal.h"
#include "core/planning/pass_moves.h"
#include "core/toolpath/apt.h"

namespace bliskrun {
namespace hub_detail {
namespace {

// One part's program (hub_finish_moves(part)), without its lead-in or its
// lead-out where the join replaces them.
Toolpath part_moves(const HubFinishPart& part, bool lead_in, bool lead_out) {
  return passes_to_moves(part.passes, part.connections, lead_in, lead_out);
}

}  // namespace

Program program_of(const HubFinishResult& r) {
  Program p;
  const bool both = !r.root.passes.empty() && !r.channel.passes.empty();
  const bool joined = both && r.join.clear;
  p.root = part_moves(r.root, true, !joined);
  p.channel = part_moves(r.channel, !joined, true);
  if (!both) return p;
  const int row = r.channel.passes.front().row;
  if (joined) {
    for (const ToolPose& pose : r.join.poses) {
      Move m;
      m.kind = Move::Kind::Rapid;
      m.pose = pose;
      m.row = row;
      m.motion = "link";
      p.join.push_back(std::move(m));
    }
  } else {
    Move stop;
    stop.kind = Move::Kind::Stop;
    stop.row = row;
    stop.motion = "stop";
    stop.reason = r.join.reason;
    p.join.push_back(std::move(stop));
  }
  return p;
}

}  // namespace hub_detail

using hub_detail::part_moves;
using hub_detail::Program;
using hub_detail::program_of;

Toolpath hub_finish_moves(const HubFinishPart& part) { return part_moves(part, true, true); }

Toolpath hub_finish_moves(const HubFinishResult& r) {
  Program p = program_of(r);
  Toolpath out = std::move(p.root);
  out.insert(out.end(), p.join.begin(), p.join.end());
  out.insert(out.end(), p.channel.begin(), p.channel.end());
  return out;
}

std::string hub_finish_apt(const HubFinishResult& result, const HubFinishRequest& rq) {
  std::ostringstream os;
  char buf[240];
  os << "$$ bliskrun hub and blade-root finish\n";
  os << "$$ TOOL " << (rq.tool ? rq.tool->description() : std::string("?")) << "\n";
  std::snprintf(buf, sizeof buf, "$$ SCALLOP %.6f CHORD_TOL %.6f ROOT_ROWS %d CHANNEL_ROWS %d POSES %d REFUSALS %zu\n",
                rq.scallop_mm, rq.steps.chord_tol_mm, result.root.rows, result.channel.rows,
                result.root.poses + result.channel.poses, result.refusals.size());
  os << buf;
  os << "MULTAX\n";
  const Program p = program_of(result);
  auto rows = [](int row) { return "$$ ROW " + std::to_string(row) + "\n"; };
  if (!p.root.empty()) {
    os << "$$ OPERATION root\n";
    write_apt_moves(os, p.root, rows);
  }
  if (!p.join.empty()) {
    if (result.join.clear) os << "$$ JOIN root to channel (" << result.join_route << ")\n";
    write_apt_moves(os, p.join, rows, "JOIN REFUSED");
  }
  if (!p.channel.empty()) {
    os << "$$ OPERATION channel\n";
    write_apt_moves(os, p.channel, rows);
  }
  os << "FINI\n";
  return os.str();
}

}  // namespace bliskrun
