// Strip width of a flat-end mill against closed forms (edge paper §1.1,
// §3.1), the two-sided side-slip search (§3.2) and the tolerance-band
// conditions.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "core/common/error.h"
#include "core/planning/edge_strip.h"
#include "test_support.h"

namespace bliskrun {
namespace {

// Cylinder of radius rho about the Y axis, material inside: u around (the
// feed, angle (u - 0.5) * span), v along the axis; S(0.5, 0.5) = (0, 0, rho)
// with pu along +X and the normal +Z.
class StripCylinder : public Surface {
 public:
  StripCylinder(double rho, double angle_span, double length) : rho_(rho), a_(angle_span), len_(length) {}
  SurfaceDerivs eval(double u, double v) const override {
    const double t = (u - 0.5) * a_, c = std::cos(t), s = std::sin(t);
    SurfaceDerivs d;
    d.p = Vec3(rho_ * s, (v - 0.5) * len_, rho_ * c);
    d.pu = a_ * Vec3(rho_ * c, 0, -rho_ * s);
    d.pv = Vec3(0, len_, 0);
    d.puu = a_ * a_ * Vec3(-rho_ * s, 0, -rho_ * c);
    return d;
  }

 private:
  double rho_, a_, len_;
};

// Sphere of radius rho: u = longitude about Y (the feed runs along the great
// circle v = 0.5), v = latitude; S(0.5, 0.5) = (0, 0, rho), pu +X, pv +Y.
class Sphere : public Surface {
 public:
  Sphere(double rho, double span) : rho_(rho), a_(span) {}
  SurfaceDerivs eval(double u, double v) const override {
    const double al = (u - 0.5) * a_, la = (v - 0.5) * a_;
    const double ca = std::cos(al), sa = std::sin(al), cl = std::cos(la), sl = std::sin(la);
    SurfaceDerivs d;
    d.p = rho_ * Vec3(cl * sa, sl, cl * ca);
    d.pu = a_ * rho_ * Vec3(cl * ca, 0, -cl * sa);
    d.pv = a_ * rho_ * Vec3(-sl * sa, cl, -sl * ca);
    return d;
  }

