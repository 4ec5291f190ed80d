#pragma once
// Small check-surface meshes with known geometry for the collision tests.
#include "core/geometry/mesh.h"

namespace bliskrun::test {

// Planar grid on origin + [0,1]·u + [0,1]·v, n_u × n_v quads, two triangles each.
inline TriangleMesh grid_mesh(const Vec3& origin, const Vec3& u, const Vec3& v, int n_u = 1, int n_v = 1) {
  TriangleMesh m;
  for (int i = 0; i <= n_u; ++i) {
    for (int j = 0; j <= n_v; ++j) m.vertices.push_back(origin + u * (double(i) / n_u) + v * (double(j) / n_v));
  }
  auto id = [&](int i, int j) { return i * (n_v + 1) + j; };
  for (int i = 0; i < n_u; ++i) {
    for (int j = 0; j < n_v; ++j) {
      m.triangles.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      m.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  }
  return m;
}

// Closed axis-aligned box, 12 triangles, counter-clockwise seen from outside.
inline TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi) {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k) {
    m.vertices.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  }
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.emplace_back(q[0], q[1], q[2]);
    m.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return m;
}

}  // namespace bliskrun::test
