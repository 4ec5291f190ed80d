// The four steps of core/repair together, as issue 16's loft will use them:
// scattered, shuffled, noisy sections with strays, some measured clockwise,
// one with its leading edge missing -> ordered, oriented, smoothed, aligned.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "core/repair/section_curve.h"
#include "core/repair/section_points.h"
#include "repair/section_shapes.h"

namespace bliskrun {
namespace {

TEST(SectionPipeline, ShuffledSectionsOfATwistingBladeComeOutAlignedOneAboveTheOther) {
  const int sections = 6;
  const Vec3 middle(30, 3, 0);
  std::vector<std::vector<Vec3>> loops;
  std::vector<Mat3> twist;
  for (int k = 0; k < sections; ++k) {
    twist.push_back(Eigen::AngleAxisd(deg_to_rad(2.0 * k), Vec3::UnitZ()).toRotationMatrix());
    std::vector<Vec3> p = test::blade_profile(1200, 0, 0.3, 40 + k);
    for (Vec3& q : p) q = middle + twist[k] * (q - middle) + Vec3(0, 0, 4.0 * k);
    test::add_noise(p, 0.004, 50 + k);
    if (k == 3)  // the damaged one: nothing within 1.5 mm of its LE
      p.erase(std::remove_if(p.begin(), p.end(),
                             [&](const Vec3& q) { return (twist[3].transpose() * (q - middle)).x() < 1.5 - 30; }),
              p.end());
    for (int s = 0; s < 8; ++s) {  // strays off the suction side
      const Vec3& q = p[s * 20];
      p.push_back(q + Vec3(0, 0.3 + 0.1 * s, 0));
    }
    if (k % 2) std::reverse(p.begin(), p.end());
    std::shuffle(p.begin(), p.end(), std::mt19937(60 + k));
    const OrderedSection o = order_section(p);
    EXPECT_GE(o.rejected.size(), 8u) << k;
    EXPECT_LE(o.rejected.size(), 10u) << k;
    EXPECT_EQ(o.gaps.size(), k == 3 ? 1u : 0u) << k;
    loops.push_back(pick(p, o.order));
  }
  const std::vector<OrientedSection> oriented = orient_sections(loops, Vec3::UnitZ());
  for (const OrientedSection& s : oriented) EXPECT_GT(vector_area(s.loop).z(), 0);
  // The complete sections are smoothed and aligned; the damaged one is the
  // loft's to rebuild (paper §1.4): its profile, shorter by the missing edge,
  // does not correspond sample by sample.
  std::vector<int> complete;
  std::vector<ClosedCurve> curves;
  for (int k = 0; k < sections; ++k)
    if (k != 3) complete.push_back(k), curves.push_back(smooth_section(oriented[k].loop, 0.1).curve);
  const AlignedSections aligned = align_section_starts(curves, 2048);
  // Each start is where the first section's start went with the twist.
  const Vec3 first = aligned.curves[0].point(aligned.curves[0].t_min());
  double worst = 0;
  for (size_t j = 1; j < complete.size(); ++j) {
    const int k = complete[j];
    const Vec3 target = middle + twist[k] * (Vec3(first.x(), first.y(), 0) - middle) + Vec3(0, 0, 4.0 * k);
    worst = std::max(worst, (aligned.curves[j].point(aligned.curves[j].t_min()) - target).norm());
  }
  std::printf("[ measured ] 6 shuffled sections twisting 2 deg each, one without its LE: the 5 complete ones start "
              "within %.4f mm of the twisted first start\n",
              worst);
  EXPECT_LT(worst, 0.05);
}

}  // namespace
}  // namespace bliskrun
