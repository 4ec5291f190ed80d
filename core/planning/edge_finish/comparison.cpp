// The paper's comparison (edge paper Fig. 8 and 9): the strip widths along
// one row by the paper's optimum, ours (each l its own φ) and the
// conventional side-edge positioning, and the rows the side-edge
// positioning needs over the same window.
#include <algorithm>
#include <string>

#include "core/common/error.h"
#include "core/planning/edge_finish/internal.h"

namespace bliskrun::edge_detail {

// Along rq.comparison_row (the middle row by default).
EdgeWidthComparison compare_widths(const EdgeFinishRequest& rq, const std::vector<PlannedRow>& planned) {
  EdgeWidthComparison cmp;
  const int crow = rq.comparison_row >= 0 ? std::min<int>(rq.comparison_row, static_cast<int>(planned.size()) - 1)
                                          : static_cast<int>(planned.size()) / 2;
  const PlannedRow& pr = planned[crow];
  cmp.row = crow;
  cmp.v = pr.row.v;
  for (size_t i = 0; i < pr.contacts.size(); ++i) {
    const ContactPlan& c = pr.contacts[i];
    cmp.u.push_back(c.u);
    const double best_joint = c.joint_w.empty() ? 0 : *std::max_element(c.joint_w.begin(), c.joint_w.end());
    const double best_paper = c.paper_w.empty() ? 0 : *std::max_element(c.paper_w.begin(), c.paper_w.end());
    cmp.paper_mm.push_back(c.bottom ? best_paper : c.corner_w);
    cmp.joint_mm.push_back(c.bottom ? best_joint : c.corner_w);
    cmp.side_mm.push_back(c.side_w);
    cmp.contact.push_back(c.bottom ? "bottom" : "corner");
  }
  for (const EdgeFinishPose& p : pr.row.poses) cmp.bottom_mm.push_back(p.width_mm);
  return cmp;
}

// The side-edge positioning's own rows over the window, each spaced by its
// narrowest strip, and the window's length along the span (mm).
void plan_side_rows(const EdgeFinishRequest& rq, const std::vector<double>& ls, EdgeFinishResult& out,
                    Progress& progress) {
  double vs = rq.v0;
  int rows = 0;
  progress.begin("edge finish, side-edge rows", 0);
  while (true) {
    progress.step(rows);
    ++rows;
    const PlannedRow pr = plan_row(rq, vs, ls, true, progress);
    // The side contact is symmetric across the feed (φ = 0): half each way.
    const double w = pr.row.side_width_mm;
    if (!(w > 1e-6)) throw Error("edge finish: side-edge positioning has no strip at v = " + std::to_string(vs));
    if ((rq.v1 - vs) * max_pv(rq, vs) <= w / 2 || vs >= rq.v1 - 1e-12) break;
    vs = std::min(rq.v1, vs + w / max_pv(rq, vs));
  }
  out.side_rows = rows;
  out.side_window_mm = 0;
  const int n = 50;
  for (int i = 0; i < n; ++i)
    out.side_window_mm += (rq.edge->point(0.5, rq.v0 + (rq.v1 - rq.v0) * (i + 1) / n) -
                           rq.edge->point(0.5, rq.v0 + (rq.v1 - rq.v0) * i / n))
                              .norm();
}

}  // namespace bliskrun::edge_detail
