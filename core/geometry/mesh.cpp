#include "core/geometry/mesh.h"

#include <cmath>
#include <cstring>
#include <string>

#include "core/common/atomic_file.h"
#include "core/common/error.h"
#include "core/common/memory_budget.h"

namespace bliskrun {

namespace {

struct GridMesh {
  int nu, nv;
};

// Largest distance between the surface and the mesh of an nu x nv grid,
// split into the part due to the u spacing and to the v spacing: measured at
// edge midpoints along each direction and at the centre of each cell's
// diagonal (both triangles of a cell share it).
void sampled_error(const Surface& s, double u0, double u1, double v0, double v1, int nu, int nv,
                   double& err_u, double& err_v, Progress& progress) {
  err_u = err_v = 0;
  auto uat = [&](double i) { return u0 + (u1 - u0) * i / nu; };
  auto vat = [&](double j) { return v0 + (v1 - v0) * j / nv; };
  for (int i = 0; i <= nu; ++i) {
    progress.check();
    for (int j = 0; j <= nv; ++j) {
      const Vec3 p = s.point(uat(i), vat(j));
      if (i < nu) {
        const Vec3 q = s.point(uat(i + 1), vat(j));
        err_u = std::max(err_u, (s.point(uat(i + 0.5), vat(j)) - 0.5 * (p + q)).norm());
      }
      if (j < nv) {
        const Vec3 q = s.point(uat(i), vat(j + 1));
        err_v = std::max(err_v, (s.point(uat(i), vat(j + 0.5)) - 0.5 * (p + q)).norm());
      }
      if (i < nu && j < nv) {
        const Vec3 q = s.point(uat(i + 1), vat(j + 1));
        const double e = (s.point(uat(i + 0.5), vat(j + 0.5)) - 0.5 * (p + q)).norm();
        err_u = std::max(err_u, e);
        err_v = std::max(err_v, e);
      }
    }
  }
}

}  // namespace

TriangleMesh tessellate(const Surface& s, double chord_tol_mm, double u0, double u1, double v0,
                        double v1, Progress& progress) {
  if (!(chord_tol_mm > 0)) throw ParameterError("chord_tol", "must be > 0");
  if (!(u1 > u0) || !(v1 > v0)) throw ParameterError("window", "needs u0 < u1 and v0 < v1");
  // Chordal error of a grid shrinks as the square of the spacing, so each
  // refinement predicts the count that meets the tolerance and verifies it.
  int nu = 8, nv = 8;
  for (int round = 0; round < 12; ++round) {
    // Refused before sampling (the sampling of a huge grid is the slow part)
    // and before allocating: the mesh this grid would become.
    const double vertices = static_cast<double>(nu + 1) * (nv + 1), triangles = 2.0 * nu * nv;
    check_allocation_estimate(vertices * sizeof(Vec3) + triangles * sizeof(Eigen::Vector3i),
                              "tessellate: a " + std::to_string(nu) + " x " + std::to_string(nv) + " grid mesh for " +
                                  std::to_string(chord_tol_mm) + " mm");
    double eu, ev;
    sampled_error(s, u0, u1, v0, v1, nu, nv, eu, ev, progress);
    if (eu <= chord_tol_mm && ev <= chord_tol_mm) break;
    constexpr int kMax = 4096;
    if (eu > chord_tol_mm)
      nu = std::min(kMax, static_cast<int>(std::ceil(nu * std::sqrt(eu / chord_tol_mm) * 1.1)));
    if (ev > chord_tol_mm)
      nv = std::min(kMax, static_cast<int>(std::ceil(nv * std::sqrt(ev / chord_tol_mm) * 1.1)));
    if (round == 11) throw Error("tessellate: tolerance " + std::to_string(chord_tol_mm) +
                                 " mm not reached with a " + std::to_string(nu) + " x " +
                                 std::to_string(nv) + " grid");
  }
  return grid_mesh(s, nu, nv, u0, u1, v0, v1, progress);
}

TriangleMesh grid_mesh(const Surface& s, int nu, int nv, double u0, double u1, double v0, double v1,
                       Progress& progress) {
  if (nu < 1 || nv < 1) throw ParameterError("grid", "needs at least one cell each way");
  TriangleMesh mesh;
  mesh.vertices.reserve(static_cast<size_t>(nu + 1) * (nv + 1));
  for (int i = 0; i <= nu; ++i) {
    progress.check();
    for (int j = 0; j <= nv; ++j)
      mesh.vertices.push_back(s.point(u0 + (u1 - u0) * i / nu, v0 + (v1 - v0) * j / nv));
  }
  auto id = [&](int i, int j) { return i * (nv + 1) + j; };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      // Counter-clockwise seen from pu x pv.
      mesh.triangles.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      mesh.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return mesh;
}

void write_stl(const TriangleMesh& mesh, const std::string& path) {
  std::string out(80, '\0');
  const std::string header = "bliskrun binary STL, mm";
  std::memcpy(out.data(), header.data(), header.size());
  const uint32_t count = static_cast<uint32_t>(mesh.triangles.size());
  out.append(reinterpret_cast<const char*>(&count), 4);
  auto put = [&](const Vec3& v) {
    const float f[3] = {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
    out.append(reinterpret_cast<const char*>(f), 12);
  };
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.vertices[t.x()];
    const Vec3& b = mesh.vertices[t.y()];
    const Vec3& c = mesh.vertices[t.z()];
    const Vec3 n = (b - a).cross(c - a);
    put(n.norm() > 0 ? Vec3(n.normalized()) : Vec3::Zero());
    put(a);
    put(b);
    put(c);
    out.append(2, '\0');
  }
  write_file_atomic(path, out);
}

}  // namespace bliskrun
