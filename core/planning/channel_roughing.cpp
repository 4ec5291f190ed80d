#include "core/planning/channel_roughing.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/common/error.h"
#include "core/geometry/projection.h"
#include "core/geometry/root_find.h"

namespace bliskrun {

const char* to_string(ChannelPassKind kind) {
  switch (kind) {
    case ChannelPassKind::Notch: return "notch";
    case ChannelPassKind::WidenLeft: return "widen left";
    case ChannelPassKind::WidenRight: return "widen right";
  }
  return "?";
}

namespace {

double wrap_angle(double a) {  // to (-pi, pi]
  while (a > kPi) a -= 2 * kPi;
  while (a <= -kPi) a += 2 * kPi;
  return a;
}

// The channel's hub section and axes at one station.
struct Station {
  double t = 0;
  double u_hub = 0;                   // hub meridian parameter
  double theta_mid = 0;               // notch angle
  double theta_limit[2] = {0, 0};     // left, right: the ball (grown by the stock) touches hub and face
  Vec3 notch_axis = Vec3::UnitZ();
  Vec3 finishing_axis[2];             // left, right
  Vec3 top = Vec3::Zero();            // ball centre of the first notch level
  double sign = 1;                    // orients the hub normal into the channel
};

class Channel {
 public:
  explicit Channel(const ChannelRequest& rq) : rq_(rq), r_(rq.cutter->ball_radius_mm()) {}

  // Hub point and unit normal (into the channel) at angle theta of a station.
  void hub_at(const Station& s, double theta, Vec3& p, Vec3& n) const {
    double v = theta / (2 * kPi);
    v -= std::floor(v);
    const SurfaceDerivs d = rq_.hub->eval(s.u_hub, v);
    p = d.p;
    n = s.sign * d.pu.cross(d.pv).normalized();
  }
  Vec3 ball_centre(const Station& s, double theta) const {
    Vec3 p, n;
    hub_at(s, theta, p, n);
    return p + (r_ + rq_.stock_mm) * n;
  }

  Station station(double t) const {
    Station s;
    s.t = t;
    Vec3 hub_pt[2], shroud_pt[2], ruling[2];
    const ChannelFace* faces[2] = {&rq_.left, &rq_.right};
    double u_sum = 0, theta[2];
    for (int i = 0; i < 2; ++i) {
      const double v = faces[i]->v_at(t);
      hub_pt[i] = faces[i]->face->point(0, v);
      shroud_pt[i] = faces[i]->face->point(1, v);
      ruling[i] = (shroud_pt[i] - hub_pt[i]).normalized();
      theta[i] = std::atan2(hub_pt[i].y(), hub_pt[i].x());
      ProjectionOptions po;
      const SurfaceProjection pr = project_to_surface(*rq_.hub, hub_pt[i], po);
      if (!pr.ok) throw Error("channel at t = " + std::to_string(t) + ": a face's hub point does not project onto the hub (" + pr.failure + ")");
      u_sum += pr.u;
    }
    // Both faces must look into the channel (out of their material, towards
    // the other face): a swapped pair or a face of the wrong side would
    // otherwise give a "channel" through a blade.
    for (int i = 0; i < 2; ++i) {
      const SurfaceDerivs d = faces[i]->face->eval(0, faces[i]->v_at(t));
      if (d.pu.cross(d.pv).dot(hub_pt[1 - i] - hub_pt[i]) <= 0)
        throw Error(std::string("channel at t = ") + std::to_string(t) + ": the " + (i == 0 ? "left" : "right") +
                    " face does not face the " + (i == 0 ? "right" : "left") +
                    " one (its normal, out of the material, points away from the channel)");
    }
    s.u_hub = 0.5 * u_sum;
    theta[1] = theta[0] + wrap_angle(theta[1] - theta[0]);
    s.notch_axis = (ruling[0] + ruling[1]).normalized();
    s.top = 0.5 * (shroud_pt[0] + shroud_pt[1]);
    {
      Vec3 p, n;
      s.sign = 1;
      hub_at(s, 0.5 * (theta[0] + theta[1]), p, n);
      if (n.dot(s.top - p) < 0) s.sign = -1;
    }
    // Distance from the ball centre on the hub at angle th to face i.
    ProjectionOptions po[2];
    const auto distance = [&](int i, double th) {
      const SurfaceProjection pr = project_to_surface(*faces[i]->face, ball_centre(s, th), po[i]);
      if (!pr.ok) throw Error("channel at t = " + std::to_string(t) + ": a ball centre does not project onto a face");
      po[i].seed = Eigen::Vector2d(pr.u, pr.v);
      return pr.distance;
    };
    // The middle: the ball centre as far from one face as from the other
    // (on leaning blades not halfway in angle at the hub).
    {
      const auto g = [&](double th) { return distance(0, th) - distance(1, th); };
      s.theta_mid = illinois_root(g, theta[0], theta[1], g(theta[0]), g(theta[1]), 1e-10);
    }
    // Where the ball, grown by the stock, touches both hub and face: the
    // root of dist(centre, face) - (r + stock) between the middle and the
    // face's own hub point.
    const double grown = r_ + rq_.stock_mm;
    for (int i = 0; i < 2; ++i) {
      const Surface& face = *faces[i]->face;
      const auto g = [&](double th) { return distance(i, th) - grown; };
      const double a = s.theta_mid, b = theta[i];
      const double ga = g(a), gb = g(b);
      if (!(ga > 0))
        throw Error("channel at t = " + std::to_string(t) + ": a ball of radius " + std::to_string(r_) +
                    " mm with " + std::to_string(rq_.stock_mm) + " mm stock does not fit between the blades");
      s.theta_limit[i] = gb < 0 ? illinois_root(g, a, b, ga, gb, 1e-9) : b;
      // The finishing axis of that face at this station (the swarf axis);
      // the face's ruling where flank_axis finds none.
      try {
        s.finishing_axis[i] = flank_axis(face, faces[i]->v_at(t), rq_.hub, *rq_.cutter).pose.axis;
      } catch (const Error&) {
        s.finishing_axis[i] = ruling[i];
      }
    }
    return s;
  }

