#include "core/planning/edge_finish.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <utility>

#include "core/common/error.h"
#include "core/common/parallel.h"
#include "core/planning/links.h"
#include "core/sim/undercut.h"

namespace bliskrun {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

void validate(const EdgeFinishRequest& rq) {
  if (!rq.edge) throw ParameterError("edge", "missing edge region surface");
  if (!rq.tool) throw ParameterError("tool", "missing tool");
  flat_end_of(*rq.tool);
  if (!rq.world) throw ParameterError("world", "missing collision world");
  if (!(rq.v0 >= 0 && rq.v1 <= 1 && rq.v0 < rq.v1)) throw ParameterError("span", "expected 0 <= v0 < v1 <= 1");
  if (!(rq.band.e1_mm <= 0)) throw ParameterError("e1", "the overcut limit must be <= 0");
  if (!(rq.band.e2_mm > rq.band.e1_mm)) throw ParameterError("e2", "the undercut limit must exceed e1");
  if (rq.l_count < 1) throw ParameterError("l_count", "must be >= 1");
  if (!(rq.retract_mm > 0)) throw ParameterError("retract", "must be > 0");
  if (rq.threads < 1) throw ParameterError("threads", "must be >= 1");
  if (!(rq.tilt_lead_step_rad > 0 && rq.tilt_lead_max_rad >= rq.tilt_lead_step_rad && rq.tilt_lead_max_rad < kPi / 2))
    throw ParameterError("tilt_lead_max", "expected tilt_lead_step <= tilt_lead_max < 90 deg");
  if (!(rq.tilt_slip_step_rad > 0)) throw ParameterError("tilt_slip_step", "must be > 0");
  if (!(rq.hub_clearance_mm >= 0)) throw ParameterError("hub_clearance", "must be >= 0");
  if (!rq.reach_axis.isZero() && std::abs(rq.reach_axis.norm() - 1) > 1e-9)
    throw ParameterError("reach", "the reach axis must be a unit vector");
  if (!(rq.reach_min_rad >= 0 && rq.reach_min_rad < rq.reach_max_rad && rq.reach_max_rad <= kPi))
    throw ParameterError("reach", "expected 0 <= min < max <= 180 deg");
}

// Parts of a row around the edge, [u0, u1] each, in u order.
using Intervals = std::vector<std::pair<double, double>>;

// Everything one contact contributes to its row.
struct ContactPlan {
  double u = 0;
  EdgeFrame frame;
  bool bottom = false, any = false;   // a bottom position exists / any position exists
  std::vector<double> paper_w, joint_w;  // per l_j (0 = infeasible)
  std::vector<double> joint_phi;
  double paper_phi = 0;
  EdgePosition corner;                // when !bottom
  double corner_w = 0;
  double side_w = 0;                  // conventional side-edge positioning
  int evaluations = 0;
  int piece = 0;  // which part of a partial row (plan_row's `only`) it belongs to
  std::shared_ptr<const ContactStrip> strip;
};

double score(const StripWidth& w) { return w.gouges || !w.touches ? 0.0 : w.width_mm; }

std::vector<double> l_grid(const FlatEnd& f, double r_e, int count) {
  const double hi = f.radius_mm - f.corner_mm;
  if (count == 1 || r_e >= hi) return {hi};
  std::vector<double> l;
  for (int j = 0; j < count; ++j) l.push_back(r_e + (hi - r_e) * j / (count - 1));
  return l;
}

// A row's condition-① samples beyond its contacts' strips: they depend on
// the row's span alone, not on the contact, so a row samples them once and
// its contacts' strips share them (of a contact's 2946 samples on the
// built-in LE, 1680 are the flanks' and 861 these lines; a third of the
// poses are contacts inserted between others, each sampling its strip):
//  - the flanks' (the flank u of the row's v, from the flanks' edge ends);
//  - with gouge_whole_u, the edge region's: every gouge_stride-th line
//    across the feed, each over the whole round, the lines spaced for the
//    row's smallest |pv| so they reach half_width_mm either side at every
//    contact (a contact's own strip samples are spaced for its own |pv|).
using RowGougeSamples = std::shared_ptr<const SharedGougeSamples>;
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

// The positions a row's contacts took as planned (before any tilt), in u
// order: where a partial row between two rows starts its own (RowSeeds).
struct SeedContact {
  double u = 0;
  EdgePosition position;
};
using RowSeed = std::vector<SeedContact>;

// The rows either side of a partial row (either may be null).
struct RowSeeds {
  const RowSeed* below = nullptr;
  const RowSeed* above = nullptr;
};

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

ContactPlan plan_contact(const EdgeFinishRequest& rq, double u, double v, const std::vector<double>& ls,
                         bool side_only, const RowGougeSamples& row_samples, const RowSeeds* seeds = nullptr) {
  ContactPlan c;
  c.u = u;
  const SurfaceDerivs d = rq.edge->eval(u, v);
  c.frame = edge_frame(d);
  c.strip = make_strip(rq, c.frame, u, v, row_samples);
  const ContactStrip& strip = *c.strip;
  if (seeds && !side_only) {
    ContactPlan seeded = c;
    if (seeded_contact(ls, *seeds, seeded)) return seeded;
    c.evaluations = seeded.evaluations;  // the seeds' tries dropped, their evaluations counted
  }
  const CornerPosition side = corner_min_lead(strip, rq.side_min_lead_rad);
  c.side_w = side.feasible ? side.width.width_mm : 0.0;
  c.evaluations += 1;
  if (side_only) return c;
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
  // Concave part: the corner with the smallest lead that does not gouge.
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

struct PlannedRow {
  EdgeFinishRow row;
  // Where the row is cut, in v order (row.v unless it is a partial row cut
  // after the row above it: see the simulated partial rows).
  std::optional<double> cut_after_v;
  // Per pose of row.poses (in planned order): clear_row proved it against
  // the design guards as it stands (clear, lifted clear, or tilted clear),
  // so the checks need not sweep the guards over it again.
  std::vector<char> design_proved;
  RowGougeSamples row_samples;  // the row's condition-① samples beyond its strips (row_gouge_samples)
  std::vector<ContactPlan> contacts;
  BalancedRow emitted;
};

// `only` (may be null): plan just the contacts within these parts of the
// row, each with the contact just outside either end (so the strips reach
// over the whole part), for a partial row; each part's contacts carry its
// index as their piece.
PlannedRow plan_row(const EdgeFinishRequest& rq, double v, const std::vector<double>& ls, bool side_only,
                    Progress& progress, const Intervals* only = nullptr, const RowSeeds* seeds = nullptr) {
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

// The position a contact takes in the emitted path, or false.
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

// The traverse's waypoint round the edge's front, for a link between passes
// whose axes turn by more than 90 degrees (one-way rows: the passes lie on
// either side of the edge): the mean of the two normals points off the
// edge; the tool goes there at the retract distance plus its radius. None
// otherwise.
std::vector<ToolPose> round_the_front(const EdgeFinishRequest& rq, const EdgeFinishPose& a, const EdgeFinishPose& b) {
  if (a.pose.axis.dot(b.pose.axis) >= 0) return {};
  Vec3 front = a.normal + b.normal;
  if (front.norm() < 1e-6) front = a.normal.cross(b.contact - a.contact).cross(a.normal);
  front.normalize();
  return {{0.5 * (a.contact + b.contact) + (rq.retract_mm + flat_end_of(*rq.tool).radius_mm) * front, front}};
}

// Whether a pose's axis is within the machine's reach (EdgeFinishRequest::
// reach_axis, reach_min_rad, reach_max_rad).
bool within_reach(const EdgeFinishRequest& rq, const ToolPose& pose) {
  if (rq.reach_axis.isZero()) return true;
  const double c = pose.axis.normalized().dot(rq.reach_axis);
  return c >= std::cos(rq.reach_max_rad) - 1e-12 && c <= std::cos(rq.reach_min_rad) + 1e-12;
}

// The most a pose that cuts the blade beside its strip is lifted off its
// contact (lift_clear), mm.
constexpr double kMaxLiftMm = 0.003;

// What every pose and cutting motion is proved against beyond the world:
// the design surfaces the way the independent simulation sweeps them
// (core/sim GougeGuard: the edge region over the machined span and both
// flanks near their edge ends, dense samples, the whole swept tool). The
// contact strips see only samples across the feed through each contact: a
// motion into a tilted pose was found cutting 4.4 um into the round between
// them on the built-in LE, and on Rotor 67's TE untilted corner contacts on
// the round cut up to 14 um beside their strips (84 of 1900 poses in a
// tenth of the span) — the torus leaning over a round smaller than itself.
// Allowed: the band's overcut less what the samples can miss.
struct DesignGuards {
  std::unique_ptr<GougeGuard> edge;
  std::vector<std::unique_ptr<GougeGuard>> flanks;
  double e1_mm = 0;
  double corner_mm = 0;

  double allowed(const GougeGuard& g) const { return std::max(0.0, -e1_mm - g.between_samples_mm(corner_mm)); }
  double least_allowed() const {
    double a = allowed(*edge);
    for (const auto& g : flanks) a = std::min(a, allowed(*g));
    return a;
  }
  // The deepest cut below the allowance of the tool moving a -> b (the ends
  // included or not), over the edge region and the flanks; 0 if none.
  double deepest(const Tool& tool, const ToolPose& a, const ToolPose& b, bool ends) const {
    double d = edge->deepest_cut(tool, a, b, allowed(*edge), ends, ends).depth_mm;
    for (const auto& g : flanks) d = std::min(d, g->deepest_cut(tool, a, b, allowed(*g), ends, ends).depth_mm);
    return d;
  }
};

// The checks a pose must pass: the whole tool clear of the world, and the
// design guards.
struct PoseChecks {
  const ToolBody& body;
  const DesignGuards& guards;
  // Why the pose itself fails the guards ("" if it does not); with
  // `liftable`, only by more than a lift can take off (lift_clear).
  std::string gouge(const Tool& tool, const ToolPose& pose, bool liftable = false) const {
    const double d = guards.deepest(tool, pose, pose, true);
    if (d >= 0 || (liftable && -d - guards.least_allowed() < kMaxLiftMm)) return "";
    char buf[96];
    std::snprintf(buf, sizeof buf, "the tool cuts %.1f um into the blade beside its contact strip", -1e3 * d);
    return buf;
  }
};

// A pose that cuts the blade beside its strip by a little more than the
// guards allow is lifted off along the surface normal at its contact by the
// excess (repeated: where the surface turns away from the contact a lift
// clears less than itself), up to kMaxLiftMm; it then leaves that much more
// at its contact, far inside e2. The strip's samples across the feed are
// 0.1 mm apart and the optimum puts them at e1 exactly, so between them the
// guards (32 um apart) find the pose 0.1-0.7 um deeper: on Rotor 67's LE 373
// such contacts had no tilted axis that cut less either. Deeper cuts (a
// torus leaning over a round smaller than itself) are tilted instead.
// False (the pose as it was) if the lift would exceed the limit or the
// lifted pose is not clear of the world.
bool lift_clear(const EdgeFinishRequest& rq, const PoseChecks& checks, EdgeFinishPose& p) {
  constexpr double kExtraMm = 5e-5;  // past the allowance, so one lift usually does
  const EdgeFinishPose original = p;
  double lifted = 0;
  for (int it = 0; it < 4; ++it) {
    const double d = checks.guards.deepest(*rq.tool, p.pose, p.pose, true);
    if (d >= 0) {
      if (!rq.world->check(checks.body, p.pose, rq.clearances, 0).clear) break;
      const StripWidth w = p.strip->width(p.pose);
      if (w.gouges || !w.touches) break;
      p.width_mm = w.width_mm;
      p.left_mm = w.left_mm;
      p.right_mm = w.right_mm;
      p.lift_mm = lifted;
      return true;
    }
    const double excess = -d - checks.guards.least_allowed() + kExtraMm;
    lifted += excess;
    if (lifted > kMaxLiftMm) break;
    p.pose.tip += excess * p.normal;
  }
  p = original;
  return false;
}

// Waypoints in front of the edge between two passes: the round's middle
// (u = 0.5) at the passes' mean span, out along its normal by the retract
// distance plus the tool's diameter, with the first pass's axis and then
// the second's (the axis turns there, clear of the blades).
std::vector<ToolPose> in_front(const EdgeFinishRequest& rq, const EdgeFinishPose& a, const EdgeFinishPose& b,
                               double retract_mm) {
  const EdgeFrame f = edge_frame(rq.edge->eval(0.5, 0.5 * (a.v + b.v)));
  const Vec3 at = f.point + (retract_mm + 2 * flat_end_of(*rq.tool).radius_mm) * f.z;
  return {{at, a.pose.axis}, {at, b.pose.axis}};
}

// Where the optimum's tool is not clear of the world (on the sides of an
// edge in a narrow passage the surface normal points at the neighbour), the
// contact moves to the corner torus with the axis leaning further from the
// normal — the paper's §1.2(a) positioning — found by the drum finish's
// interference loop (core/collision tilt_until_clear): λ = 90° − θ falls
// from 90° − tilt_lead_step in tilt_lead_step steps down to 90° −
// tilt_lead_max, the side-slip w = φ − 90° all round from the optimum's in
// tilt_slip_step steps; an axis must be within the machine's range
// (axis_limit), keep condition ① and ② on the contact's samples and clear
// the world with the whole tool (the motion into it is the caller's).
// `hint` (may be null): the (λ, w) the row's last tilted contact took, tried
// first — ours: neighbouring contacts keep one axis where it clears, so the
// row turns its axis less and breaks into fewer passes, and a contact
// beside the neighbouring blade asks one axis instead of dozens.
TiltOutcome clear_alternative(const EdgeFinishRequest& rq, const PoseChecks& checks, EdgeFinishPose& p,
                              const TiltAccepted* hint) {
  const ToolBody& body = checks.body;
  const ContactFrame frame{p.contact, p.strip->frame().x, p.strip->frame().z};
  TiltSettings s;
  s.lead0_rad = kPi / 2 - rq.tilt_lead_step_rad;
  s.lead_step_rad = -rq.tilt_lead_step_rad;
  s.lead_max_rad = kPi / 2 - rq.tilt_lead_max_rad;
  s.tilt0_rad = p.position.side_slip_rad - kPi / 2;
  s.allow_tilt = true;
  s.tilt_step_rad = rq.tilt_slip_step_rad;
  s.tilt_range_rad = kPi - 0.5 * rq.tilt_slip_step_rad;  // all round, w0 + 180° once
  s.clearances = rq.clearances;
  s.motion_tol_mm = rq.motion_tol_mm;
  s.axis_limit = rq.axis_limit;
  const ContactStrip& strip = *p.strip;
  // Tilted axes lean towards the edge's front (the round's middle normal at
  // this span), out of the passage: an axis leaning back into it (on the
  // built-in LE's pressure side, 80 deg along the flank) beside one leaning
  // out flips the axis by 120-135 deg between neighbouring contacts, and
  // no link proves that turn beside the neighbouring blade.
  const Vec3 front = edge_frame(rq.edge->eval(0.5, p.v)).z;
  s.pose_filter = [&](const ToolPose& pose) -> std::string {
    if (pose.axis.dot(front) < 0) return "leans back into the passage";
    if (!within_reach(rq, pose)) return "beyond the machine's reach";
    const StripWidth w = strip.width(pose);
    if (w.gouges) return "gouges the blade (" + std::to_string(1e3 * w.deepest_mm) + " um or deeper)";
    if (!w.touches) return "leaves more than e2 at the contact";
    return "";
  };
  // The guards sweep thousands of samples: only for axes the world clears.
  s.clear_pose_filter = [&](const ToolPose& pose) { return checks.gouge(*rq.tool, pose, true); };
  // Tilted first with room to spare (rq.tilt_room_mm on the shank and
  // holder): an axis found at the bare clearance leaves the shank a few um
  // outside it beside the neighbouring blade, and every traverse of a link
  // between two such poses then grazes it (27 links on the built-in LE were
  // refused by < 0.4 um). Without room only where no axis has it.
  TiltSettings roomy = s;
  roomy.clearances.shank_mm += rq.tilt_room_mm;
  roomy.clearances.holder_mm += rq.tilt_room_mm;
  TiltOutcome o;
  for (const TiltSettings* settings : {&roomy, &s}) {
    if (hint) {
      // The hint's side-slip at its lead and, failing that, at more lead:
      // a row that flips its lean from one side of the feed to the other
      // (axes 120-135 deg apart beside the neighbouring blade on the
      // built-in LE) needs a link there that no retract proves.
      TiltSettings one = *settings;
      one.lead0_rad = hint->lead_rad;
      one.lead_max_rad = std::min(one.lead_max_rad, hint->lead_rad);
      one.tilt0_rad = hint->tilt_rad;
      one.allow_tilt = false;
      o = tilt_until_clear(*rq.world, body, frame, 0, one);
    }
    if (!o.accepted) o = tilt_until_clear(*rq.world, body, frame, 0, *settings);
    if (o.accepted || !(rq.tilt_room_mm > 0)) break;
  }
  if (o.accepted) {
    const EdgeFinishPose before = p;
    const StripWidth w = strip.width(o.pose.pose);
    p.position = {EdgeContact::Corner, 0, kPi / 2 - o.pose.lead_rad, o.pose.tilt_rad + kPi / 2};
    p.pose = o.pose.pose;
    p.width_mm = w.width_mm;
    p.left_mm = w.left_mm;
    p.right_mm = w.right_mm;
    p.tilted = true;
    // An axis that cuts beside its strip by no more than a lift takes off
    // is lifted (Rotor 67's LE: axes at 0.8-0.9 um against 0.75 allowed).
    if (!checks.gouge(*rq.tool, p.pose).empty() && !lift_clear(rq, checks, p)) {
      p = before;
      o.accepted = false;
      o.refusal.reason = "the tilted axis cuts the blade beside its strip and no lift of <= 3 um clears it";
    }
  }
  return o;
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

// refine_row for the tilted poses clear_row made: contacts were stepped for
// the planned positions' chord height, but a tilted pose cuts with the
// corner torus, whose centre runs on a round of radius ρ + r (0.9 mm on the
// built-in LE's 0.4 mm round with r 0.5) and sags ~2 um between contacts
// stepped for 1 um on the round — every such motion dipped below e1 and
// became a link (1092 of the built-in LE's 1571 links). Between two tilted
// poses whose motion dips below e1, a contact is inserted half-way with the
// blended lead and side-slip, proved as clear_row proves a pose (world,
// reach, design guards with a lift, condition ① and ② on its strip); where
// the blend is not clear the pair stays a link, as before.
// A break refine_row put between two contacts of the same part because they
// were of different families (bottom <-> corner) is reconsidered when both
// are tilted now (one family): on Rotor 67's TE the row's first contact
// (u 0, a corner) and its next (u 0.19, a bottom) were both tilted to one
// axis, and the flank's overlap between them — the steps are far apart
// where the row is nearly straight — was never cut (26 um left).
void refine_tilted(const EdgeFinishRequest& rq, const PoseChecks& checks, PlannedRow& pr) {
  constexpr int kMaxInserted = 6;  // per original pair: the sag falls 4x per halving
  std::vector<EdgeFinishPose>& poses = pr.row.poses;
  std::vector<char>& proved = pr.design_proved;
  size_t i = 0;
  int inserted_here = 0;
  while (i + 1 < poses.size()) {
    const EdgeFinishPose& a = poses[i];
    EdgeFinishPose& b = poses[i + 1];
    const bool joinable = a.tilted && b.tilted && proved[i] && proved[i + 1] && a.piece == b.piece &&
                          std::abs(b.u - a.u) >= 1e-7;
    const bool dips = joinable && motion_deepest(a, b, *a.strip, *b.strip) < rq.band.e1_mm;
    if (joinable && !dips) b.break_before = false;  // one family now: cut across
    if (!dips || inserted_here >= kMaxInserted) {
      ++i;
      inserted_here = 0;
      continue;
    }
    auto [m, w] = halfway_pose(rq, pr.row_samples, a, b,
                               {EdgeContact::Corner, 0, 0.5 * (a.position.lead_rad + b.position.lead_rad),
                                a.position.side_slip_rad + 0.5 * std::remainder(b.position.side_slip_rad -
                                                                                    a.position.side_slip_rad,
                                                                                2 * kPi)});
    m.tilted = true;
    const bool ok = !w.gouges && w.touches && within_reach(rq, m.pose) &&
                    rq.world->check(checks.body, m.pose, rq.clearances, 0).clear &&
                    (checks.gouge(*rq.tool, m.pose).empty() || lift_clear(rq, checks, m));
    if (!ok) {  // the blend is not proved: the pair stays a link
      ++i;
      inserted_here = 0;
      continue;
    }
    poses.insert(poses.begin() + static_cast<long>(i) + 1, std::move(m));
    proved.insert(proved.begin() + static_cast<long>(i) + 1, 1);
    ++pr.row.inserted_contacts;
    ++inserted_here;
  }
}

// Each pose of a row that is not clear of the world tilted clear where it
// can be (clear_alternative, each contact hinted by the row's last tilted
// one, in u order), before the rows are checked in cutting order: the
// tilted strips are narrower than the optimum's the rows were spaced by,
// and the infill below needs their true widths. A pose that cannot be
// tilted clear is left as planned; the checks refuse it.
//
// The hints carry a lean along the row; where it stops clearing, the
// search may find the opposite lean, and the axis flips by 120-135 degrees
// between neighbouring contacts beside the neighbouring blade — a link no
// retract proves (the built-in LE's pressure side, every row). The hints
// are carried both ways along the row and the way with fewer flips kept
// (then the one whose narrowest strip is wider).
void clear_row(const EdgeFinishRequest& rq, const PoseChecks& checks, PlannedRow& pr) {
  EdgeFinishRow& row = pr.row;
  struct Along {
    std::vector<EdgeFinishPose> poses;
    std::vector<char> proved;  // PlannedRow::design_proved
    int tilted = 0;
  };
  auto tilted_along = [&](bool backwards) {
    Along a{row.poses, std::vector<char>(row.poses.size(), 0), 0};
    TiltAccepted last;
    last.index = -1;
    const size_t n = a.poses.size();
    for (size_t k = 0; k < n; ++k) {
      const size_t i = backwards ? n - 1 - k : k;
      EdgeFinishPose& p = a.poses[i];
      if (within_reach(rq, p.pose) && rq.world->check(checks.body, p.pose, rq.clearances, 0).clear &&
          (checks.gouge(*rq.tool, p.pose).empty() || lift_clear(rq, checks, p))) {
        a.proved[i] = 1;
        continue;
      }
      const TiltOutcome t = clear_alternative(rq, checks, p, last.index >= 0 ? &last : nullptr);
      if (!t.accepted) continue;
      a.proved[i] = 1;  // the tilt accepts only axes the guards pass (lifted if need be)
      last = t.pose;
      ++a.tilted;
    }
    return a;
  };
  auto flips = [](const std::vector<EdgeFinishPose>& poses) {
    int f = 0;
    for (size_t i = 0; i + 1 < poses.size(); ++i) f += poses[i].pose.axis.dot(poses[i + 1].pose.axis) < 0 ? 1 : 0;
    return f;
  };
  auto narrowest = [](const std::vector<EdgeFinishPose>& poses) {
    double w = std::numeric_limits<double>::infinity();
    for (const EdgeFinishPose& p : poses) w = std::min(w, p.width_mm);
    return w;
  };
  Along best = tilted_along(false);
  if (flips(best.poses) > 0) {
    Along back = tilted_along(true);
    if (flips(back.poses) < flips(best.poses) ||
        (flips(back.poses) == flips(best.poses) && narrowest(back.poses) > narrowest(best.poses)))
      best = std::move(back);
  }
  row.poses = std::move(best.poses);
  pr.design_proved = std::move(best.proved);
  row.tilted_contacts += best.tilted;
  refine_tilted(rq, checks, pr);
}

// Poses in the other cutting order. A break belongs to the pair it
// separates: it moves to the pose that now comes second.
void reverse_poses(std::vector<EdgeFinishPose>& ps) {
  const size_t n = ps.size();
  std::vector<bool> breaks(n);
  for (size_t i = 0; i < n; ++i) breaks[i] = ps[i].break_before;
  std::reverse(ps.begin(), ps.end());
  for (size_t j = 0; j < n; ++j) ps[j].break_before = j > 0 && breaks[n - j];
}

// The row cut the other way: its poses and passes in reverse.
EdgeFinishRow reversed_row(EdgeFinishRow row) {
  if (row.poses.empty()) return row;
  const int last = row.poses.back().segment;
  reverse_poses(row.poses);
  for (EdgeFinishPose& p : row.poses) p.segment = last - p.segment;
  row.reversed = !row.reversed;
  return row;
}

// The links between consecutive passes of rows[0 .. n) — standing at row
// indices r0 .. in the cutting order — the first from `prev` (the last
// pose before them, in row prev_row; null: none). prev / prev_row end at
// the rows' last pose.
struct LinkEnds {
  const EdgeFinishPose *from, *to;
  int from_row, to_row;
};
std::vector<LinkEnds> pass_links(const EdgeFinishRow* rows, size_t n, int r0, const EdgeFinishPose*& prev,
                                 int& prev_row) {
  std::vector<LinkEnds> out;
  for (size_t j = 0; j < n; ++j) {
    const std::vector<EdgeFinishPose>& poses = rows[j].poses;
    const int r = r0 + static_cast<int>(j);
    for (size_t i = 0; i < poses.size(); ++i) {
      const bool starts_pass = i == 0 || poses[i].segment != poses[i - 1].segment;
      if (starts_pass && prev) out.push_back({prev, &poses[i], prev_row, r});
      prev = &poses[i];
      prev_row = r;
    }
  }
  return out;
}

// How far a row's strips reach at u towards higher v (`up`: their right
// sides) or lower v (left): between two poses the tool sweeps from one
// strip to the other, so their reaches interpolated — the smaller one
// where the two are not joined by a cut (a break: each covers only its
// own side); 0 outside the row's poses (a partial row covers only part of
// the round).
double reach_at(const EdgeFinishRow& row, double u, bool up) {
  const std::vector<EdgeFinishPose>& ps = row.poses;
  auto side = [&](const EdgeFinishPose& p) { return up ? p.right_mm : p.left_mm; };
  for (size_t i = 0; i + 1 < ps.size(); ++i) {
    if (!(ps[i].u <= u && u <= ps[i + 1].u)) continue;
    const double a = side(ps[i]), b = side(ps[i + 1]);
    if (ps[i + 1].break_before || ps[i + 1].u - ps[i].u < 1e-12) return std::min(a, b);
    const double t = (u - ps[i].u) / (ps[i + 1].u - ps[i].u);
    return a + t * (b - a);
  }
  if (ps.size() == 1 && std::abs(ps[0].u - u) < 1e-9) return side(ps[0]);
  return 0;
}

// The u intervals (on kGapSamples samples around) where rows a (lower v)
// and b leave a strip between them that neither reaches: their distance
// along the span exceeds a's reach up plus b's reach down by more than
// slack_mm. b may be the window's end (reach 0). Each interval padded by
// two samples.
constexpr int kGapSamples = 200;
Intervals gaps_between(const Surface& edge, const EdgeFinishRow& a, const EdgeFinishRow* b, double b_v,
                       double slack_mm, const Intervals& within) {
  Intervals out;
  const double du = 1.0 / kGapSamples;
  for (const auto& [lo, hi] : within) {
    double open = -1;
    for (int i = 0; i <= kGapSamples; ++i) {
      const double u = i * du;
      const bool inside = u >= lo - 1e-12 && u <= hi + 1e-12;
      bool gap = false;
      if (inside) {
        const double d = (edge.point(u, b_v) - edge.point(u, a.v)).norm();
        gap = d - reach_at(a, u, true) - (b ? reach_at(*b, u, false) : 0.0) > slack_mm;
      }
      if (gap && open < 0) open = u;
      if ((!gap || i == kGapSamples) && open >= 0) {
        const double end = gap ? u : u - du;
        out.push_back({std::max(0.0, open - 2 * du), std::min(1.0, end + 2 * du)});
        open = -1;
      }
    }
  }
  // Merge overlaps left by the padding.
  Intervals merged;
  for (const auto& iv : out) {
    if (!merged.empty() && iv.first <= merged.back().second) merged.back().second = std::max(merged.back().second, iv.second);
    else merged.push_back(iv);
  }
  return merged;
}

// A partial row at v over the intervals: only the contacts within them
// planned (plan_row's `only`; l balanced over those), each interval its own
// pass.
PlannedRow infill_row(const EdgeFinishRequest& rq, const PoseChecks& checks, double v, const std::vector<double>& ls,
                      const Intervals& where, const RowSeeds& seeds, Progress& progress) {
  PlannedRow pr = plan_row(rq, v, ls, false, progress, &where, &seeds);
  emit_poses(rq, v, ls, pr);
  pr.row.infill = true;
  clear_row(rq, checks, pr);
  return pr;
}

// Partial rows between a (lower) and b (or the window's end at b_v) where
// their strips as emitted — tilted ones are narrower than the spacing
// assumed — leave material: one at the middle over the gaps' intervals,
// then the same for each half, to `depth` levels. Appended to `out`.
void fill_gaps(const EdgeFinishRequest& rq, const PoseChecks& checks, const std::vector<double>& ls,
               const EdgeFinishRow& a, const EdgeFinishRow* b, double b_v, const RowSeeds& seeds,
               const Intervals& within, int depth, std::vector<PlannedRow>& out, Progress& progress) {
  // Gaps narrower than this are left: beyond a strip's end the material
  // rises from e2 as the corner turns away from the surface, by 0.1 um
  // over 0.01 mm for r 0.5 (measured: 0.063 mm, 1 um by that rule, left
  // 24 um on the built-in LE where 0.02 mm leaves 11 um).
  constexpr double slack = 0.02;
  const Intervals gaps = gaps_between(*rq.edge, a, b, b_v, slack, within);
  if (gaps.empty() || depth == 0) return;
  // Against the window's end the partial row goes on the end itself.
  const double v = b ? 0.5 * (a.v + b_v) : b_v;
  out.push_back(infill_row(rq, checks, v, ls, gaps, seeds, progress));
  const size_t m = out.size() - 1;
  // out may grow (and move) below: copy the middle row.
  const EdgeFinishRow mid = out[m].row;
  const RowSeed mid_seed = seed_of(rq, out[m], ls);
  fill_gaps(rq, checks, ls, a, &mid, mid.v, {seeds.below, &mid_seed}, gaps, depth - 1, out, progress);
  if (b) fill_gaps(rq, checks, ls, mid, b, b_v, {&mid_seed, seeds.above}, gaps, depth - 1, out, progress);
}

// The span window's ends against hub and casing (EdgeFinishRequest::hub,
// casing). `lowest_clear(f, a, b)`: the lowest v in [a, b] with f(v) >= 0, f
// negative at a and growing with v (margins from a surface of revolution
// grow with the span), bracketed to 1e-4 in v (a few um of span); none when
// f(b) < 0. The hub's margin plans a whole row per value (the φ search at
// every contact): by false position with the Illinois rule, since the
// margin grows nearly linearly with the span — 5-8 rows where bisection
// from [v0, v1] planned 15 — with a bisection step wherever false position
// would shrink the bracket by less than a quarter.
template <class F>
std::optional<double> lowest_clear(const F& f, double a, double b) {
  double f_lo = f(a);
  if (f_lo >= 0) return a;
  double f_hi = f(b);
  if (f_hi < 0) return std::nullopt;
  double lo = a, hi = b;
  int kept = 0;  // > 0: hi kept that many times in a row; < 0: lo
  while (hi - lo > 1e-4) {
    const double width = hi - lo;
    double mid = hi - f_hi * width / (f_hi - f_lo);
    if (!(mid > lo + 1e-5 && mid < hi - 1e-5)) mid = 0.5 * (lo + hi);
    const double f_mid = f(mid);
    if (f_mid >= 0) {
      hi = mid;
      f_hi = f_mid;
      kept = std::min(kept, 0) - 1;
      if (kept <= -2) f_lo *= 0.5;  // Illinois: lo kept twice
    } else {
      lo = mid;
      f_lo = f_mid;
      kept = std::max(kept, 0) + 1;
      if (kept >= 2) f_hi *= 0.5;
    }
    if (hi - lo > 0.75 * width) {  // slow: bisect once
      const double m = 0.5 * (lo + hi);
      const double f_m = f(m);
      (f_m >= 0 ? hi : lo) = m;
      (f_m >= 0 ? f_hi : f_lo) = f_m;
      kept = 0;
    }
  }
  return hi;
}

// Smallest radial offset from the hub, less the clearance, of the cutter's
// surface at every contact of the row at v as planned (positions before any
// tilting clear of the world: the row the optimum wants).
double row_hub_margin(const EdgeFinishRequest& rq, double v, const std::vector<double>& ls,
                      const std::vector<Vec3>& cutter, Progress& progress) {
  const PlannedRow pr = plan_row(rq, v, ls, false, progress);
  double margin = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < pr.contacts.size(); ++i) {
    EdgePosition pos;
    if (!chosen_position(rq, pr.contacts[i], pr.emitted.l_index[i], ls, pos)) continue;
    const Eigen::Isometry3d T = tool_to_part(pr.contacts[i].strip->pose(pos));
    for (const Vec3& q : cutter) margin = std::min(margin, rq.hub->radial_offset(T * q) - rq.hub_clearance_mm);
  }
  return margin;
}

// Narrows rq's window to the hub and casing; returns the hub strip (mm).
double fit_window_to_hub_and_casing(EdgeFinishRequest& rq, const std::vector<double>& ls, Progress& progress) {
  constexpr int kAround = 21;
  if (rq.casing) {
    // Lowest span whose every point (sampled around) is outside the casing.
    auto beyond_tip = [&](double v) {
      double m = std::numeric_limits<double>::infinity();
      for (int i = 0; i < kAround; ++i) m = std::min(m, rq.casing->radial_offset(rq.edge->point(i / (kAround - 1.0), v)));
      return m;
    };
    rq.v1 = lowest_clear(beyond_tip, rq.v0, rq.v1).value_or(rq.v1);
    if (rq.v1 <= rq.v0 + 1e-9)
      throw Error("edge finish: the span window lies beyond the casing (no blade edge in it)");
  }
  if (!rq.hub) return 0;
  const Profile& c = rq.tool->cutter();
  const std::vector<Vec3> cutter = c.surface_samples(c.z_min(), c.z_max(), 6, 24);
  Progress quiet(&progress);
  const std::optional<double> clear =
      lowest_clear([&](double v) { return row_hub_margin(rq, v, ls, cutter, quiet); }, rq.v0, rq.v1);
  if (!clear)
    throw Error("edge finish: no row of the window keeps the cutter " + std::to_string(rq.hub_clearance_mm) +
                " mm outside the hub (the tool is too large for the edge here)");
  const double first = *clear;
  // The strip below the first row: along each iso-u line from the hub (or
  // the requested v0, if higher) up to the first row.
  double strip = 0;
  for (int i = 0; i < kAround; ++i) {
    const double u = i / (kAround - 1.0);
    auto above_hub = [&](double v) { return rq.hub->radial_offset(rq.edge->point(u, v)); };
    const double from = lowest_clear(above_hub, rq.v0, first).value_or(first);
    double len = 0;
    constexpr int kSteps = 16;
    for (int k = 0; k < kSteps; ++k)
      len += (rq.edge->point(u, from + (first - from) * (k + 1) / kSteps) -
              rq.edge->point(u, from + (first - from) * k / kSteps)).norm();
    strip = std::max(strip, len);
  }
  rq.v0 = first;
  return strip;
}

// How many times the rows are simulated for material left (below).
constexpr int kSimulatedInfillRounds = 2;

// Where the rows (sorted by v) as checked leave more than e2 on the edge
// region over the window — their cutting passes simulated by the
// independent simulation's method (core/sim simulate_undercut), 0.1 mm
// along the span (the triangles the rows leave at their ends narrow to a
// point: at 0.25 mm a 27 um one on the built-in TE went unseen) and
// kGapSamples around — as partial rows to add: each at
// half-way between the two rows around the part left (at the window's end
// above the last row), over the u intervals left, padded by two samples.
struct SimulatedGap {
  double v = 0;        // where the partial row goes
  Intervals where;     // the parts of the round it covers
  size_t below = 0;    // the row below it (index into the rows given)
};
std::vector<SimulatedGap> simulated_gaps(const EdgeFinishRequest& rq, const std::vector<PlannedRow>& rows,
                                         Progress& progress) {
  std::vector<ToolPass> passes;
  for (const PlannedRow& pr : rows) {
    const std::vector<EdgeFinishPose>& ps = pr.row.poses;
    for (size_t i = 0; i < ps.size(); ++i) {
      if (i == 0 || ps[i].segment != ps[i - 1].segment) passes.emplace_back();
      passes.back().push_back(ps[i].pose);
    }
  }
  if (passes.empty() || rows.empty()) return {};
  // Length of t -> at(t), t in [0, 1], as an n-segment polyline.
  auto length = [](const auto& at, int n) {
    double l = 0;
    for (int i = 0; i < n; ++i) l += (at(static_cast<double>(i + 1) / n) - at(static_cast<double>(i) / n)).norm();
    return l;
  };
  const double span_mm = length([&](double t) { return rq.edge->point(0.5, rq.v0 + (rq.v1 - rq.v0) * t); }, 32);
  const double around_mm = length([&](double t) { return rq.edge->point(t, 0.5 * (rq.v0 + rq.v1)); }, 64);
  UndercutOptions o;
  o.samples_u = kGapSamples + 1;
  o.samples_v = std::clamp(static_cast<int>(span_mm / 0.1), 16, 2000);
  // Between samples h apart the material left can rise above what they see
  // by about h^2 / (8 r) under the corner radius r (2.5 um at 0.1 mm, r
  // 0.5: Rotor 67's TE read 19.8 um here where the recipe's own samples
  // found 22.6): a part is left if it reaches e2 less that.
  const double h = std::max(span_mm / (o.samples_v - 1), around_mm / (o.samples_u - 1));
  const double left_above = rq.band.e2_mm - h * h / (8 * flat_end_of(*rq.tool).corner_mm);
  // Only whether a sample is left above that matters here: material is
  // tracked to e2 + 10 um (a sample left higher, or untouched, reads +inf
  // and is left all the same) and gouges to 10 um (the guards and the
  // independent simulation measure those). The shorter traces and the
  // narrower reach around the tool (the tiles the cutter can touch within
  // 0.03 mm, not 0.1): 1.24 -> 1.07 s wall on the built-in LE, same gaps.
  o.search_above_mm = std::max(rq.band.e2_mm, 0.0) + 0.01;
  o.search_below_mm = 0.01;
  // A sample once left below that is done with: the passes that cut it
  // again (the next row's overlap, the cutter hovering over it) are not
  // traced there.
  o.settled_mm = left_above;
  o.v0 = rq.v0;
  o.v1 = rq.v1;
  o.threads = rq.threads;
  Progress quiet(&progress);
  const UndercutResult r = simulate_undercut(*rq.edge, *rq.tool, passes, o, quiet);
  // Per pair of rows (k: between rows k and k + 1; rows.size() - 1: above
  // the last), the u samples left.
  std::vector<std::vector<int>> left(rows.size());
  for (int j = 0; j < r.samples_v; ++j) {
    const double v = o.v0 + (o.v1 - o.v0) * j / (r.samples_v - 1);
    if (v < rows.front().row.v) continue;  // below the first row: the window's start
    size_t k = 0;
    while (k + 1 < rows.size() && rows[k + 1].row.v <= v) ++k;
    for (int i = 0; i < r.samples_u; ++i)
      if (r.residual_mm[static_cast<size_t>(i) * r.samples_v + j] > left_above) left[k].push_back(i);
  }
  std::vector<SimulatedGap> out;
  const double du = 1.0 / (r.samples_u - 1);
  for (size_t k = 0; k < rows.size(); ++k) {
    std::vector<int>& us = left[k];
    if (us.empty()) continue;
    std::sort(us.begin(), us.end());
    us.erase(std::unique(us.begin(), us.end()), us.end());
    Intervals iv;
    int lo = us.front(), hi = us.front();
    auto close = [&] { iv.push_back({std::max(0.0, (lo - 2) * du), std::min(1.0, (hi + 2) * du)}); };
    for (size_t n = 1; n < us.size(); ++n) {
      if (us[n] > hi + 4) {
        close();
        lo = us[n];
      }
      hi = us[n];
    }
    close();
    const bool above_last = k + 1 == rows.size();
    const double v = above_last ? rq.v1 : 0.5 * (rows[k].row.v + rows[k + 1].row.v);
    if (above_last && rq.v1 - rows[k].row.v < 1e-9) continue;  // the last row is on the window's end
    out.push_back({v, std::move(iv), k});
  }
  return out;
}

}  // namespace

EdgeFinishResult plan_edge_finish(const EdgeFinishRequest& request, Progress& progress) {
  validate(request);
  EdgeFinishResult out;
  const FlatEnd fe = flat_end_of(*request.tool);
  if (request.r_e_mm > fe.radius_mm - fe.corner_mm)
    throw ParameterError("r_e", "the cutting-speed radius exceeds the flat bottom (R - r = " +
                                    std::to_string(fe.radius_mm - fe.corner_mm) + " mm)");
  const std::vector<double> ls = l_grid(fe, request.r_e_mm, request.l_count);
  // The window as hub and casing leave it; everything below plans in it.
  EdgeFinishRequest rq = request;
  const auto t_rows = Clock::now();  // the rows the window's fit plans count as rows
  out.hub_strip_mm = fit_window_to_hub_and_casing(rq, ls, progress);
  out.v0 = rq.v0;
  out.v1 = rq.v1;
  const ToolBody body(*rq.tool, rq.tool_tol_mm);

  // Span speed: the largest |pv| over a row, so a span step in mm becomes a
  // v step that no contact exceeds.
  auto max_pv = [&](double v) {
    double m = 0;
    for (int i = 0; i <= 20; ++i) m = std::max(m, rq.edge->eval(i / 20.0, v).pv.norm());
    return m;
  };

  // ---- rows: bottom method ----
  std::vector<PlannedRow> planned;
  double v = rq.v0;
  progress.begin("edge finish rows", 0);
  while (true) {
    progress.step(static_cast<long>(planned.size()));
    PlannedRow pr = plan_row(rq, v, ls, false, progress);
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
      const double to_end = (rq.v1 - v) * max_pv(v);
      if (to_end <= pr.row.right_min_mm) {
        planned.push_back(std::move(pr));
        break;
      }
      planned.push_back(std::move(pr));
      v = std::min(rq.v1, v + span_step / max_pv(v));
    } else {
      planned.push_back(std::move(pr));
      break;
    }
  }
  planned.back().row.spacing_mm = 0;
  out.rows_seconds = seconds_since(t_rows);

  // ---- comparison row (Fig. 8) ----
  const int crow = rq.comparison_row >= 0 ? std::min<int>(rq.comparison_row, static_cast<int>(planned.size()) - 1)
                                          : static_cast<int>(planned.size()) / 2;
  {
    const PlannedRow& pr = planned[crow];
    EdgeWidthComparison& cmp = out.comparison;
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
  }

  // ---- side-edge positioning over the same window: its own rows ----
  const auto t_side = Clock::now();
  {
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
      if ((rq.v1 - vs) * max_pv(vs) <= w / 2 || vs >= rq.v1 - 1e-12) break;
      vs = std::min(rq.v1, vs + w / max_pv(vs));
    }
    out.side_rows = rows;
    out.side_window_mm = 0;
    const int n = 50;
    for (int i = 0; i < n; ++i)
      out.side_window_mm += (rq.edge->point(0.5, rq.v0 + (rq.v1 - rq.v0) * (i + 1) / n) -
                             rq.edge->point(0.5, rq.v0 + (rq.v1 - rq.v0) * i / n))
                                .norm();
  }
  out.side_seconds = seconds_since(t_side);

