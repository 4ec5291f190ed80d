#include "core/planning/drum_finish.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/common/error.h"
#include "core/geometry/mesh.h"
#include "tests/collision/test_meshes.h"
#include "test_support.h"

namespace bliskrun {
namespace {

using test::grid_mesh;

// Concave cylinder patch of radius R, axis along x at (y = Y0, z = R): the
// chord (v) runs along x, the span (u) around the circle, so the normal
// curvature across the feed is 1/R everywhere. Far from the z axis so the
// hub/casing cylinders about z cut it along nearly iso-u lines.
constexpr double kR = 100, kY0 = 1000, kL = 20, kPhi = 0.3;

class CylinderFlank : public Surface {
 public:
  SurfaceDerivs eval(double u, double v) const override {
    const double phi = -kPhi + 2 * kPhi * u, dphi = 2 * kPhi;
    SurfaceDerivs d;
    d.p = Vec3(kL * (v - 0.5), kY0 + kR * std::sin(phi), kR - kR * std::cos(phi));
    d.pu = Vec3(0, kR * std::cos(phi), kR * std::sin(phi)) * dphi;
    d.pv = Vec3(kL, 0, 0);
    d.puu = Vec3(0, -kR * std::sin(phi), kR * std::cos(phi)) * dphi * dphi;
    return d;
  }
};

SurfaceOfRevolution radial_cylinder(double r) { return SurfaceOfRevolution({Vec2(-200, r), Vec2(200, r)}); }


struct DrumFixture {
  Tool tool = test::paper_drum_wheel();
  SurfaceOfRevolution hub = radial_cylinder(kY0 + kR * std::sin(-0.25));
  SurfaceOfRevolution casing = radial_cylinder(kY0 + kR * std::sin(0.25));
  CollisionWorld world;
  DrumFinishRequest request() const {
    DrumFinishRequest rq;
    rq.flank = std::make_shared<CylinderFlank>();
    rq.hub = &hub;
    rq.casing = &casing;
    rq.tool = &tool;
    rq.world = &world;
    rq.flip_normal = true;  // pu × pv points away from the axis, into the material
    rq.residual_height_mm = 0.014;
    rq.links.retract_mm = 5;
    return rq;
  }
};

TEST(DrumFinish, TrimmedBetweenHubAndCasingRowsSpacedByTheClosedFormCutWidth) {
  DrumFixture f;
  // A neighbouring "blade" wall far above the passage.
  f.world.add("neighbour", grid_mesh(Vec3(-50, kY0 - 100, 40), Vec3(100, 0, 0), Vec3(0, 200, 0), 4, 4));
  const DrumFinishRequest rq = f.request();
  const DrumFinishResult res = plan_drum_finish(rq);
  ASSERT_GE(res.rows.size(), 3u);
  EXPECT_EQ(res.rows.front().u, res.first_row_u);
  EXPECT_EQ(res.rows.back().u, 1.0);
  for (double v : {0.0, 0.5, 1.0}) EXPECT_NEAR(f.hub.radial_offset(res.trimmed->point(0, v)), 0, 1e-6);
  for (double v : {0.0, 0.5, 1.0}) EXPECT_NEAR(f.casing.radial_offset(res.trimmed->point(1, v)), 0, 1e-6);

  const double expected = f.tool.cut_width(f.tool.flank_contact_height(), 1 / kR, rq.residual_height_mm).width_mm;
  ASSERT_GT(expected, 0);
  for (size_t r = 0; r + 1 < res.rows.size(); ++r) {
    EXPECT_NEAR(res.rows[r].width_mm, expected, 1e-3 * expected) << "row " << r;
    if (r + 2 < res.rows.size()) {
      // 3-D gap between consecutive rows never exceeds the width.
      double gap_max = 0;
      for (double v : {0.0, 0.25, 0.5, 0.75, 1.0})
        gap_max = std::max(gap_max, (res.trimmed->point(res.rows[r + 1].u, v) -
                                     res.trimmed->point(res.rows[r].u, v)).norm());
      EXPECT_LE(gap_max, expected * (1 + 1e-6));
      EXPECT_GT(gap_max, 0.98 * expected);
    }
  }
  EXPECT_EQ(res.total_refusals, 0);
  EXPECT_LE(res.max_deviation_mm, rq.steps.chord_tol_mm * (1 + 1e-9));

  // Every emitted pose: clear by an independent check; axis leans to the tip (+y).
  ToolBody body(f.tool);
  int n = 0;
  for (const DrumFinishRow& row : res.rows)
    for (const DrumFinishPose& p : row.poses) {
      EXPECT_TRUE(f.world.check(body, p.pose, rq.tilt.clearances).clear);
      EXPECT_GT(p.pose.axis.y(), 0.9);
      ++n;
    }
  EXPECT_EQ(n, res.total_poses);
  EXPECT_EQ(res.refused_links, 0);
  EXPECT_EQ(res.links.size(), res.rows.size() - 1);

  // APT output is deterministic and has one GOTO per pose plus two per link
  // and the lead-in and lead-out, each proved along the normal.
  EXPECT_TRUE(res.lead_in.clear) << res.lead_in.reason;
  EXPECT_TRUE(res.lead_out.clear) << res.lead_out.reason;
  EXPECT_NEAR((res.lead_in.away.tip - res.rows.front().poses.front().pose.tip).norm(), res.lead_in.offset_mm, 1e-9);
  const std::string apt = drum_finish_apt(res, rq);
  EXPECT_EQ(apt, drum_finish_apt(plan_drum_finish(rq), rq));
  size_t gotos = 0;
  for (size_t at = apt.find("GOTO/"); at != std::string::npos; at = apt.find("GOTO/", at + 1)) ++gotos;
  EXPECT_EQ(gotos, static_cast<size_t>(res.total_poses) + 2 * res.links.size() + 2);
}

// Smallest radial offset from the hub over a dense sampling of the whole
// cutter surface (60 rings x 90 around plus the end faces) at `pose`.
double min_hub_offset(const Tool& tool, const SurfaceOfRevolution& hub, const ToolPose& pose) {
  const Profile& c = tool.cutter();
  const Eigen::Isometry3d T = tool_to_part(pose);
  double m = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= 60; ++i) {
    const double z = c.z_min() + (c.z_max() - c.z_min()) * i / 60;
    const double r = c.radius_at(std::clamp(z, c.z_min() + 1e-9, c.z_max() - 1e-9));
    for (double f : {1.0, 0.75, 0.5, 0.25})
      for (int k = 0; k < 90; ++k) {
        const double a = 2 * kPi * k / 90;
        m = std::min(m, hub.radial_offset(T * Vec3(f * r * std::cos(a), f * r * std::sin(a), z)));
        if (i > 0 && i < 60) break;  // inner points only on the end faces
      }
  }
  return m;
}

TEST(DrumFinish, FirstRowIsTheLowestWhereTheWheelClearsTheHub) {
  DrumFixture f;
  f.world.add("neighbour", grid_mesh(Vec3(-50, kY0 - 100, 40), Vec3(100, 0, 0), Vec3(0, 200, 0), 4, 4));
  DrumFinishRequest rq = f.request();
  rq.hub_clearance_mm = 0.05;
  const DrumFinishResult res = plan_drum_finish(rq);
  // At u' = 0 the test::paper_drum_wheel's lower half would be in the hub: the first row is raised.
  ASSERT_GT(res.first_row_u, 0.01);
  ASSERT_FALSE(res.rows.front().poses.empty());
  double lowest = std::numeric_limits<double>::infinity();
  for (const DrumFinishPose& p : res.rows.front().poses) lowest = std::min(lowest, min_hub_offset(f.tool, f.hub, p.pose));
  // Clear by the clearance (to the rule's sampling, a few um), and not much
  // more: the rule took the lowest row that clears.
  EXPECT_GE(lowest, rq.hub_clearance_mm - 5e-3);
  EXPECT_LE(lowest, rq.hub_clearance_mm + 0.02);
  // The 3-D strip left above the hub curve is what the report says.
  EXPECT_NEAR(res.hub_strip_mm, (res.trimmed->point(res.first_row_u, 0.5) - res.trimmed->point(0, 0.5)).norm(), 0.05);
  // A row 0.3 mm lower would put the test::paper_drum_wheel into the hub.
  const double du = 0.3 / res.trimmed->eval(res.first_row_u, 0.5).pu.norm();
  ContactFrame frame;
  const SurfaceDerivs d = res.trimmed->eval(res.first_row_u - du, 0.5);
  frame.point = d.p;
  frame.normal = -d.pu.cross(d.pv).normalized();  // flip_normal
  frame.tangent = d.pv.normalized();
  Vec3 axis = axis_from_lead_tilt(frame, 0, 0);
  if (axis.dot(d.pu) < 0) axis = axis_from_lead_tilt(frame, 0, kPi);
  EXPECT_LT(min_hub_offset(f.tool, f.hub, place_tool(f.tool, frame, axis)), rq.hub_clearance_mm - 0.05);
}

// The emitted path on the concave cylinder, simulated: the rows are straight
// (chord error 0) and spaced by the cut width for the residual height, so
// the scallop between two full-width rows is the residual height itself,
// and nothing is cut below the design.
TEST(DrumFinish, SimulatedPathLeavesTheResidualHeightAndNoGouge) {
  DrumFixture f;
  f.world.add("neighbour", grid_mesh(Vec3(-50, kY0 - 100, 40), Vec3(100, 0, 0), Vec3(0, 200, 0), 4, 4));
  const DrumFinishRequest rq = f.request();
  const DrumFinishResult plan = plan_drum_finish(rq);
  UndercutOptions o;
  o.samples_u = 300;
  o.samples_v = 60;
  o.v0 = 0.2;  // away from the row ends, where the test::paper_drum_wheel runs out
  o.v1 = 0.8;
  const DrumFinishSimulation full = simulate_drum_finish(plan, rq, o);
  const UndercutResult& sim = full.undercut;
  EXPECT_EQ(sim.untouched, 0);
  EXPECT_LE(sim.undercut_max_mm, rq.residual_height_mm * 1.005);
  EXPECT_GE(sim.undercut_max_mm, rq.residual_height_mm * 0.95);
  EXPECT_GE(sim.overcut_mm, -2 * o.tol_mm);  // the tracing stops within tol_mm of the tool
  // Rows are hub -> tip: the first sample row lies on the first row's
  // contact line (material 0), whatever the flip.
  const size_t first = static_cast<size_t>(full.first_machined_row) * sim.samples_v;
  EXPECT_GT(full.first_machined_row, 0);  // the hub strip is sampled too
  for (int j = 0; j < sim.samples_v; ++j) EXPECT_NEAR(sim.residual_mm[first + j], 0, 1e-4) << j;
  // Every other row removed: the kept rows are two spacings (~6.4 mm)
  // apart, wider than the test::paper_drum_wheel's 4 mm head, so a strip between them is
  // never reached within search_above (untouched): the simulation sees the
  // spacing.
  DrumFinishResult sparse = plan;
  for (size_t r = 1; r < sparse.rows.size(); r += 2) sparse.rows[r].poses.clear();
  const UndercutResult coarse = simulate_drum_finish(sparse, rq, o).undercut;
  EXPECT_GT(coarse.untouched, sim.samples_v * 2);
}

// Issue 11: the simulation sweeps every move of the program, links too. The
// planned links leave along the normal and cut nothing; the same plan with
// its links replaced by the old rule (straight up the axis by 5 mm, then
// across) cuts into the concave flank, and the simulation names the move.
TEST(DrumFinish, SimulationSweepsTheLinksAndCatchesAnInjectedGougingLink) {
  DrumFixture f;
  f.world.add("neighbour", grid_mesh(Vec3(-50, kY0 - 100, 40), Vec3(100, 0, 0), Vec3(0, 200, 0), 4, 4));
  const DrumFinishRequest rq = f.request();
  const DrumFinishResult plan = plan_drum_finish(rq);
  ASSERT_GE(plan.links.size(), 2u);
  for (const DrumFinishLink& l : plan.links) {
    ASSERT_TRUE(l.clear) << l.reason;
    EXPECT_GT(l.offset_mm, 0.0);
    EXPECT_GE(l.deepest_cut_mm, -rq.links.allowed_overcut_mm);
  }
  UndercutOptions o;
  o.samples_u = 150;
  o.samples_v = 60;
  const DrumFinishSimulation planned = simulate_drum_finish(plan, rq, o);
  EXPECT_GE(planned.undercut.overcut_mm, -2 * o.tol_mm);

  DrumFinishResult injected = plan;
  DrumFinishLink& l = injected.links[1];
  const ToolPose& a = injected.rows[l.from_row].poses.back().pose;
  const ToolPose& b = injected.rows[l.to_row].poses.front().pose;
  ToolPose up_a = a, up_b = b;
  up_a.tip += 5 * a.axis;
  up_b.tip += 5 * b.axis;
  l.moves = {up_a, up_b};
  const DrumFinishSimulation gouged = simulate_drum_finish(injected, rq, o);
  // The barrel (R_c 50) sliding 5 mm along the concave span (R 100) cuts far
  // beyond the tolerance (s^2 / (2 (R - R_c)) = 250 um before the head ends).
  EXPECT_LT(gouged.undercut.overcut_mm, -0.05);
  ASSERT_GE(gouged.overcut_move, 0);
  EXPECT_EQ(gouged.overcut_row, l.to_row);
  EXPECT_TRUE(gouged.overcut_motion == "retract" || gouged.overcut_motion == "traverse" ||
              gouged.overcut_motion == "approach")
      << gouged.overcut_motion;
  const Toolpath moves = drum_finish_moves(injected);
  EXPECT_EQ(moves.at(gouged.overcut_move).motion, gouged.overcut_motion);
}

TEST(DrumFinish, AllFlanksOnTwoThreadsMatchOneByOne) {
  DrumFixture f;
  f.world.add("neighbour", grid_mesh(Vec3(-50, kY0 - 100, 40), Vec3(100, 0, 0), Vec3(0, 200, 0), 4, 4));
  std::vector<DrumFinishRequest> rqs(3, f.request());
  rqs[1].residual_height_mm = 0.008;
  rqs[2].zigzag = false;
  const std::vector<DrumFinishResult> two = plan_drum_finish_all(rqs, 2);
  ASSERT_EQ(two.size(), 3u);
  for (size_t k = 0; k < rqs.size(); ++k)
    EXPECT_EQ(drum_finish_apt(two[k], rqs[k]), drum_finish_apt(plan_drum_finish(rqs[k]), rqs[k])) << k;
  EXPECT_GT(two[1].rows.size(), two[0].rows.size());  // smaller residual, more rows
  EXPECT_THROW(plan_drum_finish_all(rqs, 0), ParameterError);
}

TEST(DrumFinish, AWallInThePathGivesRefusalsNotPoses) {
  DrumFixture f;
  // Horizontal wall 6 mm above the flank bottom: the test::paper_drum_wheel (radius 4, axis
  // 4 mm above the contact) reaches 8 mm there, whatever the lead.
  f.world.add("wall", grid_mesh(Vec3(-50, kY0 - 100, 6), Vec3(100, 0, 0), Vec3(0, 200, 0), 4, 4));
  const DrumFinishResult res = plan_drum_finish(f.request());
  EXPECT_GT(res.total_refusals, 0);
  ToolBody body(f.tool);
  for (const DrumFinishRow& row : res.rows)
    for (const DrumFinishPose& p : row.poses) {
      const PoseCheck c = f.world.check(body, p.pose, {});
      EXPECT_TRUE(c.clear) << "row u " << row.u << " v " << p.v << " tip " << p.pose.tip.transpose() << " axis "
                           << p.pose.axis.transpose() << " lead " << p.lead_rad << " margin " << c.min_margin_mm
                           << " poses " << res.total_poses << " refusals " << res.total_refusals;
    }
}

// Issue 41: after a roughing the flank carries its stock until the rows
// reach it, and the wheel's shank runs up along the flank above its row;
// cut from the tip down (top_down) that flank is finished (the job's stock
// check measures it on the built-in blisk: bench/RESULTS.md). The same rows
// and poses in reverse, each row keeping its direction (the zigzag still
// alternates in cutting order), linked in the order cut, every link proved.
TEST(DrumFinish, TopDownCutsTheSameRowsFromTheTipLinkedInThatOrder) {
  DrumFixture f;
  f.world.add("neighbour", grid_mesh(Vec3(-50, kY0 - 100, 40), Vec3(100, 0, 0), Vec3(0, 200, 0), 4, 4));
  DrumFinishRequest rq = f.request();
  const DrumFinishResult up = plan_drum_finish(rq);
  rq.top_down = true;
  const DrumFinishResult down = plan_drum_finish(rq);
  ASSERT_EQ(up.total_refusals + up.refused_links + down.total_refusals + down.refused_links, 0);
  ASSERT_EQ(up.rows.size(), down.rows.size());
  ASSERT_GT(up.rows.size(), 3u);
  const size_t n = up.rows.size();
  for (size_t r = 0; r < n; ++r) {
    const DrumFinishRow &a = up.rows[r], &b = down.rows[n - 1 - r];
    EXPECT_EQ(a.u, b.u);
    EXPECT_EQ(a.reversed, b.reversed);
    ASSERT_EQ(a.poses.size(), b.poses.size());
    for (size_t k = 0; k < a.poses.size(); ++k) {
      EXPECT_EQ(a.poses[k].pose.tip, b.poses[k].pose.tip);
      EXPECT_EQ(a.poses[k].pose.axis, b.poses[k].pose.axis);
    }
    if (r + 1 < n) {
      EXPECT_GT(a.spacing_du, 0);
      EXPECT_NEAR(a.spacing_du, down.rows[n - 2 - r].spacing_du, 1e-12);
      EXPECT_NE(down.rows[r].reversed, down.rows[r + 1].reversed);  // zigzag in cutting order
    }
  }
  EXPECT_EQ(down.rows.front().u, 1.0);  // the tip row first
  ASSERT_EQ(down.links.size(), n - 1);
  for (const DrumFinishLink& l : down.links) {
    EXPECT_TRUE(l.clear);
    EXPECT_EQ(l.to_row, l.from_row + 1);
    EXPECT_LT(down.rows[l.to_row].u, down.rows[l.from_row].u);
  }
  // The program: the tip row's poses first, then down row by row.
  const Toolpath moves = drum_finish_moves(down);
  int last_row = -1;
  for (const Move& m : moves) {
    ASSERT_NE(m.kind, Move::Kind::Stop);
    EXPECT_GE(m.row, last_row);
    last_row = m.row;
  }
  EXPECT_EQ(last_row, static_cast<int>(n - 1));
}

TEST(DrumFinish, MissingInputsAreNamed) {
  DrumFixture f;
  DrumFinishRequest rq = f.request();
  rq.hub = nullptr;
  EXPECT_THROW(plan_drum_finish(rq), ParameterError);
  rq = f.request();
  rq.residual_height_mm = 0;
  EXPECT_THROW(plan_drum_finish(rq), ParameterError);
}

}  // namespace
}  // namespace bliskrun