 private:
  double rho_, a_;
};

Tool strip_mill(double R, double r) { return test::flat_end_mill(R, r, 2 * R, 20); }

StripWidth width_at(const Surface& s, const Tool& tool, const EdgePosition& pos, const StripSampling& sm,
                    const Band& band) {
  const ContactStrip strip(tool, edge_frame(s.eval(0.5, 0.5)), sample_strip(s, 0.5, 0.5, sm), band);
  return strip.width(pos);
}

TEST(EdgeStripTest, PositionPutsTheContactOnTheToolWithTheAxisAsSpecified) {
  const StripCylinder cyl(0.4, 1.0, 20);
  const EdgeFrame f = edge_frame(cyl.eval(0.5, 0.5));
  const Tool tool = strip_mill(5, 1);
  const FlatEnd fe = flat_end_of(tool);
  EXPECT_DOUBLE_EQ(fe.radius_mm, 5);
  EXPECT_DOUBLE_EQ(fe.corner_mm, 1);
  const ToolPose b = position_tool(fe, f, {EdgeContact::Bottom, 2.5, 0, 0.7});
  EXPECT_NEAR((b.axis - Vec3::UnitZ()).norm(), 0, 1e-12);  // axis = normal
  EXPECT_NEAR((b.tip - f.point).norm(), 2.5, 1e-12);      // C at l from the axis, on the bottom
  EXPECT_NEAR(std::atan2(-(b.tip - f.point).y(), -(b.tip - f.point).x()), 0.7, 1e-12);  // turned by φ
  const ToolPose c = position_tool(fe, f, {EdgeContact::Corner, 0, 0.3, 0});
  EXPECT_NEAR(std::acos(c.axis.dot(Vec3::UnitZ())), 0.3, 1e-12);  // lead θ
  EXPECT_NEAR(tool.signed_distance(Vec3(tool_to_part(c).inverse() * f.point)), 0, 1e-9);
  EXPECT_THROW(position_tool(fe, f, {EdgeContact::Bottom, 4.5, 0, 0}), ParameterError);  // beyond R - r
}

// Flat bottom (sharp, r = 0) on a cylinder, feed around it, φ = 0: the band
// |β| <= acos(ρ/(ρ+e2)) meets the plane at |x| <= ρ tan β; swept, the strip
// along the generator is the longest chord of the bottom disc (centre at
// x = -l) over that band: 2 sqrt(R² - (l - ρ tan β)²).
TEST(EdgeStripTest, FlatBottomOnACylinderMatchesTheChordOfTheDisc) {
  const double rho = 0.4, e2 = 0.01, R = 5;
  const StripCylinder cyl(rho, 1.0, 20);
  const Tool tool = strip_mill(R, 0);
  const double beta = 0.999 * std::acos(rho / (rho + e2));
  StripSampling sm;
  sm.half_width_mm = 6;
  sm.across = 1201;  // 0.01 mm apart
  sm.along = 3;
  sm.along_half_mm = rho * beta;  // samples at β = 0, ±0.999 β_max
  for (double l : {1.0, 2.5, 4.0}) {
    const StripWidth w = width_at(cyl, tool, {EdgeContact::Bottom, l, 0, 0}, sm, {-0.001, e2});
    const double a = rho * std::tan(beta);
    const double expected = 2 * std::sqrt(R * R - (l - a) * (l - a));
    EXPECT_FALSE(w.gouges);
    EXPECT_NEAR(w.width_mm, expected, 0.02) << "l = " << l;
    EXPECT_NEAR(w.left_mm, w.right_mm, 0.011);
  }
  // φ = 90°: the disc's centre lies across the feed; the strip is the chord
  // along the generator through C: from -l - R to R - l, i.e. 2R.
  sm.half_width_mm = 7.5;
  sm.across = 1501;
  const StripWidth w = width_at(cyl, tool, {EdgeContact::Bottom, 2.0, 0, kPi / 2}, sm, {-0.001, e2});
  EXPECT_NEAR(w.left_mm, 2.0 + R, 0.011);
  EXPECT_NEAR(w.right_mm, R - 2.0, 0.011);
}

// Flat bottom on a sphere, φ = 90° so the disc clips the cap on one side:
// strip = ρ (β_max + atan((R - l)/ρ)) (left by the band, right by the disc).
TEST(EdgeStripTest, FlatBottomOnASphereMatchesTheClippedCap) {
  const double rho = 20, e2 = 0.01, R = 5, l = 4.8;
  const Sphere sph(rho, 0.2);
  const Tool tool = strip_mill(R, 0);
  StripSampling sm;
  sm.half_width_mm = 1.2;
  sm.across = 481;  // 0.005 mm
  sm.along = 9;
  sm.along_half_mm = 0.6;
  const StripWidth w = width_at(sph, tool, {EdgeContact::Bottom, l, 0, kPi / 2}, sm, {-0.001, e2});
  const double beta_max = std::acos(rho / (rho + e2));
  EXPECT_NEAR(w.left_mm, rho * beta_max, 0.002);
  EXPECT_NEAR(w.right_mm, rho * std::atan((R - l) / rho), 0.006);
}

// Side (corner) contact of a ball (r = R) on the cylinder's generator:
// 2 sqrt(2 r e2 - e2²). Of a torus R = 5, r = 1 with lead θ: the torus is the
// set of points at distance r from its centre circle Γ (radius R - r, height
// r), so the strip's ends along the generator are the roots y of
// dist(C + y Y_L + e2 Z_L, Γ) = r, found here by bisection — a reference
// independent of the profile's signed distance and of sphere tracing.
TEST(EdgeStripTest, SideContactOnACylinderMatchesTheBallAndTheTorus) {
  const double e2 = 0.01;
  const StripCylinder cyl(0.4, 1.0, 20);
  StripSampling sm;
  sm.half_width_mm = 2;
  sm.across = 801;  // 0.005 mm
  sm.along = 1;
  const StripWidth ball = width_at(cyl, strip_mill(3, 3), {EdgeContact::Corner, 0, 0.2, 0}, sm, {-0.001, e2});
  EXPECT_NEAR(ball.width_mm, 2 * std::sqrt(2 * 3 * e2 - e2 * e2), 0.002);

  const double R = 5, r = 1, theta = 10 * kPi / 180;
  const Tool torus_tool = strip_mill(R, r);
  const StripWidth torus = width_at(cyl, torus_tool, {EdgeContact::Corner, 0, theta, 0}, sm, {-0.001, e2});
  const EdgeFrame f = edge_frame(cyl.eval(0.5, 0.5));
  const Eigen::Isometry3d to_tool =
      tool_to_part(position_tool(flat_end_of(torus_tool), f, {EdgeContact::Corner, 0, theta, 0})).inverse();
  auto g = [&](double y) {
    const Vec3 q = to_tool * Vec3(f.point + y * f.y + e2 * f.z);
    return std::hypot(std::hypot(q.x(), q.y()) - (R - r), q.z() - r) - r;
  };
  auto root = [&](double lo, double hi) {  // g(lo) < 0 < g(hi)
    for (int i = 0; i < 100; ++i) {
      const double m = 0.5 * (lo + hi);
      (g(m) < 0 ? lo : hi) = m;
    }
    return 0.5 * (lo + hi);
  };
  const double reference = root(0, 2) - root(0, -2);
  EXPECT_NEAR(torus.width_mm, reference, 0.002);
  // ... and to first order the osculating circle across the feed, radius
  // (R - r + r sin θ)/sin θ (Meusnier on the parallel).
  EXPECT_NEAR(reference, 2 * std::sqrt(2 * (R - r + r * std::sin(theta)) / std::sin(theta) * e2), 0.1 * reference);
}

TEST(EdgeStripTest, GougingPoseIsRefusedByConditionOne) {
  // Inside a cylinder (normal flipped: material outside): a flat bottom
  // tangent at C digs into the concave wall beside it.
  const StripCylinder cyl(8, 1.0, 20);
  const Tool tool = strip_mill(5, 1);
  StripSampling sm;
  sm.half_width_mm = 6;
  sm.across = 121;
  const ContactStrip strip(tool, edge_frame(cyl.eval(0.5, 0.5), true), sample_strip(cyl, 0.5, 0.5, sm, true),
                           {-0.001, 0.02});
  const StripWidth w = strip.width({EdgeContact::Bottom, 2.0, 0, 0});
  EXPECT_TRUE(w.gouges);
  EXPECT_LT(w.deepest_mm, -0.001);
  EXPECT_EQ(w.width_mm, 0);
  // The corner with enough lead clears it (§3.2: concave parts by the corner).
  const CornerPosition c = corner_min_lead(strip, 0);
  ASSERT_TRUE(c.feasible);
  EXPECT_GT(c.position.lead_rad, 0);
  EXPECT_FALSE(c.width.gouges);
}

// ContactStrip screens condition ① by tiles of samples; every sample one
// by one (strip_width) must give the same verdict, the same width and, where
// the pose cuts below the surface within e1, the same depth (where it gouges,
// the screen stops at the first sample below e1) — over bottom and corner poses on a convex
// and a concave wall, gouging or not; the same with the gouge samples shared.
TEST(EdgeStripTest, TiledScreeningAgreesWithEverySampleOneByOne) {
  const StripCylinder cyl(8, 1.0, 20);
  const Tool tool = strip_mill(5, 1);
  const Band band{-0.001, 0.02};
  StripSampling sm;
  sm.across = 121;
  int gouging = 0, cutting = 0;
  for (bool concave : {false, true}) {
    const StripSamples samples = sample_strip(cyl, 0.5, 0.5, sm, concave);
    const ContactStrip strip(tool, edge_frame(cyl.eval(0.5, 0.5), concave), samples, band);
    // The gouge samples held apart and shared (as a row's flank samples are).
    StripSamples own = samples;
    own.gouge_p.clear();
    own.gouge_n.clear();
    const ContactStrip sharing(tool, edge_frame(cyl.eval(0.5, 0.5), concave), own, band,
                               share_gouge_samples(samples.gouge_p, samples.gouge_n));
    for (double phi = -1.5; phi <= 1.5; phi += 0.1)
      for (const EdgePosition& pos : {EdgePosition{EdgeContact::Bottom, 2.0, 0, phi},
                                      EdgePosition{EdgeContact::Bottom, 3.5, 0, phi},
                                      EdgePosition{EdgeContact::Corner, 0, 0.3, phi},
                                      EdgePosition{EdgeContact::Corner, 0, 1.0, phi}}) {
        const ToolPose pose = strip.pose(pos);
        const StripWidth tiled = strip.width(pose);
        const StripWidth each = strip_width(tool, pose, samples, band);
        const StripWidth shared = sharing.width(pose);
        ASSERT_EQ(tiled.gouges, each.gouges);
        ASSERT_EQ(shared.gouges, each.gouges);
        EXPECT_EQ(shared.width_mm, each.width_mm);
        EXPECT_EQ(tiled.touches, each.touches);
        EXPECT_EQ(tiled.width_mm, each.width_mm);
        EXPECT_EQ(tiled.left_mm, each.left_mm);
        if (each.gouges) {
          // The screen stops at the first sample below e1: a depth below e1,
          // never below the deepest; deepest() finds the deepest itself.
          for (const StripWidth* w : {&tiled, &shared}) {
            EXPECT_LT(w->deepest_mm, band.e1_mm);
            EXPECT_GE(w->deepest_mm, each.deepest_mm);
          }
          EXPECT_EQ(strip.deepest(pose), deepest_distance(tool, pose, samples, band));
          EXPECT_EQ(strip.deepest(pose), each.deepest_mm);
        } else if (each.deepest_mm < 0) {
          EXPECT_EQ(tiled.deepest_mm, each.deepest_mm);
          EXPECT_EQ(shared.deepest_mm, each.deepest_mm);
          EXPECT_EQ(strip.deepest(pose), deepest_distance(tool, pose, samples, band));
        } else {
          EXPECT_GE(tiled.deepest_mm, 0);
          EXPECT_LE(tiled.deepest_mm, each.deepest_mm);
        }
        gouging += each.gouges ? 1 : 0;
        cutting += each.width_mm > 0 ? 1 : 0;
      }
  }
  EXPECT_GT(gouging, 10);  // both verdicts are exercised
  EXPECT_GT(cutting, 10);
}

// The directed distance (the flat bottom in closed form, the corner and
// side by Newton steps, inside by tracing and bisection) against the
// line's crossing of the cutter found by marching in 0.1 um steps and
// bisecting the signed distance: from below the bottom, beside the corner
// and the side (lines down to grazing, which sphere tracing gave up on at
// ~20 deg), from inside, and lines that miss.
TEST(EdgeStripTest, DirectedDistanceMatchesTheCrossingFoundByBisection) {
  const FlatEnd cutter{5, 1};
  const double cap = 0.2;
  auto crossing = [&](const Vec3& q, const Vec3& m) {
    const double s = cutter.signed_distance(q) > 0 ? 1.0 : -1.0;  // outside: ahead; inside: behind
    double a = 0;
    for (double t = 1e-4; t <= cap; t += 1e-4) {
      if ((cutter.signed_distance(q + s * t * m) > 0) != (s > 0)) {
        double lo = a, hi = t;
        for (int k = 0; k < 60; ++k) {
          const double mid = 0.5 * (lo + hi);
          ((cutter.signed_distance(q + s * mid * m) > 0) == (s > 0) ? lo : hi) = mid;
        }
        return s * lo;
      }
      a = t;
    }
    return s * cap;
  };
  std::uint32_t seed = 12345;
  auto rnd = [&] {
    seed = seed * 1664525u + 1013904223u;
    return (seed >> 8) / 16777216.0;
  };
  int bottom = 0, corner = 0, inside = 0, missing = 0;
  for (int tried = 0, kept = 0; kept < 4000 && tried < 1000000; ++tried) {
    // A point within cap of the cutting end (a strip's samples are), a
    // direction anywhere up to 80 deg from +z (the surface normal points at
    // the tool) or its reverse.
    const Vec3 q(-7 + 14 * rnd(), -7 + 14 * rnd(), -1.5 + 4 * rnd());
    const double polar = 80 * kPi / 180 * rnd(), az = 2 * kPi * rnd();
    Vec3 m(std::sin(polar) * std::cos(az), std::sin(polar) * std::sin(az), std::cos(polar));
    if (rnd() < 0.2) m = -m;
    const double dq = cutter.signed_distance(q);
    if (std::abs(dq) < 1e-6 || std::abs(dq) > cap) continue;
    ++kept;
    const double got = directed_distance(cutter, Eigen::Isometry3d::Identity(), q, m, cap);
    const double want = crossing(q, m);
    // On the surface to the tracing's 1e-8 (along a grazing line that is
    // further in t), and at the line's crossing.
    if (std::abs(want) < cap) EXPECT_LT(std::abs(cutter.signed_distance(q + got * m)), 1.1e-8) << "q " << q.transpose();
    ASSERT_NEAR(got, want, 1e-6) << "q " << q.transpose() << " m " << m.transpose();
    const Vec3 h = q + want * m;
    if (std::abs(want) >= cap) ++missing;
    else if (dq < 0) ++inside;
    else if (std::abs(h.z()) < 1e-6 && std::hypot(h.x(), h.y()) < 4) ++bottom;
    else ++corner;
  }
  // Every kind of crossing is exercised.
  EXPECT_GT(bottom, 100);
  EXPECT_GT(corner, 100);
  EXPECT_GT(inside, 100);
  EXPECT_GT(missing, 100);
}

TEST(EdgeStripTest, SideSlipSearchFindsTheMaximumFromBothSides) {
  const SideSlipSearch s;
  const double peak = 0.3;
  const SearchResult r = search_side_slip([&](double phi) { return 1 - (phi - peak) * (phi - peak); }, s);
  EXPECT_NEAR(r.phi_rad, peak, s.min_step_rad);
  // Two peaks either side of 0 (the paper's Fig. 6), the right one higher:
  // the search from -90° finds the left, from +90° the right; the right wins.
  auto two = [](double phi) { return std::max(1.0 - 4 * std::pow(phi + 0.5, 2), 1.2 - 4 * std::pow(phi - 0.6, 2)); };
  const SearchResult t = search_side_slip(two, s);
  EXPECT_NEAR(t.phi_rad, 0.6, s.min_step_rad);
  EXPECT_NEAR(t.width_mm, 1.2, 1e-6);
  EXPECT_LT(t.evaluations, 200);
}

TEST(EdgeStripTest, BalancedLTakesTheLargestLThatKeepsTheRowWidth) {
  // Contact 1 is the narrow one (curvature peak): its best width sets the row.
  const std::vector<std::vector<double>> w = {{9, 8, 7, 6}, {5, 4.8, 4, 0}, {9, 9, 8, 4}};
  const BalancedRow b = balance_l(w);
  EXPECT_DOUBLE_EQ(b.width_mm, 5);
  EXPECT_EQ(b.l_index, (std::vector<int>{3, 0, 2}));
}

}  // namespace
}  // namespace bliskrun
