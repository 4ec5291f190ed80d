#include "core/geometry/interpolation.h"

#include <cmath>
#include <string>

#include "core/common/error.h"
#include "core/common/progress.h"
#include "core/geometry/bspline_basis.h"

namespace bliskrun {

std::vector<double> chord_length_parameters(const std::vector<Vec3>& points) {
  const size_t n = points.size();
  if (n < 2) throw ParameterError("points", "need at least 2 points, got " + std::to_string(n));
  std::vector<double> t(n, 0.0);
  for (size_t i = 1; i < n; ++i) {
    const double d = (points[i] - points[i - 1]).norm();
    if (!(d > 0))
      throw ParameterError("points", "points " + std::to_string(i - 1) + " and " +
                                         std::to_string(i) + " coincide (zero-length chord)");
    t[i] = t[i - 1] + d;
  }
  for (size_t i = 1; i < n; ++i) t[i] /= t[n - 1];
  t[n - 1] = 1.0;
  return t;
}

namespace {

// dC/dt at params[at] of the Lagrange polynomial through points[first ..
// first + count - 1] at their parameters: the end-tangent estimate for data
// without tangents (exact for polynomial data of degree < count).
Vec3 lagrange_derivative(const std::vector<Vec3>& points, const std::vector<double>& t,
                         size_t first, size_t count, size_t at) {
  Vec3 d = Vec3::Zero();
  const double x = t[at];
  for (size_t i = first; i < first + count; ++i) {
    // l_i'(x) = sum_{m != i} 1/(t_i - t_m) prod_{k != i, m} (x - t_k)/(t_i - t_k)
    double li = 0.0;
    for (size_t m = first; m < first + count; ++m) {
      if (m == i) continue;
      double prod = 1.0 / (t[i] - t[m]);
      for (size_t k = first; k < first + count; ++k) {
        if (k == i || k == m) continue;
        prod *= (x - t[k]) / (t[i] - t[k]);
      }
      li += prod;
    }
    d += li * points[i];
  }
  return d;
}

// Global cubic interpolation with end tangents for one parameter vector,
// factored once and reused for every set of points that shares it (all the
// columns, then all the rows, of a grid).
//
// n+1 points Q_k at t_k; n+3 control points P_0..P_{n+2}; clamped knots
// {0,0,0,0, t_1..t_{n-1}, 1,1,1,1}. P_0 = Q_0, P_{n+2} = Q_n, and the end
// tangents fix P_1 = Q_0 + t_1/3 D_0 and P_{n+1} = Q_n - (1 - t_{n-1})/3 D_n
// (blisk paper eq. 8). At each interior t_k exactly three cubic basis
// functions are non-zero, so C(t_k) = Q_k for k = 1..n-1 is the tridiagonal
// system of eq. 6-7 in P_2..P_n, solved by the Thomas algorithm.
class CubicInterpolator {
 public:
  explicit CubicInterpolator(std::vector<double> t) : t_(std::move(t)) {
    const int n = static_cast<int>(t_.size()) - 1;
    knots_.assign(4, 0.0);
    for (int k = 1; k < n; ++k) knots_.push_back(t_[k]);
    knots_.insert(knots_.end(), 4, 1.0);
    const int m = n - 1;  // unknowns P_2..P_n
    a_.assign(std::max(m, 0), 0);
    b_ = c_ = a_;
    for (int k = 1; k < n; ++k) {
      // t_k is knot index k + 3, so the span is k + 3 and the non-zero
      // functions are N_{k}, N_{k+1}, N_{k+2} (the N_{k+3} value is 0).
      double ders[4];
      detail::basis_derivatives(k + 3, t_[k], 3, 0, knots_, ders);
      a_[k - 1] = ders[0];  // coefficient of P_k
      b_[k - 1] = ders[1];  // P_{k+1}
      c_[k - 1] = ders[2];  // P_{k+2}
    }
    // Thomas forward elimination, coefficients only.
    cp_.assign(std::max(m, 0), 0);
    denom_.assign(std::max(m, 0), 0);
    for (int i = 0; i < m; ++i) {
      const double d = b_[i] - (i > 0 ? a_[i] * cp_[i - 1] : 0.0);
      if (std::abs(d) < 1e-300) throw Error("cubic interpolation: singular system");
      denom_[i] = d;
      cp_[i] = c_[i] / d;
    }
  }

