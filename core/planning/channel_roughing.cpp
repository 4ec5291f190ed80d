#include "core/planning/channel_roughing.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/common/error.h"
#include "core/common/parallel.h"
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

double height_to_ball(const Vec3& q, const Vec3& n, const Vec3& c, double r) {
  const Vec3 w = c - q;
  const double b = w.dot(n), disc = b * b - w.squaredNorm() + r * r;
  if (disc < 0) return std::numeric_limits<double>::infinity();
  return b - std::sqrt(disc);
}

namespace {

// The channel's hub section and axes at one station.
struct Station {
  double t = 0;
  double u_hub = 0;                   // hub meridian parameter
  Vec3 notch_centre = Vec3::Zero();   // ball centre of the deepest notch level
  Vec3 notch_axis = Vec3::UnitZ();
  Vec3 finishing_axis[2];             // left, right
  Vec3 top = Vec3::Zero();            // where the notch starts: the faces' shroud points' midpoint (level 0)
  double sign = 1;                    // orients the hub normal into the channel
  double v[2] = {0, 0};               // left, right face's chord parameter (hub point on this circle)
  Vec3 finishing_centre[2];           // ball centre of the last widening path per side
};

class Channel {
 public:
  explicit Channel(const ChannelRequest& rq)
      : rq_(rq),
        r_(rq.cutter->ball_radius_mm()),
        hub_stock_(rq.hub_stock_mm < 0 ? rq.stock_mm : rq.hub_stock_mm),
        grown_cutter_(rq.cutter->grown(rq.stock_mm)) {
    find_meridian_range();
  }

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
    return p + (r_ + hub_stock_) * n;
  }
  double hub_stock() const { return hub_stock_; }

  // The channel's stations are the hub's parallel circles from where both
  // faces have begun to where the first ends (in the hub's meridian
  // parameter), so at every station both faces' hub points lie on the
  // station's circle: the two faces' chord parameters need not match.
  void find_meridian_range() {
    const ChannelFace* faces[2] = {&rq_.left, &rq_.right};
    double in[2], out[2];
    for (int i = 0; i < 2; ++i) {
      in[i] = hub_u_of(*faces[i], faces[i]->v_inlet);
      out[i] = hub_u_of(*faces[i], faces[i]->v_outlet);
    }
    const bool increasing = (out[0] - in[0]) + (out[1] - in[1]) > 0;
    if ((out[0] > in[0]) != increasing || (out[1] > in[1]) != increasing)
      throw Error("channel: the two faces run in opposite directions along the hub (check left_v and right_v: "
                  "each is {v at the inlet, v at the outlet})");
    u_in_ = increasing ? std::max(in[0], in[1]) : std::min(in[0], in[1]);
    u_out_ = increasing ? std::min(out[0], out[1]) : std::max(out[0], out[1]);
    if ((u_out_ > u_in_) != increasing) throw Error("channel: the two faces' parts do not overlap along the hub");
  }

  // The hub's meridian parameter under a face's hub point at chord v.
  double hub_u_of(const ChannelFace& f, double v) const {
    const SurfaceProjection pr = project_to_surface(*rq_.hub, f.face->point(0, v), ProjectionOptions{});
    if (!pr.ok)
      throw Error("channel: a face's hub point (v = " + std::to_string(v) + ") does not project onto the hub (" +
                  pr.failure + ")");
    return pr.u;
  }

  // The chord parameter of face f whose hub point lies on the hub circle u.
  double v_on_circle(const ChannelFace& f, double u) const {
    const auto g = [&](double v) { return hub_u_of(f, v) - u; };
    const double a = f.v_inlet, b = f.v_outlet, ga = g(a), gb = g(b);
    if (ga == 0) return a;
    if (gb == 0) return b;
    if ((ga > 0) == (gb > 0)) return std::abs(ga) < std::abs(gb) ? a : b;  // at an end, to rounding
    return illinois_root(g, a, b, ga, gb, 1e-11);
  }

