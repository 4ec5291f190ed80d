// Links between cutting passes (issue 11): how a side-cutting drum wheel
// leaves a concave flank. Retracting along its axis - nearly tangent to the
// flank - drags the barrel into the finished surface by the closed form
// below; leaving along the normal does not, and the gouge guard sees both.
#include "core/planning/links.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "collision/test_meshes.h"
#include "core/collision/tilt.h"
#include "core/common/error.h"
#include "core/sim/undercut.h"
#include "test_support.h"

namespace bliskrun {
namespace {

// A concave cylinder of radius kRho about the x axis, material outside it:
// v runs along x (the chord), u around the circle (the span), so the span
// direction is curved with radius kRho and the normal out of the material
// points to the axis.
constexpr double kRho = 100, kL = 20, kPhi = 0.15;

class ConcaveCylinder : public Surface {
 public:
  SurfaceDerivs eval(double u, double v) const override {
    const double phi = -kPhi + 2 * kPhi * u, dphi = 2 * kPhi;
    SurfaceDerivs d;
    d.p = Vec3(kL * (v - 0.5), kRho * std::sin(phi), -kRho * std::cos(phi));
    d.pu = Vec3(0, kRho * std::cos(phi), kRho * std::sin(phi)) * dphi;
    d.pv = Vec3(kL, 0, 0);
    d.puu = Vec3(0, -kRho * std::sin(phi), kRho * std::cos(phi)) * dphi * dphi;
    return d;
  }
};

// Drum wheel 2 of the blisk paper: D_t 8, R_c 50, L_c 4.
constexpr double kRc = 50;
Tool link_wheel() { return Tool::drum_wheel({8, kRc, 4, {6, 96}, {}}); }

UndercutOptions sampling() {
  UndercutOptions o;
  o.samples_u = 301;  // 0.1 mm along the 30 mm span
  o.samples_v = 201;  // 0.1 mm along the 20 mm chord
  o.flip_normal = true;  // pu x pv points away from the axis, into the material
  o.sweep_step_mm = 0.01;
  o.search_below_mm = 0.5;
  return o;
}

// The wheel touching the flank at (u, 0.5) with its axis along the span
// (the drum-finish axis at lead 0), as the planner places it.
LinkEnd contact_end(const Tool& tool, double u) {
  const SurfaceDerivs d = ConcaveCylinder().eval(u, 0.5);
  ContactFrame f;
  f.point = d.p;
  f.normal = -d.pu.cross(d.pv).normalized();
  f.tangent = d.pv.normalized();
  const Vec3 axis = d.pu.normalized();
  return {place_tool(tool, f, axis), f.normal};
}

// The old link rule: straight up the axis by s. The barrel's meridian (radius
// R_c) slides along the concave span (radius rho): at axial offset z from the
// contact it sits z^2 / (2 R_c) above the tangent line and meets the flank
// z' = s + z along it, s'^2 / (2 rho) above; the deepest cut,
// max_z (s + z)^2 / (2 rho) - z^2 / (2 R_c) = s^2 / (2 (rho - R_c)) at
// z = s R_c / (rho - R_c), on the head while that is within L_c / 2. Even the
// contact point alone (z = 0) enters by s^2 / (2 rho).
TEST(Links, AxisRetractOnAConcaveFlankCutsInByTheClosedForm) {
  const Tool tool = link_wheel();
  const ConcaveCylinder flank;
  const GougeGuard guard(flank, sampling());
  const LinkEnd a = contact_end(tool, 0.5);
  for (double s : {0.5, 1.0, 1.5}) {
    SCOPED_TRACE(s);
    ToolPose up = a.pose;
    up.tip += s * a.pose.axis;
    const GougeGuard::Cut cut = guard.deepest_cut(tool, a.pose, up, 0, false, true);
    const double closed_form = s * s / (2 * (kRho - kRc));
    EXPECT_NEAR(-cut.depth_mm, closed_form, 0.01 * closed_form + guard.between_samples_mm(4));
    EXPECT_GT(-cut.depth_mm, s * s / (2 * kRho));
    // The simulation of the same motion as a pass finds the same gouge.
    UndercutOptions o = sampling();
    o.threads = 1;
    const UndercutResult sim = simulate_undercut(flank, tool, {{a.pose, up}}, o);
    EXPECT_NEAR(sim.overcut_mm, cut.depth_mm, 1e-4);
    EXPECT_EQ(sim.overcut_pass, 0);
  }
}

TEST(Links, NormalRetractLeavesTheConcaveFlankAndTheAxisRuleOnlyWhereItCutsWithinTheAllowance) {
  const Tool tool = link_wheel();
  const ConcaveCylinder flank;
  const GougeGuard guard(flank, sampling());
  const CollisionWorld nothing;
  const ToolBody body(tool, 0.02);
  LinkChecks checks;
  checks.world = &nothing;
  checks.body = &body;
  checks.guard = &guard;
  checks.guard_margin_mm = guard.between_samples_mm(4);
  // Two neighbouring rows, 2.4 mm apart along the span (a drum-finish row
  // spacing), linked at the same end.
  const LinkEnd a = contact_end(tool, 0.5), b = contact_end(tool, 0.5 + 2.4 / (2 * kPhi * kRho));
  LinkOptions o;
  o.allowed_overcut_mm = 0.002;
  const PlannedLink normal = plan_link(a, b, checks, o);
  ASSERT_TRUE(normal.clear) << normal.reason;
  EXPECT_EQ(normal.offset_mm, o.retract_mm);
  EXPECT_GE(normal.deepest_cut_mm, -o.allowed_overcut_mm);
  ASSERT_EQ(normal.via.size(), 2u);
  EXPECT_NEAR((normal.via[0].tip - a.pose.tip).dot(a.normal), o.retract_mm, 1e-9);
  EXPECT_EQ(normal.legs.size(), 3u);
  EXPECT_EQ(normal.legs.back(), LinkLeg::Approach);
  // The old rule, now proved against the flank: it is accepted only at an
  // offset s whose cut s^2 / (2 (rho - R_c)) stays within the allowance.
  o.direction = RetractDirection::ToolAxis;
  const PlannedLink axis = plan_link(a, b, checks, o);
  const double s_max = std::sqrt(2 * (kRho - kRc) * o.allowed_overcut_mm);  // 0.45 mm
  if (axis.clear) {
    EXPECT_LE(axis.offset_mm, s_max);
    EXPECT_GE(axis.deepest_cut_mm, -o.allowed_overcut_mm);
  }
  // Unchecked against the flank it would have gone the full 5 mm.
  checks.guard = nullptr;
  const PlannedLink blind = plan_link(a, b, checks, o);
  ASSERT_TRUE(blind.clear);
  EXPECT_EQ(blind.offset_mm, o.retract_mm);
  const GougeGuard::Cut old_cut = guard.deepest_cut(tool, a.pose, blind.via[0], 0, false, true);
  EXPECT_LT(old_cut.depth_mm, -0.05);  // tens of um into the finished flank
}

// The world leaves the blade being machined to the gouge guards for the
// cutter, and the guards sample only near the pass: a traverse beyond
// them was proved by nothing (a route up the span on Rotor 67's TE cut
// 0.1 mm into a flank, found only by the recipe's simulation). With the
// left-out pairs as the traverse's world, a traverse whose cutter runs
// through a ridge of the own blade is refused; the shank, above the
// ridge, passes either way.
// A flat end's links: up its axis by retract_mm.
LinkOptions up_the_axis(double retract_mm) {
  LinkOptions o;
  o.direction = RetractDirection::ToolAxis;
  o.retract_mm = retract_mm;
  return o;
}

TEST(Links, ATraverseIsProvedAgainstTheOwnBladeForTheCutter) {
  const Tool tool = test::flat_end_mill(3, 0.5, 9, 20);
  const ToolBody body(tool, 1e-3);
  CollisionWorld world;
  CheckSurfaceOptions own;
  own.parts.cutter = false;
  world.add("own blade", test::grid_mesh(Vec3(-50, -50, 0), Vec3(100, 0, 0), Vec3(0, 100, 0), 4, 4), own);
  world.add("own blade ridge", test::box_mesh(Vec3(9, -20, -1), Vec3(11, 20, 5)), own);  // 5 mm high
  LinkChecks checks;
  checks.world = &world;
  checks.body = &body;
  LinkOptions o = up_the_axis(3);
  o.min_retract_mm = 0.5;
  const LinkEnd a{{Vec3(0, 0, 0), Vec3::UnitZ()}, Vec3::UnitZ()};
  const LinkEnd b{{Vec3(20, 0, 0), Vec3::UnitZ()}, Vec3::UnitZ()};
  EXPECT_TRUE(plan_link(a, b, checks, o).clear);  // the hole: nothing sees the cutter in the ridge
  checks.traverse_world = world.unchecked_pairs();
  const PlannedLink refused = plan_link(a, b, checks, o);
  EXPECT_FALSE(refused.clear);
  EXPECT_NE(refused.reason.find("traverse not clear"), std::string::npos) << refused.reason;
  EXPECT_NE(refused.reason.find("cutter vs own blade ridge"), std::string::npos) << refused.reason;
  // Over the ridge (a waypoint lifting the tool 8 mm): proved.
  const PlannedLink over = plan_link(a, b, checks, o, {{Vec3(0, 0, 8), Vec3::UnitZ()}, {Vec3(20, 0, 8), Vec3::UnitZ()}});
  EXPECT_TRUE(over.clear) << over.reason;
}

// Stock on a face (CheckSurfaceOptions::stock) is an obstacle for the shank
// and holder only: the cutter cuts it, so it is not one of the pairs the
// traverse world adds back for the cutter (the built-in TE after a
// roughing: a link from its first row, the cutter in the hub's stock as
// every pose there is, refused "cutter vs hub's stock" on every route).
TEST(Links, StockIsNoObstacleForTheCutterEvenOnATraverse) {
  CollisionWorld world;
  CheckSurfaceOptions stock;
  stock.parts.cutter = false;
  stock.margin_mm = 0.5;
  stock.stock = true;
  world.add("hub's stock", test::grid_mesh(Vec3(-50, -50, 0), Vec3(100, 0, 0), Vec3(0, 100, 0), 4, 4), stock);
  EXPECT_TRUE(world.unchecked_pairs() == nullptr);
  CheckSurfaceOptions own;
  own.parts.cutter = false;
  world.add("own blade", test::box_mesh(Vec3(9, -20, -1), Vec3(11, 20, 5)), own);
  const auto left = world.unchecked_pairs();
  ASSERT_TRUE(left != nullptr);
  ASSERT_EQ(left->size(), 1);
  EXPECT_EQ(left->name(0), "own blade");
}

// The least angle off the pole's line along every leg of a link, sampled
// as the machine moves (PoseMotion), with the closed form's.
double least_off_pole(const LinkEnd& a, const PlannedLink& link, const LinkEnd& b, const Vec3& pole) {
  std::vector<ToolPose> chain{a.pose};
  chain.insert(chain.end(), link.via.begin(), link.via.end());
  chain.push_back(b.pose);
  double least = kPi;
  for (size_t s = 0; s + 1 < chain.size(); ++s) {
    const PoseMotion m(chain[s], chain[s + 1]);
    double leg = kPi;
    for (int i = 0; i <= 2000; ++i)
      leg = std::min(leg, std::acos(std::min(1.0, std::abs(m.pose_at(i / 2000.0).axis.normalized().dot(pole)))));
    EXPECT_NEAR(angle_off_pole(chain[s].axis, chain[s + 1].axis, pole), leg, 2e-4) << "leg " << s;
    least = std::min(least, leg);
  }
  return least;
}

// A link between two axes 10 deg either side of the C table's axis: turned
// along the great circle, the axis passes through the pole, where C must
// turn half a revolution at once (the built-in blisk job's trailing edge:
// 0.002 deg off it, refused by the Heidenhain post). With the pole given,
// every leg keeps 1 deg off it: the axis carried round at 2 deg, C turning
// in steps of at most 22.5 deg; the ends are the passes' own.
TEST(Links, ALinkKeepsItsAxisOffTheTablesPole) {
  const Tool tool = test::flat_end_mill(3, 0.5, 9, 20);
  const ToolBody body(tool, 1e-3);
  const CollisionWorld nothing;
  LinkChecks checks;
  checks.world = &nothing;
  checks.body = &body;
  LinkOptions o = up_the_axis(3);
  const double tilt = 10 * kPi / 180;
  const LinkEnd a{{Vec3(0, 0, 0), Vec3(std::sin(tilt), 0, std::cos(tilt))}, Vec3::UnitZ()};
  const LinkEnd b{{Vec3(20, 5, 0), Vec3(-std::sin(tilt), 0, std::cos(tilt))}, Vec3::UnitZ()};
  const Vec3 pole = Vec3::UnitZ();
  const PlannedLink through = plan_link(a, b, checks, o);
  ASSERT_TRUE(through.clear) << through.reason;
  EXPECT_LT(least_off_pole(a, through, b, pole), 1e-6);
  EXPECT_LT(angle_off_pole(a.pose.axis, b.pose.axis, pole), 1e-9);
  o.pole = pole;
  o.pole_clearance_rad = kPi / 180;
  const PlannedLink round = plan_link(a, b, checks, o);
  ASSERT_TRUE(round.clear) << round.reason;
  EXPECT_GE(least_off_pole(a, round, b, pole), o.pole_clearance_rad);
  EXPECT_GT(round.via.size(), through.via.size() + 6);  // half a turn in steps of <= 22.5 deg
  // The table's axis either way along it is the same pole.
  o.pole = -pole;
  EXPECT_GE(least_off_pole(a, plan_link(a, b, checks, o), b, pole), o.pole_clearance_rad);
  // A link that keeps off the pole is left as it was.
  const LinkEnd c{{Vec3(20, 5, 0), Vec3(std::sin(2 * tilt), 0, std::cos(2 * tilt))}, Vec3::UnitZ()};
  EXPECT_EQ(plan_link(a, c, checks, o).via.size(), plan_link(a, c, checks, up_the_axis(3)).via.size());
}

TEST(Links, RejectsBadOptions) {
  const Tool tool = link_wheel();
  const CollisionWorld nothing;
  const ToolBody body(tool, 0.02);
  LinkChecks checks;
  checks.world = &nothing;
  checks.body = &body;
  const LinkEnd a = contact_end(tool, 0.5), b = contact_end(tool, 0.6);
  LinkOptions o;
  o.retract_mm = 0;
  EXPECT_THROW(plan_link(a, b, checks, o), ParameterError);
  o = {};
  o.min_retract_mm = 10;
  EXPECT_THROW(plan_link(a, b, checks, o), ParameterError);
  o = {};
  o.allowed_overcut_mm = -1;
  EXPECT_THROW(plan_link(a, b, checks, o), ParameterError);
  checks.world = nullptr;
  EXPECT_THROW(plan_link(a, b, checks, LinkOptions{}), ParameterError);
}

}  // namespace
}  // namespace bliskrun
