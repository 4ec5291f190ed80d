// The edge region of a blade (core/parts/edge_region.h) on the built-in
// blisk's exact flanks: a round of the blade's edge radius tangent to both
// flanks, joined to them within the overlap, normal out of the material.
#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"
#include "core/geometry/differential.h"
#include "core/geometry/projection.h"
#include "core/parts/builtin_blisk.h"
#include "core/parts/edge_region.h"

namespace bliskrun {
namespace {

EdgeRegion leading_edge(const BuiltinBlisk& blisk, double overlap) {
  EdgeRegionRequest rq;
  rq.first = blisk.flank_surface(0, FlankSide::kPressure);  // v = 0 at the LE
  rq.second = blisk.flank_surface(0, FlankSide::kSuction);  // v = 1 at the LE
  rq.overlap_mm = overlap;
  return build_edge_region(rq);
}

TEST(EdgeRegionTest, LeadingEdgeIsTheRoundOfTheBladeJoinedToBothFlanks) {
  const BuiltinBlisk blisk;
  const EdgeRegion e = leading_edge(blisk, 0.3);
  // The built-in edge circle has radius r_le in the unrolled section; wrapped
  // on the cylinder at r >= 60 mm it stays within ~0.3 %.
  EXPECT_NEAR(e.radius_min_mm, blisk.params().le_radius_mm, 0.01);
  EXPECT_NEAR(e.radius_max_mm, blisk.params().le_radius_mm, 0.01);
  EXPECT_LT(e.circle_misfit_mm, 0.005);
  EXPECT_LT(e.fit_deviation_mm, 5e-4);
  EXPECT_NEAR(e.overlap_mm, 0.3, 0.01);
  // The round's middle is convex with curvature ~ -1/r_le across (around).
  const SurfaceCurvature c = curvature(e.surface->eval(0.5, 0.5));
  EXPECT_NEAR(c.k2, -1 / blisk.params().le_radius_mm, 0.1 / blisk.params().le_radius_mm);
  // Normal out of the material: away from the blade's mid-chord, upstream.
  const Vec3 mid = 0.5 * (blisk.flank_surface(0, FlankSide::kPressure)->point(0.5, 0.5) +
                          blisk.flank_surface(0, FlankSide::kSuction)->point(0.5, 0.5));
  EXPECT_GT(c.normal.dot((e.surface->point(0.5, 0.5) - mid).normalized()), 0.9);
  EXPECT_LT(c.normal.z(), -0.2);
  // Within the overlap the region lies on the flanks (projection distance).
  for (double v : {0.05, 0.5, 0.95}) {
    for (double f : {0.0, 0.5, 0.9}) {
      const Vec3 pa = e.surface->point(f * e.round_u0 * 0.9, v);
      const SurfaceProjection pr = project_to_surface(*blisk.flank_surface(0, FlankSide::kPressure), pa);
      ASSERT_TRUE(pr.ok) << pr.failure;
      EXPECT_LT(pr.distance, 5e-4) << "v " << v << " f " << f;
      const Vec3 pb = e.surface->point(1 - f * (1 - e.round_u1) * 0.9, v);
      const SurfaceProjection qb = project_to_surface(*blisk.flank_surface(0, FlankSide::kSuction), pb);
      ASSERT_TRUE(qb.ok) << qb.failure;
      EXPECT_LT(qb.distance, 5e-4) << "v " << v << " f " << f;
    }
  }
  EdgeRegionRequest bad;
  EXPECT_THROW(build_edge_region(bad), ParameterError);
}

}  // namespace
}  // namespace bliskrun
