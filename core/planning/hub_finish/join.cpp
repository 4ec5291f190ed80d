// The join: one link from the root's last pose to the channel's first, by
// each route in turn — through the channel (its rows' middles raised), then
// straight, then over the blades — the first that proves kept, with how
// close the tool comes to the part on the way.
#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <utility>

#include "core/geometry/mesh.h"
#include "core/planning/hub_finish/internal.h"

namespace bliskrun::hub_detail {
namespace {

// The channel's route for the join: the pose nearest the middle of each
// channel row (t = 0.5), `lift_mm` up its axis, from the row nearest
// z_from to the one nearest z_to, rows at least `spacing_mm` apart in z
// (the first and last always).
std::vector<ToolPose> channel_waypoints(const HubFinishPart& channel, double z_from, double z_to, double lift_mm,
                                        double spacing_mm) {
  struct Mid {
    double level = 0, off = 1e300;
    const HubFinishPose* pose = nullptr;
  };
  std::vector<Mid> rows;  // by row, in the channel's row order
  for (const HubFinishPass& pass : channel.passes) {
    if (pass.row >= static_cast<int>(rows.size())) rows.resize(static_cast<size_t>(pass.row) + 1);
    Mid& m = rows[static_cast<size_t>(pass.row)];
    m.level = pass.level;
    for (const HubFinishPose& p : pass.poses)
      if (std::abs(p.t - 0.5) < m.off) m.off = std::abs(p.t - 0.5), m.pose = &p;
  }
  std::vector<const Mid*> have;
  for (const Mid& m : rows)
    if (m.pose) have.push_back(&m);
  if (have.empty()) return {};
  std::sort(have.begin(), have.end(), [](const Mid* a, const Mid* b) { return a->level < b->level; });
  auto nearest = [&](double z) {
    size_t best = 0;
    for (size_t i = 1; i < have.size(); ++i)
      if (std::abs(have[i]->level - z) < std::abs(have[best]->level - z)) best = i;
    return best;
  };
  const long from = static_cast<long>(nearest(z_from)), to = static_cast<long>(nearest(z_to));
  const long step = to >= from ? 1 : -1;
  std::vector<ToolPose> out;
  double last = 0;
  for (long i = from;; i += step) {
    const Mid& m = *have[static_cast<size_t>(i)];
    if (i == from || i == to || std::abs(m.level - last) >= spacing_mm) {
      const ToolPose& p = m.pose->pose;
      out.push_back({p.tip + lift_mm * unit_axis(p.axis), p.axis});
      last = m.level;
    }
    if (i == to) break;
  }
  return out;
}

// How close the tool comes to the part between the join's two retracted
// poses (the legs that leave and reach the cutting poses touch it by
// design): the whole tool against the world and both blades' closed
// surfaces (which the proofs see the cutter against through the guards
// only), at poses along the legs no tool point moves more than 0.5 mm
// between, resolved up to 2 mm. Returns the margin and what it is against.
std::pair<double, std::string> join_clearance(const std::vector<ToolPose>& via, const LinkChecks& checks,
                                              const CollisionWorld& blades) {
  constexpr double kStepMm = 0.5, kHorizonMm = 2;
  std::pair<double, std::string> out{kHorizonMm, "nothing within " + std::to_string(kHorizonMm) + " mm"};
  const double reach = checks.body->tool().reach();
  for (size_t i = 0; i + 1 < via.size(); ++i) {
    const PoseMotion motion(via[i], via[i + 1]);
    const int n = std::max(1, static_cast<int>(std::ceil(motion.max_point_speed(reach) / kStepMm)));
    for (int k = 0; k <= n; ++k) {
      const ToolPose pose = motion.pose_at(static_cast<double>(k) / n);
      for (const CollisionWorld* w : {checks.world, &blades}) {
        const PoseCheck pc = w->check(*checks.body, pose, checks.clearances, kHorizonMm);
        if (pc.min_margin_mm < out.first) out = {pc.min_margin_mm, describe(pc, *w)};
      }
    }
  }
  return out;
}

}  // namespace

void plan_join(HubFinishResult& res, const LinkChecks& checks, const LinkOptions& lo, double ball_r,
               const CollisionWorld& flute_world) {
  HubFinishConnection& join = res.join;
  join.kind = HubFinishConnection::Kind::Link;
  if (res.root.passes.empty() || res.channel.passes.empty()) {
    join.reason = "nothing to join: the plan has only one part";
    return;
  }
  const auto t0 = SteadyClock::now();
  const HubFinishPose& a = res.root.passes.back().poses.back();
  const HubFinishPose& b = res.channel.passes.front().poses.front();
  join.from_pass = static_cast<int>(res.root.passes.size()) - 1;
  join.to_pass = 0;
  const LinkEnd from{a.pose, a.normal}, to{b.pose, b.normal};

  // Over the blades: both ends far enough up their axes that the tool's
  // ball is outside the blades' tips by 1 mm more than the chord between
  // the two raised tips sags towards the axis.
  double tip_radius = 0;
  for (const Surface* s : {res.blade_closed.get(), res.next_closed.get()})
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; j < 360; ++j) {
        const Vec3 p = s->point(0.9 + 0.01 * i, j / 360.0);
        tip_radius = std::max(tip_radius, std::hypot(p.x(), p.y()));
      }
  const double turn = std::abs(wrap_near(angle_of(a.pose.tip) - angle_of(b.pose.tip), 0));
  const double high_radius = tip_radius * (2 - std::cos(0.5 * turn)) + ball_r + 1;
  double rise_mm = 0;
  bool can_rise = true;
  for (const ToolPose* p : {&a.pose, &b.pose}) {
    const Vec3 radial = Vec3(p->tip.x(), p->tip.y(), 0).normalized();
    const double outward = unit_axis(p->axis).dot(radial);
    if (outward < 0.2) can_rise = false;
    else rise_mm = std::max(rise_mm, (high_radius - p->tip.dot(radial)) / outward - lo.min_retract_mm);
  }

