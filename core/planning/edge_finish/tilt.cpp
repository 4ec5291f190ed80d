// Poses tilted clear of the world: where the optimum's tool is not clear
// (beside the neighbouring blade), the contact moves to the corner torus
// with the axis leaning further (the paper's §1.2(a), by the interference
// loop of core/collision/tilt.h); a pose that cuts beside its strip by a
// little is lifted instead; tilted neighbours are blended where the motion
// between them dips.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/common/parallel.h"
#include "core/planning/edge_finish/internal.h"

namespace bliskrun::edge_detail {

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

namespace {

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

}  // namespace

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
  // Whether each pose as planned is clear (lifted if need be), asked once:
  // the way back asks it of the same poses again (-1: not asked yet).
  std::vector<signed char> planned_clear(row.poses.size(), -1);
  std::vector<EdgeFinishPose> planned_lifted(row.poses.size());
  auto clear_as_planned = [&](size_t i, EdgeFinishPose& p) {
    if (planned_clear[i] < 0) {
      EdgeFinishPose q = p;
      planned_clear[i] = within_reach(rq, q.pose) && rq.world->check(checks.body, q.pose, rq.clearances, 0).clear &&
                                 (checks.gouge(*rq.tool, q.pose).empty() || lift_clear(rq, checks, q))
                             ? 1
                             : 0;
      if (planned_clear[i]) planned_lifted[i] = std::move(q);
    }
    if (planned_clear[i]) p = planned_lifted[i];
    return planned_clear[i] == 1;
  };
  auto tilted_along = [&](bool backwards) {
    Along a{row.poses, std::vector<char>(row.poses.size(), 0), 0};
    TiltAccepted last;
    last.index = -1;
    const size_t n = a.poses.size();
    for (size_t k = 0; k < n; ++k) {
      const size_t i = backwards ? n - 1 - k : k;
      EdgeFinishPose& p = a.poses[i];
      if (clear_as_planned(i, p)) {
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

void clear_rows(const EdgeFinishRequest& rq, const PoseChecks& checks, std::vector<PlannedRow>& planned,
                Progress& progress) {
  Progress quiet(&progress);
  run_parallel(planned.size(), rq.threads, quiet, "edge finish tilting",
               [&](size_t k, Progress&) { clear_row(rq, checks, planned[k]); });
}

}  // namespace bliskrun::edge_detail
