#pragma once
// Point inversion: the closest point of a surface or curve to a given point
// (impeller paper §5, eq. 33–35). Newton's method from a seed found by a
// coarse sample, restricted to the domain so that answers on the boundary are
// correct. Failure is reported, never a wrong answer.
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/curve.h"
#include "core/geometry/surface.h"

namespace bliskrun {

struct ProjectionOptions {
  int seed_samples_u = 24;  // coarse grid for the seed
  int seed_samples_v = 24;
  double tol_mm = 1e-9;     // stop when the step moves the point less than this
  int max_iterations = 50;
  // (u, v) near the foot, when the caller knows it (e.g. a data point's own
  // grid parameters): Newton starts there and the coarse sample is taken only
  // if that start does not converge. Surfaces only.
  std::optional<Eigen::Vector2d> seed;
};

struct SurfaceProjection {
  bool ok = false;
  double u = 0, v = 0;
  Vec3 point = Vec3::Zero();
  double distance = 0;   // |q - point|
  bool on_boundary = false;
  std::string failure;   // why, when !ok
};

SurfaceProjection project_to_surface(const Surface& s, const Vec3& q,
                                     const ProjectionOptions& opts = {});

struct CurveProjection {
  bool ok = false;
  double t = 0;
  Vec3 point = Vec3::Zero();
  double distance = 0;
  std::string failure;
};

CurveProjection project_to_curve(const Curve& c, const Vec3& q,
                                 const ProjectionOptions& opts = {});

// The coarse sample project_to_curve seeds from: n + 1 points at
// t_min + (t_max - t_min) i / n, n = max(8, 4 seed_samples_u). A caller
// projecting many points onto one curve (a surface of revolution's
// meridian) computes it once and passes it to the overload below; results
// are the same.
std::vector<Vec3> curve_seed_samples(const Curve& c, const ProjectionOptions& opts = {});
CurveProjection project_to_curve(const Curve& c, const Vec3& q, const ProjectionOptions& opts,
                                 const std::vector<Vec3>& seed_samples);

}  // namespace bliskrun