  // The hub point nearest x and its unit normal into the channel.
  void hub_under(const Station& s, const Vec3& x, Vec3& p, Vec3& n) const {
    // Newton from the station's circle at x's angle: the foot is near.
    ProjectionOptions po;
    double v = std::atan2(x.y(), x.x()) / (2 * kPi);
    po.seed = Eigen::Vector2d(s.u_hub, v - std::floor(v));
    const SurfaceProjection pr = project_to_surface(*rq_.hub, x, po);
    if (!pr.ok) throw Error("channel at t = " + std::to_string(s.t) + ": a point does not project onto the hub (" + pr.failure + ")");
    const SurfaceDerivs d = rq_.hub->eval(pr.u, pr.v);
    p = d.p;
    n = s.sign * d.pu.cross(d.pv).normalized();
  }
  // The ball centre over the hub under x (r + hub stock along the hub normal).
  Vec3 ball_centre_over(const Station& s, const Vec3& x) const {
    Vec3 p, n;
    hub_under(s, x, p, n);
    return p + (r_ + hub_stock_) * n;
  }
  // The ball centre c moved along `axis` until it is r + hub stock over the
  // hub (Newton on the height along the hub normal).
  Vec3 slide_onto_hub_offset(const Station& s, Vec3 c, const Vec3& axis) const {
    for (int it = 0; it < 20; ++it) {
      Vec3 p, n;
      hub_under(s, c, p, n);
      const double error = (c - p).dot(n) - (r_ + hub_stock_), along = axis.dot(n);
      if (std::abs(error) < 1e-10) return c;
      if (std::abs(along) < 0.1)
        throw Error("channel at t = " + std::to_string(s.t) + ": the finishing axis lies along the hub; its ball "
                    "cannot be slid onto the hub stock");
      c -= axis * (error / along);
    }
    return c;
  }

  Station station(double t) const {
    Station s;
    s.t = t;
    s.u_hub = u_in_ + (u_out_ - u_in_) * t;
    Vec3 hub_pt[2], shroud_pt[2], ruling[2];
    const ChannelFace* faces[2] = {&rq_.left, &rq_.right};
    double theta[2];
    for (int i = 0; i < 2; ++i) {
      const double v = s.v[i] = v_on_circle(*faces[i], s.u_hub);
      hub_pt[i] = faces[i]->face->point(0, v);
      shroud_pt[i] = faces[i]->face->point(1, v);
      ruling[i] = (shroud_pt[i] - hub_pt[i]).normalized();
      theta[i] = std::atan2(hub_pt[i].y(), hub_pt[i].x());
    }
    // Both faces must look into the channel (out of their material, towards
    // the other face): a swapped pair or a face of the wrong side would
    // otherwise give a "channel" through a blade.
    for (int i = 0; i < 2; ++i) {
      const SurfaceDerivs d = faces[i]->face->eval(0, s.v[i]);
      if (d.pu.cross(d.pv).dot(hub_pt[1 - i] - hub_pt[i]) <= 0)
        throw Error(std::string("channel at t = ") + std::to_string(t) + ": the " + (i == 0 ? "left" : "right") +
                    " face does not face the " + (i == 0 ? "right" : "left") +
                    " one (its normal, out of the material, points away from the channel)");
    }
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
    const auto g = [&](double th) { return distance(0, th) - distance(1, th); };
    const double theta_mid = illinois_root(g, theta[0], theta[1], g(theta[0]), g(theta[1]), 1e-10);
    s.notch_centre = ball_centre(s, theta_mid);
    // The last widening path of each side is the finishing (swarf) pose of
    // the cutter grown by the stock (flank_axis, §4.3): the real cutter on
    // that axis leaves the stock on the face along the whole flute and on
    // the hub, so the side ends where the finishing cut begins. Where
    // flank_axis finds no axis, the ball alone: the angle where the grown
    // ball touches hub and face (the root of dist - (r + stock) between the
    // middle and the face), with the face's ruling as the axis.
    const double grown = r_ + rq_.stock_mm;
    for (int i = 0; i < 2; ++i) {
      const Surface& face = *faces[i]->face;
      if (!(distance(i, theta_mid) > grown))
        throw Error("channel at t = " + std::to_string(t) + ": a ball of radius " + std::to_string(r_) +
                    " mm with " + std::to_string(rq_.stock_mm) + " mm stock does not fit between the blades");
      try {
        const FlankAxis fa = flank_axis(face, s.v[i], rq_.hub, grown_cutter_);
        s.finishing_axis[i] = fa.pose.axis;
        s.finishing_centre[i] =
            hub_stock_ == rq_.stock_mm ? fa.ball_centre : slide_onto_hub_offset(s, fa.ball_centre, fa.pose.axis);
      } catch (const Error&) {
        const auto touch = [&](double th) { return distance(i, th) - grown; };
        const double a = theta_mid, b = theta[i], ga = touch(a), gb = touch(b);
        s.finishing_axis[i] = ruling[i];
        s.finishing_centre[i] = ball_centre(s, gb < 0 ? illinois_root(touch, a, b, ga, gb, 1e-9) : b);
      }
    }
    return s;
  }

