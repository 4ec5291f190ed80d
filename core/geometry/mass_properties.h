#pragma once
// Mass, centre of gravity and inertia of solids (issue 39: the payload a
// robot program states — ABB loaddata [mass, cog, aom, ix, iy, iz], KUKA
// $LOAD {M, CM {X, Y, Z, A, B, C}, J {X, Y, Z}} — from the blade body and a
// stated gripper, not a point mass).
//
// A closed triangulated surface is integrated exactly by the divergence
// theorem (each triangle's contribution to the volume integrals of 1, x, y,
// z, x², y², z², xy, yz, zx in closed form; D. Eberly, "Polyhedral Mass
// Properties (Revisited)", 2002): exact for any polyhedron, so a box or a
// prism is its closed form to rounding and a curved solid converges with its
// tessellation. The simple solids a gripper is stated as (box, cylinder)
// have their closed forms. Everything is in mm and kg; inertia in kg·mm²
// about the centre of gravity along the axes of the frame the centre of
// gravity is given in (divide by 1e6 for the controllers' kg·m²).
#include <array>
#include <vector>

#include "core/common/types.h"
#include "core/geometry/registration.h"  // Frame

namespace bliskrun {

struct MassProperties {
  double mass_kg = 0;
  double volume_mm3 = 0;
  Vec3 cog_mm = Vec3::Zero();
  Mat3 inertia_kg_mm2 = Mat3::Zero();  // about cog_mm, in the frame cog_mm is in
};

// A closed, consistently oriented triangulated surface (every edge shared by
// exactly two triangles, once in each direction; inward or outward normals
// alike) of a solid of uniform density (kg/mm³; g/cm³ × 1e-6). Throws Error
// naming an edge where the surface is open or inconsistently oriented.
MassProperties solid_mass_properties(const std::vector<Vec3>& vertices,
                                     const std::vector<std::array<int, 3>>& triangles, double density_kg_mm3);

// The closed surface through a stack of closed loops (each loop the same
// number of points, not repeating its first; consecutive loops joined by
// quads, the first and last capped by a fan from their centroid): the
// vertices and triangles solid_mass_properties takes. A blade is its
// sections across the span.
void closed_loft_mesh(const std::vector<std::vector<Vec3>>& loops, std::vector<Vec3>& vertices,
                      std::vector<std::array<int, 3>>& triangles);

// Closed forms. A box of edges `size` along the axes of `where`, centred on
// its origin; a solid cylinder of `radius` and `length` about `where`'s z
// axis, centred on its origin.
MassProperties box_mass_properties(double mass_kg, const Vec3& size_mm, const Frame& where = Frame::Identity());
MassProperties cylinder_mass_properties(double mass_kg, double radius_mm, double length_mm,
                                        const Frame& where = Frame::Identity());

// The same body described in another frame: `to_new` maps the old frame's
// coordinates into the new one.
MassProperties transformed(const MassProperties& m, const Frame& to_new);
// Two bodies as one (parallel-axis theorem), both in the same frame.
MassProperties combined(const MassProperties& a, const MassProperties& b);

// The principal axes of an inertia tensor: moments (kg·mm²) and the axes as
// the columns of a rotation (right-handed), each axis the one nearest the
// frame's own x, y, z in turn (a diagonal tensor keeps the identity).
struct PrincipalInertia {
  Vec3 moments_kg_mm2 = Vec3::Zero();
  Mat3 axes = Mat3::Identity();
};
PrincipalInertia principal_inertia(const Mat3& inertia_kg_mm2);

}  // namespace bliskrun
