#include "core/planning/trimmed_surface.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"

namespace bliskrun {
namespace {

// A curved base flank: a twisted, bent sheet with known derivatives.
class Sheet : public Surface {
 public:
  SurfaceDerivs eval(double u, double v) const override {
    SurfaceDerivs d;
    d.p = Vec3(40 * v, 30 * u, 3 * std::sin(2 * v) + 2 * u * u * v);
    d.pu = Vec3(0, 30, 4 * u * v);
    d.pv = Vec3(40, 0, 6 * std::cos(2 * v) + 2 * u * u);
    d.puu = Vec3(0, 0, 4 * v);
    d.puv = Vec3(0, 0, 4 * u);
    d.pvv = Vec3(0, 0, -12 * std::sin(2 * v));
    return d;
  }
};

// Hub and tip boundaries in parameter space, like a conical hub cutting a
// flank that reaches past it: not iso-lines.
double hub_u(double v) { return 0.05 + 0.06 * v * v; }
double tip_u(double v) { return 0.97 - 0.04 * std::sin(3 * v); }

ParameterBoundary sample_boundary(double (*f)(double), int n) {
  std::vector<double> v(n), u(n);
  for (int i = 0; i < n; ++i) {
    v[i] = static_cast<double>(i) / (n - 1);
    u[i] = f(v[i]);
  }
  return ParameterBoundary(v, u);
}

TEST(TrimmedSurface, IsoLinesStartOnHubAndEndOnTip) {
  auto base = std::make_shared<Sheet>();
  const TrimmedSurface trimmed(base, sample_boundary(hub_u, 60), sample_boundary(tip_u, 60));
  for (double v : {0.0, 0.137, 0.5, 0.81, 1.0}) {
    // u' = 0 is the hub curve and u' = 1 the tip curve (eq. 16), to the
    // accuracy of the cubic fit of 60 samples.
    EXPECT_NEAR((trimmed.point(0, v) - base->point(hub_u(v), v)).norm(), 0, 1e-5) << v;
    EXPECT_NEAR((trimmed.point(1, v) - base->point(tip_u(v), v)).norm(), 0, 1e-5) << v;
    const Vec2 uv = trimmed.base_parameters(0.5, v);
    EXPECT_NEAR(uv.x(), 0.5 * (hub_u(v) + tip_u(v)), 1e-6);
  }
}

TEST(TrimmedSurface, DerivativesMatchFiniteDifferences) {
  auto base = std::make_shared<Sheet>();
  const TrimmedSurface s(base, sample_boundary(hub_u, 40), sample_boundary(tip_u, 40));
  const double h = 1e-5;
  for (double u : {0.2, 0.7}) {
    for (double v : {0.3, 0.6}) {
      const SurfaceDerivs d = s.eval(u, v);
      const SurfaceDerivs du_p = s.eval(u + h, v), du_m = s.eval(u - h, v);
      const SurfaceDerivs dv_p = s.eval(u, v + h), dv_m = s.eval(u, v - h);
      EXPECT_LT((d.pu - (du_p.p - du_m.p) / (2 * h)).norm(), 1e-5);
      EXPECT_LT((d.pv - (dv_p.p - dv_m.p) / (2 * h)).norm(), 1e-5);
      EXPECT_LT((d.puu - (du_p.pu - du_m.pu) / (2 * h)).norm(), 1e-4);
      EXPECT_LT((d.puv - (dv_p.pu - dv_m.pu) / (2 * h)).norm(), 1e-4);
      EXPECT_LT((d.pvv - (dv_p.pv - dv_m.pv) / (2 * h)).norm(), 1e-4);
    }
  }
}

TEST(TrimmedSurface, RejectsCrossingBoundaries) {
  auto base = std::make_shared<Sheet>();
  EXPECT_THROW(TrimmedSurface(base, sample_boundary(tip_u, 20), sample_boundary(hub_u, 20)),
               ParameterError);
}

TEST(ParameterBoundary, RejectsUnorderedSamples) {
  EXPECT_THROW(ParameterBoundary({0, 0.5, 0.4, 1}, {0.1, 0.1, 0.1, 0.1}), ParameterError);
  EXPECT_THROW(ParameterBoundary({0.1, 0.5, 0.7, 1}, {0.1, 0.1, 0.1, 0.1}), ParameterError);
}

}  // namespace
}  // namespace bliskrun
