#pragma once
// Triangle meshes: tessellation of a surface with a chordal tolerance, for
// collision (FCL BVH models) and export (STL).
#include <string>
#include <vector>

#include "core/geometry/surface.h"

namespace bliskrun {

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<Eigen::Vector3i> triangles;  // indices into vertices, CCW seen from the normal
};

// Grid tessellation of s over [u0,u1]x[v0,v1], refined (per direction) until
// the distance between each triangle and the surface is within chord_tol_mm.
TriangleMesh tessellate(const Surface& s, double chord_tol_mm,
                        double u0 = 0, double u1 = 1, double v0 = 0, double v1 = 1);

// Binary STL, written atomically.
void write_stl(const TriangleMesh& mesh, const std::string& path);

}  // namespace bliskrun
