#pragma once
// Triangle meshes: tessellation of a surface with a chordal tolerance, for
// collision (FCL BVH models) and export (STL).
#include <string>
#include <vector>

#include "core/common/progress.h"
#include "core/geometry/surface.h"

namespace bliskrun {

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<Eigen::Vector3i> triangles;  // indices into vertices, CCW seen from the normal
};

// Grid tessellation of s over [u0,u1]x[v0,v1], refined (per direction) until
// the distance between each triangle and the surface is within chord_tol_mm.
// Checks `progress` for cancellation once per grid row (a 4096-wide row is a
// few ms of work); refuses, before allocating, a mesh whose estimated size
// exceeds the run's memory budget (core/common/memory_budget.h).
TriangleMesh tessellate(const Surface& s, double chord_tol_mm,
                        double u0 = 0, double u1 = 1, double v0 = 0, double v1 = 1,
                        Progress& progress = Progress::none());

// The nu x nv grid of s's parameters over [u0,u1]x[v0,v1] as a mesh:
// (nu + 1)(nv + 1) corners s.point(u, v), two triangles a cell (tessellate's
// mesh, at a density given rather than found). Checks `progress` once per
// grid row.
TriangleMesh grid_mesh(const Surface& s, int nu, int nv, double u0 = 0, double u1 = 1, double v0 = 0, double v1 = 1,
                       Progress& progress = Progress::none());

// Binary STL, written atomically.
void write_stl(const TriangleMesh& mesh, const std::string& path);

}  // namespace bliskrun
