#pragma once
// Surfaces of revolution about the Z axis (hub, casing) from a meridian
// profile given as (z, r) points, and intersection of a flank with them.
#include <memory>
#include <vector>

#include "core/geometry/curve.h"
#include "core/geometry/projection.h"
#include "core/geometry/surface.h"

namespace bliskrun {

// r(z) swept about Z. u runs along the meridian (profile parameter), v is the
// angle theta / (2 pi) in [0, 1].
class SurfaceOfRevolution : public Surface {
 public:
  // `meridian` holds (z, r) pairs ordered along the profile (at least 2).
  explicit SurfaceOfRevolution(const std::vector<Vec2>& meridian);
  // The profile as a curve whose points are (z, r, 0) over its [t_min,
  // t_max] (evaluated exactly, not through samples: an impeller's hub is
  // its blade's hub curve revolved); `seed_samples` coarse points seed
  // radial_offset's projection.
  SurfaceOfRevolution(std::shared_ptr<const Curve> meridian_zr, int seed_samples);
  SurfaceDerivs eval(double u, double v) const override;
  // Signed radial offset of q from the surface in its meridian plane:
  // > 0 when q is farther from the axis than the profile at q's position.
  // It is q's distance from the surface (signed): the nearest point of a
  // surface of revolution lies in q's own meridian half-plane.
  double radial_offset(const Vec3& q) const;
  // The unit direction in which radial_offset grows at q (its gradient):
  // from q's foot on the profile towards q, turned about the axis into q's
  // meridian half-plane (the profile's normal there when q is on it).
  // Taken from the foot, not by differences of radial_offset: where the
  // profile interpolates dense, rounded data (Rotor 67's hub near its
  // trailing edge) it wiggles at the um scale, the foot of a point a few mm
  // off jumps between the wiggles, and a difference across such a jump is
  // no direction at all (up to 3.5 long, pointing into the hub).
  Vec3 offset_direction(const Vec3& q) const;
  // r of the profile at axial position z (profile must be single-valued in z
  // there); throws Error if z is outside the profile.
  double radius_at(double z) const;
  // The surface `d` mm away along the normal pu x pv (d < 0: the other
  // side), its profile interpolated through `samples` points of this one's
  // offset. Used to check a cutter that is meant to touch this surface
  // against the surface a little inside it. Throws ParameterError when the
  // profile's curvature radius somewhere is below |d| on the side it moves
  // to (the offset would fold) or samples < 8.
  SurfaceOfRevolution offset(double d, int samples = 400) const;
  // The profile: points (z, r, 0) over its [t_min, t_max]; u runs over it.
  const Curve& profile() const { return *meridian_; }

 private:
  // radial_offset, and the direction it grows in (z, r, 0) when asked.
  double offset_in_meridian(const Vec3& q, Vec3* direction_zr) const;

  std::shared_ptr<const Curve> meridian_;  // points (z, r, 0)
  // radial_offset's projection settings and the coarse sample of the
  // meridian it seeds from, computed once (it is called per cutter point).
  ProjectionOptions foot_options_;
  std::vector<Vec3> foot_seeds_;
};

// Curve where a surface meets a surface of revolution, as (u, v) parameter
// points of `s` ordered along v, found by bracketing along each iso-v line
// and refining with Newton/bisection. Throws Error if some iso-v line does
// not cross the revolution surface.
struct SurfaceCurveOnSurface {
  std::vector<double> u, v;  // parameters on s
  std::vector<Vec3> points;
};
SurfaceCurveOnSurface intersect_with_revolution(const Surface& s,
                                                const SurfaceOfRevolution& rev,
                                                int samples_v = 200);

}  // namespace bliskrun
