#pragma once
// FCL geometry of a tool: one collision object per part (cutter, shank,
// holder), so clearances can differ per part.
//
// Cylindrical parts (shanks, holders, contact wheels, sharp flat-end mills)
// are fcl::Cylinder: exact. Other cutters are the convex hull of their
// profile revolved as a polygon: the meridian is replaced by its tangent
// (circumscribed) polyline within tol_mm, and each ring by a regular N-gon
// circumscribing the circle of its radius, with N chosen so the ring's
// corners stand at most tol_mm outside. Hence the FCL body CONTAINS the true
// solid and lies within overestimate_mm (<= ~2 tol_mm) outside it: a
// clearance FCL reports is at most overestimate_mm smaller than the truth,
// never larger, and a pose FCL calls clear is clear.
#include <memory>
#include <vector>

#include <fcl/fcl.h>

#include "core/tools/tool.h"

namespace bliskrun {

struct FclToolPart {
  ToolPartId id = ToolPartId::Cutter;
  std::shared_ptr<fcl::CollisionGeometryd> geometry;
  Eigen::Isometry3d in_tool = Eigen::Isometry3d::Identity();  // geometry frame -> tool frame
  double overestimate_mm = 0;  // how far the FCL body may stand outside the part
  double reach_mm = 0;         // largest distance of a body point from the reference point
};

// The present parts of `tool`, cutter first. Throws ParameterError("tol_mm")
// unless 0 < tol_mm.
std::vector<FclToolPart> fcl_parts(const Tool& tool, double tol_mm);

// The circumscribed polygonal solid of revolution as vertices and faces
// (faces as index lists, counter-clockwise seen from outside), before it
// goes into FCL; exposed for tests and export.
struct RevolvedPolytope {
  std::vector<Vec3> vertices;
  std::vector<std::vector<int>> faces;
  double overestimate_mm = 0;
};
RevolvedPolytope circumscribed_polytope(const Profile& profile, double tol_mm);

}  // namespace bliskrun
