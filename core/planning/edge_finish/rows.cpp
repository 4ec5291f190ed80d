// Rows around the edge at constant span v (the paper's §3.2): each row's
// contacts stepped by chord height and planned on the workers, l balanced
// along the row, the emitted poses refined where the motion between two
// dips below e1, and the rows spaced by their narrowest strips.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "core/common/error.h"
#include "core/common/parallel.h"
#include "core/planning/edge_finish/internal.h"

namespace bliskrun::edge_detail {

// `only` (may be null): plan just the contacts within these parts of the
// row, each with the contact just outside either end (so the strips reach
// over the whole part), for a partial row; each part's contacts carry its
// index as their piece.
PlannedRow plan_row(const EdgeFinishRequest& rq, double v, const std::vector<double>& ls, bool side_only,
                    Progress& progress, const Intervals* only, const RowSeeds* seeds) {
  PlannedRow pr;
  pr.row.v = v;
  const IsoVCurve curve(*rq.edge, v);
  const RowSteps steps = plan_row_steps(curve, rq.steps);
  pr.row.max_deviation_mm = steps.max_deviation_mm;
  const size_t n = steps.t.size();
  std::vector<int> piece(n, 0);
  if (only) {
    std::vector<int> owner(n, -1);
    for (size_t i = 0; i < n; ++i)
      for (size_t k = 0; k < only->size(); ++k)
        if (steps.t[i] >= (*only)[k].first - 1e-12 && steps.t[i] <= (*only)[k].second + 1e-12) owner[i] = static_cast<int>(k);
    piece = owner;
    for (size_t i = 0; i < n; ++i) {
      if (piece[i] >= 0) continue;
      if (i + 1 < n && owner[i + 1] >= 0) piece[i] = owner[i + 1];
      else if (i > 0 && owner[i - 1] >= 0) piece[i] = owner[i - 1];
    }
    // A part with no step inside it (the steps are far apart where the
    // row is nearly straight: on Rotor 67's TE overlap from u 0 to 0.19)
    // takes the steps either side: the cut between them covers it. Without
    // them the partial row was empty and the part stayed as it was (26 um).
    for (size_t k = 0; k < only->size(); ++k) {
      if (std::find(owner.begin(), owner.end(), static_cast<int>(k)) != owner.end()) continue;
      const auto above = std::lower_bound(steps.t.begin(), steps.t.end(), (*only)[k].second);
      const size_t hi = static_cast<size_t>(above - steps.t.begin());
      if (hi < n && piece[hi] < 0) piece[hi] = static_cast<int>(k);
      if (hi > 0 && piece[hi - 1] < 0) piece[hi - 1] = static_cast<int>(k);
    }
  }
  std::vector<size_t> which;
  for (size_t i = 0; i < n; ++i)
    if (piece[i] >= 0) which.push_back(i);
  // The contacts of a row are independent (each its own samples and
  // searches): on rq.threads workers, each writing its own slot.
  pr.contacts.resize(which.size());
  pr.row_samples = row_gouge_samples(rq, v);
  const RowGougeSamples& row_samples = pr.row_samples;
  Progress quiet(&progress);  // cancelled with the caller's, its own bar
  run_parallel(which.size(), rq.threads, quiet, "edge finish contacts", [&](size_t k, Progress&) {
    pr.contacts[k] = plan_contact(rq, steps.t[which[k]], v, ls, side_only, row_samples, seeds);
    pr.contacts[k].piece = piece[which[k]];
  });
  for (const ContactPlan& c : pr.contacts) pr.row.strip_evaluations += c.evaluations;
  // Over the contacts where the side-edge positioning has a gouge-free
  // position (a contact where it has none does not bound its rows; the
  // count of such contacts is left to the width table of the comparison).
  double side = std::numeric_limits<double>::infinity();
  for (const ContactPlan& c : pr.contacts)
    if (c.side_w > 0) side = std::min(side, c.side_w);
  pr.row.side_width_mm = std::isfinite(side) ? side : 0.0;
  if (side_only) return pr;
  const BalancedRow paper = balance(pr.contacts, true, ls.size());
  const BalancedRow joint = balance(pr.contacts, false, ls.size());
  pr.row.paper_width_mm = paper.width_mm;
  pr.row.joint_width_mm = joint.width_mm;
  pr.emitted = rq.optimum == EdgeOptimum::Paper ? paper : joint;
  pr.row.width_mm = pr.emitted.width_mm;
  return pr;
}

double motion_deepest(const EdgeFinishPose& a, const EdgeFinishPose& b, const ContactStrip& sa, const ContactStrip& sb) {
  const PoseMotion m(a.pose, b.pose);
  double d = std::numeric_limits<double>::infinity();
  for (double t : {0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875}) {
    const ToolPose p = m.pose_at(t);
    d = std::min({d, sa.deepest(p), sb.deepest(p)});
  }
  return d;
}

// The contact half-way between two poses of a row (same part), at
// `position`, on a strip of its own: what refine_row and refine_tilted
// insert. Returns the pose and its strip's width there.
std::pair<EdgeFinishPose, StripWidth> halfway_pose(const EdgeFinishRequest& rq, const RowGougeSamples& row_samples,
                                                   const EdgeFinishPose& a, const EdgeFinishPose& b,
                                                   const EdgePosition& position) {
  EdgeFinishPose m;
  m.u = 0.5 * (a.u + b.u);
  m.v = a.v;
  m.position = position;
  const EdgeFrame f = edge_frame(rq.edge->eval(m.u, m.v));
  m.strip = make_strip(rq, f, m.u, m.v, row_samples);
  const StripWidth w = m.strip->width(m.position);
  m.pose = m.strip->pose(m.position);
  m.contact = f.point;
  m.normal = f.z;
  m.width_mm = w.width_mm;
  m.left_mm = w.left_mm;
  m.right_mm = w.right_mm;
  m.inserted = true;
  m.piece = a.piece;
  return {std::move(m), w};
}

namespace {

// The contact positions fix the tool at the contacts, but the straight
// motion between two of them (tip on the chord, axis turning) swings the
// tool's far side — l from the contact on a round of radius ρ — through a
// chord of radius ~ sqrt(ρ² + l²), far more than the contact's own chord
// height. Where the motion, sampled at t = 1/8 ... 7/8 against both
// contacts' samples, dips below e1, a contact is inserted half-way with the
// blended position (same family: l, θ, φ averaged) until it does not; a
// switch between bottom and corner cannot be blended and becomes a link.
void refine_row(const EdgeFinishRequest& rq, const RowGougeSamples& row_samples, std::vector<EdgeFinishPose>& poses,
                std::vector<std::shared_ptr<const ContactStrip>>& strips, int& inserted) {
  size_t i = 0;
  while (i + 1 < poses.size()) {
    const EdgeFinishPose& a = poses[i];
    const EdgeFinishPose& b = poses[i + 1];
    if (b.break_before || motion_deepest(a, b, *strips[i], *strips[i + 1]) >= rq.band.e1_mm) {
      ++i;
      continue;
    }
    const bool same = a.position.contact == b.position.contact;
    if (!same || std::abs(b.u - a.u) < 1e-7) {
      poses[i + 1].break_before = true;
      ++i;
      continue;
    }
    auto [m, w] = halfway_pose(rq, row_samples, a, b,
                               {a.position.contact, 0.5 * (a.position.l_mm + b.position.l_mm),
                                0.5 * (a.position.lead_rad + b.position.lead_rad),
                                0.5 * (a.position.side_slip_rad + b.position.side_slip_rad)});
    if (w.gouges) {  // the blend itself gouges: cut no further along, link over
      poses[i + 1].break_before = true;
      ++i;
      continue;
    }
    strips.insert(strips.begin() + static_cast<long>(i) + 1, m.strip);
    poses.insert(poses.begin() + static_cast<long>(i) + 1, std::move(m));
    ++inserted;
  }
}

}  // namespace

// The emitted positions of a planned row as poses in u order (contacts
// without a feasible position skipped), refined for the motions between
// them (refine_row); sets the row's smallest strip sides and its contact
// counts and returns its narrowest strip (+inf when it has none).
double emit_poses(const EdgeFinishRequest& rq, double v, const std::vector<double>& ls, PlannedRow& pr) {
  double left = std::numeric_limits<double>::infinity(), right = left, narrowest = left;
  std::vector<std::shared_ptr<const ContactStrip>> strips;
  int last_piece = 0;
  for (size_t i = 0; i < pr.contacts.size(); ++i) {
    const ContactPlan& c = pr.contacts[i];
    EdgePosition pos;
    if (!chosen_position(rq, c, pr.emitted.l_index[i], ls, pos)) continue;
    const ContactStrip& strip = *c.strip;
    const StripWidth w = strip.width(pos);
    EdgeFinishPose p;
    p.pose = strip.pose(pos);
    p.contact = c.frame.point;
    p.normal = c.frame.z;
    p.u = c.u;
    p.v = v;
    p.position = pos;
    p.width_mm = w.width_mm;
    p.left_mm = w.left_mm;
    p.right_mm = w.right_mm;
    p.strip = c.strip;
    // A partial row's parts are passes of their own: no cut across the
    // part of the round between them.
    p.break_before = !pr.row.poses.empty() && c.piece != last_piece;
    p.piece = c.piece;
    last_piece = c.piece;
    pr.row.poses.push_back(p);
    strips.push_back(c.strip);
    left = std::min(left, w.left_mm);
    right = std::min(right, w.right_mm);
    narrowest = std::min(narrowest, w.width_mm);
    if (pos.contact == EdgeContact::Bottom) ++pr.row.bottom_contacts;
    else ++pr.row.corner_contacts;
  }
  refine_row(rq, pr.row_samples, pr.row.poses, strips, pr.row.inserted_contacts);
  pr.row.left_min_mm = std::isfinite(left) ? left : 0;
  pr.row.right_min_mm = std::isfinite(right) ? right : 0;
  return narrowest;
}

double max_pv(const EdgeFinishRequest& rq, double v) {
  double m = 0;
  for (int i = 0; i <= 20; ++i) m = std::max(m, rq.edge->eval(i / 20.0, v).pv.norm());
  return m;
}

// From the window's start, each row a step of its narrowest strip above the
// last, up to the window's end. A row without a strip below the end is an
// error (no feasible position there).
std::vector<PlannedRow> plan_rows(const EdgeFinishRequest& rq, const std::vector<double>& ls, Progress& progress,
                                  std::optional<PlannedRow> first) {
  std::vector<PlannedRow> planned;
  double v = rq.v0;
  progress.begin("edge finish rows", 0);
  while (true) {
    progress.step(static_cast<long>(planned.size()));
    const bool given = planned.empty() && first && first->row.v == v;
    PlannedRow pr = given ? std::move(*first) : plan_row(rq, v, ls, false, progress);
    const double narrowest = emit_poses(rq, v, ls, pr);
    // §3.2: rows spaced by the smallest strip along the row. The strips are
    // lopsided (up by right, down by left at each contact) but the next row's
    // contacts sit where this row's do and have about the same strips, so at
    // each place along the row right + next left ~ this contact's width.
    // The simulation (core/sim) measures what that leaves.
    const double span_step = std::isfinite(narrowest) ? narrowest : 0.0;
    const bool last = v >= rq.v1 - 1e-12;
    if (!last && !(span_step > 1e-6)) {
      planned.push_back(std::move(pr));
      throw Error("edge finish: row at v = " + std::to_string(v) + " has no strip (no feasible position)");
    }
    if (!last) {
      pr.row.spacing_mm = span_step;
      // Stop when this row's strip already reaches the window's end.
      const double to_end = (rq.v1 - v) * max_pv(rq, v);
      if (to_end <= pr.row.right_min_mm) {
        planned.push_back(std::move(pr));
        break;
      }
      planned.push_back(std::move(pr));
      v = std::min(rq.v1, v + span_step / max_pv(rq, v));
    } else {
      planned.push_back(std::move(pr));
      break;
    }
  }
  planned.back().row.spacing_mm = 0;
  return planned;
}

}  // namespace bliskrun::edge_detail
