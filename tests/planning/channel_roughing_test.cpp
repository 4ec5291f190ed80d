#include "core/planning/channel_roughing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/collision/collision_world.h"
#include "core/common/error.h"
#include "core/geometry/mesh.h"
#include "core/geometry/projection.h"

namespace bliskrun {
namespace {

// A blade face in the plane through Z at angle theta, radii 50 -> 100 mm,
// 20 mm high, its rulings leaning by `lean` rad towards +theta. v runs
// inward when `reversed` (so the right face's normal also points into the
// channel).
class RadialFace : public Surface {
 public:
  RadialFace(double theta, double lean, bool reversed) : th_(theta), lean_(lean), rev_(reversed) {}
  SurfaceDerivs eval(double u, double v) const override {
    const Vec3 radial(std::cos(th_), std::sin(th_), 0), tangential(-std::sin(th_), std::cos(th_), 0);
    const Vec3 ruling = 20 * (std::cos(lean_) * Vec3::UnitZ() + std::sin(lean_) * tangential);
    const double s = rev_ ? -50 : 50, r = rev_ ? 100 - 50 * v : 50 + 50 * v;
    SurfaceDerivs d;
    d.p = r * radial + u * ruling;
    d.pu = ruling;
    d.pv = s * radial;
    return d;
  }
  // Distance from c to the face, the rectangle radii 50..100 by 20 mm up
  // the ruling: radial and ruling are orthonormal, so its nearest point has
  // the clamped in-plane coordinates.
  double distance(const Vec3& c) const {
    const Vec3 radial(std::cos(th_), std::sin(th_), 0);
    const double a = std::clamp(c.dot(radial), 50.0, 100.0), b = std::clamp(c.dot(ruling()), 0.0, 20.0);
    return (c - a * radial - b * ruling()).norm();
  }
  Vec3 ruling() const {
    return (std::cos(lean_) * Vec3::UnitZ() + std::sin(lean_) * Vec3(-std::sin(th_), std::cos(th_), 0)).normalized();
  }