  const std::vector<double>& knots() const { return knots_; }

  // Control points for `q` (size n+1) with end tangents d0, dn.
  std::vector<Vec3> solve(const Vec3* q, size_t stride, const Vec3& d0, const Vec3& dn) const {
    const int n = static_cast<int>(t_.size()) - 1;
    std::vector<Vec3> p(n + 3);
    p[0] = q[0];
    p[n + 2] = q[n * stride];
    p[1] = q[0] + (t_[1] / 3.0) * d0;
    p[n + 1] = q[n * stride] - ((1.0 - t_[n - 1]) / 3.0) * dn;
    const int m = n - 1;
    if (m <= 0) return p;
    std::vector<Vec3> rhs(m);
    for (int k = 1; k < n; ++k) rhs[k - 1] = q[k * stride];
    rhs[0] -= a_[0] * p[1];
    rhs[m - 1] -= c_[m - 1] * p[n + 1];
    // Forward sweep, then back substitution.
    rhs[0] /= denom_[0];
    for (int i = 1; i < m; ++i) rhs[i] = (rhs[i] - a_[i] * rhs[i - 1]) / denom_[i];
    for (int i = m - 2; i >= 0; --i) rhs[i] -= cp_[i] * rhs[i + 1];
    for (int i = 0; i < m; ++i) p[i + 2] = rhs[i];
    return p;
  }

