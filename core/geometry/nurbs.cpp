#include "core/geometry/nurbs.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/common/error.h"
#include "core/geometry/bspline_basis.h"

namespace bliskrun {

namespace {

using Vec4 = Eigen::Vector4d;
using detail::kMaxDegree;

std::vector<Vec4> homogeneous(const char* name, const std::vector<Vec3>& ctrl,
                              const std::vector<double>& weights) {
  if (weights.size() != ctrl.size())
    throw ParameterError(name, "needs one weight per control point (" +
                                   std::to_string(ctrl.size()) + "), got " +
                                   std::to_string(weights.size()));
  std::vector<Vec4> hw(ctrl.size());
  for (size_t k = 0; k < ctrl.size(); ++k) {
    const double w = weights[k];
    if (!(std::isfinite(w) && w > 0))
      throw ParameterError(name, "weight " + std::to_string(k) + " must be finite and > 0, got " +
                                     std::to_string(w));
    if (!ctrl[k].allFinite())
      throw ParameterError(name, "control point " + std::to_string(k) + " is not finite");
    hw[k] << w * ctrl[k], w;
  }
  return hw;
}

// Maps the domain [U[p], U[n+1]] onto [0, 1]; knots outside the domain of an
// unclamped vector map outside [0, 1] alike.
void rescale(std::vector<double>& U, int p, int n_ctrl) {
  const double a = U[p], b = U[n_ctrl];
  for (double& k : U) k = (k - a) / (b - a);
  U[p] = 0.0;
  U[n_ctrl] = 1.0;  // exact ends, whatever the rounding above
}

}  // namespace

// ---- surface ---------------------------------------------------------------

NurbsSurface::NurbsSurface(int degree_u, int degree_v, std::vector<double> knots_u,
                           std::vector<double> knots_v, int rows, int cols,
                           std::vector<Vec3> ctrl, std::vector<double> weights)
    : degree_u_(degree_u), degree_v_(degree_v), knots_u_(std::move(knots_u)),
      knots_v_(std::move(knots_v)), rows_(rows), cols_(cols) {
  if (rows_ < 1 || cols_ < 1 || ctrl.size() != static_cast<size_t>(rows_) * cols_)
    throw ParameterError("nurbs surface", "control net must hold rows * cols points");
  detail::check_knots("nurbs surface u", degree_u_, knots_u_, rows_);
  detail::check_knots("nurbs surface v", degree_v_, knots_v_, cols_);
  hw_ = homogeneous("nurbs surface", ctrl, weights);
  rescale(knots_u_, degree_u_, rows_);
  rescale(knots_v_, degree_v_, cols_);
  polynomial_ = std::all_of(weights.begin(), weights.end(),
                            [&](double w) { return w == weights.front(); });
}

NurbsSurface::NurbsSurface(const BSplineSurface& s)
    : NurbsSurface(s.degree_u(), s.degree_v(), s.knots_u(), s.knots_v(), s.rows(), s.cols(),
                   [&] {
                     std::vector<Vec3> c;
                     c.reserve(static_cast<size_t>(s.rows()) * s.cols());
                     for (int i = 0; i < s.rows(); ++i)
                       for (int j = 0; j < s.cols(); ++j) c.push_back(s.control_point(i, j));
                     return c;
                   }(),
                   std::vector<double>(static_cast<size_t>(s.rows()) * s.cols(), 1.0)) {}

Vec3 NurbsSurface::control_point(int i, int j) const {
  const Vec4& h = hw_[static_cast<size_t>(i) * cols_ + j];
  return h.head<3>() / h.w();
}

SurfaceDerivs NurbsSurface::eval(double u, double v) const {
  const int p = degree_u_, q = degree_v_;
  u = std::clamp(u, 0.0, 1.0);
  v = std::clamp(v, 0.0, 1.0);
  const int su = detail::find_span(rows_ - 1, p, u, knots_u_);
  const int sv = detail::find_span(cols_ - 1, q, v, knots_v_);
  double nu[3 * (kMaxDegree + 1)] = {}, nv[3 * (kMaxDegree + 1)] = {};
  detail::basis_derivatives(su, u, p, std::min(2, p), knots_u_, nu);
  detail::basis_derivatives(sv, v, q, std::min(2, q), knots_v_, nv);
  // Homogeneous derivatives A (w-weighted point) and w together, v first.
  Vec4 h = Vec4::Zero(), hu = Vec4::Zero(), hv = Vec4::Zero();
  Vec4 huu = Vec4::Zero(), huv = Vec4::Zero(), hvv = Vec4::Zero();
  for (int i = 0; i <= p; ++i) {
    Vec4 c0 = Vec4::Zero(), c1 = Vec4::Zero(), c2 = Vec4::Zero();
    const Vec4* row = &hw_[static_cast<size_t>(su - p + i) * cols_ + (sv - q)];
    for (int j = 0; j <= q; ++j) {
      c0 += nv[j] * row[j];
      c1 += nv[(q + 1) + j] * row[j];
      c2 += nv[2 * (q + 1) + j] * row[j];
    }
    const double b0 = nu[i], b1 = nu[(p + 1) + i], b2 = nu[2 * (p + 1) + i];
    h += b0 * c0;
    hu += b1 * c0;
    huu += b2 * c0;
    hv += b0 * c1;
    huv += b1 * c1;
    hvv += b0 * c2;
  }
  // Quotient rule: S = A / w, then each derivative of A = w S solved for S's.
  const double iw = 1.0 / h.w();
  SurfaceDerivs out;
  out.p = h.head<3>() * iw;
  out.pu = (hu.head<3>() - hu.w() * out.p) * iw;
  out.pv = (hv.head<3>() - hv.w() * out.p) * iw;
  out.puu = (huu.head<3>() - 2 * hu.w() * out.pu - huu.w() * out.p) * iw;
  out.puv = (huv.head<3>() - hu.w() * out.pv - hv.w() * out.pu - huv.w() * out.p) * iw;
  out.pvv = (hvv.head<3>() - 2 * hv.w() * out.pv - hvv.w() * out.p) * iw;
  return out;
}

// ---- curve -----------------------------------------------------------------

NurbsCurve::NurbsCurve(int degree, std::vector<double> knots, std::vector<Vec3> ctrl,
                       std::vector<double> weights)
    : degree_(degree), knots_(std::move(knots)) {
  detail::check_knots("nurbs curve", degree_, knots_, ctrl.size());
  hw_ = homogeneous("nurbs curve", ctrl, weights);
}

std::vector<Vec3> NurbsCurve::control_points() const {
  std::vector<Vec3> c;
  c.reserve(hw_.size());
  for (const Vec4& h : hw_) c.push_back(h.head<3>() / h.w());
  return c;
}

std::vector<double> NurbsCurve::weights() const {
  std::vector<double> w;
  w.reserve(hw_.size());
  for (const Vec4& h : hw_) w.push_back(h.w());
  return w;
}

CurveDerivs NurbsCurve::eval(double t) const {
  const int p = degree_, n = static_cast<int>(hw_.size()) - 1;
  t = std::clamp(t, t_min(), t_max());
  const int span = detail::find_span(n, p, t, knots_);
  double ders[3 * (kMaxDegree + 1)] = {};
  detail::basis_derivatives(span, t, p, std::min(2, p), knots_, ders);
  Vec4 h = Vec4::Zero(), ht = Vec4::Zero(), htt = Vec4::Zero();
  for (int j = 0; j <= p; ++j) {
    const Vec4& c = hw_[span - p + j];
    h += ders[j] * c;
    ht += ders[(p + 1) + j] * c;
    htt += ders[2 * (p + 1) + j] * c;
  }
  const double iw = 1.0 / h.w();
  CurveDerivs out;
  out.p = h.head<3>() * iw;
  out.dt = (ht.head<3>() - ht.w() * out.p) * iw;
  out.dtt = (htt.head<3>() - 2 * ht.w() * out.dt - htt.w() * out.p) * iw;
  return out;
}

}  // namespace bliskrun
