#include <algorithm>
#include <cmath>
#include <string>

#include "core/common/error.h"
#include "core/geometry/bspline_basis.h"
#include "core/geometry/curve.h"
#include "core/geometry/surface.h"

namespace bliskrun {

using detail::check_knots;
using detail::kMaxDegree;

// ---- curve -----------------------------------------------------------------

BSplineCurve::BSplineCurve(int degree, std::vector<double> knots, std::vector<Vec3> ctrl)
    : degree_(degree), knots_(std::move(knots)), ctrl_(std::move(ctrl)) {
  check_knots("curve", degree_, knots_, ctrl_.size());
}

CurveDerivs BSplineCurve::eval(double t) const {
  const int p = degree_, n = static_cast<int>(ctrl_.size()) - 1;
  t = std::clamp(t, t_min(), t_max());
  const int span = detail::find_span(n, p, t, knots_);
  double ders[3 * (kMaxDegree + 1)];
  const int nd = std::min(2, p);
  detail::basis_derivatives(span, t, p, nd, knots_, ders);
  CurveDerivs out;
  for (int j = 0; j <= p; ++j) {
    const Vec3& c = ctrl_[span - p + j];
    out.p += ders[j] * c;
    out.dt += ders[(p + 1) + j] * c;
    if (nd >= 2) out.dtt += ders[2 * (p + 1) + j] * c;
  }
  return out;
}

BSplineCurve BSplineCurve::with_knot_inserted(double t, int times) const {
  if (!(t > t_min() && t < t_max()))
    throw ParameterError("t", "knot to insert must lie inside the curve's domain");
  BSplineCurve c = *this;
  for (int r = 0; r < times; ++r) {
    const int p = c.degree_, n = static_cast<int>(c.ctrl_.size()) - 1;
    const int k = detail::find_span(n, p, t, c.knots_);
    // Boehm's algorithm: p new points replace p - 1 old ones.
    std::vector<Vec3> q(c.ctrl_.size() + 1);
    for (int i = 0; i <= k - p; ++i) q[i] = c.ctrl_[i];
    for (int i = k - p + 1; i <= k; ++i) {
      const double a = (t - c.knots_[i]) / (c.knots_[i + p] - c.knots_[i]);
      q[i] = (1 - a) * c.ctrl_[i - 1] + a * c.ctrl_[i];
    }
    for (int i = k; i <= n; ++i) q[i + 1] = c.ctrl_[i];
    c.knots_.insert(c.knots_.begin() + k + 1, t);
    c.ctrl_ = std::move(q);
  }
  return c;
}

// ---- surface ---------------------------------------------------------------

BSplineSurface::BSplineSurface(int degree_u, int degree_v, std::vector<double> knots_u,
                               std::vector<double> knots_v, int rows, int cols,
                               std::vector<Vec3> ctrl)
    : degree_u_(degree_u), degree_v_(degree_v), knots_u_(std::move(knots_u)),
      knots_v_(std::move(knots_v)), rows_(rows), cols_(cols), ctrl_(std::move(ctrl)) {
  if (rows_ < 1 || cols_ < 1 || ctrl_.size() != static_cast<size_t>(rows_) * cols_)
    throw ParameterError("surface", "control net must hold rows * cols points");
  check_knots("surface u", degree_u_, knots_u_, rows_);
  check_knots("surface v", degree_v_, knots_v_, cols_);
}

SurfaceDerivs BSplineSurface::eval(double u, double v) const {
  const int p = degree_u_, q = degree_v_;
  u = std::clamp(u, knots_u_[p], knots_u_[rows_]);
  v = std::clamp(v, knots_v_[q], knots_v_[cols_]);
  const int su = detail::find_span(rows_ - 1, p, u, knots_u_);
  const int sv = detail::find_span(cols_ - 1, q, v, knots_v_);
  double nu[3 * (kMaxDegree + 1)] = {}, nv[3 * (kMaxDegree + 1)] = {};
  detail::basis_derivatives(su, u, p, std::min(2, p), knots_u_, nu);
  detail::basis_derivatives(sv, v, q, std::min(2, q), knots_v_, nv);
  // Combine along v first for each row of the local net, then along u.
  SurfaceDerivs out;
  for (int i = 0; i <= p; ++i) {
    Vec3 c0 = Vec3::Zero(), c1 = Vec3::Zero(), c2 = Vec3::Zero();
    const Vec3* row = &ctrl_[static_cast<size_t>(su - p + i) * cols_ + (sv - q)];
    for (int j = 0; j <= q; ++j) {
      c0 += nv[j] * row[j];
      c1 += nv[(q + 1) + j] * row[j];
      c2 += nv[2 * (q + 1) + j] * row[j];
    }
    const double b0 = nu[i], b1 = nu[(p + 1) + i], b2 = nu[2 * (p + 1) + i];
    out.p += b0 * c0;
    out.pu += b1 * c0;
    out.puu += b2 * c0;
    out.pv += b0 * c1;
    out.puv += b1 * c1;
    out.pvv += b0 * c2;
  }
  return out;
}

}  // namespace bliskrun