 private:
  std::vector<double> t_, knots_;
  std::vector<double> a_, b_, c_, cp_, denom_;
};

// Estimated end tangents of data at parameters t (see EndTangents).
std::pair<Vec3, Vec3> estimate_end_tangents(const std::vector<Vec3>& q, const std::vector<double>& t) {
  const size_t n = q.size(), count = std::min<size_t>(4, n);
  return {lagrange_derivative(q, t, 0, count, 0), lagrange_derivative(q, t, n - count, count, n - 1)};
}

void check_params(const std::vector<double>& t, size_t n) {
  if (t.size() != n)
    throw ParameterError("params", "need one parameter per point (" + std::to_string(n) +
                                       "), got " + std::to_string(t.size()));
  if (t.front() != 0.0 || t.back() != 1.0)
    throw ParameterError("params", "parameters must run from 0 to 1");
  for (size_t i = 1; i < t.size(); ++i)
    if (!(t[i] > t[i - 1]))
      throw ParameterError("params", "parameters must increase strictly (index " +
                                         std::to_string(i) + ")");
}

}  // namespace

BSplineCurve interpolate_cubic(const std::vector<Vec3>& points, const std::vector<double>& params,
                               const EndTangents& ends) {
  const std::vector<double> t = params.empty() ? chord_length_parameters(points) : params;
  if (points.size() < 2)
    throw ParameterError("points", "need at least 2 points, got " + std::to_string(points.size()));
  check_params(t, points.size());
  auto [d0, dn] = estimate_end_tangents(points, t);
  if (ends.start) d0 = *ends.start;
  if (ends.end) dn = *ends.end;
  const CubicInterpolator interp(t);
  return BSplineCurve(3, interp.knots(), interp.solve(points.data(), 1, d0, dn));
}

GridParameters averaged_grid_parameters(const PointGrid& g) {
  if (g.rows < 2 || g.cols < 2)
    throw ParameterError("grid", "needs at least 2 x 2 points, got " + std::to_string(g.rows) +
                                     " x " + std::to_string(g.cols));
  GridParameters out;
  out.u.assign(g.rows, 0.0);
  out.v.assign(g.cols, 0.0);
  std::vector<double> chord(std::max(g.rows, g.cols));
  // Eq. 4: chord-length parameters of every column (along u), averaged.
  for (int j = 0; j < g.cols; ++j) {
    double total = 0;
    for (int i = 1; i < g.rows; ++i) {
      chord[i] = (g.at(i, j) - g.at(i - 1, j)).norm();
      if (!(chord[i] > 0))
        throw ParameterError("grid", "points (" + std::to_string(i - 1) + ", " + std::to_string(j) +
                                         ") and (" + std::to_string(i) + ", " + std::to_string(j) +
                                         ") coincide");
      total += chord[i];
    }
    double acc = 0;
    for (int i = 1; i < g.rows; ++i) {
      acc += chord[i];
      out.u[i] += acc / total;
    }
  }
  for (int i = 0; i < g.rows; ++i) {
    double total = 0;
    for (int j = 1; j < g.cols; ++j) {
      chord[j] = (g.at(i, j) - g.at(i, j - 1)).norm();
      if (!(chord[j] > 0))
        throw ParameterError("grid", "points (" + std::to_string(i) + ", " + std::to_string(j - 1) +
                                         ") and (" + std::to_string(i) + ", " + std::to_string(j) +
                                         ") coincide");
      total += chord[j];
    }
    double acc = 0;
    for (int j = 1; j < g.cols; ++j) {
      acc += chord[j];
      out.v[j] += acc / total;
    }
  }
  for (double& u : out.u) u /= g.cols;
  for (double& v : out.v) v /= g.rows;
  out.u.back() = 1.0;
  out.v.back() = 1.0;
  return out;
}

BSplineSurface interpolate_grid(const PointGrid& g) {
  if (g.points.size() != static_cast<size_t>(g.rows) * g.cols)
    throw ParameterError("grid", "holds " + std::to_string(g.points.size()) +
                                     " points, expected rows * cols = " +
                                     std::to_string(static_cast<size_t>(g.rows) * g.cols));
  return interpolate_grid(g, averaged_grid_parameters(g));
}

BSplineSurface interpolate_grid(const PointGrid& g, const GridParameters& par) {
  if (g.rows < 2 || g.cols < 2 || g.points.size() != static_cast<size_t>(g.rows) * g.cols)
    throw ParameterError("grid", "needs at least 2 x 2 points and rows * cols of them");
  check_params(par.u, g.rows);
  check_params(par.v, g.cols);
  const CubicInterpolator along_u(par.u), along_v(par.v);
  const int R = g.rows + 2, C = g.cols + 2;

  // Eq. 5, first pass: each column of data (along u) -> R intermediate
  // control points.
  std::vector<Vec3> mid(static_cast<size_t>(R) * g.cols);
  std::vector<Vec3> column(g.rows);
  for (int j = 0; j < g.cols; ++j) {
    cancellation_point();
    for (int i = 0; i < g.rows; ++i) column[i] = g.at(i, j);
    const auto [d0, dn] = estimate_end_tangents(column, par.u);
    const std::vector<Vec3> p = along_u.solve(column.data(), 1, d0, dn);
    for (int i = 0; i < R; ++i) mid[static_cast<size_t>(i) * g.cols + j] = p[i];
  }
  // Second pass: each row of intermediate control points (along v) is new
  // "data"; the result interpolates the grid whatever end tangents these
  // rows get, so they are estimated the same way.
  std::vector<Vec3> ctrl(static_cast<size_t>(R) * C);
  std::vector<Vec3> row(g.cols);
  for (int i = 0; i < R; ++i) {
    cancellation_point();
    for (int j = 0; j < g.cols; ++j) row[j] = mid[static_cast<size_t>(i) * g.cols + j];
    const auto [d0, dn] = estimate_end_tangents(row, par.v);
    const std::vector<Vec3> p = along_v.solve(row.data(), 1, d0, dn);
    std::copy(p.begin(), p.end(), ctrl.begin() + static_cast<size_t>(i) * C);
  }
  return BSplineSurface(3, 3, along_u.knots(), along_v.knots(), R, C, std::move(ctrl));
}

}  // namespace bliskrun
