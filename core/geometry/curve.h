#pragma once
// Parametric curves on t in [0, 1] (or the curve's own domain) and B-spline
// curves of any degree.
#include <vector>

#include "core/common/types.h"

namespace bliskrun {

// A point of a curve and its derivatives with respect to the parameter.
struct CurveDerivs {
  Vec3 p = Vec3::Zero();
  Vec3 dt = Vec3::Zero();   // dC/dt
  Vec3 dtt = Vec3::Zero();  // d2C/dt2
};

// Anything that can be evaluated with derivatives to second order.
class Curve {
 public:
  virtual ~Curve() = default;
  virtual CurveDerivs eval(double t) const = 0;
  virtual double t_min() const { return 0.0; }
  virtual double t_max() const { return 1.0; }
  Vec3 point(double t) const { return eval(t).p; }
};

// Non-rational B-spline curve. Control points are 3-D; a curve in a surface's
// parameter plane uses (u, v, 0).
class BSplineCurve : public Curve {
 public:
  BSplineCurve() = default;
  // Throws ParameterError unless knots.size() == ctrl.size() + degree + 1,
  // knots are non-decreasing and degree >= 1.
  BSplineCurve(int degree, std::vector<double> knots, std::vector<Vec3> ctrl);

  CurveDerivs eval(double t) const override;
  double t_min() const override { return knots_[degree_]; }
  double t_max() const override { return knots_[knots_.size() - degree_ - 1]; }

  int degree() const { return degree_; }
  const std::vector<double>& knots() const { return knots_; }
  const std::vector<Vec3>& control_points() const { return ctrl_; }

  // Returns a curve with knot t inserted `times` times (Boehm); same shape.
  BSplineCurve with_knot_inserted(double t, int times = 1) const;

 private:
  int degree_ = 0;
  std::vector<double> knots_;
  std::vector<Vec3> ctrl_;
};

// Polyline through points at the given parameters (used for sampled curves
// such as hub/tip intersection curves before fitting).
struct SampledCurve {
  std::vector<double> t;
  std::vector<Vec3> points;
};

}  // namespace bliskrun
