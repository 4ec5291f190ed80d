#include "core/sim/undercut.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "core/collision/tilt.h"
#include "core/common/error.h"
#include "test_support.h"

namespace bliskrun {
namespace {

// The plane z = 0 over [-10, 10] x [-5, 5], normal +Z (material below).
class UndercutPlane : public Surface {
 public:
  SurfaceDerivs eval(double u, double v) const override {
    SurfaceDerivs d;
    d.p = Vec3(20 * u - 10, 10 * v - 5, 0);
    d.pu = Vec3(20, 0, 0);
    d.pv = Vec3(0, 10, 0);
    return d;
  }
};

Tool undercut_ball(double radius) {
  BallEndMillSpec spec;
  spec.radius_mm = radius;
  spec.flute_length_mm = 2 * radius;
  spec.shank = {2 * radius, 30};
  return Tool::ball_end_mill(spec);
}

ToolPose pose_at(double x, double y, double z) { return {Vec3(x, y, z), Vec3::UnitZ()}; }

UndercutOptions plane_options() {
  UndercutOptions o;
  o.samples_u = 41;   // x every 0.5 mm
  o.samples_v = 101;  // y every 0.1 mm
  o.search_above_mm = 1.0;
  return o;
}

TEST(Undercut, TwoBallPassesLeaveTheAnalyticScallop) {
  const double r = 5, w = 2;
  const std::vector<ToolPass> passes = {{pose_at(-12, -w / 2, 0), pose_at(12, -w / 2, 0)},
                                        {pose_at(-12, w / 2, 0), pose_at(12, w / 2, 0)}};
  const UndercutOptions o = plane_options();
  const UndercutResult res = simulate_undercut(UndercutPlane(), undercut_ball(r), passes, o);
  ASSERT_EQ(res.residual_mm.size(), static_cast<size_t>(41 * 101));
  for (int i = 0; i < o.samples_u; ++i) {
    for (int j = 0; j < o.samples_v; ++j) {
      const double y = -5 + 10.0 * j / (o.samples_v - 1);
      // The lowest point of either ball over (x, y): r - sqrt(r^2 - dy^2),
      // untouched where both are farther than the search range.
      double expected = std::numeric_limits<double>::infinity();
      for (double yk : {-w / 2, w / 2}) {
        const double dy = std::abs(y - yk);
        if (dy < r) {
          const double h = r - std::sqrt(r * r - dy * dy);
          if (h <= o.search_above_mm) expected = std::min(expected, h);
        }
      }
      const double got = res.residual_mm[static_cast<size_t>(i) * o.samples_v + j];
      if (std::isinf(expected)) {
        EXPECT_TRUE(std::isinf(got) || got > o.search_above_mm - 1e-3) << "y=" << y;
      } else {
        EXPECT_NEAR(got, expected, 2e-5) << "x index " << i << " y=" << y;
      }
    }
  }
  // The scallop between the passes: r - sqrt(r^2 - (w/2)^2).
  EXPECT_NEAR(res.residual_mm[20 * 101 + 50], r - std::sqrt(r * r - 1), 2e-5);
  EXPECT_EQ(res.overcut_mm, 0.0);
}

// A drum wheel (barrel radius R_c, max diameter D_t, head L_c) rolled along
// x over the plane with its axis along y, one straight pass (two poses, so
// everything between them is the sweep): the material left at lateral
// offset y from the wheel's mid-plane is the barrel's drop there,
// R_c - sqrt(R_c^2 - y^2), within the head, and untouched beyond.
TEST(Undercut, DrumWheelStraightPassLeavesTheBarrelProfile) {
  const double dt = 8, rc = 20, lc = 4;
  const Tool wheel = Tool::drum_wheel({dt, rc, lc, {6, 30}, {}});
  // Tool frame: tip at the bottom centre, axis +z. Axis along +y in the part
  // frame, the wheel's widest circle touching z = 0 at y = 0.
  auto pose = [&](double x) { return ToolPose{Vec3(x, -lc / 2, dt / 2), Vec3::UnitY()}; };
  UndercutOptions o = plane_options();
  o.samples_v = 201;  // y every 0.05 mm
  const UndercutResult res = simulate_undercut(UndercutPlane(), wheel, {{pose(-14), pose(14)}}, o);
  int checked = 0;
  for (int i = 0; i < o.samples_u; ++i)
    for (int j = 0; j < o.samples_v; ++j) {
      const double y = -5 + 10.0 * j / (o.samples_v - 1);
      const double got = res.residual_mm[static_cast<size_t>(i) * o.samples_v + j];
      if (std::abs(y) < lc / 2 - 1e-9) {
        EXPECT_NEAR(got, rc - std::sqrt(rc * rc - y * y), 2e-5) << "y=" << y;
        ++checked;
      } else if (std::abs(y) > lc / 2 + 1e-9) {
        EXPECT_TRUE(std::isinf(got)) << "y=" << y << " got " << got;
      }
    }
  EXPECT_EQ(checked, o.samples_u * 79);
  EXPECT_GE(res.overcut_mm, -1e-9);
  // The largest drop is at the head's edges, y = ±L_c/2.
  EXPECT_NEAR(res.undercut_max_mm, rc - std::sqrt(rc * rc - lc * lc / 4), 2e-5);
}

TEST(Undercut, MotionBetweenPosesIsSwept) {
  // Two poses 20 mm apart: every sample on the line between them is cut to
  // zero, which a pose-only check would miss (the ball touches only two spots).
  const std::vector<ToolPass> passes = {{pose_at(-10, 0, 0), pose_at(10, 0, 0)}};
  const UndercutResult res = simulate_undercut(UndercutPlane(), undercut_ball(3), passes, plane_options());
  for (int i = 0; i < 41; ++i) EXPECT_NEAR(res.residual_mm[i * 101 + 50], 0.0, 2e-5) << i;
}

// Two tools in turn (a rougher, then a finisher): the material left is the
// lower of the two balls' profiles at every sample, and the overcut is found
// in the second run's pass, numbered after the first run's.
TEST(Undercut, SeveralToolsLeaveTheLowerOfTheirProfiles) {
  const Tool big = undercut_ball(5), small = undercut_ball(2);
  const std::vector<ToolPass> rough = {{pose_at(-12, -1, 0.2), pose_at(12, -1, 0.2)}, {pose_at(-12, 3, 0.2), pose_at(12, 3, 0.2)}};
  const std::vector<ToolPass> finish = {{pose_at(-12, 1, -0.01), pose_at(12, 1, -0.01)}};
  const UndercutOptions o = plane_options();
  const UndercutResult res = simulate_undercut(UndercutPlane(), {ToolRun{&big, &rough}, ToolRun{&small, &finish}}, o);
  for (int j = 0; j < o.samples_v; ++j) {
    const double y = -5 + 10.0 * j / (o.samples_v - 1);
    double expected = std::numeric_limits<double>::infinity();
    for (double yk : {-1.0, 3.0})
      if (std::abs(y - yk) < 5) expected = std::min(expected, 0.2 + 5 - std::sqrt(25 - (y - yk) * (y - yk)));
    if (std::abs(y - 1) < 2) expected = std::min(expected, -0.01 + 2 - std::sqrt(4 - (y - 1) * (y - 1)));
    if (expected > o.search_above_mm) continue;
    EXPECT_NEAR(res.residual_mm[20 * 101 + j], expected, 2e-5) << "y=" << y;
  }
  EXPECT_NEAR(res.overcut_mm, -0.01, 2e-5);
  EXPECT_EQ(res.overcut_pass, 2);  // the finisher's pass, after the rougher's two
  // One run of the same passes gives what the single-tool call gives.
  const UndercutResult one = simulate_undercut(UndercutPlane(), {ToolRun{&big, &rough}}, o);
  const UndercutResult same = simulate_undercut(UndercutPlane(), big, rough, o);
  EXPECT_EQ(one.residual_mm, same.residual_mm);
}

TEST(Undercut, GougeIsNegative) {
  const std::vector<ToolPass> passes = {{pose_at(-12, 0, -0.03), pose_at(12, 0, -0.03)}};
  const UndercutResult res = simulate_undercut(UndercutPlane(), undercut_ball(4), passes, plane_options());
  EXPECT_NEAR(res.overcut_mm, -0.03, 2e-5);
  EXPECT_NEAR(res.residual_mm[20 * 101 + 50], -0.03, 2e-5);
}

TEST(Undercut, StatisticsMatchTheResidualMap) {
  const std::vector<ToolPass> passes = {{pose_at(-12, -1, 0), pose_at(12, -1, 0)}, {pose_at(-12, 1, 0), pose_at(12, 1, 0)}};
  const UndercutResult res = simulate_undercut(UndercutPlane(), undercut_ball(5), passes, plane_options());
  std::vector<double> u;
  for (double x : res.residual_mm)
    if (std::isfinite(x)) u.push_back(std::max(0.0, x));
  ASSERT_FALSE(u.empty());
  double mean = 0;
  for (double x : u) mean += x;
  mean /= u.size();
  EXPECT_NEAR(res.undercut_mean_mm, mean, 1e-12);
  EXPECT_DOUBLE_EQ(res.undercut_max_mm, *std::max_element(u.begin(), u.end()));
  EXPECT_EQ(res.untouched + static_cast<int>(u.size()), 41 * 101);
}

TEST(Undercut, SameResultForAnyThreadCount) {
  const std::vector<ToolPass> passes = {{pose_at(-12, -1, 0), pose_at(0, -1.2, 0.01), pose_at(12, -1, 0)},
                                        {pose_at(-12, 1, 0), pose_at(12, 1.3, 0)}};
  UndercutOptions one = plane_options(), two = plane_options();
  one.threads = 1;
  two.threads = 2;
  const UndercutResult a = simulate_undercut(UndercutPlane(), undercut_ball(5), passes, one);
  const UndercutResult b = simulate_undercut(UndercutPlane(), undercut_ball(5), passes, two);
  ASSERT_EQ(a.residual_mm.size(), b.residual_mm.size());
  for (size_t i = 0; i < a.residual_mm.size(); ++i)
    ASSERT_EQ(std::memcmp(&a.residual_mm[i], &b.residual_mm[i], sizeof(double)), 0) << i;
}

// settled_mm: a sample left at or below it is traced no more. Where more
// is left the map is the same to the bit; where less, it still reads at
// most settled_mm (the later, deeper cuts are not traced); and fewer lines
// are traced. Three overlapping passes of a ball, scallops 0.1 mm apart.
TEST(Undercut, SettledSamplesAreTracedNoMoreAndTheRestIsUnchanged) {
  std::vector<ToolPass> passes;
  for (double y : {-0.1, 0.0, 0.1}) passes.push_back({pose_at(-12, y, 0), pose_at(12, y, 0)});
  UndercutOptions all = plane_options(), settled = plane_options();
  settled.settled_mm = 0.002;
  const UndercutResult a = simulate_undercut(UndercutPlane(), undercut_ball(5), passes, all);
  const UndercutResult b = simulate_undercut(UndercutPlane(), undercut_ball(5), passes, settled);
  ASSERT_EQ(a.residual_mm.size(), b.residual_mm.size());
  int above = 0, below = 0;
  for (size_t i = 0; i < a.residual_mm.size(); ++i) {
    if (a.residual_mm[i] > settled.settled_mm) {
      ++above;
      ASSERT_EQ(std::memcmp(&a.residual_mm[i], &b.residual_mm[i], sizeof(double)), 0) << i;
    } else {
      ++below;
      EXPECT_LE(b.residual_mm[i], settled.settled_mm) << i;
      EXPECT_GE(b.residual_mm[i], a.residual_mm[i]) << i;
    }
  }
  EXPECT_GT(above, 100);
  EXPECT_GT(below, 100);
  EXPECT_LT(b.line_evaluations, a.line_evaluations);
}

TEST(Undercut, CostFollowsSamplesNearTheToolNotAllSamples) {
  // Doubling the sampled area away from a short pass (same density) must not
  // double the work: far tiles are pruned by the Lipschitz bound.
  const std::vector<ToolPass> passes = {{pose_at(-9, 0, 0), pose_at(-8, 0, 0)}};
  UndercutOptions near = plane_options(), wide = plane_options();
  wide.samples_u = 81;
  wide.u1 = 2;  // x up to +30 mm
  const UndercutResult a = simulate_undercut(UndercutPlane(), undercut_ball(2), passes, near);
  const UndercutResult b = simulate_undercut(UndercutPlane(), undercut_ball(2), passes, wide);
  EXPECT_EQ(a.tool_positions, b.tool_positions);
  EXPECT_LT(b.line_evaluations, a.line_evaluations * 11 / 10);
  EXPECT_LT(a.line_evaluations, a.tool_positions * 41L * 101L / 4);
}

// A cylinder of radius 20 about X, its top near z = 0 (normal out): a flank
// the flat bottom of an end mill lies over, curving away from it.
class UndercutCylinder : public Surface {
 public:
  SurfaceDerivs eval(double u, double v) const override {
    const double r = 20, x = 16 * u - 8, a = (v - 0.5) * 0.8;
    SurfaceDerivs d;
    d.p = Vec3(x, r * std::sin(a), r * std::cos(a) - r);
    d.pu = Vec3(16, 0, 0);
    d.pv = Vec3(0, 0.8 * r * std::cos(a), -0.8 * r * std::sin(a));
    return d;
  }
};

// The guard prunes tiles of samples whose traces below the surface lie
// wholly under the cutter's lowest plane (a flat bottom over a flank). The
// pruning must never change a verdict: the deepest cut equals a brute-force
// trace of every sample (stepping 0.5 um down its normal), for flat-end
// poses lying on the plane and on the cylinder, level and tilted up to 20
// degrees, just clear and gouging by a few um at the bottom's centre or at
// its corner.
TEST(Undercut, GuardPruningBelowTheBottomAgreesWithTracingEverySample) {
  const Tool mill = test::flat_end_mill(3, 0.5, 9, 30);
  const Profile& cutter = mill.cutter();
  const UndercutPlane plane;
  const UndercutCylinder cylinder;
  int compared = 0, cut = 0;
  for (const Surface* surface : {static_cast<const Surface*>(&plane), static_cast<const Surface*>(&cylinder)}) {
    UndercutOptions o = guard_sampling(*surface, 0.1, 0.3, 0.7, 0.2, 0.8);
    const GougeGuard guard(*surface, o);
    for (double tilt_deg : {0.0, 5.0, 20.0}) {
      for (double gap_mm : {0.004, -0.002, -0.02}) {
        // The axis tilted about X, the tool touching the tangent plane
        // z = 0 at (0.3, 0, 0) (the top of both surfaces), then gap_mm above it.
        const double t = tilt_deg * kPi / 180;
        const Vec3 axis(0, std::sin(t), std::cos(t));
        ToolPose pose = place_tool(mill, {Vec3(0.3, 0, 0), Vec3::UnitX(), Vec3::UnitZ()}, axis);
        pose.tip.z() += gap_mm;
        const Eigen::Isometry3d to = tool_to_part(pose).inverse();
        const double allowed = 0.001;
        const GougeGuard::Cut c = guard.deepest_cut(mill, pose, pose, allowed, true, true);
        double brute = 0;
        for (int i = 0; i < o.samples_u; ++i)
          for (int j = 0; j < o.samples_v; ++j) {
            const SurfaceDerivs d = surface->eval(o.u0 + (o.u1 - o.u0) * i / (o.samples_u - 1),
                                                  o.v0 + (o.v1 - o.v0) * j / (o.samples_v - 1));
            const Vec3 n = d.pu.cross(d.pv).normalized();
            for (double s = -o.search_below_mm; s <= -allowed; s += 5e-4)
              if (cutter.signed_distance(to * Vec3(d.p + s * n)) <= 0) {
                brute = std::min(brute, s);
                break;
              }
          }
        ++compared;
        cut += brute < 0 ? 1 : 0;
        EXPECT_NEAR(c.depth_mm, brute, 6e-4) << "tilt " << tilt_deg << " gap " << gap_mm;
        EXPECT_EQ(c.depth_mm < 0, brute < 0) << "tilt " << tilt_deg << " gap " << gap_mm;
      }
    }
  }
  EXPECT_EQ(compared, 18);
  EXPECT_EQ(cut, 12);  // every pose 2 or 20 um in is seen gouging  // the gouging poses are seen as gouging
}

// A flat end rocking its axis ±30 deg along the feed, its corner on the
// plane: sweeping only the motion of the points near the tip (the corner's
// reach, sweep_reach_mm) evaluates fewer positions — the flute's top, 9.5
// mm up, moved three times as far — and reads no less material than the
// sweep leaves (a sweep 0.005 mm a step stands for it: within 0.1 um),
// at most the scallop a step of the corner leaves between positions more
// (step^2 / (8 r), 2.5 um at 0.1 mm, r 0.5). The positions are not a
// subset of the whole cutter's: against those it may read either way.
TEST(Undercut, SweepingTheToolsEndReadsNoLessMaterialThanTheSweepLeaves) {
  const double R = 3, r = 0.5;
  const Tool mill = test::flat_end_mill(R, r, 9, 30);
  ToolPass pass;
  for (int k = 0; k <= 16; ++k) {
    const double a = deg_to_rad(k % 2 ? 30.0 : -30.0);
    const double lift = r + (R - r) * std::sin(std::abs(a)) - r * std::cos(a);  // the corner's lowest point on z = 0
    pass.push_back({Vec3(-8 + k, 0, lift), Vec3(std::sin(a), 0, std::cos(a))});
  }
  UndercutOptions o = plane_options();
  o.sweep_step_mm = 0.005;
  const UndercutResult swept = simulate_undercut(UndercutPlane(), mill, {pass}, o);
  o.sweep_step_mm = 0.1;
  const UndercutResult whole = simulate_undercut(UndercutPlane(), mill, {pass}, o);
  o.sweep_reach_mm = std::hypot(R, 2 * r);
  const UndercutResult near = simulate_undercut(UndercutPlane(), mill, {pass}, o);
  EXPECT_LT(2 * near.tool_positions, whole.tool_positions);
  int cut = 0;
  double most = 0;
  for (size_t i = 0; i < swept.residual_mm.size(); ++i) {
    if (!std::isfinite(swept.residual_mm[i])) {
      EXPECT_FALSE(std::isfinite(near.residual_mm[i])) << i;
      continue;
    }
    ++cut;
    EXPECT_GE(near.residual_mm[i], swept.residual_mm[i] - 1e-4) << i;
    most = std::max(most, near.residual_mm[i] - swept.residual_mm[i]);
  }
  EXPECT_GT(cut, 200);
  EXPECT_LE(most, 0.1 * 0.1 / (8 * r) + 1e-4);
}

TEST(Undercut, RejectsBadOptions) {
  UndercutOptions o = plane_options();
  o.samples_u = 1;
  EXPECT_THROW(simulate_undercut(UndercutPlane(), undercut_ball(2), {}, o), ParameterError);
  o = plane_options();
  o.sweep_reach_mm = -1;
  EXPECT_THROW(simulate_undercut(UndercutPlane(), undercut_ball(2), {}, o), ParameterError);
}

}  // namespace
}  // namespace bliskrun
