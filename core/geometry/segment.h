#pragma once
// Distance from a point to a straight segment (chord checks of rows and of
// a controller's linear blocks).
#include <algorithm>

#include "core/common/types.h"

namespace bliskrun {

// |p - q| for the nearest q on the segment [a, b] (a point when a == b).
inline double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

}  // namespace bliskrun
