#pragma once
// Parametric surfaces p(u, v) on [0, 1]^2 (SPEC §2: for a blade flank u runs
// hub to tip, v along the chord) and tensor-product B-spline surfaces.
#include <vector>

#include "core/common/types.h"

namespace bliskrun {

// A point of a surface with partial derivatives to second order.
struct SurfaceDerivs {
  Vec3 p = Vec3::Zero();
  Vec3 pu = Vec3::Zero(), pv = Vec3::Zero();
  Vec3 puu = Vec3::Zero(), puv = Vec3::Zero(), pvv = Vec3::Zero();
};

// Anything evaluable on [0,1]^2 with derivatives to second order: B-spline
// surfaces, surfaces of revolution, trimmed/reparametrised flanks, analytic
// test surfaces. Differential geometry, projection and tessellation work on
// this interface.
class Surface {
 public:
  virtual ~Surface() = default;
  virtual SurfaceDerivs eval(double u, double v) const = 0;
  Vec3 point(double u, double v) const { return eval(u, v).p; }
};

// Non-rational tensor-product B-spline surface. Control net is
// ctrl[i * cols + j], i along u (rows), j along v (columns).
class BSplineSurface : public Surface {
 public:
  BSplineSurface() = default;
  // Throws ParameterError on inconsistent sizes or knots.
  BSplineSurface(int degree_u, int degree_v, std::vector<double> knots_u,
                 std::vector<double> knots_v, int rows, int cols,
                 std::vector<Vec3> ctrl);

  // Parameters outside the domain are clamped to it.
  SurfaceDerivs eval(double u, double v) const override;

  int degree_u() const { return degree_u_; }
  int degree_v() const { return degree_v_; }
  int rows() const { return rows_; }
  int cols() const { return cols_; }
  const std::vector<double>& knots_u() const { return knots_u_; }
  const std::vector<double>& knots_v() const { return knots_v_; }
  const Vec3& control_point(int i, int j) const { return ctrl_[i * cols_ + j]; }

 private:
  int degree_u_ = 0, degree_v_ = 0;
  std::vector<double> knots_u_, knots_v_;
  int rows_ = 0, cols_ = 0;
  std::vector<Vec3> ctrl_;
};

}  // namespace bliskrun
