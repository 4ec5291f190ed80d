// Edge finishing on the built-in blisk's leading edge (core/planning/
// edge_finish.h): rows around the edge, spacing by the smallest strip, the
// bottom strip against the side-edge strip, checks against the world.
#include <gtest/gtest.h>

#include <cmath>

#include "core/geometry/mesh.h"
#include "core/geometry/revolution.h"
#include "core/parts/builtin_blisk.h"
#include "core/parts/edge_region.h"
#include "core/planning/edge_finish.h"
#include "core/tools/pose.h"

namespace bliskrun {
namespace {

Tool mill(double R, double r) {
  FlatEndMillSpec s;
  s.radius_mm = R;
  s.corner_radius_mm = r;
  s.flute_length_mm = 3 * R;
  s.shank = {2 * R, 30};
  s.holder = {6 * R, 40};
  return Tool::flat_end_mill(s);
}

// A band of rows across the middle of the built-in blade's leading edge,
// with the hub as the only check surface (fast): the claims of the paper
// and of the planner, each of which can fail.
TEST(EdgeFinishTest, LeadingEdgeRowsCutWiderWithTheBottomAndNeverGouge) {
  const BuiltinBlisk blisk;
  EdgeRegionRequest er;
  er.first = blisk.flank_surface(0, FlankSide::kPressure);
  er.second = blisk.flank_surface(0, FlankSide::kSuction);
  er.overlap_mm = 0.3;
  const EdgeRegion e = build_edge_region(er);
  CollisionWorld world;
  world.add("hub", tessellate(SurfaceOfRevolution(blisk.hub_meridian()), 0.02));
  const Tool tool = mill(3, 0.5);
  EdgeFinishRequest rq;
  rq.edge = e.surface;
  rq.first = er.first;
  rq.second = er.second;
  rq.tool = &tool;
  rq.world = &world;
  rq.sampling.half_width_mm = 4;
  rq.sampling.gouge_half_mm = 4;
  rq.v0 = 0.45;
  rq.v1 = 0.55;
  const EdgeFinishResult res = plan_edge_finish(rq);
  ASSERT_GE(res.rows.size(), 2u);
  EXPECT_EQ(res.total_refusals, 0);
  EXPECT_EQ(res.refused_links, 0);
  EXPECT_GE(res.side_rows, static_cast<int>(res.rows.size()));
  for (const EdgeFinishRow& row : res.rows) {
    // Ours (each l keeps its own best φ) is no worse than the paper's average.
    EXPECT_GE(row.joint_width_mm, row.paper_width_mm - 1e-9);
    EXPECT_GT(row.width_mm, 0);
    for (size_t i = 0; i < row.poses.size(); ++i) {
      const EdgeFinishPose& p = row.poses[i];
      // The contact lies on the cutter, the strip is gouge-free (①) and wide.
      EXPECT_NEAR(tool.signed_distance(Vec3(tool_to_part(p.pose).inverse() * p.contact)), 0, 1e-6);
      const StripWidth w = p.strip->width(p.position);
      EXPECT_FALSE(w.gouges);
      EXPECT_GE(w.width_mm, row.width_mm - 1e-6) << "a pose narrower than the balanced row width";
      if (p.position.contact == EdgeContact::Bottom) EXPECT_GE(p.position.l_mm, rq.r_e_mm - 1e-12);  // ③
      // Cutting motion within e1 of the blade (independent samples: the
      // midpoint against the next contact's samples).
      if (i + 1 < row.poses.size() && row.poses[i + 1].segment == p.segment) {
        const ToolPose mid = PoseMotion(p.pose, row.poses[i + 1].pose).pose_at(0.5);
        EXPECT_GE(row.poses[i + 1].strip->deepest(mid), rq.band.e1_mm - 1e-9);
      }
    }
  }
  // Fig. 8: on the round the bottom's strip is wider than the side edge's.
  const EdgeWidthComparison& c = res.comparison;
  int round_contacts = 0;
  for (size_t i = 0; i < c.u.size(); ++i) {
    if (c.u[i] < e.round_u1 - 0.05 && c.u[i] > e.round_u0 + 0.05 && c.contact[i] == "bottom") {
      ++round_contacts;
      EXPECT_GT(c.joint_mm[i], 1.5 * c.side_mm[i]) << "u " << c.u[i];
    }
  }
  EXPECT_GT(round_contacts, 5);
  // The move list: feeds of every pose, rapids of every clear link.
  const std::vector<DrumFinishMove> moves = edge_finish_moves(res);
  long feeds = 0;
  for (const DrumFinishMove& m : moves) feeds += m.kind == DrumFinishMove::Kind::Feed;
  EXPECT_EQ(feeds, res.total_poses);
}

}  // namespace
}  // namespace bliskrun