  const ChannelRequest& rq_;
  double r_;
};

// How far above the stock surface point q, along its normal n, the ball
// (centre c, radius r) leaves material: the lower intersection of the
// normal line with the sphere, or "everywhere" when the line misses it.
// This is the scallop height as the paper draws it (Fig. 4), not the
// distance to the ball along the line to its centre.
double height_to_ball(const Vec3& q, const Vec3& n, const Vec3& c, double r) {
  const Vec3 w = c - q;
  const double b = w.dot(n), disc = b * b - w.squaredNorm() + r * r;
  if (disc < 0) return std::numeric_limits<double>::infinity();
  return b - std::sqrt(disc);
}

double hub_arc(const Channel& ch, const Station& s, double a, double b) {
  Vec3 p, n;
  ch.hub_at(s, a, p, n);
  return std::hypot(p.x(), p.y()) * std::abs(b - a);
}

}  // namespace

ChannelPlan plan_channel(const ChannelRequest& rq) {
  if (!rq.left.face || !rq.right.face) throw ParameterError("faces", "expected the two blade faces of the channel");
  if (!rq.hub) throw ParameterError("hub", "expected the hub surface of revolution");
  if (!rq.cutter) throw ParameterError("tool", "expected a ball or tapered ball-end cutter");
  if (rq.world && !rq.body) throw ParameterError("world", "a collision world needs the tool's body");
  if (rq.stations < 2) throw ParameterError("stations", "expected at least 2 stations along the channel");
  if (!(rq.stock_mm >= 0)) throw ParameterError("stock", "expected a stock >= 0 in mm");
  if (!(rq.depth_step_mm > 0)) throw ParameterError("depth_step", "expected a depth step > 0 in mm");
  const double r = rq.cutter->ball_radius_mm();
  if (!(rq.scallop_mm > 0) || rq.scallop_mm >= r)
    throw ParameterError("scallop", "expected a scallop height > 0 and below the ball radius, mm");
  if (rq.scallop_samples < 2) throw ParameterError("scallop_samples", "expected at least 2");

  const Channel ch(rq);
  std::vector<Station> st;
  st.reserve(static_cast<size_t>(rq.stations));
  for (int i = 0; i < rq.stations; ++i) st.push_back(ch.station(static_cast<double>(i) / (rq.stations - 1)));

  ChannelPlan plan;
  // Eq. 12 solved exactly, eq. 13 per side at the outlet.
  const double h = rq.scallop_mm;
  plan.step_over_mm = 2 * std::sqrt(2 * r * h - h * h);
  const Station& outlet = st.back();
  plan.outlet_width_left_mm = hub_arc(ch, outlet, outlet.theta_mid, outlet.theta_limit[0]);
  plan.outlet_width_right_mm = hub_arc(ch, outlet, outlet.theta_mid, outlet.theta_limit[1]);
  if (rq.widen) {
    plan.widen_left = std::max(1, static_cast<int>(std::ceil(plan.outlet_width_left_mm / plan.step_over_mm - 1e-9)));
    plan.widen_right = std::max(1, static_cast<int>(std::ceil(plan.outlet_width_right_mm / plan.step_over_mm - 1e-9)));
  }
  double deepest = 0;
  for (const Station& s : st) deepest = std::max(deepest, (s.top - ch.ball_centre(s, s.theta_mid)).norm());
  plan.notch_levels = std::max(1, static_cast<int>(std::ceil(deepest / rq.depth_step_mm - 1e-9)));
  plan.deepest_step_mm = deepest / plan.notch_levels;

  // The poses of a pass at a station.
  const auto notch_pose = [&](const Station& s, int level) {
    const Vec3 c = s.top + (ch.ball_centre(s, s.theta_mid) - s.top) * (static_cast<double>(level) / plan.notch_levels);
    return ToolPose{c - r * s.notch_axis, s.notch_axis};
  };
  const auto widen_angle = [&](const Station& s, int side, int k, int n) {
    return s.theta_mid + (s.theta_limit[side] - s.theta_mid) * (static_cast<double>(k) / n);
  };
  const auto widen_pose = [&](const Station& s, int side, int k, int n) {
    const Vec3 axis = (s.notch_axis + (s.finishing_axis[side] - s.notch_axis) * (static_cast<double>(k) / n)).normalized();
    return ToolPose{ch.ball_centre(s, widen_angle(s, side, k, n)) - r * axis, axis};
  };

  // Measured scallop on the hub (the stock surface) between neighbouring
  // paths at every station: notch and the widening paths of both sides.
  for (const Station& s : st) {
    if (!rq.widen) break;
    std::vector<double> angles{s.theta_mid};
    for (int k = 1; k <= plan.widen_left; ++k) angles.push_back(widen_angle(s, 0, k, plan.widen_left));
    for (int k = 1; k <= plan.widen_right; ++k) angles.push_back(widen_angle(s, 1, k, plan.widen_right));
    std::sort(angles.begin(), angles.end());
    double worst = 0;
    for (size_t i = 0; i + 1 < angles.size(); ++i) {
      const Vec3 ca = ch.ball_centre(s, angles[i]), cb = ch.ball_centre(s, angles[i + 1]);
      for (int k = 1; k < rq.scallop_samples; ++k) {
        const double th = angles[i] + (angles[i + 1] - angles[i]) * k / rq.scallop_samples;
        Vec3 p, n;
        ch.hub_at(s, th, p, n);
        const Vec3 q = p + rq.stock_mm * n;
        worst = std::max(worst, std::min(height_to_ball(q, n, ca, r), height_to_ball(q, n, cb, r)));
      }
    }
    plan.scallop_max_mm = std::max(plan.scallop_max_mm, worst);
    if (&s == &st.back()) plan.scallop_outlet_mm = worst;
  }

  // The passes in cutting order, alternating direction.
  struct Spec {
    ChannelPassKind kind;
    int index;
  };
  std::vector<Spec> specs;
  for (int j = 1; j <= plan.notch_levels; ++j) specs.push_back({ChannelPassKind::Notch, j});
  for (int k = 1; k <= plan.widen_left; ++k) specs.push_back({ChannelPassKind::WidenLeft, k});
  for (int k = 1; k <= plan.widen_right; ++k) specs.push_back({ChannelPassKind::WidenRight, k});
  std::vector<ChannelPass> passes;
  for (size_t p = 0; p < specs.size(); ++p) {
    const Spec& spec = specs[p];
    ChannelPass current{spec.kind, spec.index, {}, {}};
    const auto close = [&] {
      if (!current.poses.empty()) passes.push_back(current);
      current = ChannelPass{spec.kind, spec.index, {}, {}};
    };
    for (int q = 0; q < rq.stations; ++q) {
      const Station& s = st[static_cast<size_t>(p % 2 == 0 ? q : rq.stations - 1 - q)];
      const ToolPose pose = spec.kind == ChannelPassKind::Notch ? notch_pose(s, spec.index)
                            : spec.kind == ChannelPassKind::WidenLeft ? widen_pose(s, 0, spec.index, plan.widen_left)
                                                                      : widen_pose(s, 1, spec.index, plan.widen_right);
      if (rq.world) {
        const PoseCheck pc = rq.world->check(*rq.body, pose, rq.clearances, 0.0);
        if (!pc.clear) {
          plan.refusals.push_back({spec.kind, spec.index, s.t, "pose: " + describe(pc, *rq.world)});
          close();
          continue;
        }
        if (!current.poses.empty()) {
          const MotionCheck mc = rq.world->check_motion(*rq.body, current.poses.back(), pose, rq.clearances,
                                                        rq.motion_tol_mm);
          if (!mc.clear) {
            plan.refusals.push_back({spec.kind, spec.index, s.t,
                                     "motion from the previous pose: " + describe(mc.at, *rq.world) +
                                         (mc.undecided ? " (undecided)" : "")});
            close();  // this pose starts a new piece, reached by a link
          }
        }
      }
      current.t.push_back(s.t);
      current.poses.push_back(pose);
    }
    close();
  }

  // Links up the tool axis between consecutive pieces; the plan stops at
  // the first that cannot be proved.
  for (size_t i = 0; i < passes.size(); ++i) {
    if (i > 0 && rq.world) {
      LinkChecks checks;
      checks.world = rq.world;
      checks.body = rq.body;
      checks.clearances = rq.clearances;
      checks.motion_tol_mm = rq.motion_tol_mm;
      const ToolPose& a = passes[i - 1].poses.back();
      const ToolPose& b = passes[i].poses.front();
      PlannedLink link = plan_link({a, a.axis}, {b, b.axis}, checks, rq.link);
      if (!link.clear) {
        plan.complete = false;
        plan.stopped = std::string("link into ") + to_string(passes[i].kind) + " " + std::to_string(passes[i].index) +
                       ": " + link.reason;
        break;
      }
      plan.links.push_back(std::move(link));
    }
    plan.poses += static_cast<long>(passes[i].poses.size());
    plan.passes.push_back(std::move(passes[i]));
  }
  return plan;
}

}  // namespace bliskrun
