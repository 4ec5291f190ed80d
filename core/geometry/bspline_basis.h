#pragma once
// B-spline basis functions and their derivatives (Piegl & Tiller, The NURBS
// Book, A2.1 and A2.3). Internal to core/geometry.
#include <vector>

namespace bliskrun::detail {

// Index i of the knot span [U[i], U[i+1]) containing t, for a clamped knot
// vector of a degree-p spline with n+1 control points; t = U[n+1] maps to
// the last non-empty span.
int find_span(int n, int p, double t, const std::vector<double>& U);

// ders[k][j] = k-th derivative of N_{span-p+j, p} at t, k = 0..nd, j = 0..p.
// `ders` must hold (nd+1) * (p+1) doubles, row-major.
void basis_derivatives(int span, double t, int p, int nd, const std::vector<double>& U,
                       double* ders);

}  // namespace bliskrun::detail