  const ChannelRequest& rq_;
  double r_;
  double hub_stock_;          // the request's hub stock, or the faces'
  FlankCutter grown_cutter_;  // the cutter's offset by the faces' stock
  double u_in_ = 0, u_out_ = 1;  // the hub's meridian parameter at the inlet and outlet stations
};

// The widening paths' ball centres of one side at a station, k = 0 (the
// notch) .. n (the finishing pose): the straight line between the two
// centres, each point put back over the hub (r + stock along its normal).
std::vector<Vec3> widening_centres(const Channel& ch, const Station& s, int side, int n) {
  std::vector<Vec3> c(static_cast<size_t>(n) + 1);
  const Vec3 a = s.notch_centre, b = s.finishing_centre[side];
  c.front() = a;
  c.back() = b;
  for (int k = 1; k < n; ++k) c[static_cast<size_t>(k)] = ch.ball_centre_over(s, a + (b - a) * (static_cast<double>(k) / n));
  return c;
}

// S of eq. 13: the length of that line over the hub, from the notch's
// centre to the finishing pose's (as a polyline of 64 pieces).
double side_width(const Channel& ch, const Station& s, int side) {
  const std::vector<Vec3> c = widening_centres(ch, s, side, 64);
  double length = 0;
  for (size_t i = 1; i < c.size(); ++i) length += (c[i] - c[i - 1]).norm();
  return length;
}

// Poses between two poses of a pass on the hub, ball centres ca -> cb: the
// straight move's middle put back onto the hub's offset where it is more
// than `tol` off it (axis the two axes' mean), halving both parts until
// every middle is within tol (an error beyond 2^10 pieces). In cutting order, with
// their stations t.
void hub_chord_poses(const Channel& ch, const Station& s, const ToolPose& a, double ta, const ToolPose& b, double tb,
                     double r, double tol, int depth, std::vector<std::pair<double, ToolPose>>& out) {
  const Vec3 mid = 0.5 * ((a.tip + r * a.axis) + (b.tip + r * b.axis));
  const Vec3 on = ch.ball_centre_over(s, mid);
  if ((on - mid).norm() <= tol) return;
  if (depth >= 10)
    throw Error("channel at t = " + std::to_string(ta) + ".." + std::to_string(tb) +
                ": the ball centre cannot be kept within " + std::to_string(tol) +
                " mm of the hub's offset (1024 poses between two stations)");
  const Vec3 axis = (a.axis + b.axis).normalized();
  const ToolPose m{on - r * axis, axis};
  const double tm = 0.5 * (ta + tb);
  hub_chord_poses(ch, s, a, ta, m, tm, r, tol, depth + 1, out);
  out.emplace_back(tm, m);
  hub_chord_poses(ch, s, m, tm, b, tb, r, tol, depth + 1, out);
}

}  // namespace

