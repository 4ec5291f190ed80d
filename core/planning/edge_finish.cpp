// Blade edge finishing (edge_finish.h) as its steps, in order; each step's
// code is in core/planning/edge_finish/ (internal.h lists the files).
#include "core/planning/edge_finish.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/common/error.h"
#include "core/common/timing.h"
#include "core/planning/edge_finish/internal.h"

namespace bliskrun {
namespace {

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

}  // namespace

EdgeFinishResult plan_edge_finish(const EdgeFinishRequest& request, Progress& progress) {
  using namespace edge_detail;
  validate(request);
  EdgeFinishResult out;
  const FlatEnd fe = flat_end_of(*request.tool);
  if (request.r_e_mm > fe.radius_mm - fe.corner_mm)
    throw ParameterError("r_e", "the cutting-speed radius exceeds the flat bottom (R - r = " +
                                    std::to_string(fe.radius_mm - fe.corner_mm) + " mm)");
  const std::vector<double> ls = l_grid(fe, request.r_e_mm, request.l_count);
  // The window as hub and casing leave it; everything below plans in it.
  EdgeFinishRequest rq = request;
  const auto t_rows = SteadyClock::now();  // the rows the window's fit plans count as rows
  WindowEnds ends = fit_window_to_hub_and_casing(rq, ls, progress);
  out.hub_strip_mm = ends.hub_strip_mm;
  out.top_strip_mm = ends.top_strip_mm;
  out.v0 = rq.v0;
  out.v1 = rq.v1;
  const ToolBody body(*rq.tool, rq.tool_tol_mm);

  // ---- rows: bottom method ----
  std::vector<PlannedRow> planned = plan_rows(rq, ls, progress, std::move(ends.first_row));
  out.rows_seconds = seconds_since(t_rows);
  // ---- comparison row (Fig. 8) and the side-edge positioning's rows (Fig. 9) ----
  out.comparison = compare_widths(rq, planned);
  const auto t_side = SteadyClock::now();
  if (rq.method == EdgeMethod::Side) {  // the rows just planned are the side-edge method's
    out.side_rows = static_cast<int>(planned.size());
    set_side_window(rq, out);
  } else {
    plan_side_rows(rq, ls, out, progress);
  }
  out.side_seconds = seconds_since(t_side);

  const DesignGuards guards = design_guards(rq, fe);
  out.checked_v0 = guards.v0;
  out.checked_v1 = guards.v1;
  const PoseChecks checks{body, guards};

  // ---- poses tilted clear of the world; partial rows where that leaves material ----
  const auto t_clear = SteadyClock::now();
  clear_rows(rq, checks, planned, progress);
  out.infill_rows += fill_partial_rows(rq, checks, ls, planned, progress);
  out.clear_seconds = seconds_since(t_clear);

  // ---- order, checks, links ----
  const auto t_checks = SteadyClock::now();
  out.gouge_breaks += check_rows(rq, checks, ls, planned, progress);
  // ---- partial rows where the rows as checked still leave material ----
  const auto t_sim = SteadyClock::now();
  fill_simulated_gaps(rq, checks, ls, planned, out, progress);
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
  const auto t_links = SteadyClock::now();
  link_passes(rq, body, guards, out, progress);
  progress.end();
  out.links_seconds = seconds_since(t_links);
  out.checks_seconds = seconds_since(t_checks);
  return out;
}

}  // namespace bliskrun
