// Partial rows where the rows as checked still leave material. The strips'
// reaches are measured across the feed at each contact; what the swept tool
// leaves between contacts of two rows can differ (on the built-in TE:
// triangles between the rows' ends on the pressure flank's overlap, up to
// 27.5 um where the reaches said the rows met). The rows' passes are
// simulated over the window (core/sim, the independent simulation's method)
// and a partial row goes half-way between the two rows around every part
// left above e2; twice.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/common/parallel.h"
#include "core/planning/edge_finish/internal.h"
#include "core/sim/undercut.h"

namespace bliskrun::edge_detail {
namespace {

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
//
// `residual` carries the material left between the calls (empty the first
// time): only the rows not simulated yet (PlannedRow::simulated) are, and
// the map is the lower of theirs and the one before. Only whether a sample
// is left above left_above is read, and that does not depend on which
// passes were traced first (UndercutOptions::settled_mm), so the second
// round's partial rows are the same as from all the passes again — which
// cost as much as the first round (about a fifth of the built-in TE's plan).
std::vector<SimulatedGap> simulated_gaps(const EdgeFinishRequest& rq, std::vector<PlannedRow>& rows,
                                         std::vector<double>& residual, Progress& progress) {
  std::vector<ToolPass> passes;
  bool any_pose = false;
  for (PlannedRow& pr : rows) {
    const std::vector<EdgeFinishPose>& ps = pr.row.poses;
    any_pose = any_pose || !ps.empty();
    if (pr.simulated) continue;
    pr.simulated = true;
    for (size_t i = 0; i < ps.size(); ++i) {
      if (i == 0 || ps[i].segment != ps[i - 1].segment) passes.emplace_back();
      passes.back().push_back(ps[i].pose);
    }
  }
  if (!any_pose || rows.empty()) return {};
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
  UndercutResult r;
  if (!passes.empty()) {
    r = simulate_undercut(*rq.edge, *rq.tool, passes, o, quiet);
  } else {
    r.samples_u = o.samples_u;
    r.samples_v = o.samples_v;
    r.residual_mm.assign(static_cast<size_t>(o.samples_u) * o.samples_v, std::numeric_limits<double>::infinity());
  }
  if (residual.size() == r.residual_mm.size())
    for (size_t i = 0; i < residual.size(); ++i) r.residual_mm[i] = std::min(r.residual_mm[i], residual[i]);
  residual = r.residual_mm;
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

// The partial row for one gap, planned and checked; returns its gouge
// breaks. Cut after the row below or the row above it, whichever ends
// nearer (the zigzag's rows end on alternate sides of the edge), and from
// its end nearer there: the links into and out of it then stay on that side
// of the edge (round the front, the hub refused them beside an 18 mm
// holder).
long simulated_row(const EdgeFinishRequest& rq, const EdgeFinishRequest& one, const PoseChecks& checks,
                   const std::vector<double>& ls, const std::vector<PlannedRow>& planned, const SimulatedGap& gap,
                   PlannedRow& row, Progress& pg) {
  const RowSeed below = seed_of(rq, planned[gap.below], ls);
  const RowSeed above = gap.below + 1 < planned.size() ? seed_of(rq, planned[gap.below + 1], ls) : RowSeed{};
  row = infill_row(one, checks, gap.v, ls, gap.where, {&below, &above}, pg);
  const std::vector<EdgeFinishPose>& mine = row.row.poses;
  const size_t b = gap.below;
  auto nearer_end = [&](const std::vector<EdgeFinishPose>& r) {
    if (r.empty() || mine.empty()) return std::numeric_limits<double>::infinity();
    return std::min(std::abs(mine.front().u - r.back().u), std::abs(mine.back().u - r.back().u));
  };
  const bool after_above = b + 1 < planned.size() && nearer_end(planned[b + 1].row.poses) < nearer_end(planned[b].row.poses);
  const std::vector<EdgeFinishPose>& before = planned[after_above ? b + 1 : b].row.poses;
  if (after_above) row.cut_after_v = planned[b + 1].row.v;
  const bool reversed = !before.empty() && !mine.empty() &&
                        std::abs(mine.back().u - before.back().u) < std::abs(mine.front().u - before.back().u);
  return check_row(rq, checks, ls, row, reversed, pg);
}

}  // namespace

void fill_simulated_gaps(const EdgeFinishRequest& rq, const PoseChecks& checks, const std::vector<double>& ls,
                         std::vector<PlannedRow>& planned, EdgeFinishResult& out, Progress& progress) {
  std::vector<double> residual;  // the rows simulated so far (simulated_gaps)
  for (int round = 0; round < kSimulatedInfillRounds; ++round) {
    std::stable_sort(planned.begin(), planned.end(),
                     [](const PlannedRow& a, const PlannedRow& b) { return a.row.v < b.row.v; });
    const std::vector<SimulatedGap> gaps = simulated_gaps(rq, planned, residual, progress);
    if (gaps.empty()) break;
    EdgeFinishRequest one = rq;
    one.threads = 1;
    std::vector<PlannedRow> extra(gaps.size());
    std::vector<long> extra_breaks(gaps.size(), 0);
    run_parallel(gaps.size(), rq.threads, progress, "edge finish partial rows (simulated)", [&](size_t k, Progress& pg) {
      extra_breaks[k] = simulated_row(rq, one, checks, ls, planned, gaps[k], extra[k], pg);
    });
    for (size_t k = 0; k < extra.size(); ++k) {
      out.gouge_breaks += extra_breaks[k];
      ++out.infill_rows;
      ++out.simulated_infill_rows;
      planned.push_back(std::move(extra[k]));
    }
  }
}

}  // namespace bliskrun::edge_detail