  struct Route {
    const char* name;
    LinkOptions options;
    std::vector<ToolPose> via;
  };
  std::vector<Route> routes;
  routes.push_back({"through the channel", lo,
                    channel_waypoints(res.channel, a.centre.z(), res.channel.passes.front().level, lo.retract_mm, 3.0)});
  routes.push_back({"straight", lo, {}});
  std::string reasons;
  if (can_rise) {
    LinkOptions high = lo;
    high.axis_retract_mm = std::max(0.0, rise_mm);
    routes.push_back({"over the blades", high, {}});
  } else {
    reasons = "over the blades: an axis leans too far from radial to rise over the tips";
  }
  for (const Route& route : routes) {
    const PlannedLink pl = plan_link(from, to, checks, route.options, route.via);
    if (!pl.clear) {
      reasons += (reasons.empty() ? "" : "; ") + std::string(route.name) + ": " + pl.reason;
      continue;
    }
    join.clear = true;
    join.poses = pl.via;
    for (size_t i = 0; i < pl.via.size(); ++i) join.motion.push_back(link_leg_name(pl.legs[i]));
    res.join_route = route.name;
    res.join_offset_mm = pl.offset_mm;
    res.join_deepest_cut_mm = pl.deepest_cut_mm;
    CollisionWorld own;
    if (flute_world.size() == 0) {  // a short ball end: no flute world to reuse
      own.add("blade k", tessellate(*res.blade_closed, 0.05), {PartMask{}, 0.05});
      own.add("blade k+1", tessellate(*res.next_closed, 0.05), {PartMask{}, 0.05});
    }
    std::tie(res.join_margin_mm, res.join_margin_at) =
        join_clearance(pl.via, checks, flute_world.size() ? flute_world : own);
    break;
  }
  if (!join.clear) join.reason = "root to channel: no route proved (" + reasons + ")";
  res.join_seconds = seconds_since(t0);
}

}  // namespace bliskrun::hub_detail
