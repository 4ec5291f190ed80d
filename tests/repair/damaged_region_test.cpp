// The damaged region (repair paper §1.5) of the built-in blade against the
// material the simulated damage removed, measured independently: section
// areas by scan lines (not by clipping), integrated over height.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/parts/builtin_blisk.h"
#include "core/repair/damaged_blade.h"
#include "core/repair/damaged_region.h"
#include "repair/builtin_design.h"

namespace bliskrun {
namespace {


// Area of the closed polygon where keep(x, y) holds, by horizontal scan
// lines dy apart: the inside stretches between sorted crossings, each
// stretch integrated at the midpoint of keep's sub-steps.
template <class Keep>
double scanline_area(const std::vector<Vec2>& poly, double dy, Keep keep) {
  double y_lo = 1e300, y_hi = -1e300;
  for (const Vec2& p : poly) {
    y_lo = std::min(y_lo, p.y());
    y_hi = std::max(y_hi, p.y());
  }
  double area = 0;
  for (double y = y_lo + 0.5 * dy; y < y_hi; y += dy) {
    std::vector<double> xs;
    for (size_t j = 0; j < poly.size(); ++j) {
      const Vec2& a = poly[j];
      const Vec2& b = poly[(j + 1) % poly.size()];
      if ((a.y() > y) != (b.y() > y)) xs.push_back(a.x() + (b.x() - a.x()) * (y - a.y()) / (b.y() - a.y()));
    }
    std::sort(xs.begin(), xs.end());
    for (size_t k = 0; k + 1 < xs.size(); k += 2) {
      const int steps = std::max(1, static_cast<int>((xs[k + 1] - xs[k]) / dy));
      const double dx = (xs[k + 1] - xs[k]) / steps;
      for (int s = 0; s < steps; ++s)
        if (keep(xs[k] + (s + 0.5) * dx, y)) area += dx * dy;
    }
  }
  return area;
}


// The longest stretch of removed material along a section's inward normal
// (the thickness the region reports, header): from each vertex q of the true
// section where removed(q), along the inward normal of the polygon there,
// until the ray leaves the polygon (first crossing) or removed() stops
// holding (marched in 1 um steps).
template <class Removed>
double through_length(const std::vector<Vec2>& poly, Removed removed) {
  const size_t m = poly.size();
  double twice = 0;
  for (size_t j = 0; j < m; ++j) twice += poly[j].x() * poly[(j + 1) % m].y() - poly[j].y() * poly[(j + 1) % m].x();
  double best = 0;
  for (size_t j = 0; j < m; ++j) {
    const Vec2& q = poly[j];
    if (!removed(q)) continue;
    const Vec2 t = poly[(j + 1) % m] - poly[(j + m - 1) % m];
    Vec2 in = Vec2(-t.y(), t.x()).normalized();  // left of the direction of travel: inside for a ccw loop
    if (twice < 0) in = -in;
    double exit = 1e9;
    for (size_t k = 0; k < m; ++k) {
      const Vec2& a = poly[k];
      const Vec2 e = poly[(k + 1) % m] - a;
      const double den = in.x() * e.y() - in.y() * e.x();
      if (std::abs(den) < 1e-15) continue;
      const Vec2 w = a - q;
      const double s = (w.x() * e.y() - w.y() * e.x()) / den, u = (w.x() * in.y() - w.y() * in.x()) / den;
      if (u >= 0 && u < 1 && s > 1e-3) exit = std::min(exit, s);
    }
    double s = 0;
    while (s < exit && removed(q + (s + 0.001) * in)) s += 0.001;
    best = std::max(best, std::min(s, exit));
  }
  return best;
}

TEST(DamagedRegion, BrokenTipHasTheVolumeOfTheCut) {
  BladeDamage dmg;
  dmg.twist_rad = deg_to_rad(1.0);
  dmg.bend_mm = 0.2;
  dmg.tip = true;
  dmg.tip_span = 0.8;
  const DamagedBlade blade(test::builtin_blade_design(), dmg);
  MeasurementOptions mo;
  mo.sections = 20;
  mo.points = 800;
  const SectionMeasurement m = measure_sections(blade, mo);
  const DamagedRebuild r = rebuild_damaged(m, test::builtin_blade_design());
  ASSERT_TRUE(r.tip_extended);
  DamagedRegionOptions ro;
  ro.samples_u = 60;
  ro.samples_v = 400;
  const DamagedRegion region = damaged_region(r, m, ro);
  ASSERT_TRUE(region.tip);
  EXPECT_EQ(region.nicked_sections, 0);
  EXPECT_LT(region.face_rms_mm, 3 * mo.noise_mm);
  EXPECT_LT(std::acos(std::min(1.0, region.break_normal.dot(test::builtin_blade_design().frame.axis))), 0.01);  // the break's plane
  // The truth: the design's sections above the break (a rigid in-plane
  // motion keeps their area), scan-line areas, midpoint rule over height.
  const double H = test::builtin_blade_design().span_height(dmg.tip_span);
  const int slices = 40;
  const double dh = (test::builtin_blade_design().h_hi - H) / slices;
  double truth = 0, thickest = 0;
  for (int i = 0; i < slices; ++i) {
    const std::vector<Vec2> s = blade.deformed_section(H + (i + 0.5) * dh, 1024);
    truth += dh * scanline_area(s, 0.01, [](double, double) { return true; });
    // Above a break normal to the axis the whole section is missing: the
    // thickness along the normal is the blade's own, across it.
    if (i % 8 == 0) thickest = std::max(thickest, through_length(s, [](const Vec2&) { return true; }));
  }
  std::printf("tip cut: region %.2f mm3, truth %.2f mm3 (%.3f %%), max thickness %.3f mm, u %.3f..%.3f\n",
              region.volume_mm3, truth, 100 * (region.volume_mm3 / truth - 1), region.max_thickness_mm, region.u_from,
              region.u_to);
  EXPECT_NEAR(region.volume_mm3, truth, 0.01 * truth);
  // Along the surface normal (issue 43: not the tip's height above the
  // break). The longest is at an edge, where the normal turns fastest and
  // the ray runs along the camber: which ray is longest depends on where the
  // samples fall (measured 15.4 mm on the map's 400 v samples, 20.1 mm on the
  // truth's 1024 per section), so bounds.
  EXPECT_LE(region.max_thickness_mm, thickest + 0.05);
  EXPECT_GT(region.max_thickness_mm, 0.7 * thickest);
  EXPECT_NEAR(region.height_from_mm, H, 0.2);
  EXPECT_NEAR(region.u_to, 1, 1e-12);
  ASSERT_EQ(region.layers.size(), 3u);
  EXPECT_FALSE(region.layers[0].points.empty());
}

TEST(DamagedRegion, LeadingEdgeNickVolumeAndExtent) {
  BladeDamage dmg;
  dmg.edge = true;
  dmg.edge_from = 0.3;
  dmg.edge_to = 0.7;
  dmg.edge_depth_mm = 1.2;
  const DamagedBlade blade(test::builtin_blade_design(), dmg);
  MeasurementOptions mo;
  mo.sections = 30;
  mo.points = 800;
  const SectionMeasurement m = measure_sections(blade, mo);
  const DamagedRebuild r = rebuild_damaged(m, test::builtin_blade_design());
  DamagedRegionOptions ro;
  ro.samples_u = 60;
  ro.samples_v = 600;
  const DamagedRegion region = damaged_region(r, m, ro);
  EXPECT_FALSE(region.tip);
  EXPECT_GE(region.nicked_sections, 10);
  const double h0 = test::builtin_blade_design().span_height(dmg.edge_from), h1 = test::builtin_blade_design().span_height(dmg.edge_to);
  const int slices = 60;
  double truth = 0, deepest = 0;
  for (int i = 0; i < slices; ++i) {
    const double h = h0 + (i + 0.5) * (h1 - h0) / slices;
    const std::vector<Vec2> s = blade.deformed_section(h, 1024);
    // The nick as the header defines it: within depth d(s) of the upstream
    // extreme, along the chord to the downstream one.
    const auto [le, te] = std::minmax_element(s.begin(), s.end(), [](const Vec2& a, const Vec2& b) { return a.x() < b.x(); });
    const Vec2 le_point = *le, chord = (*te - *le).normalized();
    const double depth = dmg.edge_depth_mm * std::sin(kPi * (i + 0.5) / slices);
    truth += (h1 - h0) / slices *
             scanline_area(s, 0.005, [&](double x, double y) { return (Vec2(x, y) - le_point).dot(chord) < depth; });
    if (i % 3 == 1)
      deepest = std::max(deepest, through_length(s, [&](const Vec2& q) { return (q - le_point).dot(chord) < depth; }));
  }
  std::printf("nick: region %.3f mm3, truth %.3f mm3 (%.2f %%), max thickness %.3f mm, heights %.2f..%.2f (truth %.2f..%.2f)\n",
              region.volume_mm3, truth, 100 * (region.volume_mm3 / truth - 1), region.max_thickness_mm,
              region.height_from_mm, region.height_to_mm, h0, h1);
  // Issue 43: +4.5 % here before. The floor was the line through the gap's
  // measured ends, which lie up to a probe step (0.08 mm at 800 points)
  // beyond the cut's edges — on average half a step, the floor that much too
  // deep — and the nick was taken to run to the next section (0.7 mm past
  // its end at each end); now the edges are half a step on from the ends,
  // the nick ends where its depth runs out and its floor follows a cubic
  // between the sections. Measured -0.69 %.
  EXPECT_NEAR(region.volume_mm3, truth, 0.03 * truth);
  // Along the normal (measured 1.50 mm on the map, 1.60 mm the truth's
  // longest ray, where the flank's normal runs diagonally through the nick).
  EXPECT_LE(region.max_thickness_mm, deepest + 0.05);
  EXPECT_GT(region.max_thickness_mm, 0.85 * deepest);
  EXPECT_GT(region.height_from_mm, h0 - 1.5);
  EXPECT_LT(region.height_to_mm, h1 + 1.5);
}

// Issue 43's cases of damage of other shapes, on the recipe's measurement
// (30 sections x 2000 points, 2 um noise, strays).
SectionMeasurement measured(const DamagedBlade& blade, int seed = 1) {
  MeasurementOptions mo;
  mo.sections = 30;
  mo.points = 2000;
  mo.face_points = 0;
  mo.seed = seed;
  return measure_sections(blade, mo);
}

BladeDamage nick(double from, double to) {
  BladeDamage dmg;
  dmg.twist_rad = deg_to_rad(1.5);
  dmg.bend_mm = 0.3;
  dmg.edge = true;
  dmg.edge_from = from;
  dmg.edge_to = to;
  dmg.edge_depth_mm = 1.0;
  return dmg;
}

double removed_volume(const DamagedBlade& blade, double h0, double h1, int slices);

TEST(DamagedRegion, NicksReachingTheEndSectionsAreRegionsOfTheirVolume) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "two recipe-size measurements with their truth by scan lines (Release suite)";
#endif
  // The plane at an end section's mean height leaves the loft by the noise
  // here and there: the region clamps at the loft's end rows (it threw).
  // The truth: what the nick took between the lowest and the highest
  // measured section (the rebuilt blade's heights; beyond them there is no
  // rebuilt blade to measure a region on).
  for (const auto& [from, to] : {std::pair{0.0, 0.12}, std::pair{0.5, 1.0}}) {
    const DamagedBlade blade(test::builtin_blade_design(), nick(from, to));
    const SectionMeasurement m = measured(blade);
    const DamagedRebuild r = rebuild_damaged(m, test::builtin_blade_design());
    ASSERT_TRUE(r.quality.trusted) << r.quality.message;
    const DamagedRegion region = damaged_region(r, m);
    EXPECT_FALSE(region.empty);
    if (from == 0) EXPECT_NEAR(region.u_from, 0, 1e-12);
    if (to == 1) EXPECT_NEAR(region.u_to, 1, 1e-12);
    const double truth = removed_volume(blade, r.sections.front().height_mm, r.sections.back().height_mm, 150);
    std::printf("nick over spans %.2f-%.2f: region %.3f mm3, truth %.3f mm3 (%+.2f %%)\n", from, to, region.volume_mm3,
                truth, 100 * (region.volume_mm3 / truth - 1));
    EXPECT_NEAR(region.volume_mm3, truth, 0.03 * truth);
  }
}

// A sparser probe (800 points a section, 0.08 mm apart) on the recipe's
// twisted and bent blade: points the ordering doubted beyond a gap's end
// move the end on, counted from the gap's own end. Summed from each point
// taken, they walked an end 15 steps into a 17-step gap; the two edges met,
// the floor line turned through the blade and the region was 108.7 mm3 for
// a 5 mm3 nick (issue 43).
TEST(DamagedRegion, ASparseProbesNickOnATwistedBladeIsItsVolume) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "a recipe-size measurement with its truth by scan lines (Release suite)";
#endif
  // Seed 1: an end walked into its gap; 2: doubted points over an intact
  // trailing edge left 0.21 mm unseen, 5 um off the design; 5: they met
  // across it (seeds 3 and 4 measured +0.18 % / +0.48 %).
  for (const int seed : {1, 2, 5}) {
    const DamagedBlade blade(test::builtin_blade_design(), nick(0.35, 0.75));
    MeasurementOptions mo;
    mo.sections = 30;
    mo.points = 800;
    mo.face_points = 0;
    mo.seed = seed;
    const SectionMeasurement m = measure_sections(blade, mo);
    const DamagedRebuild r = rebuild_damaged(m, test::builtin_blade_design());
    ASSERT_TRUE(r.quality.trusted) << r.quality.message;
    DamagedRegionOptions ro;
    ro.samples_u = 60;
    ro.samples_v = 600;
    const DamagedRegion region = damaged_region(r, m, ro);
    const double truth = removed_volume(blade, test::builtin_blade_design().span_height(0.3), test::builtin_blade_design().span_height(0.8), 100);
    std::printf("seed %d: region %.3f mm3, truth %.3f mm3 (%+.2f %%), v %.3f..%.3f\n", seed, region.volume_mm3, truth,
                100 * (region.volume_mm3 / truth - 1), region.v_from, region.v_to);
    EXPECT_NEAR(region.volume_mm3, truth, 0.03 * truth) << "seed " << seed;
    EXPECT_LT(region.v_to - region.v_from, 0.1) << "seed " << seed;
  }
}

