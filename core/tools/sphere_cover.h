#pragma once
// A solid of revolution covered by spheres centred on its axis.
//
// What it is for: a distance to a surface that is cheap to evaluate at a
// point but has no mesh to hand to FCL — a surface of revolution, whose
// distance is a 2-D distance in the meridian plane
// (core/geometry/revolution_distance.h). The distance of the solid to such a
// surface is at least min_j (distance of centre j − radius j), because every
// point of the solid lies in some sphere. A ball end's ball is one sphere
// exactly, so a ball running along a hub is measured to the hub as it is.
//
// The spheres cover the profile's circumscribed polygon (Profile::
// circumscribed_polyline), slab by slab along the axis: each slab is as
// long as it can be with its smallest covering sphere (centre on the axis)
// no more than `excess_mm` wider than the solid's largest radius in it.
// Consecutive spheres are grouped under bounding spheres so a query that
// needs only a bound skips whole groups.
#include <vector>

#include "core/tools/profile.h"

namespace bliskrun {

struct AxisSphere {
  double z = 0;       // centre on the tool axis, tool frame, mm
  double radius = 0;  // mm
};

struct SphereCover {
  std::vector<AxisSphere> spheres;  // bottom first
  struct Group {
    int first = 0, count = 0;
    AxisSphere bound;  // contains every sphere of the group
  };
  std::vector<Group> groups;
  // How far the cover may stand outside the solid, radially: the polygon's
  // tolerance plus excess_mm.
  double overestimate_mm = 0;
};

// Throws ParameterError("excess_mm") unless 0 < excess_mm, ("tol_mm") unless
// 0 < tol_mm (the circumscribed polygon's tolerance).
SphereCover sphere_cover(const Profile& profile, double excess_mm, double tol_mm = 1e-3);

}  // namespace bliskrun