ChannelPlan plan_channel(const ChannelRequest& rq) {
  if (!rq.left.face || !rq.right.face) throw ParameterError("faces", "expected the two blade faces of the channel");
  if (!rq.hub) throw ParameterError("hub", "expected the hub surface of revolution");
  if (!rq.cutter) throw ParameterError("tool", "expected a ball or tapered ball-end cutter");
  if (rq.world && !rq.body) throw ParameterError("world", "a collision world needs the tool's body");
  if (rq.stations < 2) throw ParameterError("stations", "expected at least 2 stations along the channel");
  if (!(rq.stock_mm >= 0)) throw ParameterError("stock", "expected a stock >= 0 in mm");
  if (std::isnan(rq.hub_stock_mm) || rq.hub_stock_mm > rq.stock_mm)
    throw ParameterError("hub_stock", "expected a hub stock from 0 up to the faces' stock, mm");
  if (!(rq.hub_chord_tol_mm > 0)) throw ParameterError("hub_chord_tol", "expected a chord tolerance > 0 in mm");
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
  plan.hub_stock_mm = ch.hub_stock();
  // Eq. 12 solved exactly, eq. 13 per side at the outlet.
  const double h = rq.scallop_mm;
  plan.step_over_mm = 2 * std::sqrt(2 * r * h - h * h);
  const Station& outlet = st.back();
  plan.outlet_width_left_mm = side_width(ch, outlet, 0);
  plan.outlet_width_right_mm = side_width(ch, outlet, 1);
  if (rq.widen) {
    plan.widen_left = std::max(1, static_cast<int>(std::ceil(plan.outlet_width_left_mm / plan.step_over_mm - 1e-9)));
    plan.widen_right = std::max(1, static_cast<int>(std::ceil(plan.outlet_width_right_mm / plan.step_over_mm - 1e-9)));
  }
  double deepest = 0;
  for (const Station& s : st) deepest = std::max(deepest, (s.top - s.notch_centre).norm());
  plan.notch_levels = std::max(1, static_cast<int>(std::ceil(deepest / rq.depth_step_mm - 1e-9)));
  plan.deepest_step_mm = deepest / plan.notch_levels;

  // The poses of a pass at a station.
  const auto notch_pose = [&](const Station& s, int level) {
    const Vec3 c = s.top + (s.notch_centre - s.top) * (static_cast<double>(level) / plan.notch_levels);
    return ToolPose{c - r * s.notch_axis, s.notch_axis};
  };
  // Widening ball centres per station and side, k = 0..N, and the scallop
  // they leave measured on the hub (the stock surface) at every station:
  // along the line between two neighbouring ball centres, the stock surface
  // under it sampled and the height each ball leaves there taken along the
  // hub normal. Where a station's cusp exceeds h (the hub curves and the
  // channel's width varies, so eq. 13's N at the outlet is not a proof),
  // that side gets one more path, until none does.
  std::vector<std::vector<Vec3>> centres[2];
  std::vector<double> worst[2];  // per side and station
  for (int side = 0; side < 2 && rq.widen; ++side) {
    int& n = side == 0 ? plan.widen_left : plan.widen_right;
    for (;; ++n) {
      centres[side].clear();
      worst[side].assign(st.size(), 0.0);
      for (size_t i = 0; i < st.size(); ++i) {
        centres[side].push_back(widening_centres(ch, st[i], side, n));
        const std::vector<Vec3>& c = centres[side].back();
        for (size_t k = 0; k + 1 < c.size(); ++k)
          for (int j = 1; j < rq.scallop_samples; ++j) {
            Vec3 p, nh;
            ch.hub_under(st[i], c[k] + (c[k + 1] - c[k]) * (static_cast<double>(j) / rq.scallop_samples), p, nh);
            const Vec3 q = p + ch.hub_stock() * nh;
            worst[side][i] = std::max(worst[side][i], std::min(height_to_ball(q, nh, c[k], r),
                                                               height_to_ball(q, nh, c[k + 1], r)));
          }
      }
      if (*std::max_element(worst[side].begin(), worst[side].end()) <= h) break;
      ++plan.paths_added;
    }
    for (size_t i = 0; i < st.size(); ++i) plan.scallop_max_mm = std::max(plan.scallop_max_mm, worst[side][i]);
    plan.scallop_outlet_mm = std::max(plan.scallop_outlet_mm, worst[side].back());
  }
  const auto widen_pose = [&](size_t station, int side, int k, int n) {
    const Station& s = st[station];
    const Vec3 axis = (s.notch_axis + (s.finishing_axis[side] - s.notch_axis) * (static_cast<double>(k) / n)).normalized();
    return ToolPose{centres[side][station][static_cast<size_t>(k)] - r * axis, axis};
  };

  // The passes in cutting order, alternating direction.
  struct Spec {
    ChannelPassKind kind;
    int index;
  };
  std::vector<Spec> specs;
  for (int j = 1; j <= plan.notch_levels; ++j) specs.push_back({ChannelPassKind::Notch, j});
  for (int k = 1; k <= plan.widen_left; ++k) specs.push_back({ChannelPassKind::WidenLeft, k});
  for (int k = 1; k <= plan.widen_right; ++k) specs.push_back({ChannelPassKind::WidenRight, k});
  ChannelChecks checks;
  checks.world = rq.world;
  checks.body = rq.body;
  checks.clearances = rq.clearances;
  checks.motion_tol_mm = rq.motion_tol_mm;
  checks.link = rq.link;
  std::vector<ChannelPass> passes;
  ChannelPieces pieces(checks, passes, plan.refusals);
  // The passes whose ball runs on the hub: the deepest notch level and
  // every widening path.
  const auto on_hub = [&](const ChannelPass& pass) {
    return pass.kind != ChannelPassKind::Notch || pass.index == plan.notch_levels;
  };
  for (size_t p = 0; p < specs.size(); ++p) {
    const Spec& spec = specs[p];
    pieces.begin(spec.kind, spec.index);
    for (int q = 0; q < rq.stations; ++q) {
      const size_t station = static_cast<size_t>(p % 2 == 0 ? q : rq.stations - 1 - q);
      const Station& s = st[station];
      const int side = spec.kind == ChannelPassKind::WidenRight ? 1 : 0;
      const int n = side == 0 ? plan.widen_left : plan.widen_right;
      ToolPose pose = spec.kind == ChannelPassKind::Notch ? notch_pose(s, spec.index) : widen_pose(station, side, spec.index, n);
      PoseCheck pc;
      if (rq.world) {
        pc = rq.world->check(*rq.body, pose, rq.clearances, 0.0);
        // A widening pose whose flute or shank meets the blade leaning over
        // it: turn its axis further towards the finishing axis about the
        // same ball centre (eq. 14's blend taken beyond k / N), in quarters
        // of what is left, before refusing it.
        if (!pc.clear && spec.kind != ChannelPassKind::Notch && spec.index < n) {
          const Vec3 centre = pose.tip + r * pose.axis;
          for (int j = 1; j <= 4 && !pc.clear; ++j) {
            const double f = static_cast<double>(spec.index) / n, blend = f + (1 - f) * j / 4.0;
            const Vec3 axis = (s.notch_axis + (s.finishing_axis[side] - s.notch_axis) * blend).normalized();
            const ToolPose turned{centre - r * axis, axis};
            const PoseCheck tc = rq.world->check(*rq.body, turned, rq.clearances, 0.0);
            if (tc.clear) {
              pose = turned;
              pc = tc;
              ++plan.turned;
            }
          }
        }
      }
      // On the hub, the poses the chord tolerance needs between the last
      // pose and this one first; each is checked like a station's.
      const ChannelPass& current = pieces.current();
      if (on_hub(current) && !current.poses.empty()) {
        std::vector<std::pair<double, ToolPose>> between;
        hub_chord_poses(ch, s, current.poses.back(), current.t.back(), pose, s.t, r, rq.hub_chord_tol_mm, 0, between);
        plan.inserted += static_cast<long>(between.size());
        for (const auto& tp : between) pieces.add(tp.second, tp.first);
      }
      pieces.add(pose, s.t, rq.world ? &pc : nullptr);
    }
    pieces.end();
  }

  // Between consecutive pieces: where the next starts at the station the
  // last ended (the zigzag's turn), a straight step-over or step-down at
  // the feed when that motion is proved clear — the way a zigzag runs, and
  // through material this channel's earlier passes have cut or the next
  // one cuts anyway. On the hub the step keeps the ball on the hub's
  // offset too: a straight step across the channel (from one side's last
  // path to the other side's first) cuts a chord into the convex hub —
  // 72 um on the built-in impeller's inlet before these poses.
  const ChannelStep step = [&](const ChannelPass& from, const ChannelPass& to,
                               std::vector<std::pair<double, ToolPose>>& between) {
    if (from.t.back() != to.t.front()) return false;
    if (on_hub(from) && on_hub(to)) {
      const double t = to.t.front();
      const Station& s = st[static_cast<size_t>(std::lround(t * (rq.stations - 1)))];
      hub_chord_poses(ch, s, from.poses.back(), t, to.poses.front(), t, r, rq.hub_chord_tol_mm, 0, between);
    }
    return true;
  };
  join_channel_pieces(std::move(passes), checks, step, plan);
  return plan;
}