  // The design guards (DesignGuards above), over the window. Samples h
  // apart miss at most h² / (8 r) for the corner radius r: h is chosen so
  // that is a quarter of |e1| (0.032 mm for r 0.5, e1 -1 um), the counts
  // from the window's longest parameter lines in mm — the allowance keeps
  // three quarters of e1, wherever the window and however long the blade.
  DesignGuards guards;
  guards.e1_mm = rq.band.e1_mm;
  guards.corner_mm = std::max(fe.corner_mm, 1e-3);
  const double spacing = std::sqrt(2 * guards.corner_mm * std::max(-rq.band.e1_mm, 1e-3));
  guards.edge = std::make_unique<GougeGuard>(*rq.edge, guard_sampling(*rq.edge, spacing, 0, 1, rq.v0, rq.v1));
  // The flanks near their edge ends (first: v = 0, second: v = 1), where the
  // flat bottom of a pose reaches over them: 12 % of the chord, over the
  // machined span window and a tool radius + 1 mm either side of it.
  for (int k = 0; k < 2; ++k) {
    const std::shared_ptr<const Surface>& flank = k == 0 ? rq.first : rq.second;
    if (!flank) continue;
    const double fu0 = rq.span_u0 + rq.v0 * (rq.span_u1 - rq.span_u0);
    const double fu1 = rq.span_u0 + rq.v1 * (rq.span_u1 - rq.span_u0);
    const double per_u = std::max(flank->eval(0.5 * (fu0 + fu1), k == 0 ? 0.0 : 1.0).pu.norm(), 1e-9);
    const double margin = (fe.radius_mm + 1.0) / per_u;
    guards.flanks.push_back(std::make_unique<GougeGuard>(
        *flank, guard_sampling(*flank, spacing, std::max(0.0, std::min(fu0, fu1) - margin),
                               std::min(1.0, std::max(fu0, fu1) + margin), k == 0 ? 0.0 : 0.88, k == 0 ? 0.12 : 1.0)));
  }
  const PoseChecks checks{body, guards};

