// The paper's comparison (edge paper Fig. 8 and 9): the strip widths along
// one row by the paper's optimum, ours (each l its own φ) and the
// conventional side-edge positioning, and the rows the side-edge
// positioning needs over the same window.
#include <algorithm>
#include <string>

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

// The side-edge positioning's own rows over the window, planned by the
// bottom method's plan_rows with the side positions (EdgeMethod::Side): the
// same spacing (each row's narrowest strip as emitted) and the same stopping
// rule (this row's reach up covers the window's end). Before issue 38 they
// had a rule of their own (half the narrowest width, the strips taken as
// symmetric, no inserted contacts): built-in TE 17 side rows, 18 by the
// shared rule (LE 18 either way).
void plan_side_rows(const EdgeFinishRequest& rq, const std::vector<double>& ls, EdgeFinishResult& out,
                    Progress& progress) {
  EdgeFinishRequest side = rq;
  side.method = EdgeMethod::Side;
  out.side_rows = static_cast<int>(plan_rows(side, ls, progress).size());
  set_side_window(rq, out);
}

void set_side_window(const EdgeFinishRequest& rq, EdgeFinishResult& out) {
  out.side_window_mm = 0;
  const int n = 50;
  for (int i = 0; i < n; ++i)
    out.side_window_mm += (rq.edge->point(0.5, rq.v0 + (rq.v1 - rq.v0) * (i + 1) / n) -
                           rq.edge->point(0.5, rq.v0 + (rq.v1 - rq.v0) * i / n))
                              .norm();
}

}  // namespace bliskrun::edge_detail
