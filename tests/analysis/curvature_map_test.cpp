#include "core/analysis/curvature_map.h"

#include <gtest/gtest.h>

#include <regex>

#include "core/common/error.h"
#include "geometry/analytic_surfaces.h"

namespace bliskrun {
namespace {

CurvatureStats torus_stats() {
  const test::Torus torus(40.0, 10.0);
  CurvatureStatsOptions o;
  o.samples_u = 41;  // phi = 2 pi i / 40 hits the inner equator
  o.samples_v = 30;
  return curvature_stats(torus, o);
}

TEST(CurvatureMap, DeterministicSvgWithScaleAndLabels) {
  const CurvatureStats st = torus_stats();
  const std::string a = curvature_map_svg(st), b = curvature_map_svg(st);
  EXPECT_EQ(a, b);
  EXPECT_EQ(a.rfind("<?xml", 0), 0u);
  EXPECT_NE(a.find("</svg>"), std::string::npos);
  EXPECT_NE(a.find("u (span, hub to tip)"), std::string::npos);
  EXPECT_NE(a.find("v (chord)"), std::string::npos);
  // Colour bar ends label -max|K| and +max|K|: the torus outer equator has
  // K = 1 / (r (R + r)) = 0.002 and the inner one -1 / (r (R - r)).
  // (3 significant digits, fixed point).
  EXPECT_NE(a.find(">-0.00333<"), std::string::npos);
  EXPECT_NE(a.find(">0.00333<"), std::string::npos);
  // Both ends of the diverging scale appear: the torus has K > 0 and K < 0.
  EXPECT_NE(a.find("fill=\"#2"), std::string::npos);  // blue end (#2x6xax)
  EXPECT_NE(a.find("fill=\"#b"), std::string::npos);  // red end (#bx1x2x)
}

// Torus: K depends only on the tube angle (u), so every row is one colour
// and merges into one rectangle: samples_u map rectangles.
TEST(CurvatureMap, MergesEqualRuns) {
  const CurvatureStats st = torus_stats();
  CurvatureMapOptions o;
  o.levels = 16;
  const std::string svg = curvature_map_svg(st, o);
  const auto g0 = svg.find("<g shape"), g1 = svg.find("</g>");
  const std::string map = svg.substr(g0, g1 - g0);
  size_t rects = 0;
  for (size_t p = map.find("<rect"); p != std::string::npos; p = map.find("<rect", p + 1)) ++rects;
  EXPECT_EQ(rects, 41u);
}

TEST(CurvatureMap, NeedsTheMap) {
  const test::Torus torus(40.0, 10.0);
  CurvatureStatsOptions o;
  o.samples_u = 5;
  o.samples_v = 5;
  o.keep_map = false;
  EXPECT_THROW(curvature_map_svg(curvature_stats(torus, o)), ParameterError);
}

}  // namespace
}  // namespace bliskrun
