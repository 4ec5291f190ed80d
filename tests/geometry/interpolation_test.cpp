#include "core/geometry/interpolation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/common/error.h"

namespace bliskrun {
namespace {

Vec3 cubic(double t) {
  return Vec3(1 + 2 * t - 3 * t * t + 4 * t * t * t, -2 + t * t * t, 0.5 * t - 7 * t * t);
}
Vec3 cubic_d(double t) { return Vec3(2 - 6 * t + 12 * t * t, 3 * t * t, 0.5 - 14 * t); }

std::vector<double> uneven_params(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> gap(0.3, 1.7);
  std::vector<double> t(n, 0.0);
  for (int i = 1; i < n; ++i) t[i] = t[i - 1] + gap(rng);
  for (double& x : t) x /= t.back();
  t.back() = 1.0;
  return t;
}

TEST(ChordLength, ParametersAreCumulativeChordFractions) {
  const std::vector<Vec3> p = {Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(3, 4, 0), Vec3(3, 4, 2)};
  const std::vector<double> t = chord_length_parameters(p);
  ASSERT_EQ(t.size(), 4u);
  EXPECT_DOUBLE_EQ(t[0], 0);
  EXPECT_NEAR(t[1], 3.0 / 9, 1e-15);
  EXPECT_NEAR(t[2], 7.0 / 9, 1e-15);
  EXPECT_DOUBLE_EQ(t[3], 1);
}

TEST(ChordLength, RepeatedPointIsAnError) {
  EXPECT_THROW(chord_length_parameters({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0)}), ParameterError);
}

TEST(InterpolateCubic, PassesThroughEveryPoint) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 5);
  std::vector<Vec3> p;
  for (int i = 0; i < 57; ++i) p.emplace_back(i * 1.3 + noise(rng) * 0.1, noise(rng), noise(rng));
  const std::vector<double> t = chord_length_parameters(p);
  const BSplineCurve c = interpolate_cubic(p);
  for (size_t i = 0; i < p.size(); ++i) EXPECT_LT((c.point(t[i]) - p[i]).norm(), 1e-9) << i;
}

TEST(InterpolateCubic, ReproducesCubicDataExactly) {
  const std::vector<double> t = uneven_params(23, 3);
  std::vector<Vec3> p;
  for (double x : t) p.push_back(cubic(x));
  // Exact end tangents, and the default 4-point estimate (exact for cubics).
  const BSplineCurve exact = interpolate_cubic(p, t, {cubic_d(0), cubic_d(1)});
  const BSplineCurve estimated = interpolate_cubic(p, t);
  for (int k = 0; k <= 200; ++k) {
    const double x = k / 200.0;
    EXPECT_LT((exact.point(x) - cubic(x)).norm(), 1e-11) << x;
    EXPECT_LT((estimated.point(x) - cubic(x)).norm(), 1e-11) << x;
    EXPECT_LT((estimated.eval(x).dt - cubic_d(x)).norm(), 1e-9) << x;
  }
}

TEST(InterpolateCubic, TwoAndThreePoints) {
  const BSplineCurve two = interpolate_cubic({Vec3(0, 0, 0), Vec3(2, 0, 0)});
  EXPECT_LT((two.point(0.5) - Vec3(1, 0, 0)).norm(), 1e-14);
  const std::vector<Vec3> three = {Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(2, 0, 0)};
  const BSplineCurve c = interpolate_cubic(three);
  const std::vector<double> t = chord_length_parameters(three);
  for (int i = 0; i < 3; ++i) EXPECT_LT((c.point(t[i]) - three[i]).norm(), 1e-12);
}

// A bicubic polynomial surface: tensor-product interpolation reproduces it.
Vec3 bicubic(double u, double v) {
  return Vec3(10 * v + u * u * v, 20 * u - v * v * v * u, 3 * u * u * u * v * v + 2 * u * v - v * v);
}

TEST(InterpolateGrid, PassesThroughEveryGridPoint) {
  const int r = 11, c = 17;
  PointGrid g(r, c);
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < c; ++j) g.at(i, j) = bicubic(std::pow(i / (r - 1.0), 1.3), j / (c - 1.0));
  const BSplineSurface s = interpolate_grid(g);
  const GridParameters par = averaged_grid_parameters(g);
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < c; ++j) EXPECT_LT((s.point(par.u[i], par.v[j]) - g.at(i, j)).norm(), 1e-9);
}

TEST(InterpolateGrid, ReproducesBicubicDataExactly) {
  // Data sampled at known uneven parameters and interpolated at them: both
  // passes of eq. 5 meet cubic data, so the surface is the bicubic itself.
  GridParameters par{uneven_params(9, 11), uneven_params(14, 12)};
  PointGrid g(9, 14);
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 14; ++j) g.at(i, j) = bicubic(par.u[i], par.v[j]);
  const BSplineSurface s = interpolate_grid(g, par);
  for (int a = 0; a <= 20; ++a)
    for (int b = 0; b <= 20; ++b)
      EXPECT_LT((s.point(a / 20.0, b / 20.0) - bicubic(a / 20.0, b / 20.0)).norm(), 1e-10);
}

