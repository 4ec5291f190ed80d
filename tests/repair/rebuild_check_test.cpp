// The rebuild's check of itself between its sections (issue 43): on many
// seeds of a measured, twisted and bent, nicked blade, every rebuild either
// matches the truth between its sections or says it does not; a rebuild made
// wrong on purpose says so. The truth is the damage simulation's deformed
// design (damaged_blade.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/parts/builtin_blisk.h"
#include "core/repair/damaged_blade.h"
#include "core/repair/damaged_rebuild.h"
#include "repair/builtin_design.h"

namespace bliskrun {
namespace {


// Largest distance of the points from the closed polygon (nearest vertex by
// brute force, then the segments beside it).
double worst_distance(const std::vector<Vec2>& points, const std::vector<Vec2>& poly) {
  const int m = static_cast<int>(poly.size());
  double worst = 0;
  for (const Vec2& q : points) {
    int j = 0;
    for (int i = 1; i < m; ++i)
      if ((poly[i] - q).squaredNorm() < (poly[j] - q).squaredNorm()) j = i;
    double best = 1e300;
    for (int s = -1; s <= 0; ++s) {
      const Vec2& a = poly[((j + s) % m + m) % m];
      const Vec2& b = poly[(j + s + 1) % m];
      const double t = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      best = std::min(best, (a + t * (b - a) - q).norm());
    }
    worst = std::max(worst, best);
  }
  return worst;
}

// The recipe's edge case (blade_repair.lua, damage=edge).
DamagedBlade edge_blade() {
  BladeDamage dmg;
  dmg.twist_rad = deg_to_rad(1.5);
  dmg.bend_mm = 0.3;
  dmg.edge = true;
  dmg.edge_from = 0.4;
  dmg.edge_to = 0.65;
  dmg.edge_depth_mm = 1.0;
  return DamagedBlade(test::builtin_blade_design(), dmg);
}

// Largest distance of the rebuilt blade from the truth midway between its sections.
double truth_between(const DamagedRebuild& r, const DamagedBlade& blade) {
  double worst = 0;
  for (size_t k = 0; k + 1 < r.sections.size(); ++k) {
    const double h = 0.5 * (r.sections[k].height_mm + r.sections[k + 1].height_mm);
    worst = std::max(worst, worst_distance(plane_section(r.loft, r.frame, h, 400), blade.deformed_section(h, 2048)));
  }
  return worst;
}

// The recipe's measurement (30 sections, 2000 points, 2 um noise, strays) on
// 30 seeds. Before issue 43 seeds 6 and 23 were rebuilt 0.3 mm wrong between
// sections with a mean deviation of 1.6 um at them: a stray's hole beside the
// nick had been filled with the whole design loop.
TEST(RebuildCheck, ThirtySeedsNoneSilentlyWrong) {
  const DamagedBlade blade = edge_blade();
  DamagedRebuildOptions o;
  o.rebuild.threads = 2;  // the result does not depend on it
  int trusted = 0;
  std::string log;
  std::vector<int> seeds;
#ifdef BLISKRUN_SANITIZED
  // Under the sanitizers the two seeds that were silently wrong (30 take
  // ~10 minutes there; all 30 run in the Release suite).
  seeds = {6, 23};
#else
  for (int seed = 1; seed <= 30; ++seed) seeds.push_back(seed);
#endif
  for (const int seed : seeds) {
    MeasurementOptions mo;
    mo.sections = 30;
    mo.points = 2000;
    mo.face_points = 0;
    mo.seed = seed;
    const DamagedRebuild r = rebuild_damaged(measure_sections(blade, mo), test::builtin_blade_design(), o);
    const double truth = truth_between(r, blade);
    log += "seed " + std::to_string(seed) + ": check " + std::to_string(1e3 * r.quality.between_max_mm) + " um, truth " +
           std::to_string(1e3 * truth) + " um, " + r.quality.start_method + (r.quality.trusted ? "" : " NOT TRUSTED") + "\n";
    if (!r.quality.trusted) {
      EXPECT_FALSE(r.quality.message.empty());
      continue;
    }
    ++trusted;
    // Issue 43's bar: a trusted rebuild is within 10 um of the truth between its sections.
    EXPECT_LT(truth, 0.010) << "seed " << seed << " silently wrong";
  }
  // The check is not a refusal of everything: measured 30 of 30 trusted,
  // 6.8-8.2 um by the check, 7.4-8.7 um from the truth.
  EXPECT_EQ(trusted, static_cast<int>(seeds.size())) << log;
}

TEST(RebuildCheck, AWrongCurvatureStartIsRepairedByTheDesignsStart) {
  const DamagedBlade blade = edge_blade();
  MeasurementOptions mo;
  mo.sections = 12;
  mo.points = 1200;
  mo.face_points = 0;
  DamagedRebuildOptions o;
  o.forced_start_section = 5;
  o.forced_start_shift_mm = 3;
  o.forced_start_attempts = 1;  // only the curvature alignment is wrong
  const DamagedRebuild r = rebuild_damaged(measure_sections(blade, mo), test::builtin_blade_design(), o);
  ASSERT_EQ(r.quality.attempt_max_mm.size(), 2u);
  EXPECT_GT(r.quality.attempt_max_mm[0], 0.010);
  EXPECT_TRUE(r.quality.trusted) << r.quality.message;
  EXPECT_EQ(r.quality.start_method, "design");
  EXPECT_LT(truth_between(r, blade), 0.010);
}

TEST(RebuildCheck, ARebuildMadeWrongOnPurposeFails) {
  const DamagedBlade blade = edge_blade();
  MeasurementOptions mo;
  mo.sections = 12;
  mo.points = 1200;
  mo.face_points = 0;
  DamagedRebuildOptions o;
  o.forced_start_section = 5;
  o.forced_start_shift_mm = 3;  // the start moved 3 mm along the profile, in every attempt
  const DamagedRebuild r = rebuild_damaged(measure_sections(blade, mo), test::builtin_blade_design(), o);
  EXPECT_FALSE(r.quality.trusted);
  EXPECT_EQ(r.quality.attempts, 2);
  EXPECT_NE(r.quality.message.find("not trustworthy between its sections"), std::string::npos) << r.quality.message;
  EXPECT_GT(r.quality.between_max_mm, 0.010);
  // And the check saw what the truth sees: the loft is wrong between the sections.
  EXPECT_GT(truth_between(r, blade), 0.010);
  // The same measurement without the sabotage is trusted.
  const DamagedRebuild good = rebuild_damaged(measure_sections(blade, mo), test::builtin_blade_design());
  EXPECT_TRUE(good.quality.trusted) << good.quality.message;
  EXPECT_LT(truth_between(good, blade), 0.010);
}

}  // namespace
}  // namespace bliskrun
