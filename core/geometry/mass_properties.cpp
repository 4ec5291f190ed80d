#include "core/geometry/mass_properties.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "core/common/error.h"

namespace bliskrun {

namespace {

// Eberly's subexpressions of one coordinate over a triangle's corners.
struct MassTriangleTerms {
  double f1, f2, f3, g0, g1, g2;
};

MassTriangleTerms mass_triangle_terms(double w0, double w1, double w2) {
  MassTriangleTerms t;
  const double temp0 = w0 + w1, temp1 = w0 * w0, temp2 = temp1 + w1 * temp0;
  t.f1 = temp0 + w2;
  t.f2 = temp2 + w2 * t.f1;
  t.f3 = w0 * temp1 + w1 * temp2 + w2 * t.f2;
  t.g0 = t.f2 + w0 * (t.f1 + w0);
  t.g1 = t.f2 + w1 * (t.f1 + w1);
  t.g2 = t.f2 + w2 * (t.f1 + w2);
  return t;
}

}  // namespace

MassProperties solid_mass_properties(const std::vector<Vec3>& vertices,
                                     const std::vector<std::array<int, 3>>& triangles, double density_kg_mm3) {
  if (!(density_kg_mm3 > 0) || !std::isfinite(density_kg_mm3))
    throw Error("solid_mass_properties: the density must be positive");
  if (triangles.size() < 4) throw Error("solid_mass_properties: a closed surface needs at least 4 triangles");
  // Closed and consistently oriented: each directed edge once, and its
  // reverse once.
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (a < 0 || b < 0 || a >= static_cast<int>(vertices.size()) || b >= static_cast<int>(vertices.size()))
        throw Error("solid_mass_properties: a triangle names vertex " + std::to_string(a < 0 || a >= int(vertices.size()) ? a : b) +
                    " of " + std::to_string(vertices.size()));
      if (++directed[{a, b}] > 1)
        throw Error("solid_mass_properties: edge (" + std::to_string(a) + ", " + std::to_string(b) +
                    ") is used twice in one direction: the surface is not consistently oriented");
    }
  }
  for (const auto& [e, n] : directed)
    if (!directed.count({e.second, e.first}))
      throw Error("solid_mass_properties: edge (" + std::to_string(e.first) + ", " + std::to_string(e.second) +
                  ") borders one triangle only: the surface is not closed");
  // About the vertices' mean: blade coordinates hundreds of mm from the
  // origin would otherwise cancel in the second moments.
  Vec3 shift = Vec3::Zero();
  for (const Vec3& v : vertices) shift += v;
  shift /= static_cast<double>(vertices.size());
  double intg[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  for (const auto& t : triangles) {
    const Vec3 p0 = vertices[t[0]] - shift, p1 = vertices[t[1]] - shift, p2 = vertices[t[2]] - shift;
    const Vec3 d = (p1 - p0).cross(p2 - p0);
    const MassTriangleTerms x = mass_triangle_terms(p0.x(), p1.x(), p2.x());
    const MassTriangleTerms y = mass_triangle_terms(p0.y(), p1.y(), p2.y());
    const MassTriangleTerms z = mass_triangle_terms(p0.z(), p1.z(), p2.z());
    intg[0] += d.x() * x.f1;
    intg[1] += d.x() * x.f2;
    intg[2] += d.y() * y.f2;
    intg[3] += d.z() * z.f2;
    intg[4] += d.x() * x.f3;
    intg[5] += d.y() * y.f3;
    intg[6] += d.z() * z.f3;
    intg[7] += d.x() * (p0.y() * x.g0 + p1.y() * x.g1 + p2.y() * x.g2);
    intg[8] += d.y() * (p0.z() * y.g0 + p1.z() * y.g1 + p2.z() * y.g2);
    intg[9] += d.z() * (p0.x() * z.g0 + p1.x() * z.g1 + p2.x() * z.g2);
  }
  const double mult[10] = {1.0 / 6, 1.0 / 24, 1.0 / 24, 1.0 / 24, 1.0 / 60, 1.0 / 60, 1.0 / 60,
                           1.0 / 120, 1.0 / 120, 1.0 / 120};
  for (int i = 0; i < 10; ++i) intg[i] *= mult[i];
  // Inward normals give every integral the other sign.
  if (intg[0] < 0)
    for (double& v : intg) v = -v;
  if (!(intg[0] > 0)) throw Error("solid_mass_properties: the surface encloses no volume");
  const double volume = intg[0];
  const Vec3 c(intg[1] / volume, intg[2] / volume, intg[3] / volume);  // about `shift`
  MassProperties m;
  m.volume_mm3 = volume;
  m.mass_kg = density_kg_mm3 * volume;
  m.cog_mm = c + shift;
  Mat3& I = m.inertia_kg_mm2;
  I(0, 0) = intg[5] + intg[6] - volume * (c.y() * c.y() + c.z() * c.z());
  I(1, 1) = intg[4] + intg[6] - volume * (c.z() * c.z() + c.x() * c.x());
  I(2, 2) = intg[4] + intg[5] - volume * (c.x() * c.x() + c.y() * c.y());
  I(0, 1) = I(1, 0) = -(intg[7] - volume * c.x() * c.y());
  I(1, 2) = I(2, 1) = -(intg[8] - volume * c.y() * c.z());
  I(0, 2) = I(2, 0) = -(intg[9] - volume * c.z() * c.x());
  I *= density_kg_mm3;
  return m;
}

