// Tessellation under the run's limits: cancelled while
// refining towards an absurd tolerance, and refused before allocating when
// the mesh it would build exceeds the memory budget.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/common/cancel_after.h"
#include "core/common/error.h"
#include "core/common/memory_budget.h"
#include "core/geometry/mesh.h"
#include "geometry/analytic_surfaces.h"

namespace bliskrun {
namespace {

TEST(TessellateLimits, CancelledPartWay) {
  // 1e-7 mm on a 20 mm sphere refines to the 4096 x 4096 cap: minutes of
  // sampling without cancellation. Cancelled at its 50th cancellation point
  // (a count, not a delay: whatever the machine's speed, part-way).
  const test::Sphere s(20);
  Progress progress;
  request_cancel_all_after(50, "test");
  EXPECT_THROW(tessellate(s, 1e-7, 0, 1, 0, 1, progress), Cancelled);
  clear_cancel_all();
}

TEST(TessellateLimits, RefusesAMeshOverTheBudgetWithItsEstimate) {
  const test::Sphere s(20);
  set_memory_budget(64.0 * 1024 * 1024);
  std::string message;
  try {
    tessellate(s, 1e-7);
  } catch (const Error& e) {
    message = e.what();
  }
  set_memory_budget(0);
  int nu = 0, nv = 0;
  double mb = 0;
  ASSERT_EQ(std::sscanf(message.c_str(), "tessellate: a %d x %d grid mesh for %*s mm needs an estimated %lf MB", &nu,
                        &nv, &mb),
            3)
      << message;
  // The estimate is the mesh the grid becomes: (nu+1)(nv+1) vertices and
  // 2 nu nv triangles of three indices.
  const double bytes = (nu + 1.0) * (nv + 1.0) * sizeof(Vec3) + 2.0 * nu * nv * sizeof(Eigen::Vector3i);
  EXPECT_NEAR(mb, bytes / (1024.0 * 1024.0), 1e-5 * mb);
  EXPECT_GT(mb, 64);
  EXPECT_NE(message.find("more than the memory limit of 64 MB (--memory-limit)"), std::string::npos) << message;
}

}  // namespace
}  // namespace bliskrun
