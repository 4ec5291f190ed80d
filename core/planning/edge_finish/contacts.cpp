// A contact's positions and strip: the paper's two-sided φ search over the
// discretised l (§3.2), the corner positioning on concave parts, the
// side-edge positioning for the comparison, and a partial row's seeded
// contacts.
#include <algorithm>
#include <limits>
#include <memory>

#include "core/planning/edge_finish/internal.h"

namespace bliskrun::edge_detail {

double score(const StripWidth& w) { return w.gouges || !w.touches ? 0.0 : w.width_mm; }

std::vector<double> l_grid(const FlatEnd& f, double r_e, int count) {
  const double hi = f.radius_mm - f.corner_mm;
  if (count == 1 || r_e >= hi) return {hi};
  std::vector<double> l;
  for (int j = 0; j < count; ++j) l.push_back(r_e + (hi - r_e) * j / (count - 1));
  return l;
}

RowGougeSamples row_gouge_samples(const EdgeFinishRequest& rq, double v) {
  StripSamples out;
  const StripSampling& sm = rq.sampling;
  if (sm.gouge_whole_u) {
    double pv_min = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= 20; ++i) pv_min = std::min(pv_min, rq.edge->eval(i / 20.0, v).pv.norm());
    const int half = sm.across / 2;
    const double dv = sm.half_width_mm / half / std::max(pv_min, 1e-12);
    std::vector<double> lines;
    for (int j = -half; j <= half; j += std::max(sm.gouge_stride, 1)) {
      const double vj = v + j * dv;
      if (vj >= -1e-12 && vj <= 1 + 1e-12) lines.push_back(std::clamp(vj, 0.0, 1.0));
    }
    add_gouge_lines(out, *rq.edge, 0, 1, lines, sm);
  }
  const double u_f = rq.span_u0 + v * (rq.span_u1 - rq.span_u0);
  if (rq.first) add_flank_samples(out, *rq.first, u_f, 0.0, rq.sampling);
  if (rq.second) add_flank_samples(out, *rq.second, u_f, 1.0, rq.sampling);
  return share_gouge_samples(std::move(out.gouge_p), std::move(out.gouge_n));
}

std::shared_ptr<const ContactStrip> make_strip(const EdgeFinishRequest& rq, const EdgeFrame& frame, double u,
                                               double v, const RowGougeSamples& row_samples) {
  StripSampling own = rq.sampling;
  if (own.gouge_whole_u) own.gouge_along = 0;  // the region's lines beyond the strip are the row's (row_gouge_samples)
  return std::make_shared<const ContactStrip>(*rq.tool, frame, sample_strip(*rq.edge, u, v, own), rq.band, row_samples);
}

namespace {

// Ours, not the paper's: a partial row (the infill where tilted strips
// leave a gap) plans its contacts from the positions the rows either side
// took at the nearest u — the optimum varies slowly across the span, and
// the partial row only has to close a gap, not set a spacing. Each
// candidate is proved on the contact's own strip (conditions ① ② ③ at every
// l_j for a bottom position, ① ② for a corner one); the better is kept.
// The full two-sided search runs only where no candidate is feasible. On
// the built-in LE the partial rows hold 71 % of the contacts and took over
// half of the ~290 000 strip evaluations with the full search.
bool seeded_contact(const std::vector<double>& ls, const RowSeeds& seeds, ContactPlan& c) {
  std::vector<EdgePosition> candidates;
  for (const RowSeed* row : {seeds.below, seeds.above}) {
    if (!row || row->empty()) continue;
    const auto at = std::lower_bound(row->begin(), row->end(), c.u,
                                     [](const SeedContact& s, double u) { return s.u < u; });
    const SeedContact* nearest = at == row->end() ? &row->back() : &*at;
    if (at != row->begin() && at != row->end() && c.u - std::prev(at)->u < at->u - c.u) nearest = &*std::prev(at);
    candidates.push_back(nearest->position);
  }
  const ContactStrip& strip = *c.strip;
  bool any_bottom = false;
  for (const EdgePosition& p : candidates) {
    if (p.contact != EdgeContact::Bottom) continue;
    any_bottom = true;
    std::vector<double> w;
    for (double l : ls) w.push_back(score(strip.width({EdgeContact::Bottom, l, 0, p.side_slip_rad})));
    c.evaluations += static_cast<int>(ls.size());
    const double best = *std::max_element(w.begin(), w.end());
    if (best > 0 && (!c.bottom || best > *std::max_element(c.paper_w.begin(), c.paper_w.end()))) {
      c.bottom = c.any = true;
      c.paper_phi = p.side_slip_rad;
      c.paper_w = w;
      c.joint_w = w;
      c.joint_phi.assign(ls.size(), p.side_slip_rad);
    }
  }
  if (c.bottom || any_bottom) return c.bottom;  // a bottom seed that fails here: the full search decides
  for (const EdgePosition& p : candidates) {
    const double w = score(strip.width(p));
    ++c.evaluations;
    if (w > c.corner_w) {
      c.any = true;
      c.corner = p;
      c.corner_w = w;
    }
  }
  return c.any;
}

}  // namespace