  // ---- poses tilted clear of the world; partial rows where that leaves material ----
  // The rows were spaced by the optimum's strips; a pose tilted clear of
  // the neighbouring blade cuts a narrower one (corner contact, lead up to
  // 60 deg: 0.4-0.8 mm against rows 1.5 mm apart on the built-in LE's
  // pressure side), which left up to 0.1 mm there. Respacing every row for
  // the narrowest tilted strip would cut the whole round three times over;
  // partial rows go only where the strips as emitted leave a gap.
  const auto t_clear = Clock::now();
  {
    Progress quiet(&progress);
    run_parallel(planned.size(), rq.threads, quiet, "edge finish tilting",
                 [&](size_t k, Progress&) { clear_row(rq, checks, planned[k]); });
  }
  {
    // Each pair of rows on its own, pairs on rq.threads workers (each
    // planning its contacts on one).
    const Intervals whole{{0.0, 1.0}};
    constexpr int kInfillDepth = 3;  // up to 7 partial rows between two rows
    EdgeFinishRequest one = rq;
    one.threads = 1;
    std::vector<std::vector<PlannedRow>> infill(planned.size());
    std::vector<RowSeed> seeds;
    for (const PlannedRow& pr : planned) seeds.push_back(seed_of(rq, pr, ls));
    run_parallel(planned.size(), rq.threads, progress, "edge finish partial rows", [&](size_t k, Progress& pg) {
      const bool last = k + 1 == planned.size();
      fill_gaps(one, checks, ls, planned[k].row, last ? nullptr : &planned[k + 1].row,
                last ? rq.v1 : planned[k + 1].row.v, {&seeds[k], last ? nullptr : &seeds[k + 1]}, whole,
                kInfillDepth, infill[k], pg);
    });
    for (std::vector<PlannedRow>& rows : infill)
      for (PlannedRow& pr : rows) {
        planned.push_back(std::move(pr));
        ++out.infill_rows;
      }
    std::stable_sort(planned.begin(), planned.end(),
                     [](const PlannedRow& a, const PlannedRow& b) { return a.row.v < b.row.v; });
  }
  out.clear_seconds = seconds_since(t_clear);