TEST(DamagedRegion, AStretchTheProbeSkippedOnAnIntactFlankIsNoRegion) {
  // An undamaged blade whose every section misses 1.26 mm of its concave
  // flank (issue 43: an 82.9 mm3 region came of it): the design arc bridges
  // it within its sagitta g^2 / 8R, far below the probe spacing.
  BladeDamage dmg;
  dmg.twist_rad = deg_to_rad(1.5);
  dmg.bend_mm = 0.3;
  const DamagedBlade blade(test::builtin_blade_design(), dmg);
  SectionMeasurement m = measured(blade);
  int sections = 0;
  for (MeasuredSection& s : m.sections) {
    // The most concave point of the true section (turning against the
    // loop's sense), on its flank.
    const std::vector<Vec2> poly = blade.deformed_section(s.height_mm, 1024);
    const size_t n = poly.size();
    double twice = 0;
    for (size_t j = 0; j < n; ++j) twice += poly[j].x() * poly[(j + 1) % n].y() - poly[j].y() * poly[(j + 1) % n].x();
    size_t concave = 0;
    double most = 0;
    for (size_t j = 0; j < n; ++j) {
      const Vec2 a = poly[j] - poly[(j + n - 8) % n], b = poly[(j + 8) % n] - poly[j];
      const double turn = (a.x() * b.y() - a.y() * b.x()) / (a.norm() * b.norm()) * (twice > 0 ? 1 : -1);
      if (turn < most) {
        most = turn;
        concave = j;
      }
    }
    ASSERT_LT(most, 0) << "no concave flank at " << s.height_mm;
    const Vec2 c = poly[concave];
    std::vector<Vec3> kept;
    for (const Vec3& p : s.points)
      if ((m.frame.in_plane(p) - c).norm() > 0.63) kept.push_back(p);
    ASSERT_LT(kept.size(), s.points.size());
    s.points = kept;
    ++sections;
  }
  const DamagedRebuild r = rebuild_damaged(m, test::builtin_blade_design());
  ASSERT_TRUE(r.quality.trusted) << r.quality.message;
  const DamagedRegion region = damaged_region(r, m);
  EXPECT_TRUE(region.empty) << region.volume_mm3 << " mm3";
  EXPECT_EQ(region.nicks, 0);
  EXPECT_GE(region.skipped_gaps, sections);
}

