#pragma once
// A convex part of a tool (core/tools Profile) as pieces a ray can be
// intersected with in closed form: frustums of cones (cylinders, flat-end
// sides, tapers) and zones of spheres centred on the axis (ball ends),
// each a slab z0 <= z <= z1 of the solid. An arc whose centre is off the
// axis (a bull-nose corner, a drum wheel's barrel) turns a torus, whose ray
// intersection is a quartic: it is replaced by its tangent polygon, within
// `torus_tol_mm` outside the arc, so the solid removes at most that much
// more than the tool.
//
// Frame: the tool frame (z up the axis from the reference point, tool.h).
#include <vector>

#include "core/common/types.h"
#include "core/tools/profile.h"

namespace bliskrun {

// A ray p(s) = origin + s·dir (|dir| = 1) expressed in a solid's frame:
// z(s) = z0 + dz·s and r(s)² = a·s² + 2·b·s + c.
struct FrameRay {
  double z0 = 0, dz = 0;
  double a = 0, b = 0, c = 0;
  // From the ray in the part frame and the frame's origin and unit z axis.
  static FrameRay make(const Vec3& origin, const Vec3& dir, const Vec3& frame_origin, const Vec3& frame_axis) {
    const Vec3 p = origin - frame_origin;
    FrameRay r;
    r.z0 = p.dot(frame_axis);
    r.dz = dir.dot(frame_axis);
    // The parts of p and dir across the axis: r(s)² = |p⊥ + s·dir⊥|².
    r.a = 1 - r.dz * r.dz;
    if (r.a < 0) r.a = 0;
    r.b = p.dot(dir) - r.z0 * r.dz;
    r.c = p.squaredNorm() - r.z0 * r.z0;
    if (r.c < 0) r.c = 0;
    return r;
  }
};

class RevolvedSolid {
 public:
  struct Piece {
    double z0 = 0, z1 = 0;
    bool sphere = false;
    double r0 = 0, slope = 0;            // frustum: R(z) = r0 + slope·(z - z0)
    double centre_z = 0, radius = 0;     // sphere zone: r² + (z - centre_z)² <= radius²
    double radius_at(double z) const;
  };

  RevolvedSolid() = default;
  // Throws ParameterError("torus_tol_mm") unless positive.
  RevolvedSolid(const Profile& profile, double torus_tol_mm);

  // The solid swept by translating this one along its own axis by `shift`
  // mm (either sign): for a convex solid a solid of revolution again — the
  // lower part up to the widest section, a cylinder of the largest radius
  // over `shift`, the upper part shifted (what a plunge removes, exactly).
  RevolvedSolid swept_along_axis(double shift) const;

  const std::vector<Piece>& pieces() const { return pieces_; }
  double z_min() const { return z_min_; }
  double z_max() const { return z_max_; }
  double max_radius() const { return max_radius_; }

  // The span of the ray inside the solid's bounding cylinder (its largest
  // radius over its height); false when the ray misses it. Cheap: a caller
  // that can rule the ray out on this span skips the exact intersection.
  bool bound(const FrameRay& ray, double& lo, double& hi) const;
  // The span [lo, hi] of the ray inside the solid (the solid is convex, so
  // it is one span or none), given the ray's bounding span from bound().
  // False when the ray misses it.
  bool intersect(const FrameRay& ray, double bound_lo, double bound_hi, double& lo, double& hi) const;
  bool intersect(const FrameRay& ray, double& lo, double& hi) const {
    double blo, bhi;
    return bound(ray, blo, bhi) && intersect(ray, blo, bhi, lo, hi);
  }

 private:
  void finish();  // z range and largest radius from the pieces
  std::vector<Piece> pieces_;
  double z_min_ = 0, z_max_ = 0, max_radius_ = 0;
};

}  // namespace bliskrun