ContactPlan plan_contact(const EdgeFinishRequest& rq, double u, double v, const std::vector<double>& ls,
                         bool side_only, const RowGougeSamples& row_samples, const RowSeeds* seeds) {
  ContactPlan c;
  c.u = u;
  const SurfaceDerivs d = rq.edge->eval(u, v);
  c.frame = edge_frame(d);
  c.strip = make_strip(rq, c.frame, u, v, row_samples);
  const ContactStrip& strip = *c.strip;
  const bool side_method = rq.method == EdgeMethod::Side;
  // The side-edge method's position is one short search (corner_min_lead),
  // the method's definition at every contact: a partial row's contacts take
  // it too rather than a neighbour's seed.
  if (seeds && !side_only && !side_method) {
    ContactPlan seeded = c;
    if (seeded_contact(ls, *seeds, seeded)) return seeded;
    c.evaluations = seeded.evaluations;  // the seeds' tries dropped, their evaluations counted
  }
  const CornerPosition side = corner_min_lead(strip, rq.side_min_lead_rad);
  c.side_w = side.feasible ? side.width.width_mm : 0.0;
  c.evaluations += 1;
  if (side_only) return c;
  if (side_method) {  // emitted as a corner contact: the rows' steps take it as they take the bottom method's
    c.any = side.feasible;
    c.corner = side.position;
    c.corner_w = c.side_w;
    return c;
  }
  double phi_sum = 0;
  int feasible = 0;
  for (double l : ls) {
    const SearchResult r = search_side_slip(
        [&](double phi) { return score(strip.width({EdgeContact::Bottom, l, 0, phi})); }, rq.search);
    c.evaluations += r.evaluations;
    const bool plus = r.width_from_plus_mm > (1 + rq.peak_preference) * r.width_from_minus_mm;
    const double w = plus ? r.width_from_plus_mm : r.width_from_minus_mm;
    const double phi = plus ? r.phi_from_plus_rad : r.phi_from_minus_rad;
    c.joint_w.push_back(std::max(w, 0.0));
    c.joint_phi.push_back(phi);
    if (w > 0) {
      phi_sum += phi;
      ++feasible;
    }
  }
  c.bottom = feasible > 0;
  if (c.bottom) {
    c.paper_phi = phi_sum / feasible;  // §3.2: the average of the φ_j,opt
    for (double l : ls) c.paper_w.push_back(score(strip.width({EdgeContact::Bottom, l, 0, c.paper_phi})));
    c.evaluations += static_cast<int>(ls.size());
    c.any = true;
    return c;
  }
  // Concave part: the corner with the smallest lead that does not gouge,
  // then (θ, φ) as the paper positions the corner (§1.2): φ by the same
  // two-sided search at that lead and a little above it.
  const CornerPosition cp = corner_min_lead(strip, 0.0);
  c.evaluations += 1;
  if (cp.feasible) {
    c.any = true;
    c.corner = cp.position;
    c.corner_w = cp.width.width_mm;
    for (double extra_deg : {0.0, 1.0, 3.0}) {
      const double theta = cp.position.lead_rad + extra_deg * kPi / 180;
      if (theta >= kPi / 2) break;
      const SearchResult r = search_side_slip(
          [&](double phi) { return score(strip.width({EdgeContact::Corner, 0, theta, phi})); }, rq.search);
      c.evaluations += r.evaluations;
      if (r.width_mm > c.corner_w * (1 + 1e-9)) {
        c.corner_w = r.width_mm;
        c.corner = {EdgeContact::Corner, 0, theta, r.phi_rad};
      }
    }
  }
  return c;
}

// Row width of a table by balance_l, corner contacts taking their one width
// at every l.
BalancedRow balance(const std::vector<ContactPlan>& cs, bool paper, size_t nl) {
  std::vector<std::vector<double>> table;
  for (const ContactPlan& c : cs) {
    if (c.bottom) table.push_back(paper ? c.paper_w : c.joint_w);
    else table.push_back(std::vector<double>(nl, c.any ? c.corner_w : 0.0));
  }
  return balance_l(table);
}

bool chosen_position(const EdgeFinishRequest& rq, const ContactPlan& c, int l_index, const std::vector<double>& ls,
                     EdgePosition& pos) {
  if (!c.any) return false;
  if (!c.bottom) {
    pos = c.corner;
    return true;
  }
  if (l_index < 0) return false;
  pos = {EdgeContact::Bottom, ls[l_index], 0,
         rq.optimum == EdgeOptimum::Paper ? c.paper_phi : c.joint_phi[l_index]};
  return true;
}

// The positions a planned row's contacts took (RowSeed).
RowSeed seed_of(const EdgeFinishRequest& rq, const PlannedRow& pr, const std::vector<double>& ls) {
  RowSeed out;
  for (size_t i = 0; i < pr.contacts.size(); ++i) {
    EdgePosition pos;
    if (chosen_position(rq, pr.contacts[i], pr.emitted.l_index[i], ls, pos)) out.push_back({pr.contacts[i].u, pos});
  }
  return out;
}

}  // namespace bliskrun::edge_detail
