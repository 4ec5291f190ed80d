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
// A pair is also dropped when its point-to-plane distance is beyond
// `normal_gate_factor` robust standard deviations of those distances (never
// below `min_reach_mm`): stray points a little off the surface, closer than
// the point-to-point reach (which follows the model's sample spacing), would
// otherwise stay in and pull.
//
// The fine ICP converges only from within about a degree of the truth on a
// blade (pairs farther than the reach are lost, and what is left may not fix
// all six degrees of freedom). With `pre_align` a coarse stage runs first
// (issue 39): trimmed point-to-plane ICP on subsamples of scan and model from
// several starts — the given pose, the given pose turned by `capture_deg`
// about each axis either way, and the principal axes of the scan put on the
// model's under each of the four proper sign choices (the symmetries a
// principal frame cannot tell apart) — the start that ends with the smallest
// median point-to-plane distance (to the full model) wins, and the fine ICP
// goes on from it. The coarse ICP is damped (Levenberg-Marquardt) so that
// a direction the scan hardly fixes does not walk off the model.
//
// The result carries the pose's uncertainty (pose_uncertainty) and
// check_registration turns it, the convergence and the rms against the
// scanner's stated noise into a verdict with a message that says what to
// scan.
#include <limits>
#include <string>
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
                                   // (or less than 1/100 of a point's sigma, PoseUncertainty)
  double cell_mm = 0;              // nearest-neighbour grid; 0: the model's mean sample spacing
  double normal_gate_factor = 4;   // point-to-plane gate: this times the robust sigma of those distances
  bool pre_align = false;          // the coarse stage first (off: the scan starts from `initial`)
  double capture_deg = 5;          // the clamping error the coarse stage must cover: angle ...
  double capture_mm = 5;           // ... and offset (on top of the model's size, for the first reach)
};

// The pose's uncertainty from the fit (issue 39), for the motion of the scan
// as a rigid body parametrised by a small rotation w about the centroid c
// of the paired scan points and a translation t of c: each pair gives a row
// J = [(p - c) x n, n] of the point-to-plane problem, the normal matrix is
// A = sum J J^T, and with the residual variance s^2 = sum e^2 / (N - 6) the
// covariance of (w, t) is s^2 A^-1 — the least-squares estimate's, if the
// residuals are independent noise (the sampling error of the model is not:
// a dense model keeps it small against the scanner's noise).
// `condition` is A's largest over smallest eigenvalue with the rotations
// scaled by `lever_mm` (the rms distance of the points from c), so that a
// turn and a shift that move the points equally count equally; a direction
// with an eigenvalue below 1e-12 of the largest is unconstrained: condition
// and the standard deviation of every degree of freedom it moves are
// infinite.
struct PoseUncertainty {
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  int pairs = 0;
  Vec3 centroid = Vec3::Zero();                 // c, model frame, mm
  double lever_mm = 0;
  double condition = kInf;
  Vec3 sigma_rotation_rad = Vec3::Constant(kInf);    // about x, y, z through c
  Vec3 sigma_translation_mm = Vec3::Constant(kInf);  // of c along x, y, z
  double sigma_point_mm = kInf;  // the largest standard deviation of a paired point's position, any direction
  int unconstrained = 6;         // directions A does not fix
  // The least constrained motion (unit in the scaled coordinates): its
  // rotation part (rad per lever_mm) and translation part (mm).
  Vec3 weakest_rotation = Vec3::Zero(), weakest_translation = Vec3::Zero();
};

// From pairs: p the scan point in the model frame, n the model's unit normal
// at its pair, e the signed point-to-plane residual. Throws ParameterError
// unless the three have the same size; fewer than 7 pairs leave everything
// unconstrained.
PoseUncertainty pose_uncertainty(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                                 const std::vector<double>& residuals);

struct RegistrationResult {
  Frame transform = Frame::Identity();  // scan frame -> model frame
  int iterations = 0;
  bool converged = false;
  int inliers = 0, outliers = 0;
  double rms_mm = 0;      // point-to-plane distance over the inliers
  double median_mm = 0;   // point-to-point pair distance over the inliers
  PoseUncertainty uncertainty;  // at the final pose, over its inliers
  // The coarse stage (pre_align): starts tried, the winner's index (0: the
  // given pose) and its score: the median point-to-plane distance of a
  // subsample of the scan to the model where the coarse stage left it.
  int starts = 0, start = 0;
  double coarse_median_mm = 0;
};

// Throws ParameterError on an empty model or scan, or normals not matching
// the points; Error when the pairs do not constrain all six degrees of
// freedom (a flat or cylindrical piece alone) or no pair is within reach.
RegistrationResult register_points(const std::vector<Vec3>& scan, const ModelSample& model,
                                   const RegistrationOptions& options = {}, const Frame& initial = Frame::Identity());

// What a registration must show before a program is planned on it. The
// defaults from the built-in blade (tests/geometry/registration_trust_test):
// a scan of both flanks (20 000 points, 5 um noise) gives condition 1.2e4
// and a point's sigma 4 um (the blade sliding along its span is what the
// flanks fix least), the pressure flank alone 5.2e5 and 27 um (and 14 um of
// real error), the suction flank alone 1.6e4 and 5.8 um (8.6 um). Rotor 67's
// twisted blade is fixed by either flank alone (condition ~1e3, 2 um).
struct RegistrationLimits {
  double noise_mm = 0.005;      // the scanner's stated noise (1 sigma, along the normal)
  double rms_factor = 3;        // the rms may be at most this times the noise
  double max_condition = 1e5;   // of the normal matrix (PoseUncertainty::condition)
  double max_sigma_point_mm = 0.005;  // PoseUncertainty::sigma_point_mm
};

struct RegistrationCheck {
  bool trusted = false;
  std::vector<std::string> problems;  // one sentence each: what is wrong and what to scan
};

// Converged, constrained (condition and sigma_point_mm within the limits) and
// rms within rms_factor x noise; otherwise the problems, each naming the
// measured value, the limit and what to scan.
RegistrationCheck check_registration(const RegistrationResult& result, const RegistrationLimits& limits);

}  // namespace bliskrun