void ChannelPieces::begin(ChannelPassKind kind, int index, int level) {
  close();
  current_ = ChannelPass{kind, index, level, {}, {}};
}

void ChannelPieces::close() {
  if (!current_.poses.empty()) pieces_.push_back(current_);
  current_.t.clear();
  current_.poses.clear();
}

void ChannelPieces::add(const ToolPose& pose, double t, const PoseCheck* checked, const MotionCheck* motion) {
  if (checks_.world) {
    const PoseCheck pc = checked ? *checked : checks_.world->check(*checks_.body, pose, checks_.clearances, 0.0);
    if (!pc.clear) {
      refusals_.push_back({current_.kind, current_.index, current_.level, t, "pose: " + describe(pc, *checks_.world)});
      close();
      return;
    }
    if (!current_.poses.empty()) {
      const MotionCheck mc = motion ? *motion
                                    : checks_.world->check_motion(*checks_.body, current_.poses.back(), pose,
                                                                  checks_.clearances, checks_.motion_tol_mm);
      if (!mc.clear) {
        refusals_.push_back({current_.kind, current_.index, current_.level, t,
                             "motion from the previous pose: " + describe(mc.at, *checks_.world) +
                                 (mc.undecided ? " (undecided)" : "")});
        close();  // this pose starts a new piece, reached by a link
      }
    }
  }
  current_.t.push_back(t);
  current_.poses.push_back(pose);
}

