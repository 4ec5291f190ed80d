#include "core/machine/machine_bodies.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/common/error.h"

namespace bliskrun {

void bounding_sphere(const MachineBody& b, Vec3& centre, double& radius) {
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
