// The damaged region's one volume method (damaged_region.h) against closed
// forms on straight prisms, through the whole chain: measured, rebuilt,
// region. A planar cut of a prism of a blade-like section (the tip broken
// along a tilted plane), and a spherical nick (a dent) in a flat flank: the
// spherical cap π t² (3R - t) / 3, its thickness along the flank's normal t.
// The dent's floor is measured (a scanning probe follows the surface into
// it, damaged_blade.h), which is what the region takes as its floor; a gap
// model of it (no surface where material is missing, the floor the line
// between the ends) was 21 % short of a 3 mm ball before.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "core/repair/damaged_blade.h"
#include "core/repair/damaged_rebuild.h"
#include "core/repair/damaged_region.h"

namespace bliskrun {
namespace {

// A blade-like section without the ellipse's two-fold symmetry (which leaves
// the start alignment and the ICP a half-turn to choose): x = a cos t,
// y = b sin t (1 - c cos t), thicker upstream. Its area is still pi a b
// (the c term integrates to zero in the integral of x dy).
constexpr double kA = 15, kB = 2.5, kC = 0.3, kHeight = 40;  // mm, mm, -, mm

Vec2 ellipse(double t) { return Vec2(kA * std::cos(t), kB * std::sin(t) * (1 - kC * std::cos(t))); }

// The trailing edge's radius is (b (1 - c))^2 / a = 0.2 mm: the default
// smoothing length shrinks it by L^4 / R^3 = 12 um, which the rebuild's own
// check refuses; 0.06 mm keeps it to 1.6 um.
DamagedRebuildOptions rebuild_options() {
  DamagedRebuildOptions o;
  o.rebuild.smoothing_mm = 0.06;
  return o;
}

const DesignBlade& prism() {
  static const DesignBlade d = [] {
    std::vector<std::vector<Vec3>> loops;
    for (int k = 0; k <= 8; ++k) {
      std::vector<Vec3> loop;
      for (int j = 0; j < 720; ++j) {
        const Vec2 p = ellipse(2 * kPi * j / 720);
        loop.emplace_back(p.x(), p.y(), kHeight * k / 8);
      }
      loops.push_back(loop);
    }
    return design_blade(loops, 720);
  }();
  return d;
}

TEST(RegionClosedForm, PlanarCutOfAPrism) {
  // The tip broken off along a plane tilted 20 degrees towards the chord:
  // beyond it, up to the top, the volume A (h_hi - H) + tan(tilt) A x_c, the
  // centroid x_c = 0 (the plane stays inside the height range over the
  // section: tan 20 deg a = 5.5 mm < h_hi - H = 8 mm).
  BladeDamage dmg;
  dmg.tip = true;
  dmg.tip_span = 0.8;
  dmg.tip_tilt_rad = deg_to_rad(20);
  const DamagedBlade blade(prism(), dmg);
  MeasurementOptions mo;
  mo.sections = 30;
  mo.points = 1500;
  const SectionMeasurement m = measure_sections(blade, mo);
  const DamagedRebuild r = rebuild_damaged(m, prism(), rebuild_options());
  ASSERT_TRUE(r.quality.trusted) << r.quality.message;
  const DamagedRegion region = damaged_region(r, m);
  // The frame's origin is the mean of the first loop's points (x = 0); the
  // area's centroid is at x_c = -a c / 4 (the integral of x^2 dy / 2).
  const double x_c = -kA * kC / 4;
  const double truth =
      kPi * kA * kB * (prism().h_hi - prism().span_height(dmg.tip_span) + std::tan(dmg.tip_tilt_rad) * x_c);
  std::printf("prism planar cut: region %.3f mm3, closed form %.3f mm3 (%.2f %%)\n", region.volume_mm3, truth,
              100 * (region.volume_mm3 / truth - 1));
  EXPECT_NEAR(region.volume_mm3, truth, 0.03 * truth);
}

// A prism of a section with two flat flanks: the circles of radius kR1
// about (-kA, 0) (upstream) and kR2 about (kA, 0) joined by their outer
// tangents, unequal so that the start alignment has one answer. The flank
// on the +e2 side (y > 0) is straight from x = -kA + kR1 sin(phi) to
// kA + kR2 sin(phi), sin(phi) = (kR1 - kR2) / 2 kA.
constexpr double kR1 = 2.0, kR2 = 0.6, kHalf = 12, kTall = 12;  // mm

std::vector<Vec2> flat_flanked_section(int samples) {
  const double s = (kR1 - kR2) / (2 * kHalf), c = std::sqrt(1 - s * s), phi = std::asin(s);
  const Vec2 c1(-kHalf, 0), c2(kHalf, 0);
  // Counter-clockwise: the trailing-edge arc, the +e2 flank back upstream,
  // the leading-edge arc, the -e2 flank downstream; equal steps of length.
  const double arc2 = kR2 * (kPi - 2 * phi), arc1 = kR1 * (kPi + 2 * phi);
  const Vec2 up_2 = c2 + kR2 * Vec2(s, c), up_1 = c1 + kR1 * Vec2(s, c);
  const Vec2 lo_1 = c1 + kR1 * Vec2(s, -c), lo_2 = c2 + kR2 * Vec2(s, -c);
  const double flank = (up_1 - up_2).norm(), total = arc2 + arc1 + 2 * flank;
  std::vector<Vec2> out;
  for (int j = 0; j < samples; ++j) {
    double l = total * j / samples;
    if (l < arc2) {
      const double a = -(kPi / 2 - phi) + l / kR2;
      out.push_back(c2 + kR2 * Vec2(std::cos(a), std::sin(a)));
    } else if ((l -= arc2) < flank) {
      out.push_back(up_2 + (up_1 - up_2) * (l / flank));
    } else if ((l -= flank) < arc1) {
      const double a = kPi / 2 - phi + l / kR1;
      out.push_back(c1 + kR1 * Vec2(std::cos(a), std::sin(a)));
    } else {
      l -= arc1;
      out.push_back(lo_1 + (lo_2 - lo_1) * (l / flank));
    }
  }
  return out;
}

const DesignBlade& flat_flanked_prism() {
  static const DesignBlade d = [] {
    std::vector<std::vector<Vec3>> loops;
    const std::vector<Vec2> section = flat_flanked_section(1440);
    for (int k = 0; k <= 6; ++k) {
      std::vector<Vec3> loop;
      for (const Vec2& p : section) loop.emplace_back(p.x(), p.y(), kTall * k / 6);
      loops.push_back(loop);
    }
    return design_blade(loops, 1440);
  }();
  return d;
}

TEST(RegionClosedForm, SphericalNickInAFlatFlankIsItsCap) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "40 measured sections through the chain, ~1 min under the sanitizers (Release suite)";
#endif
  // A ball of radius R = 4 mm pressed t = 0.8 mm into the middle of the +e2
  // flank at mid-height: its cap, footprint radius sqrt(2 R t - t^2) = 2.4
  // mm, lies on the straight flank. The probe follows its floor; 40
  // sections 0.28 mm apart cross it (a CMM program puts sections across a
  // dent: with the blade's 30 over 40 mm, four would).
  BladeDamage dmg;
  dmg.dent = true;
  dmg.dent_span = 0.5;
  dmg.dent_chord = 0.5;
  dmg.dent_side = 1;
  dmg.dent_radius_mm = 4;
  dmg.dent_depth_mm = 0.8;
  const DamagedBlade blade(flat_flanked_prism(), dmg);
  MeasurementOptions mo;
  mo.sections = 40;
  mo.points = 1500;
  mo.face_points = 0;
  const SectionMeasurement m = measure_sections(blade, mo);
  const DamagedRebuild r = rebuild_damaged(m, flat_flanked_prism());
  ASSERT_TRUE(r.quality.trusted) << r.quality.message;
  int dented = 0;
  for (const DamagedSection& s : r.sections) dented += s.dents;
  DamagedRegionOptions ro;
  ro.samples_u = 120;
  ro.samples_v = 2400;
  const DamagedRegion region = damaged_region(r, m, ro);
  const double R = dmg.dent_radius_mm, t = dmg.dent_depth_mm;
  const double truth = kPi * t * t * (3 * R - t) / 3;
  std::printf("spherical nick: region %.4f mm3, closed form %.4f mm3 (%+.2f %%), %d dented sections, max thickness "
              "%.4f mm (closed form %.4f)\n",
              region.volume_mm3, truth, 100 * (region.volume_mm3 / truth - 1), dented, region.max_thickness_mm, t);
  // Sections within the footprint's height of the centre, less the
  // shallowest (their dent is under dent_depth, or shorter than min_dent).
  EXPECT_GE(dented, 12);
  EXPECT_EQ(region.dents, region.nicks);
  EXPECT_FALSE(region.tip);
  EXPECT_NEAR(region.volume_mm3, truth, 0.01 * truth);
  // Along the flank's normal the deepest missing material is the cap's
  // height, at its centre (the map's samples, 5 um apart in height and 23
  // um around, come within a few um of it).
  EXPECT_NEAR(region.max_thickness_mm, t, 0.01);
  // The region is the cap's footprint: 2.4 mm either side of mid-height.
  const double mid = flat_flanked_prism().span_height(0.5), foot = std::sqrt(2 * R * t - t * t);
  EXPECT_NEAR(region.height_from_mm, mid - foot, 0.3);
  EXPECT_NEAR(region.height_to_mm, mid + foot, 0.3);
}

}  // namespace
}  // namespace bliskrun
