#pragma once
// Meridian profiles of convex solids of revolution.
//
// A tool (or one part of it) is the solid swept by a region of the (r, z)
// half-plane turning about the z axis. The region is bounded by the axis and
// a chain of straight segments and circular arcs that starts on the axis at
// the bottom, runs outwards and upwards, and ends on the axis at the top, so
// the region lies to the left of the chain (counter-clockwise). Every cutter
// of the five papers has a convex region (drum and conical drum wheels,
// flat-end mills with corner radius, ball and tapered ball ends, contact
// wheels), and the profile requires it: that makes R(z) single-valued, the
// contact point for a given normal unique, and the FCL body a convex hull.
#include <utility>
#include <vector>

#include "core/common/types.h"

namespace bliskrun {

// A straight segment or a counter-clockwise (convex) circular arc in (r, z).
struct ProfileElement {
  enum class Kind { Segment, Arc };
  Kind kind = Kind::Segment;
  Vec2 start = Vec2::Zero();  // (r, z), mm
  Vec2 end = Vec2::Zero();
  // Arc only: centre and radius; the arc runs counter-clockwise from start to
  // end through less than a half turn.
  Vec2 centre = Vec2::Zero();
  double radius = 0;

  static ProfileElement segment(const Vec2& a, const Vec2& b);
  static ProfileElement arc(const Vec2& centre, double radius, const Vec2& a, const Vec2& b);
};

// A point of the profile with its outward unit normal in (r, z).
struct ProfilePoint {
  Vec2 point = Vec2::Zero();
  Vec2 normal = Vec2::Zero();
  int element = -1;  // index of the element it lies on (a vertex: the later one)
};

// Intersection of the profile with the residual surface (blisk paper §3.1,
// Fig. 6), in the 2-D section through the tool axis and the surface normal:
// s along the surface tangent in that plane, t along the surface normal
// (towards the tool), origin at the contact point.
struct CutWidth {
  double width_mm = 0;   // |P_a P_b|
  Vec2 a = Vec2::Zero();  // P_a, (s, t), on the tip side of the contact
  Vec2 b = Vec2::Zero();  // P_b, on the shank side
};

class Profile {
 public:
  Profile() = default;
  // Validates the chain: starts and ends on the axis (r = 0, within 1e-9 mm),
  // consecutive elements meet, r >= 0, z never decreases, convex turn at
  // every vertex. Throws ParameterError("profile", why) otherwise.
  explicit Profile(std::vector<ProfileElement> elements);

  const std::vector<ProfileElement>& elements() const { return elements_; }
  double z_min() const { return z_min_; }
  double z_max() const { return z_max_; }
  double max_radius() const { return max_radius_; }
  // Largest distance of a point of the solid from the origin (the tool's
  // reference point): bounds how far a point moves when the tool turns.
  double reach() const { return reach_; }

  // The solid cut by the plane at height z: the part below and the part
  // above, each closed by a segment along the cut. Throws ParameterError
  // unless z_min < z < z_max.
  std::pair<Profile, Profile> split_at(double z) const;
  // R(z): radius of the solid at height z; 0 outside [z_min, z_max].
  double radius_at(double z) const;
  // Points on the solid's surface between heights z0 and z1 (clipped to
  // [z_min, z_max]), in its frame: `rings` + 1 rings of R(z), `around`
  // points each, and the bottom face at z0 (a ring at half the radius and
  // its centre). For quick clearance rules against analytic surfaces (a
  // hub of revolution), where asking the exact check would be too costly.
  std::vector<Vec3> surface_samples(double z0, double z1, int rings, int around) const;

  // Exact signed distance from (r, z) to the profile: negative inside the
  // solid. For a solid of revolution this is the 3-D signed distance of any
  // point with that radius and height.
  double signed_distance(const Vec2& rz) const;
  // Same for a point in the tool frame (z along the axis).
  double signed_distance(const Vec3& p_tool) const;
  // Nearest point of the profile to (r, z) (r >= 0).
  ProfilePoint closest_point(const Vec2& rz) const;

  // The profile point whose outward normal is n = (n_r, n_z), n_r >= 0, unit.
  // On a vertex the normal may lie anywhere in the vertex's normal cone; on a
  // straight element whose normal equals n the contact is its first point
  // (nearest the bottom of the chain).
  ProfilePoint point_with_normal(const Vec2& n) const;

  // The side point (R(z), z), z in (z_min, z_max), with its outward normal.
  ProfilePoint side_point(double z) const;

  // Normal curvatures of the surface at the side point of height z: along the
  // meridian (1/ρ on an arc, 0 on a segment; at a vertex, those of the
  // element below) and along the parallel (n_r / r).
  double meridian_curvature(double z) const;
  double parallel_curvature(double z) const;
  // Effective cutting radius at height z along a tangent direction that makes
  // `angle_from_meridian_rad` with the meridian (Euler: k = k_m cos² + k_p sin²);
  // +infinity where the surface is flat along that direction.
  double effective_radius(double z, double angle_from_meridian_rad) const;

  // Cut width (blisk paper Fig. 6): the tool touches a surface at the side
  // point of height z_contact; in the section through the axis and the
  // surface normal, the surface has normal curvature k_surface (1/mm; with the
  // normal out of the material: > 0 concave, < 0 convex); the residual
  // surface lies residual_height_mm above it. Returns the two points where
  // the profile meets the residual curve nearest the contact on either side
  // — on an end face when the side stays below the residual height to its
  // end, so the strip is then bounded by the tool's length, which is right:
  // the residual there is below the allowed height. Exact (segment/arc
  // against circle/line). Throws ParameterError when the
  // tool cannot touch the surface there without gouging (k_surface at least
  // the profile's meridian curvature) or when the profile ends before it
  // reaches the residual height.
  CutWidth cut_width(double z_contact, double k_surface_per_mm, double residual_height_mm) const;

  // A closed polyline in (r, z) circumscribing the profile: every point of
  // the solid lies inside it, and it lies within tol_mm outside the profile
  // (arcs are replaced by tangent polygons). Starts and ends on the axis.
  std::vector<Vec2> circumscribed_polyline(double tol_mm) const;

 private:
  int element_at(double z) const;  // the non-horizontal element spanning z

  // Where the bounding cylinder's distance is the solid's own: the elements
  // shared with the cylinder's boundary (signed_distance's fast path).
  bool on_own_boundary(double r, double z) const;

  std::vector<ProfileElement> elements_;
  double z_min_ = 0, z_max_ = 0, max_radius_ = 0, reach_ = 0;
  // The parts of the bounding cylinder's boundary that are the solid's: the
  // side at max_radius for z in [side_z_lo_, side_z_hi_] (none: lo = z_max,
  // hi = z_min), the bottom face for r <= flat_bottom_r_ and the top face
  // for r <= flat_top_r_ (0: only the axis point).
  double side_z_lo_ = 0, side_z_hi_ = 0, flat_bottom_r_ = 0, flat_top_r_ = 0;
};

}  // namespace bliskrun
