#pragma once
// B-spline basis functions and their derivatives (Piegl & Tiller, The NURBS
// Book, A2.1 and A2.3). Internal to core/geometry.
#include <cstddef>
#include <vector>

namespace bliskrun::detail {

// Highest degree the fixed work arrays of basis_derivatives hold.
constexpr int kMaxDegree = 7;

// Throws ParameterError (named `name`) unless 1 <= degree <= kMaxDegree,
// knots.size() == n_ctrl + degree + 1, knots do not decrease and the domain
// [knots[degree], knots[n_ctrl]] is not empty.
void check_knots(const char* name, int degree, const std::vector<double>& knots, std::size_t n_ctrl);

// Index i of the knot span [U[i], U[i+1]) containing t, for a clamped knot
// vector of a degree-p spline with n+1 control points; t = U[n+1] maps to
// the last non-empty span.
int find_span(int n, int p, double t, const std::vector<double>& U);

// ders[k][j] = k-th derivative of N_{span-p+j, p} at t, k = 0..nd, j = 0..p.
// `ders` must hold (nd+1) * (p+1) doubles, row-major.
void basis_derivatives(int span, double t, int p, int nd, const std::vector<double>& U,
                       double* ders);

}  // namespace bliskrun::detail
