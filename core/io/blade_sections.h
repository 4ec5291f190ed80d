#pragma once
// Blade geometry given as section loops, the common result of the Rotor 37
// and HECC impeller readers. Everything is in the part frame, millimetres,
// Z on the rotor axis: a point at axial position z, radius r and angle θ is
// (r cos θ, r sin θ, z). Units are converted once, by the reader.
#include <string>
#include <vector>

#include "core/common/types.h"

namespace bliskrun {

struct BladeSections {
  std::string source;  // the file (or first file) the sections were read from
  int blade_count = 0;
  // Direction of rotation when the source states it: +1 towards +θ
  // (right-handed about +Z), -1 towards -θ, 0 not stated (the blade model
  // then takes it from the camber; core/parts/blade_model.h).
  int rotation_sign = 0;
  // Closed loops ordered hub -> tip. The closing segment (last -> first
  // point) is implied; the first point is not repeated.
  std::vector<std::vector<Vec3>> sections;
  // Meridional (z, r) polylines in mm, in flow order. Not necessarily
  // monotonic in z (radial machines turn outward).
  std::vector<Vec2> hub_meridian, casing_meridian;
};

}  // namespace bliskrun
