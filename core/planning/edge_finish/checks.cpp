// What a pose and a cutting motion are proved against: the world (the whole
// tool), the machine's reach, and the design guards (the edge region and
// both flanks near their edge ends, swept as the independent simulation
// sweeps them); and each row checked in cutting order, split into passes
// where a motion is not proved.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/common/parallel.h"
#include "core/planning/edge_finish/internal.h"

namespace bliskrun::edge_detail {

double DesignGuards::allowed() const { return std::max(0.0, -e1_mm - miss_mm); }
double DesignGuards::least_allowed() const { return allowed(); }
double DesignGuards::deepest(const Tool& tool, const ToolPose& a, const ToolPose& b, bool ends) const {
  double d = edge->deepest_cut(tool, a, b, allowed(), ends, ends).depth_mm;
  for (const auto& g : flanks) d = std::min(d, g->deepest_cut(tool, a, b, allowed(), ends, ends).depth_mm);
  return d;
}

std::string PoseChecks::gouge(const Tool& tool, const ToolPose& pose, bool liftable) const {
  const double d = guards.deepest(tool, pose, pose, true);
  if (d >= 0 || (liftable && -d - guards.least_allowed() < kMaxLiftMm)) return "";
  char buf[96];
  std::snprintf(buf, sizeof buf, "the tool cuts %.1f um into the blade beside its contact strip", -1e3 * d);
  return buf;
}

double min_pv(const Surface& edge, double v) {
  double pv = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= 20; ++i) pv = std::min(pv, edge.eval(i / 20.0, v).pv.norm());
  return std::max(pv, 1e-9);
}

namespace {

// The smallest radius of s's parameter lines over a window, along u
// (along_u) or along v, from circles through three neighbouring points
// (97 per line, 9 lines): for the edge region along u, the round's.
double line_radius_min(const Surface& s, bool along_u, double u0, double u1, double v0, double v1) {
  constexpr int kAlong = 97;
  double rho = std::numeric_limits<double>::infinity();
  auto at = [&](double line, double t) {
    return along_u ? s.point(u0 + (u1 - u0) * t, v0 + (v1 - v0) * line) : s.point(u0 + (u1 - u0) * line, v0 + (v1 - v0) * t);
  };
  for (int j = 0; j < 9; ++j)
    for (int i = 1; i + 1 < kAlong; ++i) {
      const Vec3 a = at(j / 8.0, (i - 1.0) / (kAlong - 1)), b = at(j / 8.0, i / (kAlong - 1.0)),
                 c = at(j / 8.0, (i + 1.0) / (kAlong - 1));
      const double cross = (b - a).cross(c - a).norm();
      if (cross > 1e-15) rho = std::min(rho, (b - a).norm() * (c - b).norm() * (c - a).norm() / (2 * cross));
    }
  return rho;
}

// The longest parameter line over a window along u or v (9 lines, 64 segments), mm.
double line_length_max(const Surface& s, bool along_u, double u0, double u1, double v0, double v1) {
  double len = 0;
  for (int j = 0; j <= 8; ++j) {
    double l = 0;
    for (int k = 0; k < 64; ++k) {
      const double line = j / 8.0, t0 = k / 64.0, t1 = (k + 1) / 64.0;
      l += along_u ? (s.point(u0 + (u1 - u0) * t1, v0 + (v1 - v0) * line) - s.point(u0 + (u1 - u0) * t0, v0 + (v1 - v0) * line)).norm()
                   : (s.point(u0 + (u1 - u0) * line, v0 + (v1 - v0) * t1) - s.point(u0 + (u1 - u0) * line, v0 + (v1 - v0) * t0)).norm();
    }
    len = std::max(len, l);
  }
  return len;
}

// Between samples h apart the tool's surface can dip below the design by
// what the samples miss, h² / 8 times the two surfaces' curvatures summed
// (they bend towards each other): the corner's 1/r and the design's 1/ρ
// along that direction — a flat bottom over the built-in TE's 0.3 mm round
// misses 0.42 um at 32 um, which the allowance (figured for the corner
// alone) did not keep: 1.18 um where e1 is 1 um. Each direction is spaced
// so its miss is a quarter of |e1| (around the built-in TE's round 19 um,
// along the span 32 um); the miss the counts give (a count is at most
// 8000) is returned in `miss_mm`.
UndercutOptions guard_grid(const Surface& s, double corner_mm, double e1_abs_mm, double u0, double u1, double v0,
                           double v1, double& miss_mm, double& radius_u_mm) {
  UndercutOptions o;
  o.u0 = u0;
  o.u1 = u1;
  o.v0 = v0;
  o.v1 = v1;
  miss_mm = 0;
  for (bool along_u : {true, false}) {
    const double rho = line_radius_min(s, along_u, u0, u1, v0, v1);
    const double r = 1.0 / (1.0 / corner_mm + 1.0 / std::max(rho, 1e-3));
    const double len = line_length_max(s, along_u, u0, u1, v0, v1);
    const int n = std::clamp(static_cast<int>(std::ceil(len / std::sqrt(2 * r * e1_abs_mm))) + 1, 8, 8000);
    const double h = len / (n - 1);
    miss_mm = std::max(miss_mm, h * h / (8 * r));
    (along_u ? o.samples_u : o.samples_v) = n;
    if (along_u) radius_u_mm = r;
  }
  return o;
}

}  // namespace

