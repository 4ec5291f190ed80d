#include "core/repair/section_points.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <random>

#include "core/common/error.h"
#include "repair/section_shapes.h"

namespace bliskrun {
namespace {

using test::add_noise;
using test::blade_profile;
using test::ellipse;

// A measured section with a known answer: the genuine points (their index is
// their true place around the loop) shuffled together with stray points.
struct Scrambled {
  std::vector<Vec3> points;
  std::vector<int> truth;  // per input point: true place, or -1 for a stray one
  std::vector<int> strays; // input indices of the stray points, ascending
};

// Strays `offset_mm` (and up to 3x that) off the profile, along the normal
// of the profile at evenly spread places, half outside and half inside —
// or all outside (`inside` false) for a thin profile, where one inside could
// land on the other flank and be a measured point in all but name.
Scrambled scramble(const std::vector<Vec3>& genuine, int strays, double offset_mm, unsigned seed,
                   bool inside = true) {
  std::vector<std::pair<Vec3, int>> all;
  const int n = static_cast<int>(genuine.size());
  for (int i = 0; i < n; ++i) all.emplace_back(genuine[i], i);
  for (int k = 0; k < strays; ++k) {
    const int i = (k * n) / strays + n / (2 * strays);
    const Vec3 along = genuine[(i + 1) % n] - genuine[(i + n - 1) % n];
    const Vec3 out = Vec3(along.y(), -along.x(), 0).normalized();  // outwards for a counter-clockwise loop
    all.emplace_back(genuine[i] + (k % 2 && inside ? -1 : 1) * offset_mm * (1 + 2.0 * k / strays) * out, -1);
  }
  std::shuffle(all.begin(), all.end(), std::mt19937(seed));
  Scrambled s;
  for (size_t j = 0; j < all.size(); ++j) {
    s.points.push_back(all[j].first);
    s.truth.push_back(all[j].second);
    if (all[j].second < 0) s.strays.push_back(static_cast<int>(j));
  }
  return s;
}

// Fraction of consecutive pairs of the found loop that are consecutive in the
// true order, all in one direction (either), over the genuine points kept.
double order_accuracy(const Scrambled& s, const std::vector<int>& order) {
  std::vector<int> places;
  for (int i : order)
    if (s.truth[i] >= 0) places.push_back(s.truth[i]);
  std::vector<int> sorted = places;
  std::sort(sorted.begin(), sorted.end());
  const int m = static_cast<int>(places.size());
  std::vector<int> rank(*std::max_element(sorted.begin(), sorted.end()) + 1, -1);
  for (int k = 0; k < m; ++k) rank[sorted[k]] = k;
  int forward = 0, backward = 0;
  for (int k = 0; k < m; ++k) {
    const int step = (rank[places[(k + 1) % m]] - rank[places[k]] + m) % m;
    forward += step == 1;
    backward += step == m - 1;
  }
  return static_cast<double>(std::max(forward, backward)) / m;
}

TEST(SectionOrder, RecoversAShuffledNoisyEllipseAndRejectsItsStrays) {
  // 60 x 20 mm, 800 points 0.16 mm apart, 8 um of noise, 12 strays 0.3 to
  // 0.9 mm off the profile.
  std::vector<Vec3> genuine = ellipse(30, 10, 800);
  add_noise(genuine, 0.008, 1);
  const Scrambled s = scramble(genuine, 12, 0.3, 2);
  const OrderedSection o = order_section(s.points);
  EXPECT_EQ(o.rejected, s.strays);
  EXPECT_EQ(o.order.size(), genuine.size());
  EXPECT_DOUBLE_EQ(order_accuracy(s, o.order), 1.0);
  EXPECT_EQ(o.chains, 1);
  EXPECT_TRUE(o.gaps.empty());
  EXPECT_NEAR(o.spacing_mm, 0.16, 0.02);
}

TEST(SectionOrder, OrderingAccuracyUnderNoiseOfAFractionOfTheSpacing) {
  // Noise of 0.1 and 0.25 of the spacing: points then swap places along the
  // profile now and then, so the measure is the share of true neighbours.
  for (const double sigma : {0.016, 0.04}) {
    std::vector<Vec3> genuine = ellipse(30, 10, 800);
    add_noise(genuine, sigma, 3);
    const Scrambled s = scramble(genuine, 12, 0.5, 4);
    const OrderedSection o = order_section(s.points);
    const double accuracy = order_accuracy(s, o.order);
    std::printf("[ measured ] ellipse, noise %.3f mm = %.2f spacing: %.4f of neighbours true, %zu rejected "
                "(%zu strays), outlier distance %.3f mm\n",
                sigma, sigma / o.spacing_mm, accuracy, o.rejected.size(), s.strays.size(), o.outlier_mm);
    EXPECT_GT(accuracy, sigma < 0.02 ? 0.99 : 0.9);
    for (int stray : s.strays) EXPECT_TRUE(std::binary_search(o.rejected.begin(), o.rejected.end(), stray));
    EXPECT_LT(o.rejected.size(), s.strays.size() + 8u);  // few genuine points lost
  }
}

// The thin blade probed every 0.1 mm on the suction side and round the
// edges, every 0.4 mm on the pressure side: near the trailing edge, 0.3 mm
// thick, the nearest unused point from the pressure side is on the suction
// side, where plain greedy ordering goes.
std::vector<Vec3> scanned_blade() {
  std::vector<Vec3> genuine = test::blade_scanned(0.1, 0.4);
  add_noise(genuine, 0.004, 5);
  return genuine;
}

TEST(SectionOrder, RecoversAThinBladeProfileWithoutJumpingAcrossItsEdges) {
  const Scrambled s = scramble(scanned_blade(), 10, 0.4, 6, false);
  const OrderedSection o = order_section(s.points);
  EXPECT_EQ(o.rejected, s.strays);
  EXPECT_DOUBLE_EQ(order_accuracy(s, o.order), 1.0);
  EXPECT_TRUE(o.gaps.empty());
  std::printf("[ measured ] scanned blade: %d chains joined, spacing %.3f mm, longest step %.3f mm, outlier distance "
              "%.3f mm\n",
              o.chains, o.spacing_mm, o.max_step_mm, o.outlier_mm);
}

TEST(SectionOrder, PlainNearestNeighbourOrderingFailsOnTheSameBlade) {
  // Greedy nearest-neighbour ordering (the paper without its angle test) on
  // the same points crosses the thickness: the blade test above is not easy.
  const Scrambled s = scramble(scanned_blade(), 0, 0, 6);
  std::vector<int> order{0};
  std::vector<char> used(s.points.size(), 0);
  used[0] = 1;
  for (size_t k = 1; k < s.points.size(); ++k) {
    int best = -1;
    for (size_t j = 0; j < s.points.size(); ++j)
      if (!used[j] && (best < 0 || (s.points[j] - s.points[order.back()]).norm() <
                                       (s.points[best] - s.points[order.back()]).norm()))
        best = static_cast<int>(j);
    used[best] = 1;
    order.push_back(best);
  }
  const double accuracy = order_accuracy(s, order);
  std::printf("[ measured ] scanned blade by plain nearest neighbour: %.4f of neighbours true\n", accuracy);
  EXPECT_LT(accuracy, 0.99);
}

TEST(SectionOrder, AGapAtTheLeadingEdgeIsReportedAndBridgedOnce) {
  // A damaged edge: the probed blade with nothing within 1.8 mm of its LE.
  std::vector<Vec3> genuine;
  for (const Vec3& p : test::blade_scanned(0.1, 0.4))
    if (p.x() > 1.8) genuine.push_back(p);
  add_noise(genuine, 0.004, 7);
  const Scrambled s = scramble(genuine, 6, 0.4, 8, false);
  const OrderedSection o = order_section(s.points);
  EXPECT_EQ(o.rejected, s.strays);
  EXPECT_DOUBLE_EQ(order_accuracy(s, o.order), 1.0);
  ASSERT_EQ(o.gaps.size(), 1u);
  // The gap's ends are the last points either side of the missing arc, on
  // the two flanks across the ~0.33 mm thickness there: nearer each other
  // than the longest step (the coarse flank's), the turn makes it a gap.
  const Vec3 a = s.points[o.order[o.gaps[0].after]], b = s.points[o.order[(o.gaps[0].after + 1) % o.order.size()]];
  EXPECT_NEAR(o.gaps[0].length_mm, (a - b).norm(), 1e-12);
  EXPECT_LT(std::max(a.x(), b.x()), 2.5);
  EXPECT_NEAR(o.gaps[0].length_mm, 0.33, 0.03);
  EXPECT_LT(o.gaps[0].length_mm, o.max_step_mm);
  std::printf("[ measured ] blade with its LE missing: %d chains joined, gap %.2f mm, longest step %.2f mm\n", o.chains,
              o.gaps[0].length_mm, o.max_step_mm);
}

TEST(SectionThinning, ADenseSectionComesOutEvenlySpacedMeasuredPointsWithoutItsLoneStraysAndWithItsGap) {
  // Issue 43 (ten million points): the thin blade probed every 0.5 um —
  // 250 000 points, 2 um noise, 400 strays 0.4-1.2 mm off — with its leading
  // edge missing (nothing within 1.8 mm), thinned to 25 um.
  std::vector<Vec3> genuine;
  for (const Vec3& p : test::blade_scanned(0.0005, 0.0005))
    if (p.x() > 1.8) genuine.push_back(p);
  // Strays off the noise-free profile's normals, then the noise.
  Scrambled s = scramble(genuine, 400, 0.4, 12, false);
  std::vector<Vec3> noise(s.points.size(), Vec3::Zero());
  add_noise(noise, 0.002, 11);
  for (size_t i = 0; i < s.points.size(); ++i)
    if (s.truth[i] >= 0) s.points[i] += noise[i];
  const double spacing = 0.025;
  const std::vector<int> kept = thin_section(s.points, spacing);
  // Measured points, each once: indices ascending and in range.
  ASSERT_FALSE(kept.empty());
  EXPECT_TRUE(std::is_sorted(kept.begin(), kept.end()));
  EXPECT_TRUE(std::adjacent_find(kept.begin(), kept.end()) == kept.end());
  EXPECT_GE(kept.front(), 0);
  EXPECT_LT(kept.back(), static_cast<int>(s.points.size()));
  // None of the lone strays (a stray of this density lies alone in its cells).
  int strays = 0;
  for (const int i : kept) strays += s.truth[i] < 0;
  EXPECT_EQ(strays, 0);
  // No two closer than the spacing, none more than about two apart along
  // the profile: ordered without a gap but the leading edge's.
  double closest = 1e300;
  for (size_t a = 0; a < kept.size(); ++a)
    for (size_t b = a + 1; b < kept.size(); ++b) closest = std::min(closest, (s.points[kept[a]] - s.points[kept[b]]).norm());
  EXPECT_GE(closest, spacing);
  double length = 0;
  for (size_t i = 0; i + 1 < genuine.size(); ++i) length += (genuine[i + 1] - genuine[i]).norm();
  EXPECT_GT(static_cast<double>(kept.size()), 0.45 * length / spacing);
  EXPECT_LT(static_cast<double>(kept.size()), 1.0 * length / spacing);
  std::vector<Vec3> thinned;
  for (const int i : kept) thinned.push_back(s.points[i]);
  const OrderedSection o = order_section(thinned);
  ASSERT_EQ(o.gaps.size(), 1u);
  EXPECT_NEAR(o.gaps[0].length_mm, 0.33, 0.03);
  EXPECT_TRUE(o.rejected.empty());
  std::printf("[ measured ] %zu points thinned to %zu (%.1f um apart on average, closest %.1f um)\n", s.points.size(),
              kept.size(), 1e3 * length / kept.size(), 1e3 * closest);
  // A section no denser than the spacing is left as it is.
  std::vector<Vec3> coarse;
  for (size_t i = 0; i < genuine.size(); i += 100) coarse.push_back(genuine[i]);
  EXPECT_EQ(thin_section(coarse, spacing).size(), coarse.size());
  EXPECT_THROW(thin_section(coarse, 0), ParameterError);
}

TEST(SectionOrder, ShuffledInputGivesTheSameLoop) {
  std::vector<Vec3> genuine = blade_profile(600);
  add_noise(genuine, 0.004, 9);
  const Scrambled a = scramble(genuine, 0, 0, 10), b = scramble(genuine, 0, 0, 11);
  const std::vector<Vec3> la = pick(a.points, order_section(a.points).order);
  const std::vector<Vec3> lb = pick(b.points, order_section(b.points).order);
  ASSERT_EQ(la.size(), lb.size());
  for (size_t i = 0; i < la.size(); ++i) EXPECT_EQ(la[i], lb[i]);
}

TEST(SectionOrder, RejectsUnusableInputWithTheReason) {
  const std::vector<Vec3> few = ellipse(3, 1, 7);
  EXPECT_THROW(order_section(few), ParameterError);
  std::vector<Vec3> bad = ellipse(3, 1, 50);
  bad[17].y() = std::nan("");
  try {
    order_section(bad);
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("point 17 is not finite"), std::string::npos);
  }
  EXPECT_THROW(order_section(std::vector<Vec3>(20, Vec3(1, 2, 3))), ParameterError);
  SectionOrderOptions o;
  o.max_turn_rad = 0;
  EXPECT_THROW(order_section(ellipse(3, 1, 50), o), ParameterError);
  o = {};
  o.max_turn_rad = kPi;
  EXPECT_THROW(order_section(ellipse(3, 1, 50), o), ParameterError);
  o = {};
  o.max_step_mm = -1;
  EXPECT_THROW(order_section(ellipse(3, 1, 50), o), ParameterError);
  o = {};
  o.outlier_factor = 0;
  EXPECT_THROW(order_section(ellipse(3, 1, 50), o), ParameterError);
  EXPECT_THROW(pick(few, {0, 7}), ParameterError);
}

TEST(SectionOrientation, ReversesAClockwiseSectionKeepingItsFirstPoint) {
  std::vector<std::vector<Vec3>> loops{blade_profile(200, 0), blade_profile(200, 5), blade_profile(200, 10)};
  const std::vector<Vec3> counter_clockwise = loops[1];
  std::reverse(loops[1].begin(), loops[1].end());  // clockwise, starting at the old last point
  const std::vector<OrientedSection> o = orient_sections(loops, Vec3::UnitZ());
  ASSERT_EQ(o.size(), 3u);
  EXPECT_FALSE(o[0].reversed);
  EXPECT_TRUE(o[1].reversed);
  EXPECT_FALSE(o[2].reversed);
  for (const OrientedSection& s : o) EXPECT_GT(vector_area(s.loop).z(), 0);
  // Same shape one above the other: each starts above the previous start,
  // and the reversed one runs as it did before it was reversed.
  EXPECT_EQ(o[1].loop, counter_clockwise);
  EXPECT_EQ(o[1].start, 199);
  EXPECT_EQ(o[2].start, 0);
  // Seen from below, all are clockwise: reversed relative to the input.
  const std::vector<OrientedSection> down = orient_sections(loops, -Vec3::UnitZ());
  EXPECT_TRUE(down[0].reversed);
  EXPECT_FALSE(down[1].reversed);
}

TEST(SectionOrientation, StartsFollowTheFirstSectionAcrossATwist) {
  // The second section is the first turned 1 degree about its middle and
  // started 50 points later: its start goes back to the point above the
  // first's (moved 0.1 mm by the twist, a third of the spacing).
  const std::vector<Vec3> base = blade_profile(400, 0);
  std::vector<Vec3> twisted;
  const Mat3 r = Eigen::AngleAxisd(deg_to_rad(1), Vec3::UnitZ()).toRotationMatrix();
  const Vec3 middle(30, 3, 0);
  for (size_t i = 0; i < base.size(); ++i)
    twisted.push_back(middle + r * (base[(i + 50) % base.size()] - middle) + Vec3(0, 0, 5));
  const std::vector<OrientedSection> o = orient_sections({base, twisted}, Vec3::UnitZ());
  EXPECT_EQ(o[1].start, 350);
}

TEST(SectionOrientation, RejectsAZeroAxisAndALoopSeenEdgeOn) {
  EXPECT_THROW(orient_sections({ellipse(3, 1, 20)}, Vec3::Zero()), ParameterError);
  EXPECT_THROW(orient_sections({ellipse(3, 1, 20)}, Vec3::UnitX()), ParameterError);
  EXPECT_THROW(orient_sections({{Vec3(0, 0, 0), Vec3(1, 0, 0)}}, Vec3::UnitZ()), ParameterError);
}

}  // namespace
}  // namespace bliskrun
