#include "core/parts/ruled_fit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/common/error.h"

namespace bliskrun {
namespace {

TEST(RuledFit, ARuledGridFitsExactly) {
  // A hyperbolic paraboloid sampled along its rulings.
  PointGrid g(9, 30);
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 30; ++j) {
      const double u = i / 8.0, v = j / 29.0;
      g.at(i, j) = Vec3(60 * v, 30 * u, 12 * u * (v - 0.5));
    }
  const RuledFit f = fit_ruled(g, 0, 8);
  EXPECT_LT(f.max_mm, 1e-9);
  // The surface passes through the rulings' ends and is linear between.
  EXPECT_LT((f.surface->point(0, 0) - g.at(0, 0)).norm(), 1e-9);
  EXPECT_LT((f.surface->point(1, 1) - g.at(8, 29)).norm(), 1e-9);
  EXPECT_LT((f.surface->point(0.5, 0) - g.at(4, 0)).norm(), 1e-9);
}

// Columns bulged by a parabola z = c u (1 - u): by symmetry the least-squares
// line is z = mean, so the largest distance is max |c u_i (1 - u_i) - mean|.
TEST(RuledFit, BulgedColumnsFitTheirMeanLine) {
  const double c = 0.8;
  const int rows = 11;
  PointGrid g(rows, 8);
  double mean = 0;
  for (int i = 0; i < rows; ++i) mean += c * (i / 10.0) * (1 - i / 10.0) / rows;
  double expected_max = 0, expected_sum2 = 0;
  for (int i = 0; i < rows; ++i) {
    const double e = c * (i / 10.0) * (1 - i / 10.0) - mean;
    expected_max = std::max(expected_max, std::abs(e));
    expected_sum2 += e * e;
  }
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < 8; ++j) g.at(i, j) = Vec3(5.0 * j, 20 * i / 10.0, c * (i / 10.0) * (1 - i / 10.0));
  const RuledFit f = fit_ruled(g, 0, rows - 1);
  EXPECT_NEAR(f.max_mm, expected_max, 1e-12);
  EXPECT_NEAR(f.rms_mm, std::sqrt(expected_sum2 / rows), 1e-12);
  EXPECT_THROW(fit_ruled(g, 3, 3), ParameterError);
}

}  // namespace
}  // namespace bliskrun
