#include "core/planning/flank_milling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "core/collision/collision_world.h"
#include "core/common/error.h"
#include "core/parts/impeller.h"

namespace bliskrun {
namespace {

Tool tapered(double r, double half_angle_deg, double flute) {
  TaperedBallEndMillSpec s;
  s.tip_radius_mm = r;
  s.half_angle_rad = deg_to_rad(half_angle_deg);
  s.flute_length_mm = flute;
  s.shank = {16, 40};
  s.holder = {40, 50};
  return Tool::tapered_ball_end_mill(s);
}

Tool flank_ball(double r, double flute) {
  BallEndMillSpec s;
  s.radius_mm = r;
  s.flute_length_mm = flute;
  return Tool::ball_end_mill(s);
}

double distance_to_line(const Vec3& p, const ToolPose& pose) {
  const Vec3 d = p - pose.tip;
  return (d - d.dot(pose.axis) * pose.axis).norm();
}

TEST(FlankMilling, TaperedCutterRadiusGrowsBySinBetaAlongTheAxis) {
  const FlankCutter c(tapered(3, 4, 60), 3);
  for (double s : {0.0, 1.0, 10.0, 25.0, 50.0})
    EXPECT_NEAR(c.radius_at(s), 3 + s * std::sin(deg_to_rad(4)), 1e-9) << s;
  EXPECT_NEAR(c.flute_top_mm(), 57.0, 1e-9);
  const FlankCutter b(flank_ball(4, 30), 4);
  EXPECT_NEAR(b.radius_at(12.0), 4.0, 1e-12);  // a ball end's side is a cylinder
  EXPECT_THROW(FlankCutter(flank_ball(4, 30), 3), ParameterError);
}

TEST(FlankMilling, AxisPassesThroughD1AndD2AndTheBallSitsOnTheHubOffset) {
  const Impeller imp(builtin_impeller_definition());
  const FlankCutter cutter(tapered(3, 3, 160), 3);
  for (CamberSide side : {CamberSide::kPlus, CamberSide::kMinus}) {
    const auto face = imp.face(BladeKind::kMain, 0, side);
    for (double v : {0.05, 0.3, 0.6, 0.95}) {
      const FlankAxis ax = flank_axis(*face, v, &imp.hub(), cutter);
      EXPECT_LT(distance_to_line(ax.d1, ax.pose), 1e-9);
      EXPECT_LT(distance_to_line(ax.d2, ax.pose), 1e-9);
      // D_i is the contact offset along the face normal by the cutter radius
      // at that contact's own height (not a cylinder's radius).
      EXPECT_NEAR((ax.d1 - ax.c1).norm(), 3 + ax.s1 * std::sin(deg_to_rad(3)), 1e-9);
      EXPECT_NEAR((ax.d2 - ax.c2).norm(), cutter.radius_at(std::max(0.0, ax.s2)), 1e-9);
      EXPECT_GT(ax.s1, 10.0);  // the shroud contact is well up the cone
      EXPECT_NEAR(imp.hub().radial_offset(ax.ball_centre), 3.0, 1e-7);  // eq. 29–32
      EXPECT_NEAR((ax.pose.tip + 3 * ax.pose.axis - ax.ball_centre).norm(), 0, 1e-12);
      EXPECT_GT(ax.pose.axis.dot(ax.c1 - ax.c2), 0);  // towards the shroud
    }
  }
}

// On a developable ruled face the normal is constant along each ruling, so
// the axis through D1, D2 is the ruling moved by the radius: a cylinder
// leaves no residual. The face of a cone camber with constant thickness is
// exactly developable (impeller_test).
TEST(FlankMilling, CylinderOnADevelopableRuledFaceLeavesNoResidual) {
  BladeCamber c;
  for (int i = 0; i <= 30; ++i) {
    const double a = 0.5 * kPi * i / 30;
    c.hub.push_back({Vec3(50 * std::cos(a), 50 * std::sin(a), 0), 1.0});
    c.shroud.push_back({Vec3(80 * std::cos(a), 80 * std::sin(a), 40), 1.0});
  }
  const RuledBlade blade(c);
  const FlankCutter cutter(flank_ball(5, 80), 5);
  for (CamberSide side : {CamberSide::kPlus, CamberSide::kMinus}) {
    const auto face = blade.face(side);
    std::vector<FlankAxis> axes;
    for (int j = 0; j <= 20; ++j) axes.push_back(flank_axis(*face, j / 20.0, nullptr, cutter));
    const FlankResidual r = flank_residual(*face, axes, cutter, 25);
    EXPECT_EQ(r.stats.samples, 21 * 25);
    EXPECT_LT(r.stats.max_abs_mm, 1e-6) << "side " << int(side);
  }
}

// A twisted ruled face (hyperbolic paraboloid): the normals turn along each
// ruling, the axis through the two end offsets runs closer to the face in
// between: the paper's "concave overcut" per pose (§7 (2)), zero at the ends.
class TwistedFace : public Surface {
 public:
  SurfaceDerivs eval(double u, double v) const override {
    SurfaceDerivs d;
    d.p = Vec3(60 * v, 30 * u, 30 * k * u * (v - 0.5));
    d.pu = Vec3(0, 30, 30 * k * (v - 0.5));
    d.pv = Vec3(60, 0, 30 * k * u);
    d.puv = Vec3(0, 0, 30 * k);
    return d;
  }
  double k = 0.4;
};

TEST(FlankMilling, TwistedRuledFaceIsOvercutInTheMiddleOfEachPose) {
  const TwistedFace face;
  const FlankCutter cutter(flank_ball(5, 80), 5);
  std::vector<FlankAxis> axes;
  for (double v : {0.1, 0.5, 0.9}) axes.push_back(flank_axis(face, v, nullptr, cutter));
  const int n = 21;
  const FlankResidual r = flank_residual(face, axes, cutter, n);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(r.at(a, 0), 0.0, 1e-6);
    EXPECT_NEAR(r.at(a, n - 1), 0.0, 1e-6);
    EXPECT_LT(r.at(a, n / 2), -1e-3) << "axis " << a;
    for (int k = 1; k < n - 1; ++k) EXPECT_LT(r.at(a, k), 0.0);
    // The middle value against brute force: distance from the axis point to
    // a dense sample of the face, minus the radius.
    const Vec3 p = axes[a].ball_centre + r.height_mm[a * n + n / 2] * axes[a].pose.axis;
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= 600; ++i)
      for (int j = 0; j <= 600; ++j) best = std::min(best, (face.point(i / 600.0, j / 600.0) - p).norm());
    EXPECT_NEAR(r.at(a, n / 2), best - 5, 2e-3);
  }
  EXPECT_LT(r.stats.max_mm, 1e-6);
  EXPECT_LT(r.stats.mean_mm, 0);
}

