#include "core/planning/drum_finish.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"
#include "core/geometry/mesh.h"
#include "tests/collision/test_meshes.h"

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

Tool wheel() { return Tool::drum_wheel({8, 50, 4, {6, 96}, {}}); }

struct Fixture {
  Tool tool = wheel();
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
    rq.retract_mm = 5;
    return rq;
  }
};

TEST(DrumFinish, RowsStartOnTheHubAndAreSpacedByTheClosedFormCutWidth) {
  Fixture f;
  // A neighbouring "blade" wall far above the passage.
  f.world.add("neighbour", grid_mesh(Vec3(-50, kY0 - 100, 40), Vec3(100, 0, 0), Vec3(0, 200, 0), 4, 4));
  const DrumFinishRequest rq = f.request();
  const DrumFinishResult res = plan_drum_finish(rq);
  ASSERT_GE(res.rows.size(), 3u);
  EXPECT_EQ(res.rows.front().u, 0.0);
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

  // APT output is deterministic and has one GOTO per pose plus two per link.
  const std::string apt = drum_finish_apt(res, rq);
  EXPECT_EQ(apt, drum_finish_apt(plan_drum_finish(rq), rq));
  size_t gotos = 0;
  for (size_t at = apt.find("GOTO/"); at != std::string::npos; at = apt.find("GOTO/", at + 1)) ++gotos;
  EXPECT_EQ(gotos, static_cast<size_t>(res.total_poses) + 2 * res.links.size());
}

TEST(DrumFinish, AWallInThePathGivesRefusalsNotPoses) {
  Fixture f;
  // Horizontal wall 6 mm above the flank bottom: the wheel (radius 4, axis
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

TEST(DrumFinish, MissingInputsAreNamed) {
  Fixture f;
  DrumFinishRequest rq = f.request();
  rq.hub = nullptr;
  EXPECT_THROW(plan_drum_finish(rq), ParameterError);
  rq = f.request();
  rq.residual_height_mm = 0;
  EXPECT_THROW(plan_drum_finish(rq), ParameterError);
}

}  // namespace
}  // namespace bliskrun