// The edge region and the flanks sampled by guard_grid; the allowance
// keeps what the samples can miss inside e1, wherever the window and
// however long the blade.
DesignGuards design_guards(const EdgeFinishRequest& rq, const FlatEnd& fe) {
  DesignGuards guards;
  guards.e1_mm = rq.band.e1_mm;
  const double corner = std::max(fe.corner_mm, 1e-3);
  const double e1_abs = std::max(-rq.band.e1_mm, 1e-3);
  // The edge region wherever a pose can reach, not the window alone: a
  // row's disc reaches a tool radius across its feed, so the top row cut
  // above the window (1.23 um at GOTO 1534 of the built-in LE, unchecked
  // while the guard sampled the window only) and the first below it.
  const double reach_mm = fe.radius_mm + 1.0;
  guards.v0 = std::max(0.0, rq.v0 - reach_mm / min_pv(*rq.edge, rq.v0));
  guards.v1 = std::min(1.0, rq.v1 + reach_mm / min_pv(*rq.edge, rq.v1));
  double miss = 0;
  const UndercutOptions edge_sampling =
      guard_grid(*rq.edge, corner, e1_abs, 0, 1, guards.v0, guards.v1, miss, guards.edge_radius_mm);
  guards.edge = std::make_unique<GougeGuard>(*rq.edge, edge_sampling);
  guards.edge_window = {rq.edge.get(), edge_sampling};
  guards.miss_mm = miss;
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
    double radius_u = 0;
    const UndercutOptions sampling =
        guard_grid(*flank, corner, e1_abs, std::max(0.0, std::min(fu0, fu1) - margin),
                   std::min(1.0, std::max(fu0, fu1) + margin), k == 0 ? 0.0 : 0.88, k == 0 ? 0.12 : 1.0, miss, radius_u);
    guards.flanks.push_back(std::make_unique<GougeGuard>(*flank, sampling));
    guards.flank_windows.push_back({flank.get(), sampling});
    guards.miss_mm = std::max(guards.miss_mm, miss);
  }
  return guards;
}

// Whether a pose's axis is within the machine's reach (EdgeFinishRequest::
// reach_axis, reach_min_rad, reach_max_rad).
bool within_reach(const EdgeFinishRequest& rq, const ToolPose& pose) {
  if (rq.reach_axis.isZero()) return true;
  const double c = pose.axis.normalized().dot(rq.reach_axis);
  return c >= std::cos(rq.reach_max_rad) - 1e-12 && c <= std::cos(rq.reach_min_rad) + 1e-12;
}