TEST(FlankMilling, StationsKeepBothBoundaryCurvesWithinTheChordTolerance) {
  const Impeller imp(builtin_impeller_definition());
  const auto face = imp.face(BladeKind::kMain, 0, CamberSide::kPlus);
  StepOptions steps;
  steps.chord_tol_mm = 0.005;
  const std::vector<double> v = flank_stations(*face, steps);
  ASSERT_GE(v.size(), 10u);
  EXPECT_EQ(v.front(), 0.0);
  EXPECT_EQ(v.back(), 1.0);
  for (double u : {0.0, 1.0}) {
    const IsoUCurve row(*face, u);
    for (size_t i = 1; i < v.size(); ++i) EXPECT_LE(chord_deviation(row, v[i - 1], v[i]), 0.005 + 1e-9);
  }
}

}  // namespace
}  // namespace bliskrun

namespace bliskrun {
namespace {

// The interference loop: a small obstacle inside the holder of the untilted
// poses near mid-chord. Those poses tilt (about the hub contact normal, so
// the holder swings along the chord) until the holder clears it, or are
// refused; nothing emitted collides, and every station is accounted for.
// The ball rides the hub: on every face of the built-in impeller, with the
// axes balanced (a shift along the face normal, which on a leaning blade
// has a part along the hub normal), every pose's ball centre stays on the
// hub offset, and each lead keeps it there or above all along — simulating
// the impeller job found the splitter's lead-in following the leaning face's
// normal 0.5 mm into the hub, and balanced poses pressing 6 um into it.
TEST(FlankMilling, BalancedPosesAndTheirLeadsKeepTheBallOnOrOverTheHub) {
  const Impeller imp(builtin_impeller_definition());
  const FlankCutter cutter(tapered(3, 2, 90), 3);
  const ToolBody body(cutter.tool());
  CollisionWorld nothing;
  for (BladeKind kind : {BladeKind::kMain, BladeKind::kSplitter}) {
    for (CamberSide side : {CamberSide::kPlus, CamberSide::kMinus}) {
      const auto face = imp.face(kind, 0, side);
      FlankFaceRequest rq;
      rq.face = face.get();
      rq.hub = &imp.hub();
      rq.cutter = &cutter;
      rq.world = &nothing;
      rq.body = &body;
      rq.steps.chord_tol_mm = 0.05;
      rq.residual_points = 10;
      rq.balance_residual = true;
      rq.optimise = false;  // the fitted poses' hub contact: FlankAxisFit.NeverWorsens...
      const FlankFacePlan plan = plan_flank_face(rq);
      ASSERT_GT(plan.axes.size(), 3u);
      EXPECT_EQ(plan.balanced, static_cast<int>(plan.axes.size()));
      for (const FlankAxis& a : plan.axes) EXPECT_NEAR(imp.hub().radial_offset(a.ball_centre), 3.0, 1e-7);
      for (const auto& [lead, at] : {std::pair{plan.lead_in, plan.axes.front()}, std::pair{plan.lead_out, plan.axes.back()}}) {
        ASSERT_TRUE(lead.clear) << lead.reason;
        const Vec3 to = lead.away.tip + 3 * lead.away.axis;
        double lowest = std::numeric_limits<double>::infinity();
        for (int k = 0; k <= 200; ++k)
          lowest = std::min(lowest, imp.hub().radial_offset(at.ball_centre + (to - at.ball_centre) * (k / 200.0)));
        EXPECT_GT(lowest, 3.0 - 1e-4);
        EXPECT_GT(imp.hub().radial_offset(to), 3.0 + 1.0);  // it rises off the hub
      }
    }
  }
}

TEST(FlankMilling, CollidingPosesAreTiltedClearOrRefusedNeverEmitted) {
  BladeCamber c;
  for (int i = 0; i <= 30; ++i) {
    const double a = 0.5 * kPi * i / 30;
    c.hub.push_back({Vec3(80 * std::cos(a), 80 * std::sin(a), 0), 1.0});
    c.shroud.push_back({Vec3(80 * std::cos(a), 80 * std::sin(a), 30), 1.0});
  }
  const RuledBlade blade(c);
  const auto face = blade.face(CamberSide::kPlus);
  const FlankCutter cutter(tapered(3, 2, 40), 3);
  const ToolBody body(cutter.tool());
  // Where the untilted holder's axis passes at mid-chord, 20 mm into the holder.
  const FlankAxis mid = flank_axis(*face, 0.5, nullptr, cutter);
  const Vec3 p = mid.pose.tip + (40 + 40 + 20) * mid.pose.axis;  // flutes 40, shank 40, then the holder
  TriangleMesh obstacle;
  obstacle.vertices = {p, p + Vec3(1, 0, 0), p + Vec3(0, 1, 0)};
  obstacle.triangles = {{0, 1, 2}};
  CollisionWorld world;
  world.add("obstacle", obstacle);
  FlankFaceRequest rq;
  rq.face = face.get();
  rq.cutter = &cutter;
  rq.world = &world;
  rq.body = &body;
  rq.steps.chord_tol_mm = 0.05;
  rq.max_tilt_rad = deg_to_rad(20);
  rq.tilt_step_rad = deg_to_rad(2);
  rq.residual_points = 5;
  const FlankFacePlan plan = plan_flank_face(rq);
  EXPECT_EQ(static_cast<int>(plan.axes.size() + plan.refusals.size()), plan.stations);
  EXPECT_GT(plan.tilted, 0);
  for (size_t i = 0; i < plan.axes.size(); ++i) {
    EXPECT_TRUE(world.check(body, plan.axes[i].pose, Clearances{}).clear) << i;
    if (i > 0) EXPECT_TRUE(world.check_motion(body, plan.axes[i - 1].pose, plan.axes[i].pose, Clearances{}).clear) << i;
  }
  for (const FlankRefusal& r : plan.refusals) EXPECT_NE(r.reason.find("obstacle"), std::string::npos) << r.reason;
  // The axis fit (on by default) changes no refusal: the same stations
  // refused, for the same reason, as without it.
  rq.optimise = false;
  const FlankFacePlan unfitted = plan_flank_face(rq);
  ASSERT_EQ(unfitted.refusals.size(), plan.refusals.size());
  for (size_t i = 0; i < plan.refusals.size(); ++i) {
    EXPECT_EQ(unfitted.refusals[i].v, plan.refusals[i].v);
    EXPECT_EQ(unfitted.refusals[i].reason, plan.refusals[i].reason);
  }
  EXPECT_EQ(unfitted.tilted, plan.tilted);
  // A tilted axis keeps its ball centre and stays in the tangent plane at the hub contact.
  for (size_t i = 0; i < plan.axes.size(); ++i) {
    if (plan.tilt_rad[i] == 0) continue;
    const FlankAxis& a = plan.axes[i];
    EXPECT_NEAR((a.pose.tip + 3 * a.pose.axis - a.ball_centre).norm(), 0, 1e-9);
    EXPECT_NEAR(a.pose.axis.dot(a.n2), flank_axis(*face, a.v, nullptr, cutter).pose.axis.dot(a.n2), 1e-9);
  }
}

// The reported clearance includes the leads: a point obstacle 0.8 mm off
// the ball half way along the lead-out, out of reach of every pose. The
// plan's smallest margin is the brute-force minimum over 2000 poses of each
// lead motion (within the 0.01 mm bound), not the poses' (the built-in
// splitter's lead-out passed 0.81 mm from a neighbour while 2.99 mm was
// reported).
TEST(FlankMilling, MinimumClearanceIncludesTheLeadsAsBruteForceFindsIt) {
  BladeCamber c;
  for (int i = 0; i <= 30; ++i) {
    const double a = 0.5 * kPi * i / 30;
    c.hub.push_back({Vec3(80 * std::cos(a), 80 * std::sin(a), 0), 1.0});
    c.shroud.push_back({Vec3(80 * std::cos(a), 80 * std::sin(a), 30), 1.0});
  }
  const RuledBlade blade(c);
  const auto face = blade.face(CamberSide::kPlus);
  const FlankCutter cutter(tapered(3, 2, 40), 3);
  const ToolBody body(cutter.tool());
  auto speck = [](const Vec3& p) {
    TriangleMesh m;
    m.vertices = {p, p + Vec3(0.01, 0, 0), p + Vec3(0, 0.01, 0)};
    m.triangles = {{0, 1, 2}};
    return m;
  };
  FlankFaceRequest rq;
  rq.face = face.get();
  rq.cutter = &cutter;
  rq.body = &body;
  rq.steps.chord_tol_mm = 0.5;
  rq.residual_points = 3;
  rq.optimise = false;  // a developable face: the fit keeps every axis, at a cost
  CollisionWorld far;
  far.add("far", speck(Vec3(0, 0, 500)));
  rq.world = &far;
  const FlankFacePlan first = plan_flank_face(rq);
  ASSERT_TRUE(first.lead_out.clear);
  const ToolPose last = first.axes.back().pose, away = first.lead_out.away;
  const PoseMotion out(last, away);
  const ToolPose mid = out.pose_at(0.5);
  const Vec3 flank_ball = mid.tip + 3 * mid.axis;
  // Beside the path, on the side away from the earlier poses (past the
  // face's end, where no pose reaches).
  Vec3 side = mid.axis.cross(away.tip - last.tip).normalized();
  if (side.dot(last.tip - first.axes[first.axes.size() - 2].pose.tip) < 0) side = -side;
  CollisionWorld world;
  world.add("speck", speck(flank_ball + 3.8 * side));
  rq.world = &world;
  const FlankFacePlan plan = plan_flank_face(rq);
  ASSERT_TRUE(plan.lead_in.clear && plan.lead_out.clear);
  ASSERT_LT((plan.lead_out.away.tip - away.tip).norm(), 1e-9);  // the same lead-out
  auto brute = [&](const ToolPose& a, const ToolPose& b) {
    const PoseMotion m(a, b);
    double low = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= 2000; ++k) low = std::min(low, world.check(body, m.pose_at(k / 2000.0), Clearances{}).min_margin_mm);
    return low;
  };
  const double leads = std::min(brute(plan.axes.front().pose, plan.lead_in.away), brute(last, away));
  double poses = std::numeric_limits<double>::infinity();
  for (const FlankAxis& a : plan.axes) poses = std::min(poses, world.check(body, a.pose, Clearances{}).min_margin_mm);
  EXPECT_NEAR(leads, 0.8, 0.05);
  EXPECT_GT(poses, leads + 0.5);  // only a lead comes this close
  // A lower bound within 0.01 mm; brute force samples every 1/2000 of a
  // motion whose points move less than 20 mm per unit t.
  EXPECT_LE(plan.lead_min_margin_mm, leads + 1e-9);
  EXPECT_GE(plan.lead_min_margin_mm, leads - kLeadMarginTolMm - 0.01);
  EXPECT_EQ(plan.min_margin_mm, std::min(plan.pose_min_margin_mm, plan.lead_min_margin_mm));
  EXPECT_NEAR(plan.min_margin_mm, leads, kLeadMarginTolMm + 0.01);
  std::printf("lead clearance: brute force %.4f mm, reported %.4f mm; poses %.4f mm\n", leads,
              plan.lead_min_margin_mm, poses);
}

// The root corner in closed form: a cone blade (rulings leaning out by
// alpha) on a flat hub. A ball end riding the hub and touching the face
// leaves r / sin(theta / 2) - r at the corner, theta the dihedral angle
// between face and hub on the channel side: 90 - alpha outside the cone
// (plus face), 90 + alpha inside (minus face).
TEST(FlankMilling, RootCornerMaterialIsTheBallsDistanceFromTheCorner) {
  const double alpha = deg_to_rad(20), r = 3;
  BladeCamber c;
  for (int i = 0; i <= 30; ++i) {
    const double a = 0.5 * kPi * i / 30, r2 = 80 + 30 * std::tan(alpha);
    c.hub.push_back({Vec3(80 * std::cos(a), 80 * std::sin(a), -5), 1.0});
    c.shroud.push_back({Vec3(r2 * std::cos(a), r2 * std::sin(a), 25), 1.0});
  }
  const RuledBlade blade(c);
  // The hub: the plane z = 0 (the rulings run on past it, cut back to it),
  // profile outlet -> inlet so the channel side (z > 0) is positive.
  const SurfaceOfRevolution hub(std::vector<Vec2>{Vec2(0, 200), Vec2(0, 100), Vec2(0, 10)});
  const FlankCutter cutter(flank_ball(r, 40), r);
  for (CamberSide side : {CamberSide::kPlus, CamberSide::kMinus}) {
    const auto face = blade.face(side);
    FlankFaceRequest rq;
    rq.face = face.get();
    rq.hub = &hub;
    rq.cutter = &cutter;
    rq.steps.chord_tol_mm = 0.5;
    rq.residual_points = 3;
    rq.optimise = false;  // a developable face: the fit keeps every axis, at a cost
    const FlankFacePlan plan = plan_flank_face(rq);
    ASSERT_EQ(plan.root_corner_mm.size(), plan.axes.size());
    const double theta = 0.5 * kPi + (side == CamberSide::kPlus ? -alpha : alpha);
    const double expected = r / std::sin(theta / 2) - r;
    for (size_t i = 0; i < plan.axes.size(); ++i) {
      EXPECT_NEAR(plan.axes[i].c2.z(), 0.0, 1e-9);
      EXPECT_NEAR(plan.root_corner_mm[i], expected, 1e-6) << i;
    }
    EXPECT_NEAR(plan.root_corner.max_mm, expected, 1e-6);
    std::printf("root corner, %s face: %.4f mm (closed form %.4f)\n", side == CamberSide::kPlus ? "plus" : "minus",
                plan.root_corner.max_mm, expected);
  }
}

}  // namespace
}  // namespace bliskrun

