#include "core/geometry/closed_curve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/common/error.h"

namespace bliskrun {
namespace {

std::vector<Vec3> uneven_loop(int n) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::vector<Vec3> loop;
  for (int i = 0; i < n; ++i) {
    const double th = 2 * kPi * (i + jitter(rng)) / n;
    loop.emplace_back(20 * std::cos(th), 7 * std::sin(th) + std::sin(3 * th), 0.5 * std::cos(2 * th));
  }
  return loop;
}

TEST(ClosedCurve, PassesThroughItsPointsAtTheirChordLengths) {
  const std::vector<Vec3> loop = uneven_loop(60);
  const ClosedCurve c = interpolate_closed_cubic(loop);
  double t = 0;
  for (size_t i = 0; i < loop.size(); ++i) {
    EXPECT_LT((c.point(t) - loop[i]).norm(), 1e-10) << i;
    t += (loop[(i + 1) % loop.size()] - loop[i]).norm();
  }
  EXPECT_NEAR(c.period(), t, 1e-12);
  EXPECT_DOUBLE_EQ(c.t_min(), 0);
}

TEST(ClosedCurve, IsC2AcrossItsSeamAndPeriodic) {
  const ClosedCurve c = interpolate_closed_cubic(uneven_loop(40));
  const double T = c.period();
  const CurveDerivs before = c.eval(T - 1e-9), after = c.eval(1e-9), wrapped = c.eval(0.37 + 2 * T);
  EXPECT_LT((before.p - after.p).norm(), 1e-7);
  EXPECT_LT((before.dt - after.dt).norm(), 1e-6);
  EXPECT_LT((before.dtt - after.dtt).norm(), 1e-5);
  EXPECT_LT((wrapped.p - c.point(0.37)).norm(), 1e-12);
  // Started elsewhere: the same points, the new start at t_min.
  const ClosedCurve later = c.started_at(0.4 * T);
  EXPECT_NEAR(later.t_min(), 0.4 * T, 1e-12);
  EXPECT_NEAR(later.t_max(), 1.4 * T, 1e-12);
  EXPECT_LT((later.point(later.t_min()) - c.point(0.4 * T)).norm(), 1e-12);
  EXPECT_LT((later.point(later.t_max() - 1e-3) - c.point(0.4 * T - 1e-3)).norm(), 1e-12);
}

TEST(ClosedCurve, ACircleThroughSixtyPointsIsACircleToAMicron) {
  const double R = 10;
  std::vector<Vec3> loop;
  for (int i = 0; i < 60; ++i) loop.emplace_back(R * std::cos(2 * kPi * i / 60), R * std::sin(2 * kPi * i / 60), 0);
  const ClosedCurve c = interpolate_closed_cubic(loop);
  double worst = 0, worst_k = 0;
  for (int j = 0; j < 3000; ++j) {
    const CurveDerivs d = c.eval(c.period() * j / 3000);
    worst = std::max(worst, std::abs(d.p.norm() - R));
    const double k = d.dt.cross(d.dtt).norm() / std::pow(d.dt.norm(), 3);
    worst_k = std::max(worst_k, std::abs(k * R - 1));
  }
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT(worst_k, 0.02);
}

TEST(ClosedCurve, RejectsASplineThatIsNotPeriodic) {
  const ClosedCurve c = interpolate_closed_cubic(uneven_loop(12));
  std::vector<Vec3> ctrl = c.spline().control_points();
  ctrl.back() += Vec3(0.1, 0, 0);
  EXPECT_THROW(ClosedCurve(BSplineCurve(3, c.spline().knots(), ctrl), 0), ParameterError);
  std::vector<double> knots = c.spline().knots();
  knots[1] -= 0.5;
  EXPECT_THROW(ClosedCurve(BSplineCurve(3, knots, c.spline().control_points()), 0), ParameterError);
  EXPECT_THROW(c.started_at(NAN), ParameterError);
}

TEST(ClosedCurve, RejectsTooFewRepeatedOrNonFinitePoints) {
  EXPECT_THROW(interpolate_closed_cubic({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}), ParameterError);
  std::vector<Vec3> loop = uneven_loop(10);
  loop[4] = loop[3];
  EXPECT_THROW(interpolate_closed_cubic(loop), ParameterError);
  loop = uneven_loop(10);
  loop.push_back(loop.front());  // a repeated closing point is a zero-length chord
  EXPECT_THROW(interpolate_closed_cubic(loop), ParameterError);
  loop = uneven_loop(10);
  loop[2].x() = INFINITY;
  EXPECT_THROW(interpolate_closed_cubic(loop), ParameterError);
}

TEST(ClosedCurve, AtGivenKnotsPassesThroughItsPointsThereAndClosesC2) {
  // Uniform knots from 2 to 5 (not the chord lengths, not from 0): what a
  // loft gives every section so that they share one basis.
  const std::vector<Vec3> loop = uneven_loop(40);
  std::vector<double> knots;
  for (int k = 0; k <= 40; ++k) knots.push_back(2 + 3.0 * k / 40);
  const BSplineCurve c = interpolate_closed_cubic(loop, knots);
  EXPECT_DOUBLE_EQ(c.t_min(), 2);
  EXPECT_DOUBLE_EQ(c.t_max(), 5);
  for (int k = 0; k < 40; ++k) EXPECT_LT((c.point(knots[k]) - loop[k]).norm(), 1e-10) << k;
  const CurveDerivs a = c.eval(2), b = c.eval(5);
  EXPECT_LT((a.p - b.p).norm(), 1e-10);
  EXPECT_LT((a.dt - b.dt).norm(), 1e-8);
  EXPECT_LT((a.dtt - b.dtt).norm(), 1e-6);
  // At the chord-length knots it is the chord-length curve.
  std::vector<double> chord{0};
  for (int k = 0; k < 40; ++k) chord.push_back(chord.back() + (loop[(k + 1) % 40] - loop[k]).norm());
  const ClosedCurve ref = interpolate_closed_cubic(loop);
  const BSplineCurve same = interpolate_closed_cubic(loop, chord);
  for (double t = 0; t < ref.period(); t += 0.37) EXPECT_LT((same.point(t) - ref.point(t)).norm(), 1e-10);
  EXPECT_NO_THROW(ClosedCurve(same, 0));
}

TEST(ClosedCurve, AtGivenKnotsRejectsAWrongCountOrKnotsNotIncreasing) {
  const std::vector<Vec3> loop = uneven_loop(10);
  std::vector<double> knots;
  for (int k = 0; k <= 10; ++k) knots.push_back(k);
  EXPECT_THROW(interpolate_closed_cubic(loop, std::vector<double>(knots.begin(), knots.end() - 1)), ParameterError);
  knots[4] = knots[3];
  EXPECT_THROW(interpolate_closed_cubic(loop, knots), ParameterError);
  knots[4] = NAN;
  EXPECT_THROW(interpolate_closed_cubic(loop, knots), ParameterError);
}

}  // namespace
}  // namespace bliskrun