TEST(DamagedRegion, TwoNicksAtTheSameHeightsStayTwo) {
#ifdef BLISKRUN_SANITIZED
  // A recipe-size measurement (30 x 2000 points), ~45 s under the
  // sanitizers; the region code runs there in the other tests of this suite.
  GTEST_SKIP() << "recipe-size region case runs in the Release suite";
#endif
  // A nick at the leading edge and a stretch missing over the trailing
  // edge's apex (it cannot be told from a nick) at the same heights: every
  // gap of every section kept and paired by overlap, not the largest only.
  const DamagedBlade blade(test::builtin_blade_design(), nick(0.4, 0.65));
  MeasurementOptions mo;
  mo.sections = 30;
  mo.points = 2000;
  mo.face_points = 0;
  mo.unseen_arc_mm = 1.26;
  const SectionMeasurement m = measure_sections(blade, mo);
  const DamagedRebuild r = rebuild_damaged(m, test::builtin_blade_design());
  ASSERT_TRUE(r.quality.trusted) << r.quality.message;
  const DamagedRegion region = damaged_region(r, m);
  const SectionMeasurement m_nick = measured(blade);
  const DamagedRegion nick_only = damaged_region(rebuild_damaged(m_nick, test::builtin_blade_design()), m_nick);
  int both = 0;
  for (const SectionGapFill& f : r.fills) both += f.length_mm > 0.3;
  EXPECT_GT(region.nicks, region.nicked_sections);  // two in a section
  EXPECT_GE(region.nicks, both - 2);
  // The other stretch's cap adds to the nick's volume: with the largest gap
  // of each section only, it did not.
  std::printf("nick %.2f mm3, with the trailing edge's stretch %.2f mm3\n", nick_only.volume_mm3, region.volume_mm3);
  EXPECT_GT(region.volume_mm3, 1.3 * nick_only.volume_mm3);
}