#include "core/sim/undercut.h"

namespace bliskrun {
namespace {

// The independent undercut simulation (core/sim: normal lines of the design
// face cut by the swept tool) agrees with the residual along the axes on the
// same plan: on the twisted face the deepest overcut the simulation finds
// over the dense pass (201 poses, swept between them) is the deepest residual
// along the axes, within 5 %.
TEST(FlankMilling, UndercutSimulationAgreesWithTheAxisResidual) {
  const TwistedFace face;
  const FlankCutter cutter(flank_ball(5, 80), 5);
  std::vector<FlankAxis> axes;
  ToolPass pass;
  for (int j = 0; j <= 200; ++j) {
    axes.push_back(flank_axis(face, j / 200.0, nullptr, cutter));
    pass.push_back(axes.back().pose);
  }
  const FlankResidual r = flank_residual(face, axes, cutter, 41);
  UndercutOptions o;
  o.samples_u = 41;
  o.samples_v = 201;
  o.u0 = 0.1;
  o.u1 = 0.9;
  o.v0 = 0.2;
  o.v1 = 0.8;
  o.search_above_mm = 0.5;
  o.search_below_mm = 0.5;
  o.sweep_step_mm = 0.02;
  const UndercutResult sim = simulate_undercut(face, cutter.tool(), {pass}, o);
  EXPECT_EQ(sim.untouched, 0);
  // Deepest residual over the axes inside the same window.
  double deepest = 0;
  for (int a = 0; a < r.axes; ++a) {
    if (axes[a].v < 0.2 || axes[a].v > 0.8) continue;
    for (int k = 0; k < r.points; ++k) deepest = std::min(deepest, r.at(a, k));
  }
  EXPECT_LT(deepest, -0.01);
  EXPECT_NEAR(sim.overcut_mm, deepest, 0.05 * std::abs(deepest)) << "sim " << sim.overcut_mm << " axes " << deepest;
}

}  // namespace
}  // namespace bliskrun

