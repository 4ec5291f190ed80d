#include "core/analysis/curvature_stats.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/common/error.h"
#include "core/geometry/differential.h"

namespace bliskrun {

namespace {

double euler(double k1, double k2, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return k1 * c * c + k2 * s * s;
}

}  // namespace

double max_normal_curvature_in_range(double k1, double k2, double a1, double c, double* arg) {
  // k_n has period pi and is largest at a1 + m pi. Bring the nearest such
  // angle to 0 into (-pi/2, pi/2].
  double peak = std::remainder(a1, kPi);
  if (std::abs(peak) <= c) {
    *arg = peak;
    return k1;
  }
  // Outside the range k_n falls monotonically towards the valley, so the
  // best end is the one nearer the peak (mod pi). Evaluate both: exact ties
  // keep -c.
  const double lo = euler(k1, k2, -c - a1), hi = euler(k1, k2, c - a1);
  *arg = hi > lo ? c : -c;
  return std::max(lo, hi);
}

CurvatureStats curvature_stats(const Surface& s, const CurvatureStatsOptions& opts,
                               Progress& progress) {
  if (opts.samples_u < 2) throw ParameterError("samples_u", "expected at least 2");
  if (opts.samples_v < 2) throw ParameterError("samples_v", "expected at least 2");
  if (!(opts.c_range_rad >= 0)) throw ParameterError("c_range", "expected an angle >= 0");
  const int nu = opts.samples_u, nv = opts.samples_v;
  // Beyond a quarter turn every tangent direction is reachable.
  const double c_range = std::min(opts.c_range_rad, kPi / 2);

  CurvatureStats out;
  out.samples_u = nu;
  out.samples_v = nv;
  if (opts.keep_map) out.map.resize(static_cast<size_t>(nu) * nv);
  out.K_min = std::numeric_limits<double>::infinity();
  out.K_max = -std::numeric_limits<double>::infinity();

  progress.begin("curvature analysis", nu);
  for (int i = 0; i < nu; ++i) {
    const double u = static_cast<double>(i) / (nu - 1);
    for (int j = 0; j < nv; ++j) {
      const double v = static_cast<double>(j) / (nv - 1);
      const SurfaceDerivs d = s.eval(u, v);
      const SurfaceCurvature c = curvature(d);
      CurvatureSample sample{c.K, c.H, c.k1, c.k2, 0.0};
      // Angle of dir1 from pu, positive towards n x pu.
      const Vec3 e1 = d.pu.normalized();
      const Vec3 e2 = c.normal.cross(e1);
      const double a1 = std::atan2(c.dir1.dot(e2), c.dir1.dot(e1));
      double ke_angle = 0;
      sample.ke = max_normal_curvature_in_range(c.k1, c.k2, a1, c_range, &ke_angle);
      out.K_min = std::min(out.K_min, c.K);
      out.K_max = std::max(out.K_max, c.K);
      if (c.K < 0) {
        ++out.negative_K_count;
        auto update = [&](CurvatureExtreme& e, double value, double angle) {
          if (!e.found || value > e.value) e = CurvatureExtreme{value, u, v, angle, true};
        };
        update(out.k1_max, c.k1, std::remainder(a1, kPi));
        update(out.k2_max, std::abs(c.k2), std::remainder(a1 + kPi / 2, kPi));
        update(out.ke_max, sample.ke, ke_angle);
      }
      if (opts.keep_map) out.map[static_cast<size_t>(i) * nv + j] = sample;
    }
    progress.step(i + 1);
  }
  progress.end();
  out.negative_K_fraction = static_cast<double>(out.negative_K_count) / (double(nu) * nv);
  out.k1_max.value = std::abs(out.k1_max.value);
  out.ke_max.value = std::abs(out.ke_max.value);
  return out;
}

}  // namespace bliskrun