TEST(DamagedRegion, LeadingAndTrailingEdgeNicksAtTheSameHeightsAreTwoOfTheirVolume) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "recipe-size region case runs in the Release suite";
#endif
  // Issue 43: LE and TE nicks at the same heights merged into one ~15 mm
  // thick region (only each section's largest gap was kept). Two nicks, each
  // section's two gaps paired with their own partners: two regions' worth
  // of volume, thick as each nick is.
  BladeDamage dmg = nick(0.4, 0.65);
  dmg.te_edge = true;
  dmg.te_from = 0.35;
  dmg.te_to = 0.6;
  dmg.te_depth_mm = 0.8;
  const DamagedBlade blade(test::builtin_blade_design(), dmg);
  const SectionMeasurement m = measured(blade);
  const DamagedRebuild r = rebuild_damaged(m, test::builtin_blade_design());
  ASSERT_TRUE(r.quality.trusted) << r.quality.message;
  const DamagedRegion region = damaged_region(r, m);
  const double truth = removed_volume(blade, test::builtin_blade_design().span_height(0.3), test::builtin_blade_design().span_height(0.75), 100);
  BladeDamage le_only = dmg;
  le_only.te_edge = false;
  const double le_truth = removed_volume(DamagedBlade(test::builtin_blade_design(), le_only), test::builtin_blade_design().span_height(0.3), test::builtin_blade_design().span_height(0.75), 100);
  std::printf("two nicks: region %.3f mm3 (%d in %d sections), truth %.3f mm3 (%+.2f %%; the leading edge's %.3f), "
              "max thickness %.3f mm\n",
              region.volume_mm3, region.nicks, region.nicked_sections, truth, 100 * (region.volume_mm3 / truth - 1),
              le_truth, region.max_thickness_mm);
  EXPECT_GT(region.nicks, region.nicked_sections);  // two in a section
  EXPECT_NEAR(region.volume_mm3, truth, 0.03 * truth);
  EXPECT_GT(truth, 1.3 * le_truth);  // the trailing edge's nick is a real share of it
  // Each nick's own thickness along the normal (1 mm along the chord at the
  // leading edge, ~1.5 mm along a flank's normal): not the chord between them.
  EXPECT_LT(region.max_thickness_mm, 2.0);
}

