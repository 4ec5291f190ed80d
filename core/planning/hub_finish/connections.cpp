// A part's passes connected: consecutive rows by a straight step from the
// end of one to the start of the next (along the blade, or along the
// fillet with ends of rows put in between), a cutting move proved as a
// link's legs are; other passes by a link (core/planning/links.h); a
// lead-in and a lead-out. Every connection on the workers, proved on its
// own.
#include <algorithm>
#include <cmath>
#include <string>

#include "core/common/parallel.h"
#include "core/planning/hub_finish/internal.h"

namespace bliskrun::hub_detail {
namespace {

LinkEnd end_of(const HubFinishPose& p) { return LinkEnd{p.pose, p.normal}; }

HubFinishConnection departure(const LinkChecks& checks, const LinkOptions& lo, const HubFinishPart& part,
                              const HubFinishPose& p, int from, int to, const char* what) {
  HubFinishConnection c;
  c.kind = HubFinishConnection::Kind::Departure;
  c.from_pass = from;
  c.to_pass = to;
  const PlannedDeparture d = plan_departure(end_of(p), checks, lo);
  c.clear = d.clear;
  if (d.clear) {
    c.poses = {d.away};
    c.motion = {from < 0 ? "start" : "retract"};
  } else {
    c.reason = std::string(hub_finish_op_name(part.op)) + " " + what + ": " + d.reason;
  }
  return c;
}

// Along the fillet: the ball's centre on the straight segment between two
// rows' ends cuts the corner of a tight round (the TE's, r_e + r round)
// deeper than the guards' samples see; ends of rows between (on the row's
// `high_end`, theta1, or its other) are put in until the segment's dip,
// measured on the blades themselves, is within the chord tolerance, to
// `depth` halvings. Appends to `chain` up to pb.
void fill_fillet(const FloorGeometry& floor, bool high_end, std::vector<ToolPose>& chain, const ToolPose& pa,
                 const Vec3& ca, double za, const ToolPose& pb, const Vec3& cb, double zb, int depth) {
  const double r = floor.r;
  if (depth == 0 || floor.ball_dip(ca, cb) <= floor.rq.steps.chord_tol_mm) {
    chain.push_back(pb);
    return;
  }
  const double zm = 0.5 * (za + zb);
  const FloorRow fr = floor.row_at(zm);
  const double th = high_end ? fr.theta1 : fr.theta0;
  const Vec3 cm(fr.radius * std::cos(th), fr.radius * std::sin(th), zm);
  const Vec3 axis = PoseMotion(pa, pb).pose_at(0.5).axis;
  const ToolPose pm{cm - r * axis, axis};
  fill_fillet(floor, high_end, chain, pa, ca, za, pm, cm, zm, depth - 1);
  fill_fillet(floor, high_end, chain, pm, cm, zm, pb, cb, zb, depth - 1);
}

// Consecutive rows: a straight step from the end of a to the start of b;
// false (c untouched) where the rows are not consecutive or the step is
// not proved.
bool step_between(const HubFinishRequest& rq, const LinkChecks& checks, const FloorGeometry* floor,
                  const HubFinishPart& part, const HubFinishPass& a, const HubFinishPass& b, HubFinishConnection& c) {
  const Vec3 gap = b.poses.front().centre - a.poses.back().centre;
  if (b.row == a.row + 1 && gap.norm() < 4 * std::max(part.step_max_mm, 0.05)) {
    std::vector<ToolPose> chain{a.poses.back().pose};
    if (part.op == HubFinishOp::Channel) {
      const bool high_end = !a.reversed;  // the row ended at theta1
      fill_fillet(*floor, high_end, chain, a.poses.back().pose, a.poses.back().centre, a.level,
                  b.poses.front().pose, b.poses.front().centre, b.level, 6);
    } else {
      chain.push_back(b.poses.front().pose);
    }
    const ChainProof proof = prove_chain(chain, checks, rq.allowed_overcut_mm, true, true);
    if (proof.clear) {
      c.kind = HubFinishConnection::Kind::Step;
      c.clear = true;
      for (size_t i = 1; i + 1 < chain.size(); ++i) c.poses.push_back(chain[i]), c.motion.push_back("step");
      return true;
    }
  }
  return false;
}

}  // namespace

void connect_part(const HubFinishRequest& rq, const LinkChecks& checks, const LinkOptions& lo,
                  const FloorGeometry* floor, HubFinishPart& part, Progress& own) {
  const auto t0 = SteadyClock::now();
  const int n = static_cast<int>(part.passes.size());
  if (n == 0) return;
  part.connections.resize(static_cast<size_t>(n) + 1);
  part.connections.front() = departure(checks, lo, part, part.passes.front().poses.front(), -1, 0, "lead-in");
  part.connections.back() = departure(checks, lo, part, part.passes.back().poses.back(), n - 1, -1, "lead-out");
  parallel_for_index(static_cast<size_t>(n - 1), rq.threads, [&](size_t pi) {
    own.check();
    const int p = static_cast<int>(pi);
    const HubFinishPass &a = part.passes[p], &b = part.passes[p + 1];
    HubFinishConnection c;
    c.from_pass = p;
    c.to_pass = p + 1;
    if (step_between(rq, checks, floor, part, a, b, c)) {
      part.connections[pi + 1] = std::move(c);
      return;
    }
    c.kind = HubFinishConnection::Kind::Link;
    const PlannedLink pl = plan_link(end_of(a.poses.back()), end_of(b.poses.front()), checks, lo);
    c.clear = pl.clear;
    if (pl.clear) {
      c.poses = pl.via;
      for (size_t i = 0; i < pl.via.size(); ++i) c.motion.push_back(link_leg_name(pl.legs[i]));
    } else {
      c.reason = std::string(hub_finish_op_name(part.op)) + " link from pass " + std::to_string(p) + " to " +
                 std::to_string(p + 1) + ": " + pl.reason;
    }
    part.connections[pi + 1] = std::move(c);
  });
  for (const HubFinishConnection& c : part.connections) {
    if (!c.clear) ++part.refused_connections;
    else if (c.kind == HubFinishConnection::Kind::Step) ++part.steps;
    else if (c.kind == HubFinishConnection::Kind::Link) ++part.links;
  }
  part.seconds += seconds_since(t0);
}

}  // namespace bliskrun::hub_detail