namespace bliskrun {
namespace {

// Balancing each axis on the twisted face turns the concave overcut into a
// band centred on zero: the largest error halves (before/after reported).
TEST(FlankMilling, BalancedAxesHalveTheResidualOnATwistedFace) {
  const TwistedFace face;
  const FlankCutter cutter(flank_ball(5, 80), 5);
  FlankFaceRequest rq;
  rq.face = &face;
  rq.cutter = &cutter;
  rq.steps.chord_tol_mm = 0.05;
  rq.residual_points = 21;
  rq.balance_residual = true;
  rq.optimise = false;  // the balancing alone (the fit: FlankAxisFit.BeatsTheTwoContact...)
  const FlankFacePlan plan = plan_flank_face(rq);
  ASSERT_GT(plan.axes.size(), 3u);
  EXPECT_EQ(plan.balanced, static_cast<int>(plan.axes.size()));
  const ResidualStats& before = plan.residual_unbalanced;
  const ResidualStats& after = plan.residual.stats;
  EXPECT_LT(before.max_mm, 1e-6);  // concave overcut only
  EXPECT_LT(before.min_mm, -0.01);
  EXPECT_LT(after.max_abs_mm, 0.55 * before.max_abs_mm);
  EXPECT_GT(after.max_mm, 0.4 * after.max_abs_mm);  // undercut at the ends, overcut mid-ruling
  EXPECT_LT(after.min_mm, -0.4 * after.max_abs_mm);
}

}  // namespace
}  // namespace bliskrun

