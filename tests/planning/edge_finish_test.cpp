// Edge finishing on the built-in blisk's leading edge (core/planning/
// edge_finish.h): rows around the edge, spacing by the smallest strip, the
// bottom strip against the side-edge strip, checks against the world.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>

#include "core/geometry/mesh.h"
#include "core/geometry/revolution.h"
#include "core/parts/builtin_blisk.h"
#include "core/parts/edge_region.h"
#include "core/planning/edge_finish.h"

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

TEST(EdgeFinishTest, Explore) {
  if (!std::getenv("EDGE_EXPLORE")) GTEST_SKIP();
  const BuiltinBlisk blisk;
  EdgeRegionRequest er;
  er.first = blisk.flank_surface(0, FlankSide::kPressure);
  er.second = blisk.flank_surface(0, FlankSide::kSuction);
  er.overlap_mm = 0.3;
  const EdgeRegion e = build_edge_region(er);
  fprintf(stderr, "edge r %.4f..%.4f misfit %.2e fit %.2e overlap %.3f round u %.3f..%.3f\n", e.radius_min_mm, e.radius_max_mm,
         e.circle_misfit_mm, e.fit_deviation_mm, e.overlap_mm, e.round_u0, e.round_u1);
  CollisionWorld world;
  world.add("hub", tessellate(SurfaceOfRevolution(blisk.hub_meridian()), 0.01));
  const double R = std::atof(std::getenv("EDGE_R")), r = std::atof(std::getenv("EDGE_CR"));
  const Tool tool = mill(R, r);
  EdgeFinishRequest rq;
  rq.edge = e.surface;
  rq.tool = &tool;
  rq.world = &world;
  rq.band = {-0.001, 0.02};
  rq.r_e_mm = std::min(1.0, R - r);
  rq.sampling.half_width_mm = R + 1;
  rq.sampling.gouge_half_mm = R + 1;
  rq.steps.chord_tol_mm = 0.001;
  rq.steps.max_step_mm = 0.5;
  rq.v0 = std::getenv("EDGE_V0") ? std::atof(std::getenv("EDGE_V0")) : 0.1;
  rq.v1 = std::getenv("EDGE_V1") ? std::atof(std::getenv("EDGE_V1")) : 0.9;
  const auto t0 = std::chrono::steady_clock::now();
  const EdgeFinishResult res = plan_edge_finish(rq);
  fprintf(stderr, "rows %zu side rows %d poses %d refusals %d links refused %d time %.2f (rows %.2f side %.2f checks %.2f)\n",
         res.rows.size(), res.side_rows, res.total_poses, res.total_refusals, res.refused_links,
         std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), res.rows_seconds,
         res.side_seconds, res.checks_seconds);
  for (const auto& row : res.rows)
    fprintf(stderr, " v %.3f w %.3f (paper %.3f joint %.3f side %.3f) L %.3f R %.3f contacts %zu b %d c %d ref %zu evals %d\n",
           row.v, row.width_mm, row.paper_width_mm, row.joint_width_mm, row.side_width_mm, row.left_min_mm,
           row.right_min_mm, row.poses.size(), row.bottom_contacts, row.corner_contacts, row.refusals.size(),
           row.strip_evaluations);
  const auto& c = res.comparison;
  for (size_t i = 0; i < c.u.size(); ++i)
    fprintf(stderr, "  u %.3f %s paper %.3f joint %.3f side %.3f\n", c.u[i], c.contact[i].c_str(), c.paper_mm[i], c.joint_mm[i],
           c.side_mm[i]);
  for (const auto& row : res.rows)
    for (const auto& f : row.refusals) fprintf(stderr, "  refused v %.3f u %.3f: %s\n", row.v, f.u, f.reason.c_str());
}

}  // namespace
}  // namespace bliskrun
