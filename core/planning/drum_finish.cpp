#include "core/planning/drum_finish.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/common/atomic_file.h"
#include "core/common/error.h"
#include "core/geometry/differential.h"

namespace bliskrun {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

ParameterBoundary boundary_from(const SurfaceCurveOnSurface& c) {
  return ParameterBoundary(c.v, c.u);
}

Vec3 outward_normal(const SurfaceDerivs& d, bool flip) {
  Vec3 n = d.pu.cross(d.pv).normalized();
  return flip ? Vec3(-n) : n;
}

}  // namespace

RowWidth row_width(const Surface& trimmed, const Tool& tool, double u, double residual_height_mm, int samples,
                   bool flip_normal) {
  if (samples < 2) throw ParameterError("width_samples", "at least 2 contact points per row");
  RowWidth out;
  out.width_mm = std::numeric_limits<double>::infinity();
  double max_pu = 0;
  for (int i = 0; i < samples; ++i) {
    const double v = static_cast<double>(i) / (samples - 1);
    const SurfaceDerivs d = trimmed.eval(u, v);
    // The wheel axis lies in the tangent plane across the feed, i.e. along
    // the span: the cut width depends on the normal curvature along it.
    const Vec3 across = d.pu - d.pu.dot(d.pv.normalized()) * d.pv.normalized();
    // normal_curvature is signed by pu × pv; cut_width wants it signed by
    // the normal out of the material (> 0 concave).
    const double k_along = normal_curvature(d, across.normalized());
    const double k = flip_normal ? -k_along : k_along;
    const CutWidth w = tool.cut_width(tool.flank_contact_height(), k, residual_height_mm);
    out.width_mm = std::min(out.width_mm, w.width_mm);
    max_pu = std::max(max_pu, d.pu.norm());
  }
  if (!(max_pu > 0)) throw Error("row_width: degenerate trimmed flank (|dp/du'| = 0) at u' = " + std::to_string(u));
  out.du = out.width_mm / max_pu;
  return out;
}

DrumFinishResult plan_drum_finish(const DrumFinishRequest& rq, Progress& progress) {
  if (!rq.flank) throw ParameterError("flank", "a flank surface is required");
  if (!rq.hub) throw ParameterError("hub", "a hub surface of revolution is required");
  if (!rq.casing) throw ParameterError("casing", "a casing surface of revolution is required");
  if (!rq.tool) throw ParameterError("tool", "a drum wheel is required");
  if (!rq.world) throw ParameterError("world", "a collision world (neighbouring blades, hub) is required");
  if (!(rq.residual_height_mm > 0)) throw ParameterError("residual_height_mm", "must be > 0");
  if (rq.width_samples < 2) throw ParameterError("width_samples", "at least 2");
  if (!(rq.retract_mm >= 0)) throw ParameterError("retract_mm", "must be >= 0");

  DrumFinishResult res;
  auto t0 = Clock::now();
  // §3.1 Fig. 5: trim between hub (u1) and casing (u2), eq. 16.
  const SurfaceCurveOnSurface lower = intersect_with_revolution(*rq.flank, *rq.hub, rq.trim_samples_v);
  const SurfaceCurveOnSurface upper = intersect_with_revolution(*rq.flank, *rq.casing, rq.trim_samples_v);
  res.trimmed = std::make_shared<TrimmedSurface>(rq.flank, boundary_from(lower), boundary_from(upper));
  const TrimmedSurface& ts = *res.trimmed;
  res.trim_seconds = seconds_since(t0);

  // §3.1 Fig. 6: rows from the hub (u' = 0) to the tip (u' = 1).
  t0 = Clock::now();
  const Tool& tool = *rq.tool;
  double u = 0;
  for (;;) {
    DrumFinishRow row;
    row.u = u;
    const RowWidth w = row_width(ts, tool, u, rq.residual_height_mm, rq.width_samples, rq.flip_normal);
    row.width_mm = w.width_mm;
    const bool last = u >= 1.0;
    row.spacing_du = last ? 0 : std::min(w.du, 1.0 - u);
    res.rows.push_back(std::move(row));
    if (last) break;
    if (!(w.du > 1e-9)) throw Error("plan_drum_finish: row spacing vanished at u' = " + std::to_string(u));
    u = std::min(1.0, u + w.du);
    if (res.rows.size() > 100000) throw Error("plan_drum_finish: more than 100000 rows; check residual height");
  }
  res.rows_seconds = seconds_since(t0);

  ToolBody body(tool, rq.tool_tol_mm);
  double tilt_s = 0;
  for (size_t r = 0; r < res.rows.size(); ++r) {
    DrumFinishRow& row = res.rows[r];
    row.reversed = rq.zigzag && (r % 2 == 1);
    t0 = Clock::now();
    IsoUCurve curve(ts, row.u);
    const RowSteps steps = plan_row_steps(curve, rq.steps);
    res.rows_seconds += seconds_since(t0);
    row.contacts = static_cast<int>(steps.t.size());
    row.max_deviation_mm = steps.max_deviation_mm;
    res.max_deviation_mm = std::max(res.max_deviation_mm, steps.max_deviation_mm);

    t0 = Clock::now();
    std::vector<ContactFrame> frames;
    std::vector<double> vs;
    frames.reserve(steps.t.size());
    // §3.3: X = travel direction, Z = outward normal, Y = Z × X; the axis
    // at λ = w = 0 is +Y. Pick w0 ∈ {0, π} per row so it leans towards the
    // tip (+∂p/∂u'), out of the passage on the spindle side.
    double tip_side = 0;
    for (size_t i = 0; i < steps.t.size(); ++i) {
      const size_t k = row.reversed ? steps.t.size() - 1 - i : i;
      const double v = steps.t[k];
      const SurfaceDerivs d = ts.eval(row.u, v);
      ContactFrame f;
      f.point = d.p;
      f.normal = outward_normal(d, rq.flip_normal);
      Vec3 x = row.reversed ? Vec3(-d.pv) : d.pv;
      x = (x - x.dot(f.normal) * f.normal).normalized();
      f.tangent = x;
      tip_side += f.normal.cross(x).dot(d.pu);
      frames.push_back(f);
      vs.push_back(v);
    }
    TiltSettings settings = rq.tilt;
    settings.tilt0_rad = rq.tilt.tilt0_rad + (tip_side >= 0 ? 0.0 : kPi);
    const TiltRun run = tilt_path(*rq.world, body, frames, settings, progress);
    row.refusals = run.refusals;
    for (const TiltAccepted& a : run.poses) {
      DrumFinishPose p;
      p.pose = a.pose;
      p.contact = frames[a.index].point;
      p.u = row.u;
      p.v = vs[a.index];
      p.lead_rad = a.lead_rad;
      p.tilt_rad = a.tilt_rad;
      row.poses.push_back(p);
    }
    res.total_poses += static_cast<int>(row.poses.size());
    res.total_refusals += static_cast<int>(row.refusals.size());
    tilt_s += seconds_since(t0);
    progress.step(static_cast<long>(r + 1));
  }
  res.tilt_seconds = tilt_s;

  // Links: retract along the axis, traverse, approach; each segment checked.
  t0 = Clock::now();
  const DrumFinishRow* prev = nullptr;
  int prev_index = -1;
  for (size_t r = 0; r < res.rows.size(); ++r) {
    const DrumFinishRow& row = res.rows[r];
    if (row.poses.empty()) continue;
    if (prev) {
      DrumFinishLink link;
      link.from_row = prev_index;
      link.to_row = static_cast<int>(r);
      const ToolPose& a = prev->poses.back().pose;
      const ToolPose& b = row.poses.front().pose;
      ToolPose up_a = a, up_b = b;
      up_a.tip = a.tip + rq.retract_mm * a.axis;
      up_b.tip = b.tip + rq.retract_mm * b.axis;
      const ToolPose* seq[4] = {&a, &up_a, &up_b, &b};
      const char* what[3] = {"retract", "traverse", "approach"};
      link.clear = true;
      for (int s = 0; s < 3 && link.clear; ++s) {
        const MotionCheck mc =
            rq.world->check_motion(body, *seq[s], *seq[s + 1], rq.tilt.clearances, rq.tilt.motion_tol_mm);
        if (!mc.clear) {
          link.clear = false;
          std::ostringstream os;
          os << what[s] << " from row " << prev_index << " to row " << r << " not clear at t = " << mc.t
             << (mc.undecided ? " (undecided)" : "") << ", margin " << mc.min_margin_mm << " mm";
          link.reason = os.str();
        }
      }
      if (link.clear) link.moves = {up_a, up_b};
      else ++res.refused_links;
      res.links.push_back(std::move(link));
    }
    prev = &row;
    prev_index = static_cast<int>(r);
  }
  res.link_seconds = seconds_since(t0);
  return res;
}

