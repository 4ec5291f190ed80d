#pragma once
// Differential geometry of a surface point (blisk paper §2.2, eq. 9–11, 14).
#include "core/geometry/surface.h"

namespace bliskrun {

struct SurfaceCurvature {
  Vec3 normal = Vec3::Zero();  // unit, along pu x pv
  double E = 0, F = 0, G = 0;  // first fundamental form
  double L = 0, M = 0, N = 0;  // second fundamental form (w.r.t. unit normal)
  double K = 0;                // Gaussian curvature
  double H = 0;                // mean curvature
  double k1 = 0, k2 = 0;       // principal curvatures, k1 >= k2 (signed by normal)
  Vec3 dir1 = Vec3::Zero();    // unit principal direction of k1 (3-D tangent)
  Vec3 dir2 = Vec3::Zero();    // unit principal direction of k2
};

// Throws Error if the point is singular (pu x pv == 0).
SurfaceCurvature curvature(const SurfaceDerivs& d);

// Normal curvature along a 3-D tangent direction t (projected onto the
// tangent plane and normalised): II(t)/I(t). Equals Euler's
// k1 cos^2(a) + k2 sin^2(a) with a the angle from dir1 (eq. 14).
double normal_curvature(const SurfaceDerivs& d, const Vec3& tangent);

}  // namespace bliskrun