TEST(DamagedRegion, ATrailingEdgeCornerBrokenOffAtTheTipIsItsVolume) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "recipe-size region case runs in the Release suite";
#endif
  // Issue 43's corner: the break plane through the tip's axis point tilted
  // 44 degrees downstream takes a triangle of the trailing edge from ~65 %
  // span up (+43 % before: tip and edge volume both counted). The measured
  // sections it crosses come back with a gap at the trailing edge; the face
  // is probed. The highest measured section (97 % span) is cut, so nothing
  // is extended: the rebuilt blade ends there, and the truth is taken to it.
  BladeDamage dmg;
  dmg.twist_rad = deg_to_rad(1.5);
  dmg.bend_mm = 0.3;
  dmg.tip = true;
  dmg.tip_span = 1.0;
  dmg.tip_tilt_rad = deg_to_rad(44);
  const DamagedBlade blade(test::builtin_blade_design(), dmg);
  const auto [m, r] = test::measure_and_rebuild(blade, 30, 2000);
  ASSERT_TRUE(r.quality.trusted) << r.quality.message;
  EXPECT_FALSE(r.tip_extended);
  const DamagedRegion region = damaged_region(r, m);
  const double truth = removed_volume(blade, test::builtin_blade_design().span_height(0.5), r.sections.back().height_mm, 200);
  std::printf("trailing-edge corner: region %.2f mm3 (tip plane alone %.2f), truth %.2f mm3 (%+.2f %%)\n",
              region.volume_mm3, region.tip_volume_mm3, truth, 100 * (region.volume_mm3 / truth - 1));
  EXPECT_TRUE(region.tip);
  EXPECT_NEAR(region.volume_mm3, truth, 0.03 * truth);
}