 private:
  double th_, lean_;
  bool rev_;
};

Tool ball_end(double radius) {
  BallEndMillSpec s;
  s.radius_mm = radius;
  s.flute_length_mm = 40;
  return Tool::ball_end_mill(s);
}

struct FlatChannel {
  double alpha = deg_to_rad(10);
  RadialFace left{-deg_to_rad(10), 0, false}, right{deg_to_rad(10), 0, true};
  SurfaceOfRevolution hub{std::vector<Vec2>{{0, 40}, {0, 110}}};  // the flat disc z = 0
  FlankCutter cutter{ball_end(3), 3};
  ChannelRequest request() const {
    ChannelRequest rq;
    rq.left = {&left, 0, 1};
    rq.right = {&right, 1, 0};
    rq.hub = &hub;
    rq.cutter = &cutter;
    rq.stations = 11;
    rq.stock_mm = 0.3;
    rq.scallop_mm = 0.01;
    rq.depth_step_mm = 5;
    return rq;
  }
};

TEST(ChannelRoughing, NotchAxesBisectTheChannelAndTheNotchRunsInItsMiddle) {
  // Both blades lean 12 deg the same way (a backswept channel): the notch
  // axis is the sum of the two rulings, at equal angles to each, and the
  // deepest level's ball sits stock + r above the hub, equidistant from the
  // two faces.
  FlatChannel s;
  s.left = RadialFace(-s.alpha, deg_to_rad(12), false);
  s.right = RadialFace(s.alpha, deg_to_rad(12), true);
  ChannelRequest rq = s.request();
  rq.widen = false;
  const ChannelPlan plan = plan_channel(rq);
  EXPECT_EQ(plan.notch_levels, 4);  // 20 mm down to 3.3 mm, in steps <= 5 mm
  EXPECT_LE(plan.deepest_step_mm, 5.0);
  ASSERT_EQ(plan.passes.size(), 4u);
  for (const ChannelPass& pass : plan.passes) {
    ASSERT_EQ(pass.poses.size(), 11u);
    for (const ToolPose& p : pass.poses) {
      EXPECT_NEAR(std::acos(p.axis.dot(s.left.ruling())), std::acos(p.axis.dot(s.right.ruling())), 1e-9);
      EXPECT_NEAR(p.axis.dot((s.left.ruling() + s.right.ruling()).normalized()), 1, 1e-12);
    }
  }
  // Zigzag: level 2 runs outlet -> inlet.
  EXPECT_GT(plan.passes[1].t.front(), plan.passes[1].t.back());
  const ChannelPass& deepest = plan.passes.back();
  for (size_t i = 0; i < deepest.poses.size(); ++i) {
    const Vec3 c = deepest.poses[i].tip + 3 * deepest.poses[i].axis;  // ball centre
    EXPECT_NEAR(c.z(), 3.3, 1e-9);
    // Near the inlet the middle lies in front of the leading edges, and
    // on the blade leaning over the channel the perpendicular foot falls
    // below the hub: the distances are then to the faces' edges.
    EXPECT_NEAR(s.left.distance(c), s.right.distance(c), 1e-6) << i;
  }
}

TEST(ChannelRoughing, WideningSpacingMeetsTheResidualHeightFormulaOnAFlatHub) {
  const FlatChannel s;
  const ChannelPlan plan = plan_channel(s.request());
  const double r = 3, h = 0.01, g = r + 0.3;
  // Eq. 12 solved exactly: f = 2 sqrt(2 r h - h^2); eq. 12's 2 sqrt(D h) is its first order.
  EXPECT_NEAR(plan.step_over_mm, 2 * std::sqrt(2 * r * h - h * h), 1e-12);
  EXPECT_NEAR(plan.step_over_mm, 2 * std::sqrt(2 * r * h), 1e-3);
  // S at the outlet (radius 100): from the notch's ball centre (at angle
  // 0) to the last path's, the finishing pose of the cutter grown by the
  // stock: the face's hub point (radius 100) moved g along the plane's
  // normal, at radius hypot(100, g) and angle -alpha + atan(g / 100). On
  // the flat hub the line between them stays on the hub offset.
  const double limit = s.alpha - std::atan(g / 100), outer = std::hypot(100.0, g);
  const double width = std::sqrt(outer * outer + 100 * 100 - 2 * outer * 100 * std::cos(limit));
  EXPECT_NEAR(plan.outlet_width_left_mm, width, 1e-9);
  EXPECT_NEAR(plan.outlet_width_right_mm, width, 1e-9);
  const int n = static_cast<int>(std::ceil(width / plan.step_over_mm));
  EXPECT_EQ(plan.widen_left, n);  // eq. 13
  EXPECT_EQ(plan.widen_right, n);
  EXPECT_EQ(plan.paths_added, 0);  // on a flat hub widest at the outlet, eq. 13's N suffices
  // The measured scallop: neighbouring centres S / N apart on a line at
  // g above the hub, cusp r - sqrt(r^2 - d^2 / 4) <= h (the exact eq. 12).
  const double d = width / n;
  EXPECT_NEAR(plan.scallop_outlet_mm, r - std::sqrt(r * r - d * d / 4), 1e-12);
  EXPECT_LE(plan.scallop_outlet_mm, h);
  EXPECT_GT(plan.scallop_outlet_mm, 0.9 * h);
  // Inward the channel narrows and the same N paths close up: never more.
  EXPECT_LE(plan.scallop_max_mm, plan.scallop_outlet_mm + 1e-12);
  // Passes: the notch levels, then N per side; the last path of each side
  // is the grown cutter's finishing pose (here the vertical ruling), its
  // ball g from the face and from the hub.
  ASSERT_EQ(plan.passes.size(), static_cast<size_t>(plan.notch_levels + 2 * n));
  const ChannelPass& last_left = plan.passes[static_cast<size_t>(plan.notch_levels + n - 1)];
  EXPECT_EQ(last_left.kind, ChannelPassKind::WidenLeft);
  EXPECT_EQ(last_left.index, n);
  for (size_t i = 0; i < last_left.poses.size(); ++i) {
    const ToolPose& p = last_left.poses[i];
    EXPECT_NEAR(p.axis.z(), 1, 1e-6);
    const Vec3 c = p.tip + r * p.axis;
    EXPECT_NEAR(s.left.distance(c), g, 1e-6) << i;
    EXPECT_NEAR(c.z(), g, 1e-6) << i;  // the stock above the hub
    if (last_left.t[i] == 1.0) {  // the outlet, in the open: the closed form of the plane
      const Vec3 normal(std::sin(s.alpha), std::cos(s.alpha), 0);
      EXPECT_NEAR(c.dot(normal), g, 1e-6);
    }
  }
}

TEST(ChannelRoughing, TheWideningFinishesTheHubWhileTheFacesKeepTheStock) {
  // hub_stock 0 (the paper's hub finish in the widening passes): the
  // deepest notch level and every widening path run with the ball r over
  // the flat hub; each side's last path is the grown cutter's finishing
  // pose (vertical ruling) slid down its axis, still g = r + stock from the
  // face. The widths and N are those of the same line r lower.
  const FlatChannel s;
  ChannelRequest rq = s.request();
  rq.hub_stock_mm = 0;
  const ChannelPlan plan = plan_channel(rq);
  const double r = 3, h = 0.01, g = r + 0.3;
  EXPECT_EQ(plan.hub_stock_mm, 0);
  EXPECT_EQ(plan.inserted, 0);  // a flat hub: the straight moves stay on its offset
  const double limit = s.alpha - std::atan(g / 100), outer = std::hypot(100.0, g);
  const double width = std::sqrt(outer * outer + 100 * 100 - 2 * outer * 100 * std::cos(limit));
  EXPECT_NEAR(plan.outlet_width_left_mm, width, 1e-9);
  const int n = static_cast<int>(std::ceil(width / plan.step_over_mm));
  EXPECT_EQ(plan.widen_left, n);
  EXPECT_LE(plan.scallop_max_mm, h);  // measured on the hub itself now
  for (const ChannelPass& pass : plan.passes) {
    const bool on_hub = pass.kind != ChannelPassKind::Notch || pass.index == plan.notch_levels;
    for (const ToolPose& p : pass.poses) {
      const Vec3 c = p.tip + r * p.axis;
      if (on_hub) EXPECT_NEAR(c.z(), r, 1e-9);
      else EXPECT_GT(c.z(), r + 1);
    }
  }
  const ChannelPass& last_left = plan.passes[static_cast<size_t>(plan.notch_levels + n - 1)];
  ASSERT_EQ(last_left.index, n);
  for (const ToolPose& p : last_left.poses) {
    EXPECT_NEAR(p.axis.z(), 1, 1e-6);
    EXPECT_NEAR(s.left.distance(p.tip + r * p.axis), g, 1e-6);
  }
  // More on the hub than on the faces is refused.
  rq.hub_stock_mm = 0.5;
  EXPECT_THROW(plan_channel(rq), ParameterError);
}

TEST(ChannelRoughing, OnACurvedHubPosesAreInsertedSoTheBallKeepsToTheHubOffset) {
  // A hub bulging 2 mm over the channel's middle (meridian z = 2 - (r -
  // 75)^2 / 400, curvature radius ~200 mm): between stations 5 mm apart a
  // straight move of the ball centre dips (5^2 / 8 / 203 = 15 um) into the
  // ball's offset — into the hub, once the hub is finished. With the chord
  // tolerance every move's middle keeps to the offset within it.
  FlatChannel s;
  std::vector<Vec2> m;
  for (int i = 0; i <= 70; ++i) {
    const double rad = 40 + i;
    m.emplace_back(2 - (rad - 75) * (rad - 75) / 400, rad);
  }
  s.hub = SurfaceOfRevolution(m);
  const double r = 3;
  const auto worst_middle = [&](double tol, long& inserted) {
    ChannelRequest rq = s.request();
    rq.hub_stock_mm = 0;
    rq.scallop_mm = 0.2;  // few paths
    rq.hub_chord_tol_mm = tol;
    const ChannelPlan plan = plan_channel(rq);
    inserted = plan.inserted;
    double worst = 0;
    for (const ChannelPass& pass : plan.passes) {
      if (pass.kind == ChannelPassKind::Notch && pass.index < plan.notch_levels) continue;
      for (size_t i = 0; i < pass.poses.size(); ++i) {
        const Vec3 c = pass.poses[i].tip + r * pass.poses[i].axis;
        const double on = project_to_surface(s.hub, c, ProjectionOptions{}).distance;
        EXPECT_NEAR(on, r, 1e-6) << i;  // every pose's ball on the hub's offset
        if (i == 0) continue;
        const Vec3 mid = 0.5 * (c + pass.poses[i - 1].tip + r * pass.poses[i - 1].axis);
        worst = std::max(worst, std::abs(project_to_surface(s.hub, mid, ProjectionOptions{}).distance - r));
      }
    }
    return worst;
  };
  long inserted = 0;
  EXPECT_GT(worst_middle(1.0, inserted), 0.012);  // stations alone: the dip
  EXPECT_EQ(inserted, 0);
  EXPECT_LE(worst_middle(0.005, inserted), 0.005);
  EXPECT_GT(inserted, 0);
}

TEST(ChannelRoughing, StepsAcrossAConicalHubFollowItToo) {
  // A conical hub falling 0.1 mm per mm of radius: across the channel at
  // one radius a straight step between two ball centres runs inside their
  // circle, where the hub stands higher — from one side's last widening
  // path to the other side's first that chord dips ~50 um into the hub's
  // offset. With the hub finished (hub_stock 0) every move of the emitted
  // toolpath on the hub, steps included, keeps to the offset within the
  // chord tolerance.
  FlatChannel s;
  s.hub = SurfaceOfRevolution(std::vector<Vec2>{{6, 40}, {0, 100}, {-1, 110}});
  const Tool tool = ball_end(3);
  const ToolBody body(tool);
  CollisionWorld world;
  world.add("left", tessellate(s.left, 0.02));
  world.add("right", tessellate(s.right, 0.02));
  CheckSurfaceOptions shank_only;
  shank_only.parts.cutter = false;
  world.add("hub", tessellate(s.hub, 0.02), shank_only);
  ChannelRequest rq = s.request();
  rq.stations = 5;
  rq.depth_step_mm = 30;
  rq.scallop_mm = 0.5;
  rq.hub_stock_mm = 0;
  rq.world = &world;
  rq.body = &body;
  rq.clearances.cutter_mm = 0.1;
  const ChannelPlan plan = plan_channel(rq);
  ASSERT_TRUE(plan.complete) << plan.stopped;
  EXPECT_TRUE(plan.refusals.empty());
  const Toolpath moves = channel_moves(plan);
  double worst = 0;
  int steps = 0;
  for (size_t i = 1; i < moves.size(); ++i) {
    if (moves[i].kind != Move::Kind::Feed || moves[i - 1].kind != Move::Kind::Feed) continue;
    const ChannelPass& pass = plan.passes[static_cast<size_t>(moves[i].row)];
    if (pass.kind == ChannelPassKind::Notch && pass.index < plan.notch_levels) continue;
    steps += moves[i].motion == "step";
    const Vec3 mid = 0.5 * ((moves[i].pose.tip + 3 * moves[i].pose.axis) + (moves[i - 1].pose.tip + 3 * moves[i - 1].pose.axis));
    worst = std::max(worst, std::abs(project_to_surface(s.hub, mid, ProjectionOptions{}).distance - 3));
  }
  EXPECT_GT(steps, 0);
  EXPECT_LE(worst, 0.005 + 1e-6);
  EXPECT_GT(plan.inserted, 0);
}

// A flat plate standing in the channel's middle: radii 73..77 at angle 0,
// z from 12 to 20.
class Plate : public Surface {
 public:
  SurfaceDerivs eval(double u, double v) const override {
    SurfaceDerivs d;
    d.p = Vec3(73 + 4 * v, 0, 12 + 8 * u);
    d.pu = Vec3(0, 0, 8);
    d.pv = Vec3(4, 0, 0);
    return d;
  }
};

TEST(ChannelRoughing, WithAWorldEveryMoveIsClearAndObstaclesAreLinkedAround) {
  FlatChannel s;
  const Tool tool = ball_end(3);
  const ToolBody body(tool);
  CollisionWorld world;
  world.add("left", tessellate(s.left, 0.02));
  world.add("right", tessellate(s.right, 0.02));
  world.add("hub", tessellate(s.hub, 0.02));
  ChannelRequest rq = s.request();
  // Few passes (the collision checks dominate, more so under ASan): 9
  // stations (one at t = 0.5, the plate's), 2 notch levels, 0.5 mm cusps.
  rq.stations = 9;
  rq.depth_step_mm = 10;
  rq.scallop_mm = 0.5;
  rq.world = &world;
  rq.body = &body;
  rq.clearances.cutter_mm = 0.1;
  const auto every_move_clear = [&](const ChannelPlan& plan, const CollisionWorld& w) {
    const Toolpath moves = channel_moves(plan);
    for (size_t i = 0; i < moves.size(); ++i) {
      EXPECT_TRUE(w.check(body, moves[i].pose, Clearances{}, 0.0).clear) << i;
      if (i > 0) EXPECT_TRUE(w.check_motion(body, moves[i - 1].pose, moves[i].pose, Clearances{}, 1e-2).clear) << i;
    }
    return moves;
  };

  // The open channel: no refusals; every turn of the zigzag is a direct
  // step (no via poses), so the moves are the poses plus the two leads.
  const ChannelPlan open = plan_channel(rq);
  EXPECT_TRUE(open.complete) << open.stopped;
  EXPECT_TRUE(open.refusals.empty());
  ASSERT_EQ(open.links.size() + 1, open.passes.size());
  for (const PlannedLink& l : open.links) EXPECT_TRUE(l.via.empty());
  EXPECT_TRUE(open.lead_in.clear && open.lead_out.clear);
  const Toolpath moves = every_move_clear(open, world);
  EXPECT_EQ(static_cast<long>(moves.size()), open.poses + 2);
  EXPECT_EQ(moves.front().kind, Move::Kind::Rapid);  // the lead-in's away pose
  EXPECT_EQ(moves.back().kind, Move::Kind::Rapid);

  // The plate: the poses where it stands are refused, each split pass
  // resumes past it through a link up the tool axis, and still every move
  // is clear.
  const Plate plate;
  world.add("plate", tessellate(plate, 0.02));
  const ChannelPlan blocked = plan_channel(rq);
  EXPECT_TRUE(blocked.complete) << blocked.stopped;
  ASSERT_FALSE(blocked.refusals.empty());
  for (const ChannelRefusal& r : blocked.refusals) {
    // Where the plate stands (radii 73..77 are t = 0.46..0.54; the tool's
    // body reaches a station either side), whichever part meets it.
    EXPECT_NEAR(r.t, 0.5, 0.15) << r.reason;
    EXPECT_NE(r.reason.find("plate"), std::string::npos) << r.reason;
  }
  EXPECT_GT(blocked.passes.size(), open.passes.size());
  size_t linked = 0;
  for (const PlannedLink& l : blocked.links) linked += !l.via.empty();
  EXPECT_GE(linked, 1u);
  every_move_clear(blocked, world);
}

// Several channels on two threads are the channels planned one by one
// (the requests share the cutter and the hub): the same moves, in order.
TEST(ChannelRoughing, ChannelsOnTwoThreadsMatchOneByOne) {
  FlatChannel s;
  std::vector<ChannelRequest> requests;
  for (double scallop : {0.01, 0.05, 0.2}) {
    ChannelRequest rq = s.request();
    rq.scallop_mm = scallop;
    requests.push_back(rq);
  }
  const std::vector<ChannelPlan> both = plan_channels(requests, 2);
  ASSERT_EQ(both.size(), requests.size());
  for (size_t k = 0; k < requests.size(); ++k) {
    const Toolpath a = channel_moves(plan_channel(requests[k])), b = channel_moves(both[k]);
    ASSERT_EQ(a.size(), b.size()) << k;
    for (size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].pose.tip, b[i].pose.tip) << k << " " << i;
      EXPECT_EQ(a[i].pose.axis, b[i].pose.axis) << k << " " << i;
    }
  }
  // Different scallops give different plans: the order is the requests'.
  EXPECT_GT(channel_moves(both[0]).size(), channel_moves(both[2]).size());
  EXPECT_THROW(plan_channels(requests, 0), ParameterError);
}

TEST(ChannelRoughing, RefusesWhatCannotBePlanned) {
  FlatChannel s;
  ChannelRequest rq = s.request();
  rq.scallop_mm = 0;
  EXPECT_THROW(plan_channel(rq), ParameterError);
  rq = s.request();
  rq.hub = nullptr;
  EXPECT_THROW(plan_channel(rq), ParameterError);
  // A face whose normal points away from the channel (the far face of the
  // blade): refused, naming the face.
  rq = s.request();
  const RadialFace away(-s.alpha, 0, true);  // at the left blade's place, the right blade's orientation
  rq.left = {&away, 1, 0};
  try {
    plan_channel(rq);
    ADD_FAILURE() << "a face facing away was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("left face does not face"), std::string::npos) << e.what();
  }
  // A ball wider than the inlet (2 * 50 sin 10 deg = 17 mm) does not fit.
  const FlankCutter big(ball_end(9), 9);
  rq = s.request();
  rq.cutter = &big;
  EXPECT_THROW(plan_channel(rq), Error);
}

}  // namespace
}  // namespace bliskrun