void join_channel_pieces(std::vector<ChannelPass> passes, const ChannelChecks& checks, const ChannelStep& step,
                         ChannelPath& plan) {
  LinkChecks link_checks;
  link_checks.world = checks.world;
  link_checks.body = checks.body;
  link_checks.clearances = checks.clearances;
  link_checks.motion_tol_mm = checks.motion_tol_mm;
  if (checks.world) link_checks.traverse_world = checks.world->unchecked_pairs();  // the face being machined, for the cutter
  const CollisionWorld* world = checks.world;
  for (size_t i = 0; i < passes.size(); ++i) {
    if (i > 0 && world) {
      const ToolPose& a = plan.passes.back().poses.back();  // passes[i - 1], already moved into the plan
      const ToolPose& b = passes[i].poses.front();
      std::vector<std::pair<double, ToolPose>> between;
      if (step && step(plan.passes.back(), passes[i], between)) {
        bool clear = true;
        const ToolPose* previous = &a;
        for (const auto& tp : between) {
          clear = world->check(*checks.body, tp.second, checks.clearances, 0.0).clear &&
                  world->check_motion(*checks.body, *previous, tp.second, checks.clearances, checks.motion_tol_mm).clear;
          if (!clear) break;
          previous = &tp.second;
        }
        if (clear && world->check_motion(*checks.body, *previous, b, checks.clearances, checks.motion_tol_mm).clear) {
          PlannedLink direct;  // no via poses: a direct step (along the hub where it follows it)
          direct.clear = true;
          plan.links.push_back(std::move(direct));
          for (auto it = between.rbegin(); it != between.rend(); ++it) {
            passes[i].t.insert(passes[i].t.begin(), it->first);
            passes[i].poses.insert(passes[i].poses.begin(), it->second);
          }
          plan.inserted += static_cast<long>(between.size());
          plan.poses += static_cast<long>(passes[i].poses.size());
          plan.passes.push_back(std::move(passes[i]));
          continue;
        }
      }
      // Up the axis by link.retract_mm, and where the traverse there is
      // not clear (a splitter's leading edge, a leaning blade) twice, four
      // and eight times as far: out of the channel rather than along it.
      PlannedLink link;
      LinkOptions up = checks.link;
      for (int tries = 0; tries < 4 && !link.clear; ++tries, up.retract_mm *= 2) {
        PlannedLink attempt = plan_link({a, a.axis}, {b, b.axis}, link_checks, up);
        if (attempt.clear || tries == 0) link = std::move(attempt);
      }
      if (!link.clear) {
        plan.complete = false;
        plan.stopped = std::string("link into ") + to_string(passes[i].kind) + " " + std::to_string(passes[i].index) +
                       (passes[i].level > 0 ? " of level " + std::to_string(passes[i].level) : std::string()) + ": " +
                       link.reason;
        break;
      }
      plan.links.push_back(std::move(link));
    }
    plan.poses += static_cast<long>(passes[i].poses.size());
    plan.passes.push_back(std::move(passes[i]));
  }
  if (world && !plan.passes.empty()) {
    const ToolPose& first = plan.passes.front().poses.front();
    const ToolPose& last = plan.passes.back().poses.back();
    plan.lead_in = plan_departure({first, first.axis}, link_checks, checks.link);
    plan.lead_out = plan_departure({last, last.axis}, link_checks, checks.link);
    if (!plan.lead_in.clear || !plan.lead_out.clear) {
      plan.complete = false;
      if (plan.stopped.empty())
        plan.stopped = std::string("lead-") + (plan.lead_in.clear ? "out: " + plan.lead_out.reason : "in: " + plan.lead_in.reason);
    }
  }
}