// The volume the simulated damage removed (damaged_blade.h: beyond the
// break plane, within a nick's depth of its edge along the chord, inside the
// dent's sphere), by scan lines over slices of the true (deformed) blade.
double removed_volume(const DamagedBlade& blade, double h0, double h1, int slices) {
  double v = 0;
  const double dh = (h1 - h0) / slices;
  for (int i = 0; i < slices; ++i) {
    const double h = h0 + (i + 0.5) * dh;
    const std::vector<Vec2> s = blade.deformed_section(h, 1024);
    const MissingInPlane missing = blade.missing(h, s);
    v += dh * scanline_area(s, 0.01, [&](double x, double y) { return missing.removed(Vec2(x, y)); });
  }
  return v;
}

TEST(DamagedRegion, ATiltedBreakAndANickWhereTheyMeetAreCountedOnce) {
#ifdef BLISKRUN_SANITIZED
  // A recipe-size measurement (30 x 2000 points), ~45 s under the
  // sanitizers; the region code runs there in the other tests of this suite.
  GTEST_SKIP() << "recipe-size region case runs in the Release suite";
#endif
  // The break plane tilted 30 degrees crosses measured sections (they come
  // back with a gap) and the nick runs up into it: one region, each bit of
  // missing material counted once (issue 43: +21 % and +43 % before).
  for (const bool edge : {false, true}) {
    BladeDamage dmg = nick(0.6, 1.0);
    dmg.edge = edge;
    dmg.tip = true;
    dmg.tip_span = 0.8;
    dmg.tip_tilt_rad = deg_to_rad(30);
    const DamagedBlade blade(test::builtin_blade_design(), dmg);
    const auto [m, r] = test::measure_and_rebuild(blade, 30, 2000);
    ASSERT_TRUE(r.quality.trusted) << r.quality.message;
    const DamagedRegion region = damaged_region(r, m);
    const double truth = removed_volume(blade, test::builtin_blade_design().span_height(0.5), test::builtin_blade_design().h_hi, 100);
    std::printf("tilted break%s: region %.2f mm3 (tip alone %.2f), truth %.2f mm3 (%.2f %%)\n", edge ? " and nick" : "",
                region.volume_mm3, region.tip_volume_mm3, truth, 100 * (region.volume_mm3 / truth - 1));
    EXPECT_NEAR(region.volume_mm3, truth, 0.03 * truth);
  }
}

