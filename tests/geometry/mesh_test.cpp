#include "core/geometry/mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "geometry/analytic_surfaces.h"

namespace bliskrun {
namespace {

// Largest distance from the mesh to a sphere of radius R about the origin,
// sampled densely over every triangle (closed form of the point distance).
double max_sphere_deviation(const TriangleMesh& m, double r) {
  double worst = 0;
  for (const auto& t : m.triangles) {
    const Vec3 &a = m.vertices[t.x()], &b = m.vertices[t.y()], &c = m.vertices[t.z()];
    for (int i = 0; i <= 6; ++i)
      for (int j = 0; i + j <= 6; ++j) {
        const Vec3 p = a + (b - a) * (i / 6.0) + (c - a) * (j / 6.0);
        worst = std::max(worst, std::abs(p.norm() - r));
      }
  }
  return worst;
}

TEST(Tessellate, SphereMeshStaysWithinTheChordTolerance) {
  const test::Sphere s(20);
  for (double tol : {0.05, 0.01, 0.002}) {
    const TriangleMesh m = tessellate(s, tol);
    EXPECT_LE(max_sphere_deviation(m, 20), tol) << tol;
  }
}

TEST(Tessellate, TriangleCountGrowsAsOneOverTolerance) {
  // Chordal error ~ h^2 k / 8: halving the spacing per direction quarters
  // the error, so 4x tighter tolerance -> about 4x the triangles.
  const test::Cylinder c(10, 30);
  const size_t coarse = tessellate(c, 0.04).triangles.size();
  const size_t fine = tessellate(c, 0.01).triangles.size();
  EXPECT_GT(fine, coarse * 1.6);
  EXPECT_LT(fine, coarse * 2.8);  // the cylinder is straight along z: only v refines (2x)
}

TEST(WriteStl, BinaryLayoutAndCount) {
  const TriangleMesh m = tessellate(test::Cylinder(5, 10), 0.05);
  const auto path = std::filesystem::temp_directory_path() / "bliskrun_mesh_test.stl";
  write_stl(m, path.string());
  EXPECT_EQ(std::filesystem::file_size(path), 84 + 50 * m.triangles.size());
  std::ifstream in(path, std::ios::binary);
  in.seekg(80);
  uint32_t n = 0;
  in.read(reinterpret_cast<char*>(&n), 4);
  EXPECT_EQ(n, m.triangles.size());
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace bliskrun
