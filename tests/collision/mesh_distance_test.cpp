#include "core/collision/mesh_distance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include <fcl/fcl.h>

#include "collision/test_meshes.h"
#include "core/collision/collision_world.h"
#include "core/tools/tool.h"

namespace bliskrun {
namespace {

std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> bvh(const TriangleMesh& m) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  model->beginModel(static_cast<int>(m.triangles.size()), static_cast<int>(m.vertices.size()));
  for (const Eigen::Vector3i& t : m.triangles) model->addTriangle(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
  model->endModel();
  return model;
}

double exact_distance(const fcl::BVHModel<fcl::OBBRSSd>& a, const fcl::BVHModel<fcl::OBBRSSd>& b,
                      const Eigen::Isometry3d& b_to_a) {
  fcl::DistanceRequestd request;
  fcl::DistanceResultd result;
  fcl::distance(&a, fcl::Transform3d::Identity(), &b, b_to_a, request, result);
  return result.min_distance;
}

// A 50 mm shank (the flat-end mill's, meshed by tool_fcl) lying nearly
// parallel over a finely meshed plane — the case the approximation is for:
// thousands of box pairs within a few per cent of the nearest. The bound is
// never above the exact distance nor below it over (1 + rel_err); and the
// approximate traversal does stop at a pair that is not the nearest (the
// pair it reports is farther apart than the exact distance), so the
// relative error does reach FCL's traversal (FCL 0.7's own rel_err never
// does).
TEST(MeshDistanceLowerBound, BoundsTheExactDistanceWithinItsRelativeError) {
  const auto plane = bvh(test::grid_mesh(Vec3(-60, -60, 0), Vec3(120, 0, 0), Vec3(0, 120, 0), 240, 240));
  const ToolBody body(Tool::flat_end_mill({3, 0.5, 9, {6, 50}, {12, 40}}), 1e-3);
  const fcl::BVHModel<fcl::OBBRSSd>* shank = nullptr;
  for (const FclToolPart& part : body.parts())
    if (part.id == ToolPartId::Shank) shank = part.pieces.front().geometry.get();
  ASSERT_NE(shank, nullptr);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> height(0.2, 5), tilt(-0.01, 0.01), spin(0, 2 * kPi);
  int not_nearest = 0;
  for (int k = 0; k < 40; ++k) {
    // The tool's axis (its z) turned to lie along the plane, slightly tilted.
    const double h = height(rng);
    const Eigen::Isometry3d place = Eigen::Translation3d(0, 0, h + 3.3) *
                                    Eigen::AngleAxisd(spin(rng), Vec3::UnitZ()) *
                                    Eigen::AngleAxisd(0.5 * kPi + tilt(rng), Vec3::UnitY()) *
                                    Eigen::Translation3d(0, 0, -30);
    const double exact = exact_distance(*plane, *shank, place);
    ASSERT_GT(exact, 0.05);
    for (double rel : {0.0, 0.02, 0.25}) {
      const MeshDistanceBound b = mesh_distance_lower_bound(*plane, *shank, place, 1e3, rel);
      ASSERT_TRUE(b.found);
      EXPECT_LE(b.distance_mm, exact + 1e-9) << "rel " << rel;
      EXPECT_GE(b.distance_mm, exact / (1 + rel) - 1e-9) << "rel " << rel;
      const double pair = (b.on_a - b.on_b).norm();
      EXPECT_NEAR(pair, b.distance_mm * (1 + rel), 1e-6) << "rel " << rel;
      if (rel == 0) EXPECT_NEAR(b.distance_mm, exact, 1e-9);
      if (rel == 0.25 && pair > exact + 1e-6) ++not_nearest;
      // Nothing sought beyond the seed.
      const MeshDistanceBound none = mesh_distance_lower_bound(*plane, *shank, place, 0.5 * exact, rel);
      EXPECT_FALSE(none.found);
      EXPECT_EQ(none.distance_mm, 0.5 * exact);
    }
  }
  EXPECT_GT(not_nearest, 5);
}

}  // namespace
}  // namespace bliskrun