void closed_loft_mesh(const std::vector<std::vector<Vec3>>& loops, std::vector<Vec3>& vertices,
                      std::vector<std::array<int, 3>>& triangles) {
  if (loops.size() < 2) throw Error("closed_loft_mesh: at least two loops");
  const size_t n = loops.front().size();
  if (n < 3) throw Error("closed_loft_mesh: a loop needs at least 3 points");
  for (size_t k = 0; k < loops.size(); ++k)
    if (loops[k].size() != n)
      throw Error("closed_loft_mesh: loop " + std::to_string(k + 1) + " has " + std::to_string(loops[k].size()) +
                  " points, loop 1 " + std::to_string(n));
  vertices.clear();
  triangles.clear();
  for (const auto& loop : loops) vertices.insert(vertices.end(), loop.begin(), loop.end());
  auto at = [n](size_t loop, size_t i) { return static_cast<int>(loop * n + i % n); };
  for (size_t k = 0; k + 1 < loops.size(); ++k)
    for (size_t i = 0; i < n; ++i) {
      triangles.push_back({at(k, i), at(k, i + 1), at(k + 1, i + 1)});
      triangles.push_back({at(k, i), at(k + 1, i + 1), at(k + 1, i)});
    }
  // The ends: a fan from each end loop's centroid, turned against the tube's
  // edges along that loop so every edge is crossed once each way.
  for (size_t end : {size_t(0), loops.size() - 1}) {
    Vec3 c = Vec3::Zero();
    for (const Vec3& p : loops[end]) c += p;
    vertices.push_back(c / static_cast<double>(n));
    const int centre = static_cast<int>(vertices.size()) - 1;
    for (size_t i = 0; i < n; ++i)
      triangles.push_back(end == 0 ? std::array<int, 3>{centre, at(end, i + 1), at(end, i)}
                                   : std::array<int, 3>{centre, at(end, i), at(end, i + 1)});
  }
}

MassProperties box_mass_properties(double mass_kg, const Vec3& size_mm, const Frame& where) {
  if (!(mass_kg >= 0) || !(size_mm.minCoeff() > 0)) throw Error("box_mass_properties: mass >= 0 and sizes > 0");
  MassProperties m;
  m.mass_kg = mass_kg;
  m.volume_mm3 = size_mm.prod();
  const Vec3 s2 = size_mm.cwiseProduct(size_mm);
  m.inertia_kg_mm2 = (mass_kg / 12.0 * Vec3(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y())).asDiagonal();
  return transformed(m, where);
}

MassProperties cylinder_mass_properties(double mass_kg, double radius_mm, double length_mm, const Frame& where) {
  if (!(mass_kg >= 0) || !(radius_mm > 0) || !(length_mm > 0))
    throw Error("cylinder_mass_properties: mass >= 0, radius and length > 0");
  MassProperties m;
  m.mass_kg = mass_kg;
  m.volume_mm3 = kPi * radius_mm * radius_mm * length_mm;
  const double across = mass_kg * (3 * radius_mm * radius_mm + length_mm * length_mm) / 12.0;
  m.inertia_kg_mm2 = Vec3(across, across, mass_kg * radius_mm * radius_mm / 2.0).asDiagonal();
  return transformed(m, where);
}

MassProperties transformed(const MassProperties& m, const Frame& to_new) {
  MassProperties t = m;
  t.cog_mm = to_new * m.cog_mm;
  const Mat3 R = to_new.linear();
  t.inertia_kg_mm2 = R * m.inertia_kg_mm2 * R.transpose();
  return t;
}

MassProperties combined(const MassProperties& a, const MassProperties& b) {
  MassProperties m;
  m.mass_kg = a.mass_kg + b.mass_kg;
  m.volume_mm3 = a.volume_mm3 + b.volume_mm3;
  if (!(m.mass_kg > 0)) return m;
  m.cog_mm = (a.mass_kg * a.cog_mm + b.mass_kg * b.cog_mm) / m.mass_kg;
  // Each body's tensor moved from its own centre of gravity to the common one.
  auto moved = [&](const MassProperties& p) {
    const Vec3 d = p.cog_mm - m.cog_mm;
    return Mat3(p.inertia_kg_mm2 + p.mass_kg * (d.squaredNorm() * Mat3::Identity() - d * d.transpose()));
  };
  m.inertia_kg_mm2 = moved(a) + moved(b);
  return m;
}

PrincipalInertia principal_inertia(const Mat3& inertia) {
  PrincipalInertia p;
  const Mat3 sym = 0.5 * (inertia + inertia.transpose());
  const double scale = sym.norm();
  if (!(scale > 0)) return p;
  // Already diagonal (to rounding): the frame's own axes.
  const double off = std::sqrt(sym(0, 1) * sym(0, 1) + sym(0, 2) * sym(0, 2) + sym(1, 2) * sym(1, 2));
  if (off <= 1e-12 * scale) {
    p.moments_kg_mm2 = sym.diagonal();
    return p;
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(sym);
  const Mat3 v = eig.eigenvectors();
  // Each frame axis in turn takes the eigenvector nearest it, pointing its way.
  bool used[3] = {false, false, false};
  for (int axis = 0; axis < 3; ++axis) {
    int best = -1;
    for (int k = 0; k < 3; ++k)
      if (!used[k] && (best < 0 || std::abs(v(axis, k)) > std::abs(v(axis, best)))) best = k;
    used[best] = true;
    p.axes.col(axis) = v(axis, best) < 0 ? Vec3(-v.col(best)) : Vec3(v.col(best));
    p.moments_kg_mm2[axis] = eig.eigenvalues()[best];
  }
  if (p.axes.determinant() < 0) p.axes.col(2) = -p.axes.col(2);
  return p;
}

}  // namespace bliskrun