Toolpath channel_moves(const ChannelPath& plan) {
  Toolpath moves;
  if (plan.lead_in.clear) moves.push_back({Move::Kind::Rapid, plan.lead_in.away, 0, "start", {}});
  for (size_t i = 0; i < plan.passes.size(); ++i) {
    const int pass = static_cast<int>(i);
    if (i > 0 && i - 1 < plan.links.size()) {
      const PlannedLink& link = plan.links[i - 1];
      for (size_t k = 0; k < link.via.size(); ++k) moves.push_back({Move::Kind::Rapid, link.via[k], pass, link_leg_name(link.legs[k]), {}});
    } else if (i > 0 && !plan.complete) {
      break;  // an unproved link: nothing after it
    }
    const ChannelPass& p = plan.passes[i];
    const bool step = i > 0 && i - 1 < plan.links.size() && plan.links[i - 1].via.empty();
    for (size_t k = 0; k < p.poses.size(); ++k)
      moves.push_back({Move::Kind::Feed, p.poses[k], pass, k > 0 ? "cut" : step ? "step" : "approach", {}});
  }
  if (plan.lead_out.clear && plan.links.size() + 1 == plan.passes.size())
    moves.push_back({Move::Kind::Rapid, plan.lead_out.away, static_cast<int>(plan.passes.size()) - 1, "retract", {}});
  return moves;
}

std::vector<ChannelPlan> plan_channels(const std::vector<ChannelRequest>& requests, int threads, Progress& progress) {
  std::vector<ChannelPlan> plans(requests.size());
  run_parallel(requests.size(), threads, progress, "channel roughing, channels",
               [&](size_t k, Progress&) { plans[k] = plan_channel(requests[k]); });
  return plans;
}

}  // namespace bliskrun
