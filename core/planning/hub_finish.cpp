// Hub and blade-root finishing (hub_finish.h) as its steps, in order; each
// step's code is in core/planning/hub_finish/ (internal.h lists the files).
#include "core/planning/hub_finish.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/common/parallel.h"
#include "core/planning/hub_finish/internal.h"

namespace bliskrun {

const char* hub_finish_op_name(HubFinishOp op) { return op == HubFinishOp::Root ? "root" : "channel"; }

namespace {

using namespace hub_detail;

void validate(const HubFinishRequest& rq) {
  if (!rq.blade.pressure || !rq.blade.suction) throw ParameterError("blade", "blade k's pressure and suction faces are required");
  if (!rq.next.pressure || !rq.next.suction) throw ParameterError("next", "blade k+1's pressure and suction faces are required");
  if (!rq.hub) throw ParameterError("hub", "the hub (a surface of revolution) is required");
  if (!rq.tool) throw ParameterError("tool", "a ball or tapered ball-end mill is required");
  if (rq.tool->kind() != ToolKind::BallEndMill && rq.tool->kind() != ToolKind::TaperedBallEndMill)
    throw ParameterError("tool", "expected a ball or tapered ball-end mill, got " + rq.tool->description());
  if (!rq.root && !rq.channel) throw ParameterError("root", "nothing to plan: root and channel are both off");
  if (!(rq.scallop_mm > 0 && rq.scallop_mm < 0.5 * ball_radius(*rq.tool)))
    throw ParameterError("scallop", "expected a height > 0 and below half the ball radius");
  if (!(rq.steps.chord_tol_mm > 0)) throw ParameterError("chord_tol", "expected > 0");
  if (!(rq.allowed_overcut_mm > 0)) throw ParameterError("allowed_overcut", "expected > 0");
  if (!(rq.root_top_mm > 0 && rq.root_top_mm < 50)) throw ParameterError("top", "expected a height in (0, 50) mm");
  if (rq.z_inlet_mm != rq.z_outlet_mm && !(rq.z_inlet_mm < rq.z_outlet_mm))
    throw ParameterError("z", "expected z_inlet < z_outlet");
  if (!(rq.lean_rad > 0 && rq.lean_rad < kPi / 3)) throw ParameterError("lean", "expected (0, 60) degrees");
  if (!(rq.lean_step_rad > 0)) throw ParameterError("lean_step", "expected > 0");
  if (!(rq.lean_max_rad >= rq.lean_rad && rq.lean_max_rad < kPi / 2))
    throw ParameterError("lean_max", "expected at least the lean and below 90 degrees");
  if (!(rq.side_tilt_rad >= 0) || !(rq.side_step_rad > 0)) throw ParameterError("side_tilt", "expected >= 0 (step > 0)");
  if (!(rq.guard_spacing_mm > 0)) throw ParameterError("guard_spacing", "expected > 0");
  if (rq.closed_sections < 4) throw ParameterError("closed_sections", "expected >= 4");
  if (rq.row_samples < 64) throw ParameterError("row_samples", "expected >= 64");
  if (rq.threads < 1) throw ParameterError("threads", "expected >= 1");
  if (!(rq.links.retract_mm > 0) || !(rq.links.min_retract_mm > 0 && rq.links.min_retract_mm <= rq.links.retract_mm))
    throw ParameterError("retract", "expected 0 < min_retract <= retract");
  // The cone above the ball must stand off the blade: the lean is the
  // angle between the axis and the blade.
  if (!(rq.lean_rad > taper_rad(*rq.tool)))
    throw ParameterError("lean", "expected more than the taper's half angle, " +
                                     std::to_string(taper_rad(*rq.tool) * 180 / kPi) + " degrees");
}

// The hub around both blades, 4 mm beyond their roots either way (a sector
// that may straddle angle 0), the pitch between them and the z range of
// the channel, into res.
void place_hub_sector(const HubFinishRequest& rq, const ClosedRoot& blade, const ClosedRoot& next,
                      HubFinishResult& res) {
  const SurfaceOfRevolution& hub = *rq.hub;
  res.blade_closed = blade.surface;
  res.next_closed = next.surface;
  res.pitch_rad = next.theta_centroid - blade.theta_centroid;
  if (res.pitch_rad <= 0) res.pitch_rad += 2 * kPi;
  const double pitch = res.pitch_rad;
  const double r_mid = std::hypot(blade.points[0].x(), blade.points[0].y());
  const double th0 = blade.theta_min - 4 / r_mid;
  const double th1 = wrap_near(next.theta_max, blade.theta_centroid + pitch) + 4 / r_mid;
  const auto sector = std::make_shared<const HubSector>(rq.hub, th0, th1);
  res.hub_sector = sector;
  {
    const SurfaceDerivs d = sector->eval(0.5, 0.5);
    res.hub_sector_flip = d.pu.cross(d.pv).dot(Vec3(d.p.x(), d.p.y(), 0)) < 0;
  }
  const double zh0 = hub.point(0, 0).z(), zh1 = hub.point(1, 0).z();
  const double z_in = rq.z_inlet_mm != rq.z_outlet_mm ? rq.z_inlet_mm : std::min(zh0, zh1);
  const double z_out = rq.z_inlet_mm != rq.z_outlet_mm ? rq.z_outlet_mm : std::max(zh0, zh1);
  res.z_inlet_mm = z_in;
  res.z_outlet_mm = z_out;
}

// The operation's axis rule before the interference loop: the lean and
// side tilt steps, the pose checked by the planner.
TiltSettings base_tilt(const HubFinishRequest& rq, const Planner& planner) {
  TiltSettings base;
  base.lead_step_rad = rq.lean_step_rad;
  base.allow_tilt = rq.side_tilt_rad > 0;
  base.tilt_step_rad = rq.side_step_rad;
  base.tilt_range_rad = rq.side_tilt_rad;
  base.clearances = rq.clearances;
  base.motion_tol_mm = rq.motion_tol_mm;
  base.pose_filter = [&planner](const ToolPose& p) { return planner.gouge(p); };
  return base;
}

// The links' checks: the world (whole tool) and the three guards; the
// traverse world for the ball between the blades and the hub.
LinkChecks link_checks(const HubFinishRequest& rq, const CollisionWorld& world, const ToolBody& body,
                       const Guards& guards) {
  LinkChecks checks;
  checks.world = &world;
  checks.body = &body;
  checks.clearances = rq.clearances;
  checks.motion_tol_mm = rq.motion_tol_mm;
  checks.guard = guards.blade.get();
  checks.guard_margin_mm = guards.margin;
  checks.more_guards = {{guards.next.get(), guards.margin}, {guards.hub.get(), guards.margin}};
  checks.traverse_world = world.unchecked_pairs();  // the blades either side of the channel and the hub, for the ball
  return checks;
}

}  // namespace

HubFinishResult plan_hub_finish(const HubFinishRequest& rq, Progress& progress) {
  validate(rq);
  HubFinishResult res;
  const auto t_setup = SteadyClock::now();
  const Tool& tool = *rq.tool;
  const double r = ball_radius(tool);
  const SurfaceOfRevolution& hub = *rq.hub;
  const double ref_angle = angle_of(rq.blade.pressure->point(0.5, 0.5));
  // Both blades closed on the workers (blade k+1's angles read near blade
  // k's turned forward, so that the pitch comes out positive).
  ClosedRoot closed[2];
  parallel_for_index(2, rq.threads, [&](size_t i) {
    closed[i] = close_root(i == 0 ? rq.blade : rq.next, hub, rq.closed_sections, ref_angle + (i == 0 ? 0 : 0.3),
                           kTargetHeightMm);
  });
  const ClosedRoot& blade = closed[0];
  const ClosedRoot& next = closed[1];
  res.edge_kink_deg = std::max(blade.edge_kink_deg, next.edge_kink_deg);
  place_hub_sector(rq, blade, next, res);

  Guards guards;
  CollisionWorld own_world;
  make_guards(rq, blade, next, *res.hub_sector, res.hub_sector_flip, guards, own_world);
  res.guard_spacing_mm = std::max({guards.blade->spacing_mm(), guards.next->spacing_mm(), guards.hub->spacing_mm()});
  guards.margin = std::max({guards.blade->between_samples_mm(r), guards.next->between_samples_mm(r),
                            guards.hub->between_samples_mm(r)});
  const double pose_allowed = std::max(0.0, rq.allowed_overcut_mm - guards.margin);

  const CollisionWorld& world = rq.world ? *rq.world : own_world;
  const ToolBody body(tool, rq.tool_tol_mm);
  // The cutter split for the pose checks (Planner::gouge): the ball and
  // 2 r of cone, and the flute above as a conical body.
  const double beta = taper_rad(tool);
  const double flute_from = 2 * r;
  const double flute_top = tool.cutter().z_max();
  const Tool short_tool = Tool::tapered_ball_end_mill({r, beta, flute_from, {}, {}});
  CollisionWorld flute_world;
  const std::unique_ptr<ToolBody> flute_body = flute_body_of(tool, flute_from, blade, next, flute_world);
  Clearances flute_clearance;
  flute_clearance.cutter_mm = 0.02;  // the flute stands off the finished blades
  Planner planner{rq,         world,      body,      guards,     pose_allowed,   short_tool,
                  flute_from, flute_top, flute_body.get(), flute_world, flute_clearance};
  res.setup_seconds = seconds_since(t_setup);
  const TiltSettings base = base_tilt(rq, planner);

  // ---- root rows and channel rows ------------------------------------------
  RootGeometry root(rq, blade, r);
  const std::vector<RootRow> root_rows = rq.root ? plan_root_rows(root, res) : std::vector<RootRow>{};
  std::unique_ptr<FloorGeometry> floor;
  std::vector<FloorRow> floor_rows;
  if (rq.channel) {
    floor = std::make_unique<FloorGeometry>(rq, blade, next, r, res.pitch_rad, r * root.du_per_mm);
    floor_rows = plan_floor_rows(*floor, res.z_inlet_mm, res.z_outlet_mm, res);
  }

  // ---- contacts and poses, row by row on the workers -----------------------
  const double rows_seconds = plan_passes(planner, base, root, root_rows, floor.get(), floor_rows, res, progress);

  // ---- connections: steps along the fillet / blade, links, departures -------
  const LinkChecks checks = link_checks(rq, world, body, guards);
  LinkOptions lo = rq.links;
  lo.allowed_overcut_mm = rq.allowed_overcut_mm;
  connect_part(rq, checks, lo, floor.get(), res.root, progress);
  connect_part(rq, checks, lo, floor.get(), res.channel, progress);
  plan_join(res, checks, lo, r, flute_world);
  // Rows' time shared by the poses each part planned.
  const double total_poses = std::max(1, res.root.poses + res.channel.poses);
  res.root.seconds += rows_seconds * res.root.poses / total_poses;
  res.channel.seconds += rows_seconds * res.channel.poses / total_poses;
  return res;
}

}  // namespace bliskrun
