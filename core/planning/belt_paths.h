#pragma once
// Contact-wheel paths for robotic belt grinding of a blade face (belt paper
// §2, eq. 1-6, Fig. 2; SPEC §6.3).
//
// The robot holds the blade against a contact wheel carrying the belt. The
// wheel's axis lies along the path (the belt runs across it), so across the
// path the wheel is a circle of radius r and along it a band of width w.
//
// Flow (Fig. 2): the first path is the iso-parameter curve at the face's
// edge; it is trimmed by w/2 of arc length at both ends so the wheel never
// overhangs the face; points are stepped from the start of that range by the
// chord error ε and the last point is the end of the range (eq. 1-2:
// L <= √(8εR)). At every point the step-over to the next path follows from
// the scallop height h and the face's normal curvature across the path
// (eq. 3-5, written as one formula: L = 2√(2rh / (1 + r·κ)), κ > 0 convex,
// κ < 0 concave — eq. 4 is κ = 1/R, eq. 5 κ = -1/R); the next path is placed
// at the smallest step-over found along the current one, until it leaves the
// face.
//
// The paper's correction (§2.3, eq. 6): a step computed from the current
// point's curvature is too long where the curvature rises; so the step is
// predicted, the curvature at the predicted point taken, and the step
// recomputed with the larger of the two. The same for the step-over. Where
// the paper is loose or unsafe we say so and differ:
//  - Step-over on concave regions: the larger |κ| gives the *longer* step-over
//    there (eq. 5), so "take the larger curvature" is not conservative; we
//    take the smaller of the two step-overs, which is the paper's rule on
//    convex regions.
//  - Measured, not assumed: every segment's chord error and the scallop
//    between neighbouring paths are measured by sampled distances (the wheel
//    as the cylinder of radius r about its axis through each contact); with
//    `guarantee`, a step or a step-over whose measurement exceeds ε or h is
//    shortened until it does not (the formulas are approximations).
//  - The far edge: the paper stops when the next path leaves the face, which
//    leaves a strip narrower than one step-over unground; like the last point
//    of a path, the last path is put on the far edge.
#include <string>
#include <vector>

#include "core/common/progress.h"
#include "core/geometry/surface.h"

namespace bliskrun {

struct ContactWheel {
  double radius_mm = 0;  // r
  double width_mm = 0;   // w, along the path
};

enum class BeltPathDirection { AlongV, AlongU };  // paths at constant u (run along v), or at constant v

struct BeltPathOptions {
  double chord_tol_mm = 0.01;  // ε
  double scallop_mm = 0.005;   // h
  BeltPathDirection direction = BeltPathDirection::AlongV;
  bool paper_correction = true;  // eq. 6; false: the current point's curvature only
  bool guarantee = true;         // shorten steps / step-overs whose measurement exceeds ε / h
  // The wheel is on the side of pu x pv (true) or of -(pu x pv).
  bool normal_along_pu_x_pv = true;
  double max_step_mm = 20;
  int scallop_samples = 24;  // cross-section samples between two paths, per point
};

struct BeltPath {
  double across = 0;             // the constant parameter (u for AlongV)
  std::vector<double> along;     // the parameter of each point along the path
  std::vector<Vec3> points;      // contact points
  std::vector<Vec3> normals;     // unit, the wheel's side
  std::vector<Vec3> tangents;    // unit, along the path (the wheel axis)
  std::vector<double> step_over_mm;   // eq. 4/5 (with the correction) per point
  std::vector<double> chord_mm;       // measured chord error per segment
  double chord_max_mm = 0;
  double scallop_max_mm = 0;     // measured, to the next path (0 on the last)
  double length_mm = 0;          // trimmed arc length
};

struct BeltPlan {
  std::vector<BeltPath> paths;
  long points = 0;
  double chord_max_mm = 0;
  double scallop_max_mm = 0;
  int step_halvings = 0;      // steps shortened by the guarantee
  int step_over_shrinks = 0;  // step-overs shortened by the guarantee
};

// Eq. 3-5: the step-over L for scallop h between two passes of a wheel of
// radius r over a face of normal curvature κ across the passes (> 0 convex).
// Throws ParameterError("wheel radius") where the wheel does not fit a
// concave face (r·κ <= -1).
double belt_step_over(double scallop_mm, double wheel_radius_mm, double curvature_across);

// Eq. 3 solved exactly (no small-angle approximation), for the tests and the
// comparison: the distance between contacts that leaves exactly h between
// two circles of radius r on a circle of curvature κ (κ = 0: a line).
double belt_step_over_exact(double scallop_mm, double wheel_radius_mm, double curvature_across);

// Plans the paths over the whole face. Throws ParameterError naming the
// option (wheel radius, width, tolerances) and Error naming (u, v) where the
// wheel does not fit or a step cannot meet the tolerance.
BeltPlan plan_belt_paths(const Surface& face, const ContactWheel& wheel, const BeltPathOptions& options,
                         Progress& progress = Progress::none());

}  // namespace bliskrun
