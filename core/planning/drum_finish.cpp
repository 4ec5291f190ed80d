#include "core/planning/drum_finish.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "core/common/atomic_file.h"
#include "core/common/error.h"
#include "core/common/parallel.h"
#include "core/common/timing.h"
#include "core/geometry/differential.h"
#include "core/toolpath/apt.h"

namespace bliskrun {
namespace {


Vec3 outward_normal(const SurfaceDerivs& d, bool flip) {
  Vec3 n = d.pu.cross(d.pv).normalized();
  return flip ? Vec3(-n) : n;
}

// The drum wheel's axis lies in the tangent plane across the feed, i.e.
// along the span: the unit direction there (pu without its part along pv)
// and the flank's normal curvature along it, signed by the normal out of the
// material (> 0 concave) as Profile::cut_width wants it.
struct AcrossFeed {
  Vec3 direction;
  double curvature_per_mm = 0;
};
AcrossFeed across_feed(const SurfaceDerivs& d, bool flip_normal) {
  const Vec3 pv = d.pv.normalized();
  const Vec3 across = (d.pu - d.pu.dot(pv) * pv).normalized();
  // normal_curvature is signed by pu × pv.
  const double k = normal_curvature(d, across);
  return {across, flip_normal ? -k : k};
}

// §3.3 contact frames of a row run along +v: X = travel direction,
// Z = outward normal, Y = Z × X; the axis at λ = w = 0 is +Y. The initial
// tilt w0 ∈ {0, π} (added to the settings' w0) is chosen per row so the axis
// leans towards the tip (+∂p/∂u'), out of the passage on the spindle side;
// with it the axis does not depend on the travel direction, so a row run
// backwards reuses these axes.
struct RowFrames {
  std::vector<ContactFrame> frames;
  double tilt0_rad = 0;
};
RowFrames row_frames(const TrimmedSurface& ts, double u, const std::vector<double>& vs, bool flip_normal,
                     double tilt0_rad) {
  RowFrames out;
  out.frames.reserve(vs.size());
  double tip_side = 0;
  for (double v : vs) {
    const SurfaceDerivs d = ts.eval(u, v);
    ContactFrame f;
    f.point = d.p;
    f.normal = outward_normal(d, flip_normal);
    f.tangent = (d.pv - d.pv.dot(f.normal) * f.normal).normalized();
    tip_side += f.normal.cross(f.tangent).dot(d.pu);
    out.frames.push_back(f);
  }
  out.tilt0_rad = tilt0_rad + (tip_side >= 0 ? 0.0 : kPi);
  return out;
}

// Points on the cutter's surface below its flank contact height (the part
// that can reach into the hub), in the tool frame: rings of the profile and
// the bottom face.
std::vector<Vec3> cutter_lower_samples(const Tool& tool) {
  const Profile& c = tool.cutter();
  return c.surface_samples(c.z_min(), tool.flank_contact_height(), 3, 24);
}

// Smallest radial offset from the hub, minus the clearance, of the cutter's
// lower samples at `samples` contacts of the row at u' (initial axes).
double hub_margin(const TrimmedSurface& ts, const DrumFinishRequest& rq, const std::vector<Vec3>& lower,
                  double u) {
  std::vector<double> vs(rq.width_samples);
  for (int i = 0; i < rq.width_samples; ++i) vs[i] = static_cast<double>(i) / (rq.width_samples - 1);
  const RowFrames rf = row_frames(ts, u, vs, rq.flip_normal, rq.tilt.tilt0_rad);
  double margin = std::numeric_limits<double>::infinity();
  for (const ContactFrame& f : rf.frames) {
    const ToolPose pose = place_tool(*rq.tool, f, axis_from_lead_tilt(f, rq.tilt.lead0_rad, rf.tilt0_rad));
    const Eigen::Isometry3d T = tool_to_part(pose);
    for (const Vec3& q : lower) {
      margin = std::min(margin, rq.hub->radial_offset(T * q) - rq.hub_clearance_mm);
      if (margin < 0) return margin;  // bisection only needs the sign
    }
  }
  return margin;
}

// The hub clearance rule (DrumFinishRequest::hub_clearance_mm): the lowest
// u' whose row clears the hub, by bisection to 1e-4 in u' (a few um of span).
double first_clear_row(const TrimmedSurface& ts, const DrumFinishRequest& rq) {
  const std::vector<Vec3> lower = cutter_lower_samples(*rq.tool);
  if (hub_margin(ts, rq, lower, 0.0) >= 0) return 0.0;
  if (hub_margin(ts, rq, lower, 1.0) < 0)
    throw Error("plan_drum_finish: the wheel cannot clear the hub by " + std::to_string(rq.hub_clearance_mm) +
                " mm on any row of this flank (even at the tip); check the wheel's head length");
  double lo = 0, hi = 1;
  while (hi - lo > 1e-4) {
    const double mid = 0.5 * (lo + hi);
    (hub_margin(ts, rq, lower, mid) >= 0 ? hi : lo) = mid;
  }
  return hi;
}

// Whether two neighbouring rows, as tilted, leave a strip between them
// where neither wheel reaches within the residual height: their largest
// 3-D gap over the chord against the reach of a's cut above and b's below.
// 2% slack: the reaches come from the actual contacts, the spacing from
// sampled ones (h grows with the square of the gap). Rows without poses
// are not compared.
bool rows_apart(const TrimmedSurface& ts, const DrumFinishRow& a, const DrumFinishRow& b) {
  if (a.poses.empty() || b.poses.empty()) return false;
  double gap = 0;
  for (int i = 0; i <= 20; ++i) {
    const double v = i / 20.0;
    gap = std::max(gap, (ts.point(b.u, v) - ts.point(a.u, v)).norm());
  }
  return gap > 1.02 * (a.reach_above_mm + b.reach_below_mm);
}

// How far along the span each pose's cut reaches within the residual height
// below (towards the hub) and above its contact, the smallest over the row.
// Measured on the pose as placed, not from the profile's Fig. 6 width: a
// lead moves the contact along the barrel, or onto the head's edge, where
// the wheel no longer lies tangent to the surface. The wheel's meridian
// through the contact (in the plane of the axis and the contact) is walked
// from the contact towards each end until its height above the surface's
// osculating circle across the feed reaches the residual height; at an end
// without reaching it the strip ends with the wheel.
void row_reach(DrumFinishRow& row, const TrimmedSurface& ts, const Tool& tool, const DrumFinishRequest& rq) {
  row.reach_below_mm = row.reach_above_mm = std::numeric_limits<double>::infinity();
  const Profile& c = tool.cutter();
  constexpr int kSteps = 400;
  for (const DrumFinishPose& p : row.poses) {
    const SurfaceDerivs d = ts.eval(p.u, p.v);
    const Vec3 n = outward_normal(d, rq.flip_normal);
    const AcrossFeed af = across_feed(d, rq.flip_normal);
    const Vec3& across = af.direction;
    const double k = af.curvature_per_mm;
    const Eigen::Isometry3d to_part = tool_to_part(p.pose);
    const Vec3 q = to_part.inverse() * p.contact;
    const double phi = std::atan2(q.y(), q.x());
    const double zc = std::clamp(q.z(), c.z_min(), c.z_max());
    // Height above the surface and span offset of the meridian point at z.
    auto at = [&](double z, double* s_out) {
      const double r = c.radius_at(std::clamp(z, c.z_min() + 1e-9, c.z_max() - 1e-9));
      const Vec3 e = to_part * Vec3(r * std::cos(phi), r * std::sin(phi), z) - p.contact;
      const double s = e.dot(across);
      *s_out = s;
      return e.dot(n) - 0.5 * k * s * s;
    };
    double reach[2] = {0, 0};
    for (int side = 0; side < 2; ++side) {
      const double z_end = side == 0 ? c.z_min() : c.z_max();
      double z_prev = zc, s_prev = 0, s = 0;
      bool found = false;
      for (int i = 1; i <= kSteps && !found; ++i) {
        const double z = zc + (z_end - zc) * i / kSteps;
        if (at(z, &s) >= rq.residual_height_mm) {
          // Bisection between the last point below and this one.
          double lo = z_prev, hi = z;
          for (int it = 0; it < 40; ++it) {
            const double mid = 0.5 * (lo + hi);
            double sm;
            (at(mid, &sm) >= rq.residual_height_mm ? hi : lo) = mid;
          }
          at(hi, &s);
          found = true;
        } else {
          z_prev = z;
          s_prev = s;
        }
      }
      reach[side] = std::abs(found ? s : s_prev);
    }
    row.reach_below_mm = std::min(row.reach_below_mm, reach[0]);
    row.reach_above_mm = std::min(row.reach_above_mm, reach[1]);
  }
  if (row.poses.empty()) row.reach_below_mm = row.reach_above_mm = 0;
}

void insert_contacts(const TrimmedSurface& ts, double u, RowSteps& st, const std::vector<double>& split_after);

// Halves every segment of the row whose chord deviation plus the axis
// turning term ρ θ²/8 (ρ the larger distance from the tip to the contact of
// its two poses, θ the axis turn) exceeds the tolerance; returns whether
// any was. The new contacts' chord deviations are measured.
bool split_turning_segments(const TrimmedSurface& ts, double u, RowSteps& st, const std::vector<DrumFinishPose>& poses,
                            const std::vector<int>& index, double tol_mm) {
  std::vector<double> split_after;  // contact parameters to insert
  for (size_t k = 0; k + 1 < poses.size(); ++k) {
    if (index[k + 1] != index[k] + 1) continue;  // a refusal between: nothing is emitted across it
    const DrumFinishPose &a = poses[k], &b = poses[k + 1];
    const double rho = std::max((a.contact - a.pose.tip).norm(), (b.contact - b.pose.tip).norm());
    const double theta = axis_angle_rad(a.pose.axis, b.pose.axis);
    if (st.deviation_mm[index[k]] + rho * theta * theta / 8 > tol_mm * (1 + 1e-9))
      split_after.push_back(0.5 * (st.t[index[k]] + st.t[index[k] + 1]));
  }
  if (split_after.empty()) return false;
  insert_contacts(ts, u, st, split_after);
  return true;
}

// Adds contacts at the given parameters to the row's steps and measures
// the chord deviation of every segment again.
void insert_contacts(const TrimmedSurface& ts, double u, RowSteps& st, const std::vector<double>& split_after) {
  const IsoUCurve curve(ts, u);
  std::vector<double> t = st.t;
  t.insert(t.end(), split_after.begin(), split_after.end());
  std::sort(t.begin(), t.end());
  st.t = t;
  st.points.clear();
  st.deviation_mm.clear();
  st.max_deviation_mm = 0;
  for (size_t k = 0; k < t.size(); ++k) {
    st.points.push_back(curve.eval(t[k]).p);
    if (k + 1 < t.size()) {
      st.deviation_mm.push_back(chord_deviation(curve, t[k], t[k + 1]));
      st.max_deviation_mm = std::max(st.max_deviation_mm, st.deviation_mm.back());
    }
  }
}

// Halves every segment of the row whose swept wheel dips below the
// finished flank (the guard's samples) by more than the tolerance; returns
// whether any did.
// Only segments whose estimate (chord + ρθ²/8) is at least half the
// tolerance are swept: what the estimate leaves out is second order (the
// contact moving over the wheel between the poses), a small fraction of it.
// The sweep steps 0.05 mm of cutter motion, as the simulation does; the
// allowance is the tolerance less what the guard's samples can miss across
// the feed (spacing² / 8 r, r the wheel's radius).
bool split_gouging_segments(const TrimmedSurface& ts, double u, RowSteps& st, const std::vector<DrumFinishPose>& poses,
                            const std::vector<int>& index, const GougeGuard& guard, const Tool& tool, double tol_mm) {
  const double allowed = std::max(0.0, tol_mm - guard.between_samples_mm(tool.cutter().max_radius()));
  std::vector<double> split_after;
  for (size_t k = 0; k + 1 < poses.size(); ++k) {
    if (index[k + 1] != index[k] + 1) continue;
    const DrumFinishPose &a = poses[k], &b = poses[k + 1];
    const double rho = std::max((a.contact - a.pose.tip).norm(), (b.contact - b.pose.tip).norm());
    const double theta = axis_angle_rad(a.pose.axis, b.pose.axis);
    if (st.deviation_mm[index[k]] + rho * theta * theta / 8 < 0.5 * tol_mm) continue;
    if (guard.deepest_cut(tool, a.pose, b.pose, allowed, false, false, 0.05).depth_mm < 0)
      split_after.push_back(0.5 * (st.t[index[k]] + st.t[index[k] + 1]));
  }
  if (split_after.empty()) return false;
  insert_contacts(ts, u, st, split_after);
  return true;
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
    // The cut width depends on the normal curvature across the feed.
    const CutWidth w =
        tool.cut_width(tool.flank_contact_height(), across_feed(d, flip_normal).curvature_per_mm, residual_height_mm);
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
  if (!(rq.guard_spacing_mm > 0)) throw ParameterError("guard_spacing_mm", "must be > 0");
  if (!(rq.hub_clearance_mm >= 0)) throw ParameterError("hub_clearance_mm", "must be >= 0");

  DrumFinishResult res;
  auto t0 = SteadyClock::now();
  // §3.1 Fig. 5: trim between hub (u1) and casing (u2), eq. 16.
  res.trimmed = trim_between(rq.flank, *rq.hub, *rq.casing, rq.trim_samples_v);
  const TrimmedSurface& ts = *res.trimmed;

  // The first row: as low as the hub lets the wheel go.
  res.first_row_u = first_clear_row(ts, rq);
  for (int i = 0; i <= rq.width_samples; ++i) {
    const double v = static_cast<double>(i) / rq.width_samples;
    res.hub_strip_mm = std::max(res.hub_strip_mm, (ts.point(res.first_row_u, v) - ts.point(0, v)).norm());
  }
  res.trim_seconds = seconds_since(t0);

  // §3.1 Fig. 6: rows from the first row up to the tip (u' = 1), spaced
  // for the initial axis.
  t0 = SteadyClock::now();
  const Tool& tool = *rq.tool;
  std::vector<DrumFinishRow> rows;
  double u = res.first_row_u;
  for (;;) {
    DrumFinishRow row;
    row.u = u;
    const RowWidth w = row_width(ts, tool, u, rq.residual_height_mm, rq.width_samples, rq.flip_normal);
    row.width_mm = w.width_mm;
    const bool last = u >= 1.0;
    rows.push_back(std::move(row));
    if (last) break;
    if (!(w.du > 1e-9)) throw Error("plan_drum_finish: row spacing vanished at u' = " + std::to_string(u));
    u = std::min(1.0, u + w.du);
    if (rows.size() > 100000) throw Error("plan_drum_finish: more than 100000 rows; check residual height");
  }
  res.rows_seconds = seconds_since(t0);

  // Steps and tilt, row by row; then check that the rows as tilted still
  // cover the flank. A lead λ > 0 (raised by the tilt loop to clear e.g. the
  // shank from the concave blade) moves the contact along the barrel, so the
  // strip the wheel leaves within the residual height shrinks on one side;
  // where two neighbouring rows no longer meet, a row is inserted halfway
  // and everything re-planned (steps are cached per row).
  ToolBody body(tool, rq.tool_tol_mm);
  // The finished flank, sampled once, for proving the cutting moves and the
  // links against it (core/sim GougeGuard).
  const auto guard_t0 = SteadyClock::now();
  const GougeGuard guard(ts, link_guard_sampling(ts, rq.guard_spacing_mm, rq.flip_normal));
  res.guard_spacing_mm = guard.spacing_mm();
  res.link_seconds += seconds_since(guard_t0);
  Progress per_row(&progress);
  std::map<double, RowSteps> steps_cache;
  std::map<double, std::pair<std::vector<DrumFinishPose>, std::vector<TiltRefusal>>> tilt_cache;
  double tilt_s = 0;
  for (int pass = 0;; ++pass) {
    progress.begin(pass == 0 ? "drum finish rows" : "drum finish rows (after inserting rows)",
                   static_cast<long>(rows.size()));
    for (size_t r = 0; r < rows.size(); ++r) {
      DrumFinishRow& row = rows[r];
      row.reversed = rq.zigzag && (r % 2 == 1);
      t0 = SteadyClock::now();
      auto cached = steps_cache.find(row.u);
      if (cached == steps_cache.end()) {
        IsoUCurve curve(ts, row.u);
        cached = steps_cache.emplace(row.u, plan_row_steps(curve, rq.steps)).first;
      }
      const RowSteps& steps = cached->second;
      res.rows_seconds += seconds_since(t0);

      t0 = SteadyClock::now();
      // Tilted once per row, along +v: the same axes serve the row run
      // backwards (X, Y and w0 all flip, the axis does not), and a motion
      // proved clear one way is clear the other. So inserting a row, which
      // flips the zigzag direction of the rows above it, costs one row.
      auto tilted = tilt_cache.find(row.u);
      for (int round = 0; tilted == tilt_cache.end(); ++round) {
        RowSteps& st = steps_cache.at(row.u);
        const RowFrames rf = row_frames(ts, row.u, st.t, rq.flip_normal, rq.tilt.tilt0_rad);
        TiltSettings settings = rq.tilt;
        settings.tilt0_rad = rf.tilt0_rad;
        const TiltRun run = tilt_path(*rq.world, body, rf.frames, settings, per_row);
        std::vector<DrumFinishPose> poses;
        std::vector<int> index;
        for (const TiltAccepted& a : run.poses) {
          DrumFinishPose p;
          p.pose = a.pose;
          p.contact = rf.frames[a.index].point;
          p.u = row.u;
          p.v = st.t[a.index];
          p.lead_rad = a.lead_rad;
          p.tilt_rad = a.tilt_rad;
          poses.push_back(p);
          index.push_back(a.index);
        }
        // The chord tolerance bounds the contact's path between two poses;
        // where the tilt loop turns the axis by θ between them, a cutter
        // point ρ from the tip also leaves that chord by up to ρ θ²/8. Where
        // the two together exceed the tolerance the segment is halved and
        // the row tilted again (a few rounds; what is left is measured by
        // the simulation of the whole program).
        // Without the measured guarantee (eq. 17 as the paper writes it,
        // for its Fig. 13 comparison) the steps are left as planned.
        const bool guarantee = rq.steps.guarantee_tolerance && round < 6;
        if (guarantee && split_turning_segments(ts, row.u, st, poses, index, rq.steps.chord_tol_mm)) {
          ++res.turn_splits;
          continue;
        }
        // The estimate is not the proof: each cutting segment is swept
        // through the finished flank's samples, and one that dips below it
        // by more than the chord tolerance is halved too.
        if (guarantee && rq.verify_rows &&
            split_gouging_segments(ts, row.u, st, poses, index, guard, tool, rq.steps.chord_tol_mm)) {
          ++res.gouge_splits;
          continue;
        }
        tilted = tilt_cache.emplace(row.u, std::make_pair(std::move(poses), run.refusals)).first;
      }
      row.contacts = static_cast<int>(steps.t.size());
      row.max_deviation_mm = steps.max_deviation_mm;
      row.v = steps.t;
      row.deviation_mm = steps.deviation_mm;
      row.poses = tilted->second.first;
      row.refusals = tilted->second.second;
      if (row.reversed) std::reverse(row.poses.begin(), row.poses.end());
      row_reach(row, ts, tool, rq);
      tilt_s += seconds_since(t0);
      progress.step(static_cast<long>(r + 1));
    }
    progress.end();
    // Neighbouring rows that no longer meet within the residual height.
    std::vector<DrumFinishRow> refined;
    int inserted = 0;
    for (size_t r = 0; r < rows.size(); ++r) {
      refined.push_back(rows[r]);
      if (r + 1 == rows.size()) break;
      const DrumFinishRow &a = rows[r], &b = rows[r + 1];
      if (pass < 4 && b.u - a.u > 1e-4 && rows_apart(ts, a, b)) {
        DrumFinishRow mid;
        mid.u = 0.5 * (a.u + b.u);
        mid.width_mm = row_width(ts, tool, mid.u, rq.residual_height_mm, rq.width_samples, rq.flip_normal).width_mm;
        refined.push_back(std::move(mid));
        ++inserted;
      }
    }
    if (inserted == 0) break;
    res.inserted_rows += inserted;
    rows = std::move(refined);
  }
  res.tilt_seconds = tilt_s;
  for (size_t r = 0; r < rows.size(); ++r) {
    rows[r].spacing_du = r + 1 < rows.size() ? rows[r + 1].u - rows[r].u : 0.0;
    if (r + 1 < rows.size() && rows_apart(ts, rows[r], rows[r + 1])) ++res.uncovered_gaps;
    res.total_poses += static_cast<int>(rows[r].poses.size());
    res.total_refusals += static_cast<int>(rows[r].refusals.size());
    res.max_deviation_mm = std::max(res.max_deviation_mm, rows[r].max_deviation_mm);
  }
  // From the tip down (the request's top_down): the same rows in reverse;
  // each keeps its direction, so the zigzag still alternates, and the links
  // below are planned in the order they are cut.
  if (rq.top_down) {
    std::reverse(rows.begin(), rows.end());
    for (size_t r = 0; r < rows.size(); ++r) rows[r].spacing_du = r + 1 < rows.size() ? rows[r].u - rows[r + 1].u : 0.0;
  }
  res.rows = std::move(rows);

  // Links: leave along the flank normal, traverse, approach along the
  // normal (plan_link); every leg proved against the world and against the
  // finished flank itself, sampled over the whole trimmed flank.
  t0 = SteadyClock::now();
  LinkChecks checks;
  checks.world = rq.world;
  checks.body = &body;
  checks.clearances = rq.tilt.clearances;
  checks.motion_tol_mm = rq.tilt.motion_tol_mm;
  checks.guard = &guard;
  // The barrel's radius about its axis is the cutter's smallest curvature
  // radius where it crosses the flank.
  checks.guard_margin_mm = guard.between_samples_mm(tool.cutter().max_radius());
  // The guard samples the finished flank; the rest of the blade being
  // machined (its other flank, its edges) is left out for the wheel.
  checks.traverse_world = rq.world->unchecked_pairs();
  auto end_of = [&](const DrumFinishPose& p) {
    return LinkEnd{p.pose, outward_normal(ts.eval(p.u, p.v), rq.flip_normal)};
  };
  const DrumFinishRow* prev = nullptr;
  int prev_index = -1;
  for (size_t r = 0; r < res.rows.size(); ++r) {
    const DrumFinishRow& row = res.rows[r];
    if (row.poses.empty()) continue;
    if (prev) {
      progress.check();
      DrumFinishLink link;
      link.from_row = prev_index;
      link.to_row = static_cast<int>(r);
      const PlannedLink pl = plan_link(end_of(prev->poses.back()), end_of(row.poses.front()), checks, rq.links);
      link.clear = pl.clear;
      if (pl.clear) {
        link.moves = pl.via;
        link.legs = pl.legs;
        link.offset_mm = pl.offset_mm;
        link.turn_rad = pl.turn_rad;
        link.deepest_cut_mm = pl.deepest_cut_mm;
      } else {
        link.reason = "link from row " + std::to_string(prev_index) + " to row " + std::to_string(r) + ": " + pl.reason;
        ++res.refused_links;
      }
      res.links.push_back(std::move(link));
    }
    prev = &row;
    prev_index = static_cast<int>(r);
  }
  // In and out: along the normal at the first and last pose.
  const DrumFinishRow* first = nullptr;
  for (const DrumFinishRow& row : res.rows)
    if (!row.poses.empty()) {
      if (!first) first = &row;
      prev = &row;
    }
  if (first) {
    auto departure = [&](const DrumFinishPose& p, const char* what) {
      DrumFinishEnd e = plan_departure(end_of(p), checks, rq.links);
      if (!e.clear) {
        e.reason = std::string(what) + ": " + e.reason;
        ++res.refused_links;
      }
      return e;
    };
    res.lead_in = departure(first->poses.front(), "lead-in");
    res.lead_out = departure(prev->poses.back(), "lead-out");
  }
  res.link_seconds = seconds_since(t0);
  return res;
}

std::vector<DrumFinishResult> plan_drum_finish_all(const std::vector<DrumFinishRequest>& requests, int threads,
                                                   Progress& progress) {
  std::vector<DrumFinishResult> results(requests.size());
  run_parallel(requests.size(), threads, progress, "drum finish, flanks",
               [&](size_t k, Progress& own) { results[k] = plan_drum_finish(requests[k], own); });
  return results;
}

ToolpathPasses drum_finish_passes(const DrumFinishResult& result) {
  return toolpath_passes(drum_finish_moves(result));
}

DrumFinishSimulation simulate_drum_finish(const DrumFinishResult& result, const DrumFinishRequest& request,
                                          UndercutOptions o, Progress& progress) {
  if (!result.trimmed) throw ParameterError("result", "a drum-finish plan with its trimmed flank");
  if (!request.tool) throw ParameterError("tool", "the plan's drum wheel");
  const ToolpathPasses passes = drum_finish_passes(result);
  // The machined window's samples as the caller asked (samples_u over
  // [first_row_u, 1]), continued at the same spacing down to the hub curve.
  DrumFinishSimulation sim;
  if (o.samples_u < 2) throw ParameterError("samples_u", "at least 2");
  const double du = (1 - result.first_row_u) / (o.samples_u - 1);
  sim.first_machined_row = du > 0 ? static_cast<int>(std::floor(result.first_row_u / du + 1e-9)) : 0;
  o.u0 = result.first_row_u - sim.first_machined_row * du;
  o.u1 = 1;
  o.samples_u += sim.first_machined_row;
  o.machined_u0 = result.first_row_u - 0.5 * du;
  o.machined_u1 = 1;
  o.flip_normal = request.flip_normal;
  sim.undercut = simulate_undercut(*result.trimmed, *request.tool, passes.passes, o, progress);
  if (sim.undercut.overcut_pass >= 0) {
    const Toolpath moves = drum_finish_moves(result);
    sim.overcut_move = passes.first_move.at(sim.undercut.overcut_pass) + sim.undercut.overcut_pose;
    const Move& m = moves.at(sim.overcut_move);
    sim.overcut_motion = m.motion;
    sim.overcut_row = m.row;
  }
  return sim;
}

Toolpath drum_finish_moves(const DrumFinishResult& result) {
  Toolpath moves;
  bool started = false;
  int prev_row = -1;
  auto stop = [&](int row, const std::string& reason) {
    Move m;
    m.kind = Move::Kind::Stop;
    m.row = row;
    m.motion = "stop";
    m.reason = reason;
    moves.push_back(std::move(m));
  };
  int last_row = -1;
  for (size_t r = 0; r < result.rows.size(); ++r) {
    const DrumFinishRow& row = result.rows[r];
    if (row.poses.empty()) continue;
    const int ri = static_cast<int>(r);
    last_row = ri;
    if (!started) {
      if (result.lead_in.clear) moves.push_back({Move::Kind::Rapid, result.lead_in.away, ri, "start", {}});
      else stop(ri, result.lead_in.reason);
    }
    if (started) {
      // The link from the previous row with poses into this one; a plan
      // edited afterwards (rows emptied) may have none: then the program
      // stops rather than imply an unproved move.
      const DrumFinishLink* found = nullptr;
      for (const DrumFinishLink& l : result.links)
        if (l.to_row == ri && l.from_row == prev_row) found = &l;
      if (!found) {
        stop(ri, "no proved link from row " + std::to_string(prev_row) + " to row " + std::to_string(ri));
      } else if (!found->clear) {
        stop(ri, found->reason);
      } else {
        const DrumFinishLink& l = *found;
        for (size_t k = 0; k < l.moves.size(); ++k)
          moves.push_back({Move::Kind::Rapid, l.moves[k], ri, link_leg_name(l.legs.at(k)), {}});
      }
    }
    for (size_t k = 0; k < row.poses.size(); ++k) {
      // After a refused link the program stops: the row's first pose is
      // reached by the operator, not by a proved move.
      const bool after_stop = !moves.empty() && moves.back().kind == Move::Kind::Stop;
      const char* motion = k > 0 ? "cut" : (moves.empty() || after_stop) ? "start" : "approach";
      moves.push_back({Move::Kind::Feed, row.poses[k].pose, ri, motion, {}});
    }
    started = true;
    prev_row = ri;
  }
  if (started) {
    if (result.lead_out.clear) moves.push_back({Move::Kind::Rapid, result.lead_out.away, last_row, "retract", {}});
    else stop(last_row, result.lead_out.reason);
  }
  return moves;
}

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
  write_apt_moves(os, drum_finish_moves(result), [&](int row) {
    const DrumFinishRow& r = result.rows[row];
    std::snprintf(buf, sizeof buf, "$$ ROW %d U %.6f WIDTH %.6f\n", row, r.u, r.width_mm);
    return std::string(buf);
  }, "LINK REFUSED");
  os << "FINI\n";
  return os.str();
}

void write_drum_finish_apt(const std::string& path, const DrumFinishResult& result,
                           const DrumFinishRequest& request) {
  write_file_atomic(path, drum_finish_apt(result, request));
}

}  // namespace bliskrun