namespace bliskrun {
namespace {

// Issue 40 item 0: the axis fit (optimise_flank_axis).

// The wall of a hole of radius R (a concave cylinder, normal towards the
// axis): exactly developable, so a ball end's side (a cylinder of radius r)
// fits it along a whole ruling, its axis parallel to Z at R - r from it.
class HoleWall : public Surface {
 public:
  SurfaceDerivs eval(double u, double v) const override {
    const double t = 0.8 * v, dt = 0.8;
    SurfaceDerivs d;
    d.p = Vec3(R * std::cos(t), R * std::sin(t), 30 * u);
    d.pu = Vec3(0, 0, 30);
    d.pv = Vec3(-R * std::sin(t) * dt, R * std::cos(t) * dt, 0);
    d.pvv = Vec3(-R * std::cos(t) * dt * dt, -R * std::sin(t) * dt * dt, 0);
    return d;
  }
  double R = 40;
};

// The start axis turned by `angle` about `about` through the ball centre
// and moved by `shift`: a wrong start for the fit.
FlankAxis disturbed(const FlankAxis& ax, const Vec3& about, double angle, const Vec3& shift, double r) {
  FlankAxis d = ax;
  const Eigen::AngleAxisd turn(angle, about.normalized());
  d.ball_centre += shift;
  d.pose.axis = (turn * ax.pose.axis).normalized();
  d.pose.tip = d.ball_centre - r * d.pose.axis;
  d.d1 = d.ball_centre + turn * (ax.d1 - ax.ball_centre);
  d.d2 = d.ball_centre + turn * (ax.d2 - ax.ball_centre);
  return d;
}

TEST(FlankAxisFit, FindsTheExactAxisOfACylinderOnAHoleWall) {
  const HoleWall wall;
  const double r = 5;
  const FlankCutter cutter(flank_ball(r, 60), r);
  FlankFitOptions o;
  for (double v : {0.2, 0.7}) {
    const FlankAxis exact = flank_axis(wall, v, nullptr, cutter);
    // The two-contact axis is exact here (closed form: parallel to Z, R - r
    // from it), and the fit leaves it alone.
    EXPECT_NEAR(Vec2(exact.ball_centre.x(), exact.ball_centre.y()).norm(), wall.R - r, 1e-9);
    EXPECT_NEAR(std::abs(exact.pose.axis.z()), 1.0, 1e-12);
    const FlankAxisFit same = optimise_flank_axis(wall, exact, nullptr, cutter, o);
    EXPECT_FALSE(same.improved);
    EXPECT_LT(same.after.max_abs_mm, 1e-9);
    // From a start 0.3 deg and 0.05 mm off, the fit comes back to the
    // closed form: residual ~0, the axis parallel to Z at R - r.
    const FlankAxis wrong = disturbed(exact, Vec3(1, 1, 0), deg_to_rad(0.3), Vec3(0.03, -0.04, 0), r);
    const FlankAxisFit fit = optimise_flank_axis(wall, wrong, nullptr, cutter, o);
    EXPECT_GT(wrong.pose.axis.dot(Vec3::UnitZ()), 0);
    EXPECT_GT(fit.before.max_abs_mm, 0.03);
    ASSERT_TRUE(fit.improved);
    EXPECT_LT(fit.after.max_abs_mm, 1e-5);
    EXPECT_NEAR(fit.axis.pose.axis.z(), 1.0, 1e-8);
    const Vec3 c = fit.axis.ball_centre;
    EXPECT_NEAR(Vec2(c.x(), c.y()).norm(), wall.R - r, 1e-5);
    EXPECT_NEAR(fit.correction_rad, deg_to_rad(0.3), 1e-6);
    std::printf("hole wall v = %.1f: residual %.2e -> %.2e mm in %d evaluations\n", v, fit.before.max_abs_mm,
                fit.after.max_abs_mm, fit.evaluations);
  }
}

// On the hyperbolic paraboloid the two-contact axis's error is the concave
// overcut measured (against brute force) in TwistedRuledFaceIsOvercut...;
// balancing halves it; the fit does better than both, within its bound on
// the turn.
TEST(FlankAxisFit, BeatsTheTwoContactAndBalancedAxesOnATwistedFace) {
  const TwistedFace face;
  const FlankCutter cutter(flank_ball(5, 80), 5);
  const ToolBody body(cutter.tool());
  FlankFaceRequest rq;
  rq.face = &face;
  rq.cutter = &cutter;
  rq.steps.chord_tol_mm = 0.05;
  rq.residual_points = 21;
  rq.optimise = false;
  const FlankFacePlan paper = plan_flank_face(rq);
  rq.balance_residual = true;
  const FlankFacePlan balanced = plan_flank_face(rq);
  rq.balance_residual = false;
  rq.optimise = true;
  const FlankFacePlan fitted = plan_flank_face(rq);
  ASSERT_EQ(fitted.axes.size(), paper.axes.size());
  EXPECT_GT(fitted.optimised, static_cast<int>(fitted.axes.size()) / 2);
  // The "before" of the fitted plan is the paper's plan.
  EXPECT_EQ(fitted.residual_before.max_abs_mm, paper.residual.stats.max_abs_mm);
  EXPECT_EQ(fitted.residual_before.min_mm, paper.residual.stats.min_mm);
  const double two_contact = paper.residual.stats.max_abs_mm, centred = balanced.residual.stats.max_abs_mm;
  const double after = fitted.residual.stats.max_abs_mm;
  EXPECT_LT(after, 0.8 * centred);
  EXPECT_LT(after, 0.4 * two_contact);
  // Never worse, pose by pose; and the turn bound.
  for (size_t i = 0; i < fitted.axes.size(); ++i) {
    EXPECT_LE(fitted.correction_rad[i], rq.fit.max_axis_correction_rad + 1e-12) << i;
    if (i == 0) continue;
    auto angle = [](const Vec3& a, const Vec3& b) { return std::acos(std::clamp(a.dot(b), -1.0, 1.0)); };
    EXPECT_LE(angle(fitted.axes[i].pose.axis, fitted.axes[i - 1].pose.axis),
              angle(paper.axes[i].pose.axis, paper.axes[i - 1].pose.axis) + 2 * rq.fit.max_axis_correction_rad + 1e-12)
        << i;
  }
  std::printf("twisted face: two-contact %.4f, balanced %.4f, fitted %.4f mm (max |residual|)\n", two_contact,
              centred, after);
}

// The stated bias: with overcut counted twice the fit trades overcut for
// material left — less overcut than the centred fit, and its own weighted
// band max(left, 2 overcut) no wider than the centred fit's.
TEST(FlankAxisFit, OvercutWeightLeansTheBandTowardsMaterialLeft) {
  const TwistedFace face;
  const FlankCutter cutter(flank_ball(5, 80), 5);
  FlankFaceRequest rq;
  rq.face = &face;
  rq.cutter = &cutter;
  rq.steps.chord_tol_mm = 0.2;
  rq.residual_points = 21;
  const FlankFacePlan centred = plan_flank_face(rq);
  rq.fit.overcut_weight = 2;
  const FlankFacePlan leaning = plan_flank_face(rq);
  const ResidualStats& c = centred.residual.stats;
  const ResidualStats& l = leaning.residual.stats;
  EXPECT_GT(l.min_mm, c.min_mm + 1e-4);  // less overcut
  EXPECT_GT(l.max_mm, c.max_mm);         // paid for by material left
  EXPECT_LE(std::max(l.max_mm, -2 * l.min_mm), std::max(c.max_mm, -2 * c.min_mm) + 1e-6);
  std::printf("twisted face, overcut weight 1 / 2: %+.4f / %+.4f vs %+.4f / %+.4f mm\n", c.max_mm, c.min_mm, l.max_mm,
              l.min_mm);
}

// The default (optimise = true) never worsens the largest residual: the
// built-in impeller's four faces (a tapered ball end riding the hub), the
// fitted plan against optimise = false, pose by pose and per face; every
// fitted ball centre still on the hub offset; neighbouring axes turn at most
// twice the correction bound more than the unfitted ones.
TEST(FlankAxisFit, NeverWorsensTheBuiltInImpellerFacesAndKeepsTheBallOnTheHub) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "four faces fitted pose by pose: seconds under the sanitizers";
#endif
  const Impeller imp(builtin_impeller_definition());
  const FlankCutter cutter(tapered(3, 2, 90), 3);
  for (BladeKind kind : {BladeKind::kMain, BladeKind::kSplitter}) {
    for (CamberSide side : {CamberSide::kPlus, CamberSide::kMinus}) {
      const auto face = imp.face(kind, 0, side);
      FlankFaceRequest rq;
      rq.face = face.get();
      rq.hub = &imp.hub();
      rq.cutter = &cutter;
      rq.steps.chord_tol_mm = 1;  // ~10 poses a face: the test's cost is the fit's
      rq.steps.max_step_mm = 40;
      rq.residual_points = 12;
      rq.balance_residual = true;
      rq.optimise = false;
      const FlankFacePlan off = plan_flank_face(rq);
      rq.optimise = true;
      const FlankFacePlan on = plan_flank_face(rq);
      ASSERT_EQ(on.axes.size(), off.axes.size());
      EXPECT_GT(on.optimised, 0);
      EXPECT_EQ(on.residual_before.max_abs_mm, off.residual.stats.max_abs_mm);
      EXPECT_LE(on.residual.stats.max_abs_mm, off.residual.stats.max_abs_mm);
      const FlankResidual& a = on.residual;
      const FlankResidual& b = off.residual;
      for (int i = 0; i < a.axes; ++i) {
        double ma = 0, mb = 0;
        for (int k = 0; k < a.points; ++k) {
          ma = std::max(ma, std::abs(a.at(i, k)));
          mb = std::max(mb, std::abs(b.at(i, k)));
        }
        EXPECT_LE(ma, mb) << i;
        EXPECT_NEAR(imp.hub().radial_offset(on.axes[i].ball_centre), 3.0, 1e-7) << i;
        if (i > 0) {
          auto angle = [](const Vec3& x, const Vec3& y) { return std::acos(std::clamp(x.dot(y), -1.0, 1.0)); };
          EXPECT_LE(angle(on.axes[i].pose.axis, on.axes[i - 1].pose.axis),
                    angle(off.axes[i].pose.axis, off.axes[i - 1].pose.axis) + 2 * rq.fit.max_axis_correction_rad + 1e-12);
        }
      }
      std::printf("built-in %s %s: max |residual| %.4f -> %.4f mm (%d of %zu poses fitted)\n",
                  kind == BladeKind::kMain ? "main" : "splitter", side == CamberSide::kPlus ? "plus" : "minus",
                  off.residual.stats.max_abs_mm, on.residual.stats.max_abs_mm, on.optimised, on.axes.size());
    }
  }
}

}  // namespace
}  // namespace bliskrun
