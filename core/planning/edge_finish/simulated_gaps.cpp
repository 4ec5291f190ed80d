// Partial rows where the rows as checked still leave material. The strips'
// reaches are measured across the feed at each contact; what the swept tool
// leaves between contacts of two rows can differ (on the built-in TE:
// triangles between the rows' ends on the pressure flank's overlap, up to
// 27.5 um where the reaches said the rows met). The rows' passes are
// simulated over the window (core/sim, the independent simulation's method)
// and a partial row goes half-way between the two rows around every part
// left above e2, or rising above it between two samples (a ridge); twice.
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
// independent simulation's method (core/sim simulate_undercut), 0.05 mm
// along the span (the triangles the rows leave at their ends narrow to a
// point: at 0.25 mm a 27 um one on the built-in TE went unseen; the ridges
// between tilted rows (left_or_ridge) are told apart by their sides only at
// 0.05: at 0.1 the TE after a roughing kept 21.7 um) and
// kGapSamples around — as partial rows to add: each at
// half-way between the two rows around the part left (at the window's end
// above the last row), over the u intervals left, padded by two samples.
// Which samples of a residual map (row-major, u outer) count as left: those
// above left_above, and beside a ridge along the span whose top rises above
// ridge_above between two samples. Between two rows the material left is a
// cusp — two tool sweeps meeting in a ridge — not a smooth bump: it rises
// towards the ridge from both sides, steepest at the ridge, and where a
// tilted pose's torus meets a neighbour's at a steep angle the ridge is
// narrower than the samples (on the built-in TE after a roughing, rows
// tilted off the edge rounds' stock: 21.7 um at the region's end between
// samples 0.1 mm apart that read 14-15.5, e2 20). The top is put where the
// two sides' secants through their last two samples meet — a lower bound of
// it where each side is convex, as a cusp's are — and the sample nearer it
// counts as left.
std::vector<char> left_or_ridge(const UndercutResult& r, double left_above, double ridge_above) {
  const size_t nv = static_cast<size_t>(r.samples_v);
  std::vector<char> left(r.residual_mm.size(), 0);
  for (size_t i = 0; i < left.size(); ++i) left[i] = r.residual_mm[i] > left_above;
  for (size_t row = 0; row < static_cast<size_t>(r.samples_u); ++row) {
    const double* res = &r.residual_mm[row * nv];
    for (size_t j = 1; j + 2 < nv; ++j) {
      const double a = res[j - 1], b = res[j], c = res[j + 1], d = res[j + 2];
      if (!(std::isfinite(a) && std::isfinite(b) && std::isfinite(c) && std::isfinite(d))) continue;
      const double rise_up = b - a, rise_down = c - d;  // towards the ridge from below and from above
      if (!(rise_up > 0 && rise_down > 0)) continue;
      const double x = std::clamp((c + rise_down - b) / (rise_up + rise_down), 0.0, 1.0);
      if (b + rise_up * x > ridge_above) left[row * nv + (x < 0.5 ? j : j + 1)] = 1;
    }
  }
  return left;
}

struct SimulatedGap {
  double v = 0;        // where the partial row goes
  Intervals where;     // the parts of the round it covers
  size_t below = 0;    // the row below it (index into the rows given)
};
//
// `residual` carries the material left between the calls (empty the first
// time): only the rows not simulated yet (PlannedRow::simulated) are, and
// the map is the lower of theirs and the one before — the same as from all
// the passes again, which cost as much as the first round (about a fifth of
// the built-in TE's plan).
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
  o.samples_v = std::clamp(static_cast<int>(span_mm / 0.05), 16, 4000);
  // Between samples h apart the material left can rise above what they see
  // by about h^2 / (8 r) under the corner radius r (2.5 um at 0.1 mm, r
  // 0.5: Rotor 67's TE read 19.8 um here where the recipe's own samples
  // found 22.6): a part is left if it reaches e2 less that; a ridge between
  // samples if its top reaches e2 (left_or_ridge).
  const double h = std::max(span_mm / (o.samples_v - 1), around_mm / (o.samples_u - 1));
  const double left_above = rq.band.e2_mm - h * h / (8 * flat_end_of(*rq.tool).corner_mm);
  // Material is tracked to e2 + 10 um (a sample left higher, or untouched,
  // reads +inf and is left all the same) and gouges to 10 um (the guards
  // and the independent simulation measure those). The shorter traces and
  // the narrower reach around the tool (the tiles the cutter can touch
  // within 0.03 mm, not 0.1): 1.24 -> 1.07 s wall on the built-in LE, same
  // gaps. Every sample is traced to its lowest (no settled_mm): the ridges
  // are read from the samples' values, and a sample left where the first
  // pass that took it below e2 left it would read by the order the passes
  // were traced in (the partial rows then changed with the threads).
  o.search_above_mm = std::max(rq.band.e2_mm, 0.0) + 0.01;
  o.search_below_mm = 0.01;
  // Tool positions 0.1 mm of cutter-point motion apart, not the
  // simulation's 0.05: positions are samples of a continuous sweep, so
  // either spacing reads at least what the sweep leaves (never a gap
  // missed), the coarser at most ~step^2 / (8 r) = 2.5 um more under the
  // 0.5 mm corner, which could only add a partial row. On the built-in and
  // Rotor 67's edges it adds none (the same poses and passes) and halves
  // this simulation: Rotor 67's TE 8.1 -> 4.4 s CPU.
  o.sweep_step_mm = 0.1;
  // ... of the cutter's points within its radius plus its corner of the
  // tip (the bottom and the corner torus, which cut the round), not of its
  // whole length: a row turns the axis round the edge (~4 deg a motion on
  // the built-in TE), which moved the flute's top 9.5 mm from the tip five
  // times as far as the corner. The side higher up, where it touches at
  // all, is read coarser: more material, never less.
  const FlatEnd& fe = flat_end_of(*rq.tool);
  o.sweep_reach_mm = std::hypot(fe.radius_mm, 2 * fe.corner_mm);
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
  const std::vector<char> left_at = left_or_ridge(r, left_above, rq.band.e2_mm);
  std::vector<std::vector<int>> left(rows.size());
  for (int j = 0; j < r.samples_v; ++j) {
    const double v = o.v0 + (o.v1 - o.v0) * j / (r.samples_v - 1);
    if (v < rows.front().row.v) continue;  // below the first row: the window's start
    size_t k = 0;
    while (k + 1 < rows.size() && rows[k + 1].row.v <= v) ++k;
    for (int i = 0; i < r.samples_u; ++i)
      if (left_at[static_cast<size_t>(i) * r.samples_v + j]) left[k].push_back(i);
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