namespace {

// Every cutting motion is swept by the design guards, smooth ones within
// one contact family too: the strips' samples across the feed through each
// contact do not see between them (a smooth motion of the built-in TE's
// row 21 cut 1.18 um, e1 1 um, when only changes of family, tilted or
// lifted poses and axes turning > 5 degrees were swept). It costs ~5 % of
// the plan's CPU there.
bool motion_gouges(const EdgeFinishRequest& rq, const PoseChecks& checks, const EdgeFinishPose& pa,
                   const EdgeFinishPose& pb) {
  return checks.guards.deepest(*rq.tool, pa.pose, pb.pose, false) < 0;
}

// A cutting motion into p that the design guards find a little beyond
// their allowance (within e1, but past what their samples can vouch for:
// on the built-in TE half the row's passes were one move long, their
// motions found 0.75-1.0 um deep where the allowance is 0.75) is made good
// by lifting p off along its normal by the excess (repeated: the motion
// lifts only in proportion to how near p the dip is), up to kMaxLiftMm
// with any lift p had: a lift of tenths of a um leaves that much more at
// its contact, far inside e2 (the simulated partial rows see what it
// leaves). p is changed only if the lifted pose and the motion into it are
// proved (world, guards, strips); false otherwise, p as it was.
bool lift_motion(const EdgeFinishRequest& rq, const PoseChecks& checks, const EdgeFinishPose& a, EdgeFinishPose& p) {
  constexpr double kExtraMm = 5e-5;
  EdgeFinishPose q = p;
  for (int it = 0; it < 4; ++it) {
    const double d = checks.guards.deepest(*rq.tool, a.pose, q.pose, false);
    if (d >= 0) {
      if (q.lift_mm == p.lift_mm) return false;  // the motion was not refused by the guards: not ours to lift
      if (!checks.gouge(*rq.tool, q.pose).empty()) return false;
      if (!rq.world->check(checks.body, q.pose, rq.clearances, 0).clear) return false;
      if (!rq.world->check_motion(checks.body, a.pose, q.pose, rq.clearances, rq.motion_tol_mm).clear) return false;
      const StripWidth w = q.strip->width(q.pose);
      if (w.gouges || !w.touches) return false;
      if (motion_deepest(a, q, *a.strip, *q.strip) < rq.band.e1_mm) return false;
      q.width_mm = w.width_mm;
      q.left_mm = w.left_mm;
      q.right_mm = w.right_mm;
      p = q;
      return true;
    }
    const double excess = -d - checks.guards.least_allowed() + kExtraMm;
    if (q.lift_mm + excess > kMaxLiftMm) return false;
    q.lift_mm += excess;
    q.pose.tip += excess * q.normal;
  }
  return false;
}

// Where lifting p alone does not help (the dip lies near the pose before
// it, a = poses[last]: on the built-in TE 111 motions stayed 0.76 um deep
// with p lifted 0.8 um), both ends are lifted by the excess, each within
// kMaxLiftMm with any lift it had; a's motion in from the pose before it
// (same pass) is proved again, and so are both poses and the motion a -> p.
// poses[last] and p are changed only if all of that holds.
bool lift_both(const EdgeFinishRequest& rq, const PoseChecks& checks, std::vector<EdgeFinishPose>& poses, long last,
               EdgeFinishPose& p) {
  constexpr double kExtraMm = 5e-5;
  EdgeFinishPose a = poses[static_cast<size_t>(last)], q = p;
  const EdgeFinishPose* before =
      last > 0 && poses[static_cast<size_t>(last) - 1].segment == a.segment ? &poses[static_cast<size_t>(last) - 1] : nullptr;
  auto proved_pose = [&](EdgeFinishPose& x) {
    if (!checks.gouge(*rq.tool, x.pose).empty()) return false;
    if (!rq.world->check(checks.body, x.pose, rq.clearances, 0).clear) return false;
    const StripWidth w = x.strip->width(x.pose);
    if (w.gouges || !w.touches) return false;
    x.width_mm = w.width_mm;
    x.left_mm = w.left_mm;
    x.right_mm = w.right_mm;
    return true;
  };
  auto proved_motion = [&](const EdgeFinishPose& x, const EdgeFinishPose& y) {
    return checks.guards.deepest(*rq.tool, x.pose, y.pose, false) >= 0 &&
           motion_deepest(x, y, *x.strip, *y.strip) >= rq.band.e1_mm &&
           rq.world->check_motion(checks.body, x.pose, y.pose, rq.clearances, rq.motion_tol_mm).clear;
  };
  for (int it = 0; it < 4; ++it) {
    const double d = checks.guards.deepest(*rq.tool, a.pose, q.pose, false);
    if (d >= 0 && it > 0) {
      if (!proved_pose(a) || !proved_pose(q) || !proved_motion(a, q)) return false;
      if (before && !proved_motion(*before, a)) return false;
      poses[static_cast<size_t>(last)] = a;
      p = q;
      return true;
    }
    const double excess = std::max(-d - checks.guards.least_allowed(), 0.0) + kExtraMm;
    if (a.lift_mm + excess > kMaxLiftMm || q.lift_mm + excess > kMaxLiftMm) return false;
    a.lift_mm += excess;
    a.pose.tip += excess * a.normal;
    q.lift_mm += excess;
    q.pose.tip += excess * q.normal;
  }
  return false;
}

// Whether the cutting motion from poses[last] into p is within e1 of the
// blade — by the strips' cheaper test, then the guards' sweep — or is made
// so by lifting p (lift_motion) or, with both_ends, both poses (lift_both).
// A lift moves every point of the tool by at most kMaxLiftMm along the
// contact's normal, so where the strips find the motion deeper than e1 by
// more than that, along sample normals near the contact's, no lift proves
// it: not tried (the built-in LE's row checks spent 0.8 of 2.2 s CPU
// sweeping such motions, each deep through the round, with the guards).
// Not a proof for a sample whose normal line grazes the tool — a lift
// across it can change its depth by more than the lift — but never unsafe:
// a motion not lifted is a break, reached by a proved link. On the built-in
// and Rotor 67's four edges no lift that would have been proved was left
// out (the same poses and passes, the built-in APT byte for byte).
bool cutting_motion_proved(const EdgeFinishRequest& rq, const PoseChecks& checks, std::vector<EdgeFinishPose>& poses,
                           long last, EdgeFinishPose& p, bool both_ends) {
  const EdgeFinishPose& a = poses[static_cast<size_t>(last)];
  const double strips = motion_deepest(a, p, *a.strip, *p.strip);
  if (strips >= rq.band.e1_mm && !motion_gouges(rq, checks, a, p)) return true;
  if (strips < rq.band.e1_mm - kMaxLiftMm) return false;
  return lift_motion(rq, checks, a, p) || (both_ends && lift_both(rq, checks, poses, last, p));
}

// Why a pose clear_row did not prove fails (the world, the reach, the
// guards less a lift); "" if it passes. A pose clear_row proved (clear of
// the world within reach, and of the design guards) is taken as proved:
// the same queries again.
std::string pose_refusal(const EdgeFinishRequest& rq, const PoseChecks& checks, EdgeFinishPose& p, bool proved) {
  std::string reason;
  if (!proved) {
    const PoseCheck pc = rq.world->check(checks.body, p.pose, rq.clearances, 0);
    if (!pc.clear) reason = describe(pc, *rq.world);
    else if (!within_reach(rq, p.pose)) reason = "axis beyond the machine's reach";
    else if (!(reason = checks.gouge(*rq.tool, p.pose)).empty() && lift_clear(rq, checks, p))
      reason.clear();
  }
  return reason;
}

}  // namespace