namespace {
void put_goto(std::ostringstream& os, const ToolPose& p) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "GOTO/%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n", p.tip.x(), p.tip.y(), p.tip.z(),
                p.axis.x(), p.axis.y(), p.axis.z());
  os << buf;
}
}  // namespace

std::string drum_finish_apt(const DrumFinishResult& result, const DrumFinishRequest& rq) {
  std::ostringstream os;
  char buf[240];
  os << "$$ bliskrun drum wheel flank finish\n";
  os << "$$ TOOL " << (rq.tool ? rq.tool->description() : std::string("?")) << "\n";
  std::snprintf(buf, sizeof buf, "$$ RESIDUAL_HEIGHT %.6f CHORD_TOL %.6f ROWS %zu POSES %d REFUSALS %d\n",
                rq.residual_height_mm, rq.steps.chord_tol_mm, result.rows.size(), result.total_poses,
                result.total_refusals);
  os << buf;
  os << "MULTAX\n";
  // A refused link leaves the rows on either side unlinked: stop so no
  // unchecked move is implied between them.
  size_t link = 0;
  bool started = false;
  for (size_t r = 0; r < result.rows.size(); ++r) {
    const DrumFinishRow& row = result.rows[r];
    if (row.poses.empty()) continue;
    if (started) {
      const DrumFinishLink& l = result.links.at(link++);
      if (!l.clear) {
        os << "$$ LINK REFUSED: " << l.reason << "\n";
        os << "STOP\n";
      } else {
        for (const ToolPose& m : l.moves) {
          os << "RAPID\n";
          put_goto(os, m);
        }
      }
    }
    std::snprintf(buf, sizeof buf, "$$ ROW %zu U %.6f WIDTH %.6f\n", r, row.u, row.width_mm);
    os << buf;
    for (const DrumFinishPose& p : row.poses) put_goto(os, p.pose);
    started = true;
  }
  os << "FINI\n";
  return os.str();
}

void write_drum_finish_apt(const std::string& path, const DrumFinishResult& result,
                           const DrumFinishRequest& request) {
  write_file_atomic(path, drum_finish_apt(result, request));
}

}  // namespace bliskrun
