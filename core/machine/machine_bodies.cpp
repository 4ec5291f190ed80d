#include "core/machine/machine_bodies.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/common/error.h"

namespace bliskrun {

void bounding_sphere(const MachineBody& b, Vec3& centre, double& radius) {
  if (b.shape == BodyShape::Mesh) {
    // About the placed vertices' box centre: within a few percent of the
    // smallest sphere for a blade, and one pass.
    Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
    for (const auto& m : b.meshes)
      for (const Vec3& v : m->vertices) {
        const Vec3 p = b.placement * v;
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    centre = 0.5 * (lo + hi);
    radius = 0;
    for (const auto& m : b.meshes)
      for (const Vec3& v : m->vertices) radius = std::max(radius, (b.placement * v - centre).norm());
    radius += b.margin_mm;
    return;
  }
  if (b.shape == BodyShape::Box) {
    centre = 0.5 * (b.min_mm + b.max_mm);
    radius = 0.5 * (b.max_mm - b.min_mm).norm();
    return;
  }
  // A cylinder or cone lies within the sphere about its axis' middle that
  // reaches the rim of its end circles.
  centre = 0.5 * (b.from_mm + b.to_mm);
  radius = std::hypot(0.5 * (b.to_mm - b.from_mm).norm(), b.radius_mm);
}

void validate_bodies(const std::vector<MachineBody>& bodies, const std::vector<std::string>& frames,
                     const std::string& where) {
  std::set<std::string> names;
  for (size_t i = 0; i < bodies.size(); ++i) {
    const MachineBody& b = bodies[i];
    const std::string field = where + "[" + std::to_string(i + 1) + "]";
    if (b.name.empty()) throw ParameterError(field + ".name", "expected a name");
    if (!names.insert(b.name).second)
      throw ParameterError(field + ".name", "'" + b.name + "' names two bodies; names must be unique");
    if (std::find(frames.begin(), frames.end(), b.frame) == frames.end()) {
      std::string list;
      for (const std::string& f : frames) list += (list.empty() ? "" : ", ") + f;
      throw ParameterError(field + ".frame", "'" + b.frame + "' is no frame of this machine, expected one of: " + list);
    }
    if (b.shape == BodyShape::Mesh) {
      size_t triangles = 0;
      for (size_t k = 0; k < b.meshes.size(); ++k) {
        const std::string mesh = field + ".meshes[" + std::to_string(k + 1) + "]";
        if (!b.meshes[k]) throw ParameterError(mesh, "expected a mesh");
        const TriangleMesh& m = *b.meshes[k];
        for (const Vec3& v : m.vertices)
          if (!v.allFinite()) throw ParameterError(mesh, "expected finite vertices");
        for (const Eigen::Vector3i& t : m.triangles)
          for (int j = 0; j < 3; ++j)
            if (t[j] < 0 || t[j] >= static_cast<int>(m.vertices.size()))
              throw ParameterError(mesh, "triangle vertex index " + std::to_string(t[j]) + " outside the " +
                                             std::to_string(m.vertices.size()) + " vertices");
        triangles += m.triangles.size();
      }
      if (triangles == 0) throw ParameterError(field + ".meshes", "expected at least one triangle");
      if (!b.mesh_names.empty() && b.mesh_names.size() != b.meshes.size())
        throw ParameterError(field + ".mesh_names", "expected one name per mesh (" + std::to_string(b.meshes.size()) +
                                                        "), got " + std::to_string(b.mesh_names.size()));
      for (size_t k = 0; k < b.mesh_names.size(); ++k)
        if (b.mesh_names[k].empty())
          throw ParameterError(field + ".mesh_names[" + std::to_string(k + 1) + "]", "expected a non-empty name");
      if (!b.placement.matrix().allFinite()) throw ParameterError(field + ".placement", "expected a finite placement");
      if (!std::isfinite(b.margin_mm) || b.margin_mm < 0)
        throw ParameterError(field + ".margin", "expected a margin >= 0 mm");
      continue;
    }
    if (b.shape == BodyShape::Box) {
      if (!b.min_mm.allFinite() || !b.max_mm.allFinite())
        throw ParameterError(field + ".box", "expected finite corners");
      for (int k = 0; k < 3; ++k)
        if (!(b.min_mm[k] < b.max_mm[k]))
          throw ParameterError(field + ".box", std::string("expected min < max along ") + "XYZ"[k] + ", got " +
                                                   std::to_string(b.min_mm[k]) + " and " + std::to_string(b.max_mm[k]));
      continue;
    }
    const char* kind = b.shape == BodyShape::Cylinder ? ".cylinder" : ".cone";
    if (!b.from_mm.allFinite() || !b.to_mm.allFinite())
      throw ParameterError(field + kind, "expected finite end points");
    if ((b.to_mm - b.from_mm).norm() < 1e-6)
      throw ParameterError(field + kind, "expected distinct end points (a length > 0)");
    if (!std::isfinite(b.radius_mm) || !(b.radius_mm > 0))
      throw ParameterError(field + ".radius", "expected a radius > 0 mm");
  }
}

}  // namespace bliskrun