  // ---- order, checks, links ----
  const auto t_checks = Clock::now();
  // Swept only where the contact strips' view is least to be trusted: a
  // change of contact family (bottom <-> corner), a tilted pose, or an axis
  // turning more than 5 degrees between the poses (the swept tool then leaves
  // the strips' samples). Smooth motions within one family stay with the
  // strips' check, and the independent simulation checks every move after.
  auto risky = [&](const EdgeFinishPose& a, const EdgeFinishPose& b) {
    return a.position.contact != b.position.contact || a.tilted || b.tilted || a.lift_mm > 0 || b.lift_mm > 0 ||
           a.pose.axis.normalized().dot(b.pose.axis.normalized()) < std::cos(deg_to_rad(5.0));
  };
  auto motion_gouges = [&](const EdgeFinishPose& pa, const EdgeFinishPose& pb) {
    return risky(pa, pb) && guards.deepest(*rq.tool, pa.pose, pb.pose, false) < 0;
  };
  // Each row on its own (its passes, tilts and breaks depend on nothing
  // outside it), rows on rq.threads workers; totals summed in row order.
  // Returns the row's gouge breaks.
  auto check_row = [&](PlannedRow& pr, bool reversed, Progress& row_progress) -> long {
    long gouge_breaks = 0;
    EdgeFinishRow& row = pr.row;
    std::vector<EdgeFinishPose> candidates = std::move(row.poses);
    row.poses.clear();
    row.reversed = reversed;
    if (row.reversed) reverse_poses(candidates);
    std::vector<char> proved = pr.design_proved;
    proved.resize(candidates.size(), 0);
    if (row.reversed) std::reverse(proved.begin(), proved.end());
    int segment = 0;
    long last = -1;  // index in row.poses of the previous emitted pose of this pass
    TiltAccepted last_tilt;    // the row's last tilted contact's axis (index -1: none yet)
    last_tilt.index = -1;
    for (size_t ci = 0; ci < candidates.size(); ++ci) {
      EdgeFinishPose& p = candidates[ci];
      row_progress.check();
      if (p.break_before && last >= 0) {
        ++segment;
        last = -1;
      }
      // A pose clear_row proved (clear of the world within reach, and of
      // the design guards) is taken as proved: the same queries again.
      std::string reason;
      if (!proved[ci]) {
        const PoseCheck pc = rq.world->check(body, p.pose, rq.clearances, 0);
        if (!pc.clear) reason = describe(pc, *rq.world);
        else if (!within_reach(rq, p.pose)) reason = "axis beyond the machine's reach";
        else if (!(reason = checks.gouge(*rq.tool, p.pose)).empty() && lift_clear(rq, checks, p))
          reason.clear();
      }
      if (reason.empty() && last >= 0 &&
          !rq.world->check_motion(body, row.poses[last].pose, p.pose, rq.clearances, rq.motion_tol_mm).clear) {
        // The pose is clear, the cutting motion into it is not: a new pass,
        // reached by a proved link.
        ++segment;
        last = -1;
      }
      TiltOutcome tilt;
      if (!reason.empty()) {
        // The pose alone must clear (the interference loop's cheap query);
        // the motion from the previous pose is asked once below, and a
        // pose it cannot reach by cutting is reached by a link — asking it
        // of every candidate axis cost a swept FCL query each, minutes per
        // edge beside the neighbouring blade.
        tilt = clear_alternative(rq, checks, p, last_tilt.index >= 0 ? &last_tilt : nullptr);
        if (!tilt.accepted) reason += "; tilting: " + tilt.refusal.reason;
      }
      bool motion_proved = false;  // the cutting motion into p, by the strips and the guards
      if (tilt.accepted) {
        reason.clear();
        ++row.tilted_contacts;
        last_tilt = tilt.pose;
        // A tilted pose is a different family from its neighbours: reach it
        // by a link unless the motion is proved clear of the world and
        // within e1 of the blade.
        if (last >= 0 &&
            (!rq.world->check_motion(body, row.poses[last].pose, p.pose, rq.clearances, rq.motion_tol_mm).clear ||
             motion_deepest(row.poses[last], p, *row.poses[last].strip, *p.strip) < rq.band.e1_mm ||
             motion_gouges(row.poses[last], p))) {
          ++segment;
          last = -1;
        }
        motion_proved = last >= 0;
      }
      if (!reason.empty()) {
        row.refusals.push_back({p.u, p.contact, reason});
        if (last >= 0) ++segment;  // the row is split: no straight move across the refused contact
        last = -1;
        continue;
      }
      // Every cutting motion within e1 of the blade (a tilted neighbour, a
      // pose after a refused one): otherwise reach this pose by a link. The
      // guards' sweep only where the strips' cheaper test passes.
      if (last >= 0 && !motion_proved &&
          (motion_deepest(row.poses[last], p, *row.poses[last].strip, *p.strip) < rq.band.e1_mm ||
           motion_gouges(row.poses[last], p))) {
        ++segment;
        ++gouge_breaks;
      }
      p.segment = segment;
      row.poses.push_back(p);
      last = static_cast<long>(row.poses.size()) - 1;
    }
    // Rows whose contacts had no feasible position at all.
    for (size_t i = 0; i < pr.contacts.size(); ++i) {
      EdgePosition pos;
      const ContactPlan& c = pr.contacts[i];
      if (!chosen_position(rq, c, pr.emitted.l_index[i], ls, pos))
        row.refusals.push_back({c.u, c.frame.point, "no gouge-free position within the band"});
    }
    return gouge_breaks;
  };
  std::vector<long> row_gouge_breaks(planned.size(), 0);
  run_parallel(planned.size(), rq.threads, progress, "edge finish checks", [&](size_t r, Progress& row_progress) {
    row_gouge_breaks[r] = check_row(planned[r], rq.zigzag && r % 2 == 1, row_progress);
  });
  for (long b : row_gouge_breaks) out.gouge_breaks += b;

