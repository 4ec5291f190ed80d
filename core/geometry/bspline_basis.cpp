#include "core/geometry/bspline_basis.h"

#include <algorithm>
#include <string>

#include "core/common/error.h"

namespace bliskrun::detail {

void check_knots(const char* name, int degree, const std::vector<double>& knots, size_t n_ctrl) {
  if (degree < 1 || degree > kMaxDegree)
    throw ParameterError(name, "degree must be in [1, " + std::to_string(kMaxDegree) + "], got " +
                                   std::to_string(degree));
  if (n_ctrl < static_cast<size_t>(degree) + 1)
    throw ParameterError(name, "needs at least degree + 1 = " + std::to_string(degree + 1) +
                                   " control points, got " + std::to_string(n_ctrl));
  if (knots.size() != n_ctrl + degree + 1)
    throw ParameterError(name, "needs control points + degree + 1 = " +
                                   std::to_string(n_ctrl + degree + 1) + " knots, got " +
                                   std::to_string(knots.size()));
  for (size_t i = 1; i < knots.size(); ++i)
    if (!(knots[i] >= knots[i - 1]))
      throw ParameterError(name, "knots must not decrease (knot " + std::to_string(i) + ")");
  if (!(knots[knots.size() - degree - 1] > knots[degree]))
    throw ParameterError(name, "knot vector has an empty domain");
}

int find_span(int n, int p, double t, const std::vector<double>& U) {
  if (t >= U[n + 1]) return n;
  if (t <= U[p]) return p;
  // First index with U[i] > t, minus one: the span holding t.
  const auto it = std::upper_bound(U.begin() + p, U.begin() + n + 2, t);
  return static_cast<int>(it - U.begin()) - 1;
}

void basis_derivatives(int span, double t, int p, int nd, const std::vector<double>& U,
                       double* ders) {
  // Small fixed-size work arrays: degrees used here are low (<= 7).
  constexpr int kMax = 8;
  double ndu[kMax][kMax], left[kMax], right[kMax], a[2][kMax];
  ndu[0][0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = t - U[span + 1 - j];
    right[j] = U[span + j] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      const double temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  for (int j = 0; j <= p; ++j) ders[j] = ndu[j][p];
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    a[0][0] = 1.0;
    for (int k = 1; k <= nd; ++k) {
      double d = 0.0;
      const int rk = r - k, pk = p - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      const int j1 = rk >= -1 ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
        d += a[s2][k] * ndu[r][pk];
      }
      ders[k * (p + 1) + r] = d;
      std::swap(s1, s2);
    }
  }
  int factor = p;
  for (int k = 1; k <= nd; ++k) {
    for (int j = 0; j <= p; ++j) ders[k * (p + 1) + j] *= factor;
    factor *= (p - k);
  }
}

}  // namespace bliskrun::detail
