#pragma once
// A root of a continuous function in a bracket where it changes sign:
// Illinois-modified regula falsi (the secant through the bracket ends, the
// end kept twice has its value halved so convergence stays superlinear), with
// a bisection step wherever the secant leaves the bracket. Used where a
// parameter is solved on a surface (a line meeting the hub offset, a ruling
// meeting the hub, a contour of a surface of revolution).

#include <algorithm>
#include <cmath>

namespace bliskrun {

// g(a) = ga and g(b) = gb must differ in sign (either may be zero); a and b
// may come in either order. Stops when the bracket is narrower than
// `tolerance` or after `max_iterations`, returning its middle.
template <class F>
double illinois_root(F&& g, double a, double b, double ga, double gb, double tolerance,
                     int max_iterations = 200) {
  for (int it = 0; it < max_iterations && std::abs(b - a) > tolerance; ++it) {
    double m = (a * gb - b * ga) / (gb - ga);
    if (!(m > std::min(a, b) && m < std::max(a, b))) m = 0.5 * (a + b);
    const double gm = g(m);
    if (gm == 0) return m;
    if ((gm > 0) == (ga > 0)) {
      a = m;
      ga = gm;
      gb *= 0.5;
    } else {
      b = m;
      gb = gm;
      ga *= 0.5;
    }
  }
  return 0.5 * (a + b);
}

}  // namespace bliskrun