TEST(DamagedRegion, ClippedAreaOfASquare) {
  const std::vector<Vec2> square{{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  EXPECT_NEAR(clipped_area(square, Vec2(1, 0), -0.5), 3.0, 1e-15);            // x > 0.5
  EXPECT_NEAR(clipped_area(square, Vec2(1, 1) / std::sqrt(2), -std::sqrt(2)), 2.0, 1e-15);  // above the diagonal x + y = 2
}

TEST(DamagedRegion, AreaInsideTheUnionOfCutsCountsOverlapsOnce) {
  const std::vector<Vec2> square{{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  // x > 1.5 and y > 1.5 overlap in a 0.5 x 0.5 corner: 1 + 1 - 0.25.
  const std::vector<Vec2> right{{1.5, -10}, {10, -10}, {10, 10}, {1.5, 10}};
  const std::vector<Vec2> top{{-10, 10}, {-10, 1.5}, {10, 1.5}, {10, 10}};  // clockwise: either orientation
  EXPECT_NEAR(area_inside(square, {right, top}), 1.75, 1e-14);
  // A cut inside another adds nothing (cuts in general position: no shared edges).
  const std::vector<Vec2> inner{{1.7, 0.5}, {1.9, 0.5}, {1.9, 1.0}, {1.7, 1.0}};
  EXPECT_NEAR(area_inside(square, {right, inner}), 1.0, 1e-14);
  EXPECT_NEAR(area_inside(square, {}), 0.0, 1e-14);
  // A non-convex cut: a notch with a floor of three segments (a dent's
  // floor) from (0.5, 2) down to (1, 1.5) and up to (1.5, 2), strip upwards.
  const std::vector<Vec2> notch{{0.5, 2}, {1, 1.5}, {1.5, 2}, {1.5, 12}, {0.5, 12}};
  EXPECT_NEAR(area_inside(square, {notch}), 0.5 * 1 * 0.5, 1e-14);
  // Against clipping: the part of a regular 64-gon beyond a line.
  std::vector<Vec2> circle;
  for (int j = 0; j < 64; ++j) circle.emplace_back(std::cos(2 * kPi * j / 64), std::sin(2 * kPi * j / 64));
  const Vec2 n = Vec2(0.6, 0.8);
  const std::vector<Vec2> beyond{{0.3 * n + 50 * Vec2(-0.8, 0.6)}, {0.3 * n + 50 * Vec2(0.8, -0.6)},
                                 {0.3 * n + 50 * Vec2(0.8, -0.6) + 50 * n}, {0.3 * n + 50 * Vec2(-0.8, 0.6) + 50 * n}};
  EXPECT_NEAR(area_inside(circle, {beyond}), clipped_area(circle, n, -0.3), 1e-12);
}

}  // namespace
}  // namespace bliskrun
