#pragma once
// The blisk paper's interference check (§3.4, eq. 20), kept as a fast
// pre-filter in front of FCL.
//
// Each check-surface point P_i goes into the tool frame, P'_i = T (P_i − P);
// with Z its height along the axis and ρ = √(X² + Y²), the point interferes
// with a part whose height range holds Z when ρ < R_part(Z) + clearance.
// The paper compares the shank radius above L_c and R(Z) inside the head;
// here every present part (cutter, shank, holder) is compared the same way.
//
// Where it and FCL disagree, by construction:
//  - it sees only the sampled points: a triangle whose vertices are all
//    clear can still pass through the tool (thin features, coarse meshes);
//  - it compares radially, not by distance: a point just below the tip or
//    beyond the holder is never in conflict, though closer than the
//    clearance;
//  - it checks poses, not the motion between them (paper Fig. 9).
// So a "clear" from it is not a proof; a conflict from it is real: a point
// with ρ < R(Z) + c lies within c of the tool's surface point (R(Z), Z).
//
// Cost is linear in the points: measured 1.1 ms per pose for the 100k
// vertices of two blade flanks, about 30 times a horizon-bounded FCL query
// on the same passage (bench/collision_bench.cpp). It pays only as a
// pre-filter on a small point set already near the tool.
#include <vector>

#include "core/tools/pose.h"
#include "core/tools/tool.h"

namespace bliskrun {

struct Clearances;

struct FastCheck {
  bool clear = true;
  long conflicts = 0;       // number of points in conflict
  long first_conflict = -1;  // index of the first one
  ToolPartId part = ToolPartId::Cutter;  // the part it conflicts with
  double min_margin_mm = 0;  // min over points inside some part's z-range of ρ − R(Z) − clearance
};

FastCheck fast_check(const Tool& tool, const ToolPose& pose, const std::vector<Vec3>& points,
                     const Clearances& clearances);

}  // namespace bliskrun
