#include "core/geometry/closed_curve.h"

#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/common/error.h"

namespace bliskrun {

namespace {

double wrap_into(double t, double lo, double period) {
  double x = std::fmod(t - lo, period);
  if (x < 0) x += period;
  return lo + x;
}

}  // namespace

ClosedCurve::ClosedCurve(BSplineCurve periodic, double start) : spline_(std::move(periodic)) {
  if (spline_.degree() != 3) throw ParameterError("periodic", "expected a cubic B-spline");
  const std::vector<Vec3>& c = spline_.control_points();
  const std::vector<double>& u = spline_.knots();
  const size_t n = c.size() - 3;  // spans of one period
  double size = 0;
  for (const Vec3& p : c) size = std::max(size, p.norm());
  for (size_t j = 0; j < 3; ++j)
    if ((c[j] - c[n + j]).norm() > 1e-9 * (1 + size))
      throw ParameterError("periodic", "the first three control points must repeat as the last three");
  for (size_t j = 0; j + 1 < 7; ++j)  // the knot spacing repeats across the seam
    if (std::abs((u[j + 1] - u[j]) - (u[n + j + 1] - u[n + j])) > 1e-9 * (1 + period()))
      throw ParameterError("periodic", "the knot spacing must repeat with the period");
  if (!std::isfinite(start)) throw ParameterError("start", "expected a finite parameter");
  start_ = wrap_into(start, spline_.t_min(), period());
}

CurveDerivs ClosedCurve::eval(double t) const {
  return spline_.eval(wrap_into(t, spline_.t_min(), period()));
}

ClosedCurve ClosedCurve::started_at(double t) const { return ClosedCurve(spline_, t); }

namespace {

void check_loop(const std::vector<Vec3>& loop) {
  const int n = static_cast<int>(loop.size());
  if (n < 4) throw ParameterError("loop", "a closed cubic needs at least 4 points, got " + std::to_string(n));
  for (int i = 0; i < n; ++i)
    if (!loop[i].allFinite()) throw ParameterError("loop", "point " + std::to_string(i) + " is not finite");
}

// The periodic cubic through loop[k] at knot u[k], u[n] closing the loop
// (period u[n] - u[0]).
BSplineCurve closed_cubic_at(const std::vector<Vec3>& loop, const std::vector<double>& u) {
  const int n = static_cast<int>(loop.size());
  const double period = u[n] - u[0];
  const auto knot = [&](int j) {  // u_j extended periodically
    const int q = (j >= 0 ? j / n : -((-j + n - 1) / n));
    return u[j - q * n] + q * period;
  };
  const auto wrap = [n](int j) { return ((j % n) + n) % n; };
  // At u_k only N_{k-3}, N_{k-2}, N_{k-1} (support [u_j, u_{j+4}]) are non-zero;
  // control points repeat with period n, so C(u_k) = p_k is cyclic tridiagonal.
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(3 * static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    const double a = std::pow(knot(k + 1) - knot(k), 2) / ((knot(k + 1) - knot(k - 2)) * (knot(k + 1) - knot(k - 1)));
    const double d = std::pow(knot(k) - knot(k - 1), 2) / ((knot(k + 2) - knot(k - 1)) * (knot(k + 1) - knot(k - 1)));
    entries.emplace_back(k, wrap(k - 3), a);
    entries.emplace_back(k, wrap(k - 2), 1 - a - d);
    entries.emplace_back(k, wrap(k - 1), d);
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(A);
  if (lu.info() != Eigen::Success) throw Error("interpolate_closed_cubic: singular interpolation system");
  Eigen::MatrixXd rhs(n, 3);
  for (int k = 0; k < n; ++k) rhs.row(k) = loop[k].transpose();
  const Eigen::MatrixXd c = lu.solve(rhs);
  // Control points c_{-3} .. c_{n-1}, knots u_{-3} .. u_{n+3}: domain [u_0, u_n].
  std::vector<Vec3> ctrl;
  ctrl.reserve(n + 3);
  for (int j = -3; j < n; ++j) ctrl.push_back(c.row(wrap(j)).transpose());
  std::vector<double> knots;
  knots.reserve(n + 7);
  for (int j = -3; j <= n + 3; ++j) knots.push_back(knot(j));
  return BSplineCurve(3, std::move(knots), std::move(ctrl));
}

}  // namespace

ClosedCurve interpolate_closed_cubic(const std::vector<Vec3>& loop) {
  check_loop(loop);
  const int n = static_cast<int>(loop.size());
  // Knots u_0 .. u_n at cumulative chord lengths; u_n = period T.
  std::vector<double> u(n + 1, 0.0);
  for (int i = 0; i < n; ++i) {
    const double h = (loop[(i + 1) % n] - loop[i]).norm();
    if (!(h > 0))
      throw ParameterError("loop", "points " + std::to_string(i) + " and " + std::to_string((i + 1) % n) +
                                       " coincide");
    u[i + 1] = u[i] + h;
  }
  return ClosedCurve(closed_cubic_at(loop, u), 0.0);
}

BSplineCurve interpolate_closed_cubic(const std::vector<Vec3>& loop, const std::vector<double>& knots) {
  check_loop(loop);
  if (knots.size() != loop.size() + 1)
    throw ParameterError("knots", "need one knot per point and one closing the loop (" +
                                      std::to_string(loop.size() + 1) + "), got " + std::to_string(knots.size()));
  for (size_t i = 0; i < knots.size(); ++i)
    if (!std::isfinite(knots[i]) || (i > 0 && !(knots[i] > knots[i - 1])))
      throw ParameterError("knots", "must be finite and increase strictly (knot " + std::to_string(i) + ")");
  return closed_cubic_at(loop, knots);
}

}  // namespace bliskrun
