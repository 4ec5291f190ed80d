// Shapes the hub finish plans on: the hub offset out of the material, a
// cubic fitted to a blade's mid-line (the ball's radius and taper:
// core/planning/ball_cutter.h).
#include <Eigen/Dense>
#include <cmath>

#include "core/planning/hub_finish/internal.h"

namespace bliskrun::hub_detail {

Vec3 unit_normal(const SurfaceDerivs& d, bool flip) {
  const Vec3 n = d.pu.cross(d.pv);
  const double len = n.norm();
  if (!(len > 1e-14)) throw Error("hub finish: a design surface is singular (pu x pv = 0)");
  return flip ? Vec3(-n / len) : Vec3(n / len);
}

SurfaceOfRevolution hub_offset_out(const SurfaceOfRevolution& hub, double d) {
  SurfaceOfRevolution a = hub.offset(d);
  if ((hub.radial_offset(a.point(0.5, 0)) > 0) == (d > 0)) return a;
  return hub.offset(-d);
}

Poly3 fit_poly3(const std::vector<double>& z, const std::vector<double>& y, const std::vector<double>& w) {
  Poly3 p;
  double s = 0;
  for (double v : z) s += v;
  p.zc = s / static_cast<double>(z.size());
  Eigen::MatrixXd A(z.size(), 4);
  Eigen::VectorXd b(z.size());
  for (size_t i = 0; i < z.size(); ++i) {
    const double x = z[i] - p.zc;
    A(i, 0) = w[i], A(i, 1) = w[i] * x, A(i, 2) = w[i] * x * x, A(i, 3) = w[i] * x * x * x;
    b(i) = w[i] * y[i];
  }
  const Eigen::Vector4d c = A.colPivHouseholderQr().solve(b);
  for (int k = 0; k < 4; ++k) p.a[k] = c(k);
  return p;
}

}  // namespace bliskrun::hub_detail
