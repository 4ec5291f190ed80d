// Partial rows where the rows' strips as emitted leave a gap: the rows were
// spaced by the optimum's strips, and a pose tilted clear of the
// neighbouring blade cuts a narrower one (corner contact, lead up to 60 deg:
// 0.4-0.8 mm against rows 1.5 mm apart on the built-in LE's pressure side),
// which left up to 0.1 mm there. Respacing every row for the narrowest
// tilted strip would cut the whole round three times over; partial rows go
// only where the strips as emitted leave a gap, each over the parts of the
// round the gap spans, seeded from the rows either side.
#include <algorithm>
#include <cmath>

#include "core/common/parallel.h"
#include "core/planning/edge_finish/internal.h"

namespace bliskrun::edge_detail {
namespace {

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

}  // namespace

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

namespace {

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

}  // namespace

// Each pair of rows on its own, pairs on rq.threads workers (each planning
// its contacts on one).
int fill_partial_rows(const EdgeFinishRequest& rq, const PoseChecks& checks, const std::vector<double>& ls,
                      std::vector<PlannedRow>& planned, Progress& progress) {
  int added = 0;
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
      ++added;
    }
  std::stable_sort(planned.begin(), planned.end(),
                   [](const PlannedRow& a, const PlannedRow& b) { return a.row.v < b.row.v; });
  return added;
}

}  // namespace bliskrun::edge_detail
