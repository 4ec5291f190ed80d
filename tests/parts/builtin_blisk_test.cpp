#include "core/parts/builtin_blisk.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/analysis/curvature_stats.h"
#include "core/common/error.h"
#include "core/geometry/differential.h"
#include "core/geometry/interpolation.h"

namespace bliskrun {
namespace {

BliskParams small_grid() {
  BliskParams p;
  p.grid_rows = 20;
  p.grid_cols = 60;
  return p;
}

double radius(const Vec3& q) { return std::hypot(q.x(), q.y()); }

TEST(BuiltinBlisk, BladeKIsBladeZeroRotated) {
  const BuiltinBlisk b(small_grid());
  ASSERT_EQ(b.blade_count(), 22);
  for (FlankSide side : {FlankSide::kPressure, FlankSide::kSuction}) {
    const PointGrid g0 = b.flank_grid(0, side);
    for (int k : {1, 7, 21}) {
      const PointGrid gk = b.flank_grid(k, side);
      const Eigen::AngleAxisd rot(2 * kPi * k / 22, Vec3::UnitZ());
      for (size_t n = 0; n < g0.points.size(); ++n)
        EXPECT_LT((rot * g0.points[n] - gk.points[n]).norm(), 1e-10);
    }
  }
}

TEST(BuiltinBlisk, HubAndCasingAreConesThirtyMillimetresApart) {
  const BuiltinBlisk b;
  const auto hub = b.hub_meridian(), casing = b.casing_meridian();
  ASSERT_EQ(hub.size(), 2u);
  EXPECT_GT(std::abs(hub[1].y() - hub[0].y()), 3.0);  // conical, not cylindrical
  EXPECT_GT(std::abs(casing[1].y() - casing[0].y()), 3.0);
  for (double z : {-20.0, 0.0, 15.0}) {
    EXPECT_NEAR(b.casing_radius_at(z) - b.hub_radius_at(z), 30.0, 1e-12);
    // Straight in (z, r).
    EXPECT_NEAR(b.hub_radius_at(z),
                hub[0].y() + (hub[1].y() - hub[0].y()) * (z - hub[0].x()) / (hub[1].x() - hub[0].x()),
                1e-12);
  }
}

// Row 0 lies at least span_extension below the hub and the last row at least
// span_extension above the casing at every chord station, and the hub cuts
// the grid obliquely (not along an iso-u row).
TEST(BuiltinBlisk, GridReachesPastHubAndCasing) {
  const BliskParams p = small_grid();
  const BuiltinBlisk b(p);
  for (FlankSide side : {FlankSide::kPressure, FlankSide::kSuction}) {
    const PointGrid g = b.flank_grid(3, side);
    double min_row = 1e9, max_row = -1e9;
    for (int j = 0; j < g.cols; ++j) {
      const Vec3& lo = g.at(0, j);
      const Vec3& hi = g.at(g.rows - 1, j);
      EXPECT_LE(radius(lo), b.hub_radius_at(lo.z()) - p.span_extension_mm + 1e-9);
      EXPECT_GE(radius(hi), b.casing_radius_at(hi.z()) + p.span_extension_mm - 1e-9);
      // Fractional row where the hub crosses this column.
      for (int i = 0; i + 1 < g.rows; ++i) {
        const double a = radius(g.at(i, j)) - b.hub_radius_at(g.at(i, j).z());
        const double c = radius(g.at(i + 1, j)) - b.hub_radius_at(g.at(i + 1, j).z());
        if (a <= 0 && c > 0) {
          const double row = i + a / (a - c);
          min_row = std::min(min_row, row);
          max_row = std::max(max_row, row);
        }
      }
    }
    EXPECT_GT(max_row - min_row, 1.5) << "the hub should cross several rows";
  }
}

// pu x pv points out of the material: away from the opposite flank of the
// same blade (suction v runs TE -> LE, so its column cols-1-j faces column j
// of the pressure flank), on the analytic flanks and on their reconstruction.
TEST(BuiltinBlisk, FlankNormalsPointOutOfTheMaterial) {
  const BuiltinBlisk b(small_grid());
  const auto ps = b.flank_surface(5, FlankSide::kPressure);
  const auto ss = b.flank_surface(5, FlankSide::kSuction);
  const BSplineSurface pi = interpolate_grid(b.flank_grid(5, FlankSide::kPressure));
  const BSplineSurface si = interpolate_grid(b.flank_grid(5, FlankSide::kSuction));
  for (double u : {0.0, 0.3, 0.7, 1.0})
    for (double v : {0.0, 0.1, 0.5, 0.9, 1.0}) {
      const SurfaceDerivs dp = ps->eval(u, v), ds = ss->eval(u, 1 - v);
      const Vec3 across = ds.p - dp.p;  // pressure -> suction through the blade
      ASSERT_GT(across.norm(), 0.5);
      EXPECT_LT(dp.pu.cross(dp.pv).dot(across), 0) << u << " " << v;
      EXPECT_GT(ds.pu.cross(ds.pv).dot(across), 0) << u << " " << v;
      EXPECT_LT(pi.eval(u, v).pu.cross(pi.eval(u, v).pv).dot(across), 0);
      EXPECT_GT(si.eval(u, 1 - v).pu.cross(si.eval(u, 1 - v).pv).dot(across), 0);
      // u runs hub -> tip.
      EXPECT_GT(dp.pu.dot(Vec3(dp.p.x(), dp.p.y(), 0).normalized()), 0);
    }
}

// Suction and pressure flanks meet the LE circle tangentially: the flank
// start points are 2 r_le apart along the camber normal, and both flank
// tangents there are perpendicular to that diameter.
TEST(BuiltinBlisk, EdgeCirclesAreTangentToBothFlanks) {
  const BliskParams p = small_grid();
  const BuiltinBlisk b(p);
  const auto ps = b.flank_surface(0, FlankSide::kPressure);
  const auto ss = b.flank_surface(0, FlankSide::kSuction);
  for (double u : {0.2, 0.8}) {
    for (const auto& [vp, vs, r] : {std::tuple{0.0, 1.0, p.le_radius_mm},
                                    std::tuple{1.0, 0.0, p.te_radius_mm}}) {
      const SurfaceDerivs dp = ps->eval(u, vp), ds = ss->eval(u, vs);
      const Vec3 diameter = ds.p - dp.p;
      // Exact in the unrolled section; wrapping onto the cylinder bends a
      // sub-millimetre diameter by ~1e-6.
      EXPECT_NEAR(diameter.norm(), 2 * r, 1e-5);
      EXPECT_NEAR(dp.pv.normalized().dot(diameter.normalized()), 0, 1e-5);
      EXPECT_NEAR(ds.pv.normalized().dot(diameter.normalized()), 0, 1e-5);
    }
  }
}

TEST(BuiltinBlisk, ValidationNamesTheParameter) {
  auto name_of = [](auto edit) -> std::string {
    BliskParams p;
    edit(p);
    try {
      BuiltinBlisk b(p);
    } catch (const ParameterError& e) {
      return e.name();
    }
    return "";
  };
  EXPECT_EQ(name_of([](BliskParams& p) { p.blade_count = 1; }), "blade_count");
  EXPECT_EQ(name_of([](BliskParams& p) { p.casing_radius_inlet_mm = 50; }), "casing_radius_inlet");
  EXPECT_EQ(name_of([](BliskParams& p) { p.hub_radius_outlet_mm = -1; }), "hub_radius_outlet");
  EXPECT_EQ(name_of([](BliskParams& p) { p.z_outlet_mm = p.z_inlet_mm; }), "z_outlet");
  EXPECT_EQ(name_of([](BliskParams& p) { p.chord_mm = 60; }), "chord");
  EXPECT_EQ(name_of([](BliskParams& p) { p.camber_tip_rad = 0; }), "camber_tip");
  EXPECT_EQ(name_of([](BliskParams& p) { p.stagger_hub_rad = deg_to_rad(85); }), "stagger_hub");
  EXPECT_EQ(name_of([](BliskParams& p) { p.max_thickness_tip_mm = 0.5; }), "max_thickness_tip");
  EXPECT_EQ(name_of([](BliskParams& p) { p.le_radius_mm = 0; }), "le_radius");
  EXPECT_EQ(name_of([](BliskParams& p) { p.grid_rows = 3; }), "grid_rows");
  EXPECT_EQ(name_of([](BliskParams& p) { p.span_extension_mm = -1; }), "span_extension");
  EXPECT_EQ(name_of([](BliskParams&) {}), "");
  EXPECT_THROW(BuiltinBlisk().flank_grid(22, FlankSide::kPressure), ParameterError);
}

// The narrowest passage against brute force: all in-span point pairs of the
// two flanks on a 0.4 mm-ish grid, then all pairs on a fine grid around the
// best coarse pair. The method's answer can only be below a sampled pair
// distance (it minimises over the same sets) and must be within the fine
// sampling's resolution of it.
TEST(BuiltinBlisk, NarrowestPassageMatchesBruteForce) {
  const BuiltinBlisk b;
  const double d = b.narrowest_passage_mm();
  EXPECT_NEAR(d, 10.5, 0.1);  // the paper's d_min

  const auto s = b.flank_surface(0, FlankSide::kSuction);
  const auto p = b.flank_surface(1, FlankSide::kPressure);
  auto in_span = [&](const Vec3& q) {
    return radius(q) >= b.hub_radius_at(q.z()) && radius(q) <= b.casing_radius_at(q.z());
  };
  struct Pt { double u, v; Vec3 q; };
  auto sample = [&](const Surface& f, double u0, double u1, double v0, double v1, int nu, int nv) {
    std::vector<Pt> out;
    for (int i = 0; i <= nu; ++i)
      for (int j = 0; j <= nv; ++j) {
        const double u = std::clamp(u0 + (u1 - u0) * i / nu, 0.0, 1.0);
        const double v = std::clamp(v0 + (v1 - v0) * j / nv, 0.0, 1.0);
        const Vec3 q = f.point(u, v);
        if (in_span(q)) out.push_back({u, v, q});
      }
    return out;
  };
  auto brute = [](const std::vector<Pt>& a, const std::vector<Pt>& c, Pt* ba, Pt* bc) {
    double best = std::numeric_limits<double>::infinity();
    for (const Pt& x : a)
      for (const Pt& y : c) {
        const double dd = (x.q - y.q).squaredNorm();
        if (dd < best) { best = dd; *ba = x; *bc = y; }
      }
    return std::sqrt(best);
  };
  Pt ba, bc;
  const double coarse = brute(sample(*s, 0, 1, 0, 1, 100, 100), sample(*p, 0, 1, 0, 1, 100, 100),
                              &ba, &bc);
  EXPECT_LE(d, coarse + 1e-9);
  // Fine windows of +-0.02 in u and v (~0.8 mm) around the coarse optimum.
  const double w = 0.02;
  Pt fa, fc;
  const double fine = brute(sample(*s, ba.u - w, ba.u + w, ba.v - w, ba.v + w, 80, 80),
                            sample(*p, bc.u - w, bc.u + w, bc.v - w, bc.v + w, 80, 80), &fa, &fc);
  EXPECT_LE(d, fine + 1e-9);
  EXPECT_GT(d, fine - 2e-3);
}

// The defaults are tuned to the order of the paper's Table 1 on the
// pressure flank's 100 x 500 reconstruction (the concave side, where the
// wheel radius matters).
TEST(BuiltinBlisk, DefaultCurvatureIsOfTheOrderOfTable1) {
  const BuiltinBlisk b;
  const BSplineSurface flank = interpolate_grid(b.flank_grid(0, FlankSide::kPressure));
  const CurvatureStats st = curvature_stats(flank);
  EXPECT_GT(st.negative_K_fraction, 0.5);
  EXPECT_NEAR(st.k1_max.value, 0.0435, 0.005);
  EXPECT_NEAR(st.k2_max.value, 0.0089, 0.003);
  EXPECT_NEAR(st.ke_max.value, 0.0195, 0.003);
  EXPECT_LT(st.ke_max.value, st.k1_max.value);
}

}  // namespace
}  // namespace bliskrun
