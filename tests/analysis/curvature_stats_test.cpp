#include "core/analysis/curvature_stats.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/common/error.h"
#include "geometry/analytic_surfaces.h"

namespace bliskrun {
namespace {

// new(u, v) = s(1 - v, u): swaps the parameter directions and keeps the
// normal's side (pv_new = -pu_old, so pu_new x pv_new = pu_old x pv_old).
class Swapped : public Surface {
 public:
  explicit Swapped(const Surface& s) : s_(s) {}
  SurfaceDerivs eval(double u, double v) const override {
    const SurfaceDerivs o = s_.eval(1 - v, u);
    SurfaceDerivs d;
    d.p = o.p;
    d.pu = o.pv;
    d.pv = -o.pu;
    d.puu = o.pvv;
    d.puv = -o.puv;
    d.pvv = o.puu;
    return d;
  }
  const Surface& s_;
};

TEST(CurvatureStats, SphereHasNoSaddleRegion) {
  const test::Sphere sphere(20.0);
  CurvatureStatsOptions o;
  o.samples_u = 30;
  o.samples_v = 40;
  const CurvatureStats st = curvature_stats(sphere, o);
  EXPECT_EQ(st.negative_K_count, 0);
  EXPECT_FALSE(st.k1_max.found);
  EXPECT_NEAR(st.K_min, 1.0 / 400, 1e-12);
  EXPECT_NEAR(st.K_max, 1.0 / 400, 1e-12);
  ASSERT_EQ(st.map.size(), 30u * 40u);
  for (const CurvatureSample& s : st.map) {
    EXPECT_NEAR(s.H, -1.0 / 20, 1e-12);
    EXPECT_NEAR(s.k1, -1.0 / 20, 1e-7);  // umbilic: sqrt(H^2 - K) of rounding
    EXPECT_NEAR(s.k2, -1.0 / 20, 1e-7);
  }
}

// Cylinder with pu along the axis: k = 1/R around, 0 along. The axis may turn
// c from pu, so k_e = k cos^2(90° - c) = sin^2(c) / R (eq. 14).
TEST(CurvatureStats, CylinderKeFollowsTheCRange) {
  const double R = 25.0;
  const test::Cylinder cyl(R, 40.0);
  for (double c_deg : {0.0, 30.0, 60.0, 90.0, 120.0}) {
    CurvatureStatsOptions o;
    o.samples_u = 5;
    o.samples_v = 7;
    o.c_range_rad = deg_to_rad(c_deg);
    const CurvatureStats st = curvature_stats(cyl, o);
    const double s = std::sin(deg_to_rad(std::min(c_deg, 90.0)));
    for (const CurvatureSample& smp : st.map) {
      EXPECT_NEAR(smp.K, 0.0, 1e-12);
      EXPECT_NEAR(smp.k1, 1 / R, 1e-12);
      EXPECT_NEAR(smp.ke, s * s / R, 1e-12) << "C range " << c_deg;
    }
  }
}

// Inner half of a torus (K < 0), parametrised so that pu runs around the
// ring and the k1 = 1/r direction (around the tube) is perpendicular to pu.
// Closed forms per sample: k1 = 1/r, k2 = cos(phi)/(R + r cos(phi)),
// k_e = k1 sin^2(c) + k2 cos^2(c).
TEST(CurvatureStats, SaddleRegionOfTorusMatchesClosedForms) {
  const double R = 40.0, r = 10.0;
  const test::Torus torus(R, r);
  const Swapped s(torus);
  CurvatureStatsOptions o;
  o.samples_u = 21;
  o.samples_v = 100;  // no sample on the parabolic lines cos(phi) = 0
  for (double c_deg : {30.0, 60.0, 90.0}) {
    o.c_range_rad = deg_to_rad(c_deg);
    const CurvatureStats st = curvature_stats(s, o);
    const double c = o.c_range_rad;
    long negative = 0;
    double k2_max = 0, ke_max = -1e9;
    for (int j = 0; j < o.samples_v; ++j) {
      // new v = 1 - old u, old u -> phi = 2 pi u_old.
      const double phi = 2 * kPi * (1 - double(j) / (o.samples_v - 1));
      const double k2 = std::cos(phi) / (R + r * std::cos(phi));
      const double K = k2 / r;
      for (int i = 0; i < o.samples_u; ++i) {
        const CurvatureSample& smp = st.at(i, j);
        EXPECT_NEAR(smp.K, K, 1e-10);
        if (K < -1e-12) {
          EXPECT_NEAR(smp.k1, 1 / r, 1e-10);
          EXPECT_NEAR(smp.k2, k2, 1e-10);
          const double ke = (1 / r) * std::sin(c) * std::sin(c) + k2 * std::cos(c) * std::cos(c);
          EXPECT_NEAR(smp.ke, ke, 1e-10);
          ++negative;
          k2_max = std::max(k2_max, std::abs(k2));
          ke_max = std::max(ke_max, ke);
        }
      }
    }
    EXPECT_EQ(st.negative_K_count, negative);
    EXPECT_NEAR(st.negative_K_fraction, double(negative) / (21 * 100), 1e-15);
    EXPECT_NEAR(st.k1_max.value, 1 / r, 1e-10);
    EXPECT_NEAR(std::abs(st.k1_max.angle_rad), kPi / 2, 1e-8);
    EXPECT_NEAR(st.k2_max.value, k2_max, 1e-10);
    EXPECT_NEAR(st.ke_max.value, ke_max, 1e-10);
    if (c_deg < 90) EXPECT_NEAR(std::abs(st.ke_max.angle_rad), c, 1e-12);
  }
  // A wider C range can only raise k_e (more directions allowed).
  o.c_range_rad = deg_to_rad(30);
  const double ke30 = curvature_stats(s, o).ke_max.value;
  o.c_range_rad = deg_to_rad(60);
  EXPECT_GT(curvature_stats(s, o).ke_max.value, ke30 + 0.03);
}

TEST(CurvatureStats, RangeMaximumMatchesBruteForce) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> k(-0.1, 0.1), ang(-4, 4), c(0, kPi / 2);
  for (int n = 0; n < 400; ++n) {
    double k1 = k(rng), k2 = k(rng);
    if (k1 < k2) std::swap(k1, k2);
    const double a1 = ang(rng), cr = c(rng);
    double arg = 0;
    const double got = max_normal_curvature_in_range(k1, k2, a1, cr, &arg);
    double brute = -1e9;
    for (int s = 0; s <= 20000; ++s) {
      const double a = -cr + 2 * cr * s / 20000.0;
      brute = std::max(brute, k1 * std::pow(std::cos(a - a1), 2) + k2 * std::pow(std::sin(a - a1), 2));
    }
    EXPECT_NEAR(got, brute, 1e-6 * (k1 - k2) + 1e-12);
    EXPECT_LE(std::abs(arg), cr + 1e-15);
    EXPECT_NEAR(k1 * std::pow(std::cos(arg - a1), 2) + k2 * std::pow(std::sin(arg - a1), 2), got,
                1e-14);
  }
}

TEST(CurvatureStats, RejectsBadOptions) {
  const test::Sphere sphere(1.0);
  CurvatureStatsOptions o;
  o.samples_u = 1;
  try {
    curvature_stats(sphere, o);
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.name(), "samples_u");
  }
  o = {};
  o.c_range_rad = -0.1;
  EXPECT_THROW(curvature_stats(sphere, o), ParameterError);
}

TEST(CurvatureStats, ProgressCancels) {
  const test::Sphere sphere(1.0);
  Progress progress;
  progress.cancel("test");
  EXPECT_THROW(curvature_stats(sphere, {}, progress), Cancelled);
}

}  // namespace
}  // namespace bliskrun