  // ---- partial rows where the rows as checked still leave material ----
  // The strips' reaches are measured across the feed at each contact; what
  // the swept tool leaves between contacts of two rows can differ (on the
  // built-in TE: triangles between the rows' ends on the pressure flank's
  // overlap, up to 27.5 um where the reaches said the rows met). The rows'
  // passes are simulated over the window (core/sim, the independent
  // simulation's method) and a partial row goes half-way between the two
  // rows around every part left above e2; twice.
  const auto t_sim = Clock::now();
  for (int round = 0; round < kSimulatedInfillRounds; ++round) {
    std::stable_sort(planned.begin(), planned.end(),
                     [](const PlannedRow& a, const PlannedRow& b) { return a.row.v < b.row.v; });
    const std::vector<SimulatedGap> gaps = simulated_gaps(rq, planned, progress);
    if (gaps.empty()) break;
    EdgeFinishRequest one = rq;
    one.threads = 1;
    std::vector<PlannedRow> extra(gaps.size());
    std::vector<long> extra_breaks(gaps.size(), 0);
    run_parallel(gaps.size(), rq.threads, progress, "edge finish partial rows (simulated)", [&](size_t k, Progress& pg) {
      const RowSeed below = seed_of(rq, planned[gaps[k].below], ls);
      const RowSeed above = gaps[k].below + 1 < planned.size() ? seed_of(rq, planned[gaps[k].below + 1], ls) : RowSeed{};
      extra[k] = infill_row(one, checks, gaps[k].v, ls, gaps[k].where, {&below, &above}, pg);
      // Cut after the row below or the row above it, whichever ends nearer
      // (the zigzag's rows end on alternate sides of the edge), and from
      // its end nearer there: the links into and out of it then stay on
      // that side of the edge (round the front, the hub refused them
      // beside an 18 mm holder).
      const std::vector<EdgeFinishPose>& mine = extra[k].row.poses;
      const size_t b = gaps[k].below;
      auto nearer_end = [&](const std::vector<EdgeFinishPose>& row) {
        if (row.empty() || mine.empty()) return std::numeric_limits<double>::infinity();
        return std::min(std::abs(mine.front().u - row.back().u), std::abs(mine.back().u - row.back().u));
      };
      const bool after_above = b + 1 < planned.size() && nearer_end(planned[b + 1].row.poses) < nearer_end(planned[b].row.poses);
      const std::vector<EdgeFinishPose>& before = planned[after_above ? b + 1 : b].row.poses;
      if (after_above) extra[k].cut_after_v = planned[b + 1].row.v;
      const bool reversed = !before.empty() && !mine.empty() &&
                            std::abs(mine.back().u - before.back().u) < std::abs(mine.front().u - before.back().u);
      extra_breaks[k] = check_row(extra[k], reversed, pg);
    });
    for (size_t k = 0; k < extra.size(); ++k) {
      out.gouge_breaks += extra_breaks[k];
      ++out.infill_rows;
      ++out.simulated_infill_rows;
      planned.push_back(std::move(extra[k]));
    }
  }
  // Cutting order: by v, a partial row cut after the row above it just
  // after that row.
  auto cut_at = [](const PlannedRow& p) { return p.cut_after_v ? std::nextafter(*p.cut_after_v, 2.0) : p.row.v; };
  std::stable_sort(planned.begin(), planned.end(),
                   [&](const PlannedRow& a, const PlannedRow& b) { return cut_at(a) < cut_at(b); });
  out.simulation_seconds = seconds_since(t_sim);
  for (size_t r = 0; r < planned.size(); ++r) {
    EdgeFinishRow& row = planned[r].row;
    out.total_poses += static_cast<int>(row.poses.size());
    for (const EdgeFinishPose& p : row.poses) out.lifted_contacts += p.lift_mm > 0 ? 1 : 0;
    out.total_refusals += static_cast<int>(row.refusals.size());
    out.max_deviation_mm = std::max(out.max_deviation_mm, row.max_deviation_mm);
    out.rows.push_back(std::move(row));
  }
  const auto t_links = Clock::now();
  // Links between consecutive passes, in cutting order: the shared link
  // builder (core/planning/links.h), up the tool axis — a bottom-cutting
  // tool leaves along its axis — every leg proved against the world with
  // the whole tool and, by the gouge guards, against the edge region and
  // both flanks within e1 (less what the guards' samples can miss).
  LinkChecks link_checks;
  link_checks.world = rq.world;
  link_checks.body = &body;
  link_checks.clearances = rq.clearances;
  link_checks.motion_tol_mm = rq.motion_tol_mm;
  link_checks.guard = guards.edge.get();
  link_checks.guard_margin_mm = guards.edge->between_samples_mm(guards.corner_mm);
  for (const auto& g : guards.flanks) link_checks.more_guards.push_back({g.get(), g->between_samples_mm(guards.corner_mm)});
  // A traverse out in front of the edge or up the span leaves the guards'
  // reach: proved against the whole blade with the cutter too (a route
  // radially out, tried for Rotor 67's TE near the hub, was found by the
  // recipe's simulation cutting 0.1 mm into a flank the guards did not
  // sample).
  link_checks.traverse_world = rq.world->unchecked_pairs();
  LinkOptions link_options;
  link_options.direction = RetractDirection::ToolAxis;
  link_options.retract_mm = rq.retract_mm;
  link_options.min_retract_mm = std::min(0.1, rq.retract_mm);
  link_options.allowed_overcut_mm = -rq.band.e1_mm;
  // The passes' ends in cutting order, then every link on rq.threads
  // workers: each is proved on its own (the world and the guards are
  // read-only), so the plan does not depend on the thread count.
  const EdgeFinishPose* before_first = nullptr;
  int before_row = -1;
  std::vector<LinkEnds> ends = pass_links(out.rows.data(), out.rows.size(), 0, before_first, before_row);
  // A link tried up the axes (round the front where the axis turns past
  // 90 deg), then out in front of the edge, then retracted three times as
  // far in front, then (with a hub) radially out.
  auto edge_link = [&](const EdgeFinishPose& from, const EdgeFinishPose& to, int from_row, int to_row) {
    PlannedLink pl = plan_link({from.pose, from.normal}, {to.pose, to.normal}, link_checks, link_options,
                               round_the_front(rq, from, to));
    if (!pl.clear) {
      // Beside the neighbouring blade a traverse between two retracted
      // poses can graze it (their shanks are both at the clearance): out in
      // front of the edge instead, turning the axis there, away from both.
      const PlannedLink out_front = plan_link({from.pose, from.normal}, {to.pose, to.normal}, link_checks,
                                              link_options, in_front(rq, from, to, rq.retract_mm));
      if (out_front.clear) pl = out_front;
      else pl.reason += "; in front of the edge: " + out_front.reason;
    }
    if (!pl.clear) {
      // Near the hub a holder turning with the axis between two retracted
      // poses can graze it by nanometres (Rotor 67's TE, 2 of 300 links):
      // retracted three times as far, in front of the edge.
      LinkOptions farther = link_options;
      farther.retract_mm = 3 * link_options.retract_mm;
      const PlannedLink far_out = plan_link({from.pose, from.normal}, {to.pose, to.normal}, link_checks, farther,
                                            in_front(rq, from, to, farther.retract_mm));
      if (far_out.clear) pl = far_out;
      else pl.reason += "; retracted " + std::to_string(farther.retract_mm) + " mm: " + far_out.reason;
    }
    if (!pl.clear && rq.hub) {
      // Where an axis leans towards the blisk's axis (Rotor 67's TE near
      // the hub: 0.4 of it radial inwards) the holder sits at its
      // clearance of the hub at the pose, and any turn of the axis near
      // there sweeps it inside: up the span first, radially out from both
      // retracted poses, turning the axis out there, and back in (2 of
      // Rotor 67's TE links). The traverse passes the blade beyond the
      // guards' samples: proved by the traverse world, which refuses it
      // where the cutter would touch the blade (it cut 0.1 mm into a flank
      // before that proof).
      const Vec3 mid = 0.5 * (from.contact + to.contact);
      const Vec3 out_dir = Vec3(mid.x(), mid.y(), 0).normalized();
      const Vec3 up_a = from.pose.tip + rq.retract_mm * from.pose.axis.normalized();
      const Vec3 up_b = to.pose.tip + rq.retract_mm * to.pose.axis.normalized();
      for (double s : {5.0, 20.0}) {
        const PlannedLink radial =
            plan_link({from.pose, from.normal}, {to.pose, to.normal}, link_checks, link_options,
                      {{up_a + s * out_dir, from.pose.axis}, {up_b + s * out_dir, to.pose.axis}});
        if (radial.clear) {
          pl = radial;
          break;
        }
        char buf[48];
        std::snprintf(buf, sizeof buf, "; %.0f mm radially out: ", s);
        pl.reason += buf + radial.reason;
      }
    }
    EdgeFinishLink link;
    link.from_row = from_row;
    link.to_row = to_row;
    link.clear = pl.clear;
    link.moves = pl.via;
    link.legs = pl.legs;
    link.offset_mm = pl.offset_mm;
    if (!pl.clear)
      link.reason = "link from row " + std::to_string(from_row) + " to row " + std::to_string(to_row) + ": " + pl.reason;
    return link;
  };
  out.links.resize(ends.size());
  run_parallel(ends.size(), rq.threads, progress, "edge finish links", [&](size_t k, Progress&) {
    out.links[k] = edge_link(*ends[k].from, *ends[k].to, ends[k].from_row, ends[k].to_row);
  });
  // A link no route proves — into a row reached across the round near
  // Rotor 67's hub, the axis turning 70-165 deg, the holder 120 mm up the
  // tool sweeping inside its clearance on every route — may be provable
  // with the rows either side cut the other way, or in the other order:
  // the finished surface is the envelope of every pass whatever the order
  // (each pass's cuts are proved on their own), and a row cut the other
  // way makes the same motions reversed. Zigzag only (one-way keeps its
  // cutting direction). A rearrangement is kept where fewer of the links
  // touching its rows are refused.
  auto rearranged = [&](size_t r0, std::vector<EdgeFinishRow> rows) {
    const size_t r1 = r0 + rows.size();
    auto in_range = [&](int row) { return static_cast<size_t>(row) >= r0 && static_cast<size_t>(row) < r1; };
    size_t k0 = 0;
    while (k0 < ends.size() && !in_range(ends[k0].from_row) && !in_range(ends[k0].to_row)) ++k0;
    size_t k1 = k0;
    while (k1 < ends.size() && (in_range(ends[k1].from_row) || in_range(ends[k1].to_row))) ++k1;
    if (k0 == k1) return false;
    // The range's links in cutting order over rows rs[0 .. n) standing at
    // r0 ..: from the pass before the range, between every two passes, to
    // the pass after it.
    auto range_ends = [&](const EdgeFinishRow* rs) {
      const EdgeFinishPose* prev = in_range(ends[k0].from_row) ? nullptr : ends[k0].from;
      int prev_row = ends[k0].from_row;
      std::vector<LinkEnds> es = pass_links(rs, r1 - r0, static_cast<int>(r0), prev, prev_row);
      if (!in_range(ends[k1 - 1].to_row)) es.push_back({prev, ends[k1 - 1].to, prev_row, ends[k1 - 1].to_row});
      return es;
    };
    const std::vector<LinkEnds> tried = range_ends(rows.data());
    if (tried.size() != k1 - k0) return false;
    std::vector<EdgeFinishLink> relinked;
    for (const LinkEnds& e : tried) relinked.push_back(edge_link(*e.from, *e.to, e.from_row, e.to_row));
    auto refused = [](auto first, auto last) {
      return std::count_if(first, last, [](const EdgeFinishLink& l) { return !l.clear; });
    };
    const auto was = refused(out.links.begin() + static_cast<long>(k0), out.links.begin() + static_cast<long>(k1));
    if (refused(relinked.begin(), relinked.end()) >= was) return false;
    for (size_t j = 0; j < rows.size(); ++j) out.rows[r0 + j] = std::move(rows[j]);
    const std::vector<LinkEnds> placed = range_ends(&out.rows[r0]);  // the same ends, pointing into out.rows
    for (size_t k = k0; k < k1; ++k) {
      ends[k] = placed[k - k0];
      out.links[k] = std::move(relinked[k - k0]);
    }
    return true;
  };
  if (rq.zigzag) {
    for (size_t k = 0; k < out.links.size(); ++k) {
      if (out.links[k].clear || ends[k].from_row == ends[k].to_row) continue;
      const size_t a = static_cast<size_t>(ends[k].from_row), b = static_cast<size_t>(ends[k].to_row);
      // Either row the other way; then the two in the other order, each
      // either way.
      const EdgeFinishRow &ra = out.rows[a], &rb = out.rows[b];
      const bool done =
          rearranged(b, {reversed_row(rb)}) || rearranged(a, {reversed_row(ra)}) ||
          (b == a + 1 && (rearranged(a, {rb, ra}) || rearranged(a, {reversed_row(rb), ra}) ||
                          rearranged(a, {rb, reversed_row(ra)}) || rearranged(a, {reversed_row(rb), reversed_row(ra)})));
      out.rearranged_rows += done ? 1 : 0;
    }
  }
  for (const EdgeFinishLink& link : out.links) out.refused_links += link.clear ? 0 : 1;
  const EdgeFinishPose* first = nullptr;
  const EdgeFinishPose* last = nullptr;
  for (const EdgeFinishRow& row : out.rows)
    if (!row.poses.empty()) {
      if (!first) first = &row.poses.front();
      last = &row.poses.back();
    }
  if (first) {
    auto departure = [&](const EdgeFinishPose& p, const char* what) {
      PlannedDeparture d = plan_departure({p.pose, p.normal}, link_checks, link_options);
      if (!d.clear) {
        d.reason = std::string(what) + ": " + d.reason;
        ++out.refused_links;
      }
      return d;
    };
    out.lead_in = departure(*first, "lead-in");
    out.lead_out = departure(*last, "lead-out");
  }
  progress.end();
  out.links_seconds = seconds_since(t_links);
  out.checks_seconds = seconds_since(t_checks);
  return out;
}

