#pragma once
// Rational B-splines (NURBS): the exact form of CAD geometry (IGES 126/128,
// STEP rational B-spline curves and surfaces, and every conic or quadric
// OCCT converts to them). Evaluated with derivatives to second order by the
// quotient rule on homogeneous coordinates (Piegl & Tiller, A4.4), never
// re-fitted or sampled.
#include <vector>

#include <Eigen/Core>

#include "core/geometry/curve.h"
#include "core/geometry/surface.h"

namespace bliskrun {

// Rational tensor-product B-spline surface. Control net ctrl[i * cols + j]
// and weights[i * cols + j], i along u (rows), j along v (columns), as
// BSplineSurface. The knot vectors are rescaled linearly so the domain
// [U[p], U[rows]] x [V[q], V[cols]] becomes [0, 1]^2 (every Surface lives
// there; the rescaling is an exact reparametrisation, not an approximation).
// Unclamped (periodic) knot vectors are accepted.
class NurbsSurface : public Surface {
 public:
  NurbsSurface() = default;
  // Throws ParameterError on inconsistent sizes or knots, or a weight that
  // is not finite and > 0.
  NurbsSurface(int degree_u, int degree_v, std::vector<double> knots_u,
               std::vector<double> knots_v, int rows, int cols, std::vector<Vec3> ctrl,
               std::vector<double> weights);
  // The same surface with unit weights (exact).
  explicit NurbsSurface(const BSplineSurface& s);

  // Parameters outside [0, 1] are clamped to it.
  SurfaceDerivs eval(double u, double v) const override;

  int degree_u() const { return degree_u_; }
  int degree_v() const { return degree_v_; }
  int rows() const { return rows_; }
  int cols() const { return cols_; }
  const std::vector<double>& knots_u() const { return knots_u_; }  // rescaled
  const std::vector<double>& knots_v() const { return knots_v_; }  // rescaled
  Vec3 control_point(int i, int j) const;
  double weight(int i, int j) const { return hw_[static_cast<size_t>(i) * cols_ + j].w(); }
  // True when every weight is equal: the surface is a plain B-spline.
  bool is_polynomial() const { return polynomial_; }

 private:
  int degree_u_ = 0, degree_v_ = 0;
  std::vector<double> knots_u_, knots_v_;
  int rows_ = 0, cols_ = 0;
  // Homogeneous control points (w x, w y, w z, w): one 4-wide accumulation
  // gives numerator and denominator together.
  std::vector<Eigen::Vector4d> hw_;
  bool polynomial_ = true;
};

// Rational B-spline curve on its own knot domain [U[p], U[n+1]] (as
// BSplineCurve; a curve in a parameter plane uses (u, v, 0)).
class NurbsCurve : public Curve {
 public:
  NurbsCurve() = default;
  // Throws ParameterError on inconsistent knots or a weight that is not
  // finite and > 0.
  NurbsCurve(int degree, std::vector<double> knots, std::vector<Vec3> ctrl,
             std::vector<double> weights);

  CurveDerivs eval(double t) const override;
  double t_min() const override { return knots_[degree_]; }
  double t_max() const override { return knots_[knots_.size() - degree_ - 1]; }

  int degree() const { return degree_; }
  const std::vector<double>& knots() const { return knots_; }
  std::vector<Vec3> control_points() const;
  std::vector<double> weights() const;

 private:
  int degree_ = 0;
  std::vector<double> knots_;
  std::vector<Eigen::Vector4d> hw_;
};

}  // namespace bliskrun
