// The edge finish as a program: its moves in cutting order (rows' passes,
// links, lead-in and lead-out; a Stop where a link is refused) and the APT
// text written from them.
#include <cstdio>
#include <sstream>
#include <string>

#include "core/planning/edge_finish.h"
#include "core/toolpath/apt.h"

namespace bliskrun {

Toolpath edge_finish_moves(const EdgeFinishResult& result) {
  Toolpath moves;
  size_t link = 0;
  bool started = false;
  int last_row = -1;
  for (size_t r = 0; r < result.rows.size(); ++r) {
    const EdgeFinishRow& row = result.rows[r];
    const int ri = static_cast<int>(r);
    for (size_t i = 0; i < row.poses.size(); ++i) {
      const bool starts_pass = i == 0 || row.poses[i].segment != row.poses[i - 1].segment;
      if (!started) {
        if (result.lead_in.clear) moves.push_back({Move::Kind::Rapid, result.lead_in.away, ri, "start", {}});
        else moves.push_back({Move::Kind::Stop, ToolPose{}, ri, "stop", result.lead_in.reason});
      }
      last_row = ri;
      bool joined = false;  // reached on the surface from the last pass: one pass with it
      bool lifted = false;  // reached by a short lift, fed: one pass with it
      if (starts_pass && started) {
        const EdgeFinishLink& l = result.links.at(link++);
        joined = l.clear && l.direct;
        lifted = l.clear && l.lifted;
        if (!l.clear) moves.push_back({Move::Kind::Stop, ToolPose{}, ri, "stop", l.reason});
        else
          for (size_t k = 0; k < l.moves.size(); ++k)
            moves.push_back({lifted ? Move::Kind::Feed : Move::Kind::Rapid, l.moves[k], ri,
                             link_leg_name(l.legs.at(k)), {}});
      }
      const bool after_stop = !moves.empty() && moves.back().kind == Move::Kind::Stop;
      const char* motion =
          !starts_pass || joined ? "cut" : (moves.empty() || after_stop) ? "start" : "approach";
      moves.push_back({Move::Kind::Feed, row.poses[i].pose, ri, motion, {}});
      started = true;
    }
  }
  if (started) {
    if (result.lead_out.clear) moves.push_back({Move::Kind::Rapid, result.lead_out.away, last_row, "retract", {}});
    else moves.push_back({Move::Kind::Stop, ToolPose{}, last_row, "stop", result.lead_out.reason});
  }
  return moves;
}

EdgeProgramStats edge_program_stats(const EdgeFinishResult& result) {
  EdgeProgramStats st;
  for (const EdgeFinishLink& l : result.links) {
    st.direct_links += l.clear && l.direct ? 1 : 0;
    st.lifted_links += l.clear && l.lifted ? 1 : 0;
  }
  const Toolpath moves = edge_finish_moves(result);
  int run = 0;  // Feed moves in the current run
  auto close_run = [&] {
    if (run > 0) ++st.passes;
    if (run > 0 && run <= 2) ++st.single_move_passes;
    run = 0;
  };
  for (size_t i = 0; i < moves.size(); ++i) {
    const Move& m = moves[i];
    if (m.kind != Move::Kind::Feed) close_run();
    else ++run;
    if (m.kind == Move::Kind::Stop || i == 0 || moves[i - 1].kind == Move::Kind::Stop) continue;
    const double d = (m.pose.tip - moves[i - 1].pose.tip).norm();
    // A short lift's legs are fed but do not cut: only a "cut" feed does
    // (the first pose of a pass is an "approach" or "start").
    const bool cutting = m.kind == Move::Kind::Feed && moves[i - 1].kind == Move::Kind::Feed && m.motion == "cut";
    (cutting ? st.cutting_mm : st.non_cutting_mm) += d;
    // Fed but not cutting: a short lift's legs (retract, traverse) and the
    // way down into the next pass's first pose.
    if (!cutting && m.kind == Move::Kind::Feed && moves[i - 1].kind == Move::Kind::Feed) st.lift_mm += d;
    if (m.kind == Move::Kind::Rapid) st.rapid_mm += d;
    if (m.kind == Move::Kind::Feed && moves[i - 1].kind == Move::Kind::Rapid) st.plunge_mm += d;
  }
  close_run();
  return st;
}

ToolpathPasses edge_finish_passes(const EdgeFinishResult& result) {
  return toolpath_passes(edge_finish_moves(result));
}

std::string edge_finish_apt(const EdgeFinishResult& result, const EdgeFinishRequest& rq, const std::string& name) {
  std::ostringstream os;
  char buf[240];
  os << "$$ bliskrun blade edge finish (flat-end bottom) " << name << "\n";
  os << "$$ TOOL " << (rq.tool ? rq.tool->description() : std::string("?")) << "\n";
  std::snprintf(buf, sizeof buf, "$$ BAND %.6f %.6f CHORD_TOL %.6f ROWS %zu POSES %d REFUSALS %d\n", rq.band.e1_mm,
                rq.band.e2_mm, rq.steps.chord_tol_mm, result.rows.size(), result.total_poses, result.total_refusals);
  os << buf << "MULTAX\n";
  write_apt_moves(os, edge_finish_moves(result), [&](int row) {
    std::snprintf(buf, sizeof buf, "$$ ROW %d V %.6f WIDTH %.6f\n", row, result.rows[row].v, result.rows[row].width_mm);
    return std::string(buf);
  });
  os << "FINI\n";
  return os.str();
}

}  // namespace bliskrun