std::vector<DrumFinishMove> edge_finish_moves(const EdgeFinishResult& result) {
  std::vector<DrumFinishMove> moves;
  size_t link = 0;
  bool started = false;
  int last_row = -1;
  for (size_t r = 0; r < result.rows.size(); ++r) {
    const EdgeFinishRow& row = result.rows[r];
    const int ri = static_cast<int>(r);
    for (size_t i = 0; i < row.poses.size(); ++i) {
      const bool starts_pass = i == 0 || row.poses[i].segment != row.poses[i - 1].segment;
      if (!started) {
        if (result.lead_in.clear) moves.push_back({DrumFinishMove::Kind::Rapid, result.lead_in.away, ri, "start", {}});
        else moves.push_back({DrumFinishMove::Kind::Stop, ToolPose{}, ri, "stop", result.lead_in.reason});
      }
      last_row = ri;
      if (starts_pass && started) {
        const EdgeFinishLink& l = result.links.at(link++);
        if (!l.clear) moves.push_back({DrumFinishMove::Kind::Stop, ToolPose{}, ri, "stop", l.reason});
        else
          for (size_t k = 0; k < l.moves.size(); ++k)
            moves.push_back({DrumFinishMove::Kind::Rapid, l.moves[k], ri, link_leg_name(l.legs.at(k)), {}});
      }
      const bool after_stop = !moves.empty() && moves.back().kind == DrumFinishMove::Kind::Stop;
      const char* motion = !starts_pass ? "cut" : (moves.empty() || after_stop) ? "start" : "approach";
      moves.push_back({DrumFinishMove::Kind::Feed, row.poses[i].pose, ri, motion, {}});
      started = true;
    }
  }
  if (started) {
    if (result.lead_out.clear) moves.push_back({DrumFinishMove::Kind::Rapid, result.lead_out.away, last_row, "retract", {}});
    else moves.push_back({DrumFinishMove::Kind::Stop, ToolPose{}, last_row, "stop", result.lead_out.reason});
  }
  return moves;
}