// Twisted blade-like sheet: the smooth surface a CAD export samples.
Vec3 blade_point(double a, double b) {
  // a: span in [0, 30] mm, b: chord in [0, 40] mm.
  const double twist = 0.6 * a / 30;
  const double camber = 3.0 * std::sin(kPi * b / 40);
  const Vec3 local(b - 20, camber, a);
  return Vec3(local.x() * std::cos(twist) - local.y() * std::sin(twist),
              local.x() * std::sin(twist) + local.y() * std::cos(twist), local.z() + 0.01 * b * b / 40);
}

TEST(InterpolateGrid, DenseGridIsAccurateBetweenRowsIncludingTheEdges) {
  // A 100 x 500 grid on non-uniform spacing, like the paper's: the surface
  // between data points, including between the first two and last two rows
  // and columns, must stay within 1 um of the true surface.
  const int r = 100, c = 500;
  PointGrid g(r, c);
  auto spacing = [](double x) { return 0.5 - 0.5 * std::cos(kPi * x); };  // clustered ends
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < c; ++j) g.at(i, j) = blade_point(30 * spacing(i / (r - 1.0)), 40 * spacing(j / (c - 1.0)));
  const BSplineSurface s = interpolate_grid(g);
  const GridParameters par = averaged_grid_parameters(g);
  double worst_edge = 0, worst_mid = 0;
  for (int i : {0, 1, 49, r - 3, r - 2}) {
    for (int j : {0, 1, 250, c - 3, c - 2}) {
      const double um = 0.5 * (par.u[i] + par.u[i + 1]), vm = 0.5 * (par.v[j] + par.v[j + 1]);
      // True surface point nearest to the interpolant's mid-cell point: find
      // it by Newton in the blade's own (a, b) from the cell centre.
      const Vec3 q = s.point(um, vm);
      double a = 30 * 0.5 * (spacing(i / (r - 1.0)) + spacing((i + 1) / (r - 1.0)));
      double b = 40 * 0.5 * (spacing(j / (c - 1.0)) + spacing((j + 1) / (c - 1.0)));
      for (int it = 0; it < 30; ++it) {
        const double h = 1e-6;
        const Vec3 p = blade_point(a, b);
        const Vec3 pa = (blade_point(a + h, b) - blade_point(a - h, b)) / (2 * h);
        const Vec3 pb = (blade_point(a, b + h) - blade_point(a, b - h)) / (2 * h);
        Eigen::Matrix2d J;
        J << pa.dot(pa), pa.dot(pb), pa.dot(pb), pb.dot(pb);
        const Eigen::Vector2d step = J.ldlt().solve(Eigen::Vector2d((q - p).dot(pa), (q - p).dot(pb)));
        a += step.x();
        b += step.y();
      }
      const double dev = (blade_point(a, b) - q).norm();
      const bool edge = i <= 1 || i >= r - 3 || j <= 1 || j >= c - 3;
      (edge ? worst_edge : worst_mid) = std::max(edge ? worst_edge : worst_mid, dev);
    }
  }
  EXPECT_LT(worst_edge, 1e-3);
  EXPECT_LT(worst_mid, 1e-3);
  RecordProperty("worst_edge_um", std::to_string(worst_edge * 1e3));
  RecordProperty("worst_mid_um", std::to_string(worst_mid * 1e3));
}

TEST(InterpolateGrid, DegenerateGridsAreErrors) {
  PointGrid one_row(1, 5);
  EXPECT_THROW(interpolate_grid(one_row), ParameterError);
  PointGrid g(3, 3);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) g.at(i, j) = Vec3(i, j, 0);
  g.at(1, 2) = g.at(1, 1);  // repeated point in a row
  EXPECT_THROW(interpolate_grid(g), ParameterError);
}

TEST(BSpline, InvalidKnotsAreErrors) {
  EXPECT_THROW(BSplineCurve(3, {0, 0, 0, 1, 1, 1}, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()}),
               ParameterError);
  EXPECT_THROW(BSplineCurve(1, {0, 1, 0.5, 1}, {Vec3::Zero(), Vec3::Ones()}), ParameterError);
}

TEST(BSpline, KnotInsertionKeepsTheShape) {
  std::vector<Vec3> p;
  for (int i = 0; i < 9; ++i) p.emplace_back(i, std::sin(i), std::cos(0.3 * i));
  const BSplineCurve c = interpolate_cubic(p);
  const BSplineCurve d = c.with_knot_inserted(0.37, 2);
  EXPECT_EQ(d.control_points().size(), c.control_points().size() + 2);
  for (int k = 0; k <= 100; ++k) {
    const double t = k / 100.0;
    EXPECT_LT((c.point(t) - d.point(t)).norm(), 1e-12);
    EXPECT_LT((c.eval(t).dtt - d.eval(t).dtt).norm(), 1e-8);
  }
}

}  // namespace
}  // namespace bliskrun