// Each row on its own: its passes, tilts and breaks depend on nothing
// outside it.
long check_row(const EdgeFinishRequest& rq, const PoseChecks& checks, const std::vector<double>& ls, PlannedRow& pr,
               bool reversed, Progress& row_progress) {
  const ToolBody& body = checks.body;
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
    std::string reason = pose_refusal(rq, checks, p, proved[ci]);
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
      // A motion clear of the world that the guards find a little past
      // their allowance lifts p as below.
      if (last >= 0 &&
          (!rq.world->check_motion(body, row.poses[last].pose, p.pose, rq.clearances, rq.motion_tol_mm).clear ||
           !cutting_motion_proved(rq, checks, row.poses, last, p, false))) {
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
    if (last >= 0 && !motion_proved && !cutting_motion_proved(rq, checks, row.poses, last, p, true)) {
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
}

long check_rows(const EdgeFinishRequest& rq, const PoseChecks& checks, const std::vector<double>& ls,
                std::vector<PlannedRow>& planned, Progress& progress) {
  long gouge_breaks = 0;
  std::vector<long> row_gouge_breaks(planned.size(), 0);
  run_parallel(planned.size(), rq.threads, progress, "edge finish checks", [&](size_t r, Progress& row_progress) {
    row_gouge_breaks[r] = check_row(rq, checks, ls, planned[r], rq.zigzag && r % 2 == 1, row_progress);
  });
  for (long b : row_gouge_breaks) gouge_breaks += b;
  return gouge_breaks;
}

}  // namespace bliskrun::edge_detail
