#include "core/geometry/differential.h"

#include <cmath>

#include "core/common/error.h"

namespace bliskrun {

SurfaceCurvature curvature(const SurfaceDerivs& d) {
  SurfaceCurvature c;
  const Vec3 n = d.pu.cross(d.pv);
  const double len = n.norm();
  c.E = d.pu.dot(d.pu);
  c.F = d.pu.dot(d.pv);
  c.G = d.pv.dot(d.pv);
  const double det_I = c.E * c.G - c.F * c.F;
  if (!(len > 1e-14 * std::max(1.0, c.E + c.G)) || !(det_I > 0))
    throw Error("curvature: singular surface point (pu x pv = 0)");
  c.normal = n / len;
  c.L = d.puu.dot(c.normal);
  c.M = d.puv.dot(c.normal);
  c.N = d.pvv.dot(c.normal);
  c.K = (c.L * c.N - c.M * c.M) / det_I;                          // eq. 11
  c.H = (c.E * c.N - 2 * c.F * c.M + c.G * c.L) / (2 * det_I);
  const double disc = std::sqrt(std::max(0.0, c.H * c.H - c.K));
  c.k1 = c.H + disc;
  c.k2 = c.H - disc;

  // Principal directions: (II - k I) (du, dv) = 0. Take the better
  // conditioned row of the 2x2 system for each k.
  auto direction = [&](double k) -> Vec3 {
    const double a = c.L - k * c.E, b = c.M - k * c.F, e = c.N - k * c.G;
    // Rows (a, b) and (b, e); a solution is (b, -a) or (e, -b).
    Eigen::Vector2d duv = std::hypot(a, b) >= std::hypot(b, e) ? Eigen::Vector2d(b, -a)
                                                                : Eigen::Vector2d(e, -b);
    Vec3 t = d.pu * duv.x() + d.pv * duv.y();
    return t.norm() > 0 ? Vec3(t.normalized()) : Vec3::Zero();
  };
  const double scale = std::max({std::abs(c.k1), std::abs(c.k2), 1e-300});
  if (disc <= 1e-10 * scale) {
    // Umbilic: every direction is principal; report a fixed orthonormal pair.
    c.dir1 = d.pu.normalized();
    c.dir2 = c.normal.cross(c.dir1);
  } else {
    c.dir1 = direction(c.k1);
    c.dir2 = c.normal.cross(c.dir1);  // orthogonal in the tangent plane
  }
  return c;
}

double normal_curvature(const SurfaceDerivs& d, const Vec3& tangent) {
  const Vec3 n = d.pu.cross(d.pv);
  const double len = n.norm();
  if (!(len > 0)) throw Error("normal_curvature: singular surface point (pu x pv = 0)");
  const Vec3 unit_n = n / len;
  // Express the tangent in (du, dv): least squares on [pu pv] after removing
  // the normal component.
  const Vec3 t = tangent - tangent.dot(unit_n) * unit_n;
  Eigen::Matrix<double, 3, 2> J;
  J.col(0) = d.pu;
  J.col(1) = d.pv;
  const Eigen::Vector2d w = (J.transpose() * J).ldlt().solve(J.transpose() * t);
  const double I = w.dot(Eigen::Vector2d(d.pu.dot(d.pu) * w.x() + d.pu.dot(d.pv) * w.y(),
                                         d.pu.dot(d.pv) * w.x() + d.pv.dot(d.pv) * w.y()));
  if (!(I > 0)) throw Error("normal_curvature: direction has no tangential component");
  const double L = d.puu.dot(unit_n), M = d.puv.dot(unit_n), N = d.pvv.dot(unit_n);
  const double II = L * w.x() * w.x() + 2 * M * w.x() * w.y() + N * w.y() * w.y();
  return II / I;
}

}  // namespace bliskrun
