#pragma once
// FCL geometry of a tool: one collision object per part (cutter, shank,
// holder), so clearances can differ per part.
//
// Every part is a BVH mesh (OBBRSS) of its circumscribed polygonal solid of
// revolution: the meridian is replaced by its tangent (circumscribed)
// polyline within tol_mm, and each ring by a regular N-gon circumscribing
// the circle of its radius, N chosen so the corners stand at most tol_mm
// outside. The mesh therefore ENCLOSES the true solid and lies within
// overestimate_mm (<= ~2 tol_mm) outside it: a clearance FCL reports is at
// most overestimate_mm smaller than the truth, never larger.
//
// Why meshes and not fcl::Convex / fcl::Cylinder: FCL bounds a shape by one
// loose OBBRSS, so a shape-vs-mesh distance visits every blade triangle
// within that slack (measured: 25–35 ms per query against a 100k-triangle
// blade); mesh-vs-mesh traversal keeps both hierarchies tight (µs).
#include <memory>
#include <vector>

#include "core/tools/fcl_fwd.h"

#include "core/tools/sphere_cover.h"
#include "core/tools/tool.h"

namespace bliskrun {

// A part's body is one or more pieces stacked along the axis. A motion
// check steps by how fast a piece can move (|Δtip| + θ·reach), so a long
// cutter is cut in two: its bottom — the ball that runs close along a hub —
// moves far slower when the axis turns than its 90 mm flute's top, and
// proving the bottom clear no longer takes the top's small steps.
struct FclPiece {
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> geometry;  // in the tool frame
  double reach_mm = 0;  // largest distance of a piece point from the reference point
  double z_max = 0;          // top of the piece along the axis, tool frame
  double overestimate_mm = 0;  // how far its body may stand outside the part
  // The piece covered by spheres on its axis (within kCoverExcessMm), for
  // check surfaces measured analytically (a surface of revolution).
  SphereCover cover;
  // The same piece meshed to kCoarsePieceTolMm, when `geometry` is finer:
  // it encloses the part too, within coarse_overestimate_mm. A motion proof
  // asks it first and takes its distance where that is far from the
  // clearance (collision_world.h), so the fine mesh is traversed only near.
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> coarse;
  double coarse_overestimate_mm = 0;
};

// The tolerance of a piece's coarse mesh (FclPiece::coarse), mm.
constexpr double kCoarsePieceTolMm = 0.01;

// How much wider than the tool its sphere cover may be, mm.
constexpr double kCoverExcessMm = 0.01;

struct FclToolPart {
  ToolPartId id = ToolPartId::Cutter;
  std::vector<FclPiece> pieces;  // bottom first; together the whole part
  double overestimate_mm = 0;    // how far the FCL body may stand outside the part (largest over the pieces)
  // The overestimate of the piece at height z (tool frame) of the axis.
  double overestimate_at(double z) const;
  double reach_mm = 0;           // largest distance of a body point from the reference point
};

// How coarsely the top piece of a long cutter is meshed, mm (its
// overestimate; see fcl_parts).
constexpr double kFluteTopTolMm = 0.05;

// The present parts of `tool`, cutter first. A cutter more than four of its
// largest radii long is cut at two radii above its bottom, and its top
// piece meshed to kFluteTopTolMm (the bottom to tol_mm). Throws
// ParameterError("tol_mm") unless 0 < tol_mm.
std::vector<FclToolPart> fcl_parts(const Tool& tool, double tol_mm);

// The circumscribed polygonal solid of revolution as vertices and convex
// planar faces (index lists, counter-clockwise seen from outside), before it
// is triangulated into FCL; exposed for tests and export.
struct RevolvedPolytope {
  std::vector<Vec3> vertices;
  std::vector<std::vector<int>> faces;
  double overestimate_mm = 0;
};
RevolvedPolytope circumscribed_polytope(const Profile& profile, double tol_mm);

}  // namespace bliskrun
