// The span window fitted to the hub and the casing: the lowest row whose
// cutter keeps hub_clearance outside the hub, the highest span still inside
// the casing, and the strip left below the first row.
#include <algorithm>
#include <limits>
#include <optional>
#include <string>

#include "core/common/error.h"
#include "core/planning/edge_finish/internal.h"

namespace bliskrun::edge_detail {
namespace {

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
                      const std::vector<Vec3>& cutter, Progress& progress, std::optional<PlannedRow>& keep) {
  PlannedRow pr = plan_row(rq, v, ls, false, progress);
  double margin = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < pr.contacts.size(); ++i) {
    EdgePosition pos;
    if (!chosen_position(rq, pr.contacts[i], pr.emitted.l_index[i], ls, pos)) continue;
    const Eigen::Isometry3d T = tool_to_part(pr.contacts[i].strip->pose(pos));
    for (const Vec3& q : cutter) margin = std::min(margin, rq.hub->radial_offset(T * q) - rq.hub_clearance_mm);
  }
  if (margin >= 0) keep = std::move(pr);  // the lowest clear row found so far is the last one clear
  return margin;
}

// Length of the iso-u line u of the edge region from span a to b, mm.
double span_length(const Surface& edge, double u, double a, double b) {
  constexpr int kSteps = 16;
  double len = 0;
  for (int k = 0; k < kSteps; ++k)
    len += (edge.point(u, a + (b - a) * (k + 1) / kSteps) - edge.point(u, a + (b - a) * k / kSteps)).norm();
  return len;
}

}  // namespace

// Narrows rq's window to the hub and casing; returns the strips left.
WindowEnds fit_window_to_hub_and_casing(EdgeFinishRequest& rq, const std::vector<double>& ls, Progress& progress) {
  constexpr int kAround = 21;
  WindowEnds ends;
  // The top strip: above the requested window's end, along each iso-u line
  // up to where it leaves the casing (the region's end without one) — 0
  // when the window reaches past the casing.
  auto top_strip = [&](double from) {
    double strip = 0;
    for (int i = 0; i < kAround; ++i) {
      const double u = i / (kAround - 1.0);
      double to = 1;
      if (rq.casing) {
        auto outside = [&](double v) { return rq.casing->radial_offset(rq.edge->point(u, v)); };
        to = lowest_clear(outside, from, 1.0).value_or(1.0);
      }
      strip = std::max(strip, span_length(*rq.edge, u, from, to));
    }
    return strip;
  };
  if (rq.casing) {
    // Lowest span whose every point (sampled around) is outside the casing.
    auto beyond_tip = [&](double v) {
      double m = std::numeric_limits<double>::infinity();
      for (int i = 0; i < kAround; ++i) m = std::min(m, rq.casing->radial_offset(rq.edge->point(i / (kAround - 1.0), v)));
      return m;
    };
    const std::optional<double> tip = lowest_clear(beyond_tip, rq.v0, rq.v1);
    if (tip) rq.v1 = *tip;
    else ends.top_strip_mm = top_strip(rq.v1);
    if (rq.v1 <= rq.v0 + 1e-9)
      throw Error("edge finish: the span window lies beyond the casing (no blade edge in it)");
  } else if (rq.v1 < 1) {
    ends.top_strip_mm = top_strip(rq.v1);
  }
  if (!rq.hub) {
    // No hub to stop at: the strip below the window is the region's below v0.
    for (int i = 0; i < kAround && rq.v0 > 0; ++i)
      ends.hub_strip_mm = std::max(ends.hub_strip_mm, span_length(*rq.edge, i / (kAround - 1.0), 0.0, rq.v0));
    return ends;
  }
  const Profile& c = rq.tool->cutter();
  const std::vector<Vec3> cutter = c.surface_samples(c.z_min(), c.z_max(), 6, 24);
  Progress quiet(&progress);
  std::optional<PlannedRow> clear_row_kept;
  const std::optional<double> clear =
      lowest_clear([&](double v) { return row_hub_margin(rq, v, ls, cutter, quiet, clear_row_kept); }, rq.v0, rq.v1);
  if (!clear)
    throw Error("edge finish: no row of the window keeps the cutter " + std::to_string(rq.hub_clearance_mm) +
                " mm outside the hub (the tool is too large for the edge here)");
  const double first = *clear;
  // The strip below the first row: along each iso-u line from the hub up to
  // the first row.
  double strip = 0;
  for (int i = 0; i < kAround; ++i) {
    const double u = i / (kAround - 1.0);
    auto above_hub = [&](double v) { return rq.hub->radial_offset(rq.edge->point(u, v)); };
    // From the hub, not the requested v0: a window started higher leaves
    // the strip below it all the same (Rotor 67's LE: 12 mm reported as 0).
    const double from = lowest_clear(above_hub, 0.0, first).value_or(first);
    strip = std::max(strip, span_length(*rq.edge, u, from, first));
  }
  rq.v0 = first;
  ends.hub_strip_mm = strip;
  if (clear_row_kept && clear_row_kept->row.v == first) ends.first_row = std::move(clear_row_kept);
  return ends;
}

}  // namespace bliskrun::edge_detail