DrumFinishPasses edge_finish_passes(const EdgeFinishResult& result) {
  return passes_of_moves(edge_finish_moves(result));
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

namespace bliskrun {
namespace {

// Where the polyline pts[from], pts[from + step], ... first falls to height
// h along t, walking out from the front; false if it does not, or an
// unknown point comes first.
bool crossing(const std::vector<Vec3>& pts, const std::vector<bool>& known, const Vec3& t, double h, int from,
              int step, Vec3& at) {
  const int n = static_cast<int>(pts.size());
  if (!known[from] || pts[from].dot(t) < h) return false;
  for (int i = from; i + step >= 0 && i + step < n; i += step) {
    if (!known[i + step]) return false;
    const double a = pts[i].dot(t) - h, b = pts[i + step].dot(t) - h;
    if (b <= 0) {
      const double f = a / (a - b);
      at = pts[i] + f * (pts[i + step] - pts[i]);
      return true;
    }
  }
  return false;
}

}  // namespace

std::vector<EdgeThickness> edge_thickness(const Surface& edge, const UndercutResult& sim, const UndercutOptions& o,
                                          const std::vector<double>& spans_v, const std::vector<double>& behind_mm) {
  const int nu = sim.samples_u, nv = sim.samples_v;
  if (nu < 3 || nv < 2 || sim.residual_mm.size() != static_cast<size_t>(nu) * nv || nu != o.samples_u ||
      nv != o.samples_v)
    throw ParameterError("simulation", "a residual map of options.samples_u x samples_v (>= 3 x 2) samples");
  for (double d : behind_mm)
    if (!(d >= 0)) throw ParameterError("behind", "distances behind the front must be >= 0 mm");
  std::vector<EdgeThickness> out;
  for (double v : spans_v) {
    if (!(v >= o.v0 - 1e-12 && v <= o.v1 + 1e-12))
      throw ParameterError("spans", "span v = " + std::to_string(v) + " outside the simulated window [" +
                                        std::to_string(o.v0) + ", " + std::to_string(o.v1) + "]");
    const double fv = o.v1 > o.v0 ? (v - o.v0) / (o.v1 - o.v0) * (nv - 1) : 0.0;
    const int j0 = std::clamp(static_cast<int>(std::floor(fv)), 0, nv - 2);
    const double f = std::clamp(fv - j0, 0.0, 1.0);
    std::vector<Vec3> design(nu), machined(nu);
    std::vector<bool> all(nu, true), known(nu, true);
    for (int i = 0; i < nu; ++i) {
      const SurfaceDerivs d = edge.eval(o.u0 + (o.u1 - o.u0) * i / (nu - 1), v);
      Vec3 n = d.pu.cross(d.pv).normalized();
      if (o.flip_normal) n = -n;
      const double r0 = sim.residual_mm[static_cast<size_t>(i) * nv + j0];
      const double r1 = sim.residual_mm[static_cast<size_t>(i) * nv + j0 + 1];
      design[i] = d.p;
      known[i] = std::isfinite(r0) && std::isfinite(r1);
      machined[i] = known[i] ? Vec3(d.p + ((1 - f) * r0 + f * r1) * n) : d.p;
    }
    const Vec3 mid = 0.5 * (design.front() + design.back());
    int front = 0;
    for (int i = 1; i < nu; ++i)
      if ((design[i] - mid).norm() > (design[front] - mid).norm()) front = i;
    const Vec3 t = (design[front] - mid).normalized();
    for (int i = 0; i < nu; ++i)
      if (design[i].dot(t) > design[front].dot(t)) front = i;
    const double top = design[front].dot(t);
    for (double d : behind_mm) {
      EdgeThickness th;
      th.v = v;
      th.behind_mm = d;
      Vec3 a, b, ma, mb;
      if (crossing(design, all, t, top - d, front, -1, a) && crossing(design, all, t, top - d, front, +1, b) &&
          crossing(machined, known, t, top - d, front, -1, ma) && crossing(machined, known, t, top - d, front, +1, mb)) {
        th.measured = true;
        th.design_mm = (a - b).norm();
        th.machined_mm = (ma - mb).norm();
      }
      out.push_back(th);
    }
  }
  return out;
}

}  // namespace bliskrun
