#pragma once
// Rigid registration of a measured point cloud to a model (belt paper §1: the
// laser scan of the blade as it sits in the gripper; repair paper §1.4:
// design sections to measured ones), by point-to-plane ICP.
//
// The model is a dense sample of its surfaces with normals. Each iteration
// pairs every scan point with its nearest model sample, drops pairs farther
// than the rejection distance, and solves the linearised point-to-plane
// problem  min Σ ((R p + t - q) · n)²  for a small rotation and translation
// (6 x 6 normal equations), applied as an exact rotation. The rejection
// distance starts at `initial_reach` (the clamping error expected: the scan
// starts from the nominal pose) and then follows the data: `outlier_factor`
// times the median pair distance, never below `min_reach`, so stray points
// (fixture, dust, the gripper) stop pulling once the bulk has converged.
#include <vector>

#include "core/common/types.h"

namespace bliskrun {

// A rigid transform, here scan frame -> model frame; the same type as
// core/machine/robot.h's Frame (a flange pose), declared here so that
// geometry does not include machine.
using Frame = Eigen::Isometry3d;

struct ModelSample {
  std::vector<Vec3> points;
  std::vector<Vec3> normals;  // unit
};

struct RegistrationOptions {
  int max_iterations = 60;
  double initial_reach_mm = 5;     // pairs farther than this are ignored at first
  double outlier_factor = 3;       // later: this times the median pair distance
  double min_reach_mm = 0.02;      // ... but never below this
  double converged_mm = 1e-7;      // stop when an update moves no point more than this
  double cell_mm = 0;              // nearest-neighbour grid; 0: the model's mean sample spacing
};

struct RegistrationResult {
  Frame transform = Frame::Identity();  // scan frame -> model frame
  int iterations = 0;
  bool converged = false;
  int inliers = 0, outliers = 0;
  double rms_mm = 0;      // point-to-plane distance over the inliers
  double median_mm = 0;   // point-to-point pair distance over the inliers
};

// Throws ParameterError on an empty model or scan, or normals not matching
// the points; Error when the pairs do not constrain all six degrees of
// freedom (a flat or cylindrical piece alone) or no pair is within reach.
RegistrationResult register_points(const std::vector<Vec3>& scan, const ModelSample& model,
                                   const RegistrationOptions& options = {}, const Frame& initial = Frame::Identity());

}  // namespace bliskrun
