#include "core/planning/row_steps.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"

namespace bliskrun {
namespace {

// Circle of radius R in the XY plane, t in [0, 1] -> angle [0, span].
class Arc : public Curve {
 public:
  Arc(double r, double span) : r_(r), span_(span) {}
  CurveDerivs eval(double t) const override {
    const double a = span_ * t, c = std::cos(a), s = std::sin(a);
    return {Vec3(r_ * c, r_ * s, 0), Vec3(-r_ * s, r_ * c, 0) * span_,
            Vec3(-r_ * c, -r_ * s, 0) * (span_ * span_)};
  }

 private:
  double r_, span_;
};

// Ellipse quarter from the flat end (minor-axis vertex) to the sharp end
// (major-axis vertex): curvature rises from b/a^2 to a/b^2 along the row.
class EllipseQuarter : public Curve {
 public:
  EllipseQuarter(double a, double b) : a_(a), b_(b) {}
  CurveDerivs eval(double t) const override {
    const double h = 0.5 * kPi;
    const double th = h * (1 - t);  // t=0 at (0, b), t=1 at (a, 0)
    const double c = std::cos(th), s = std::sin(th);
    return {Vec3(a_ * c, b_ * s, 0), Vec3(a_ * s, -b_ * c, 0) * h,
            Vec3(-a_ * c, -b_ * s, 0) * (h * h)};
  }

 private:
  double a_, b_;
};

TEST(CurveCurvature, CircleIsOneOverRadius) {
  const Arc arc(40.0, 1.0);
  for (double t : {0.0, 0.3, 1.0}) EXPECT_NEAR(curve_curvature(arc, t), 1.0 / 40.0, 1e-12);
}

TEST(ChordDeviation, CircleSagittaClosedForm) {
  const double r = 25.0, span = 0.2;
  const Arc arc(r, span);
  // Sagitta of a chord subtending angle span: r (1 - cos(span / 2)).
  EXPECT_NEAR(chord_deviation(arc, 0, 1), r * (1 - std::cos(span / 2)), 1e-10);
}

TEST(RowSteps, ConstantChordOnCircleMeetsToleranceExactly) {
  const double r = 1.0 / 0.0435;  // the paper's k1max as a radius
  const Arc arc(r, 1.0);
  StepOptions opt;
  opt.method = ChordMethod::Constant;
  opt.guarantee_tolerance = false;
  opt.chord_tol_mm = 0.002;
  const RowSteps steps = plan_row_steps(arc, opt);
  // Eq. 17 is exact on a circle: every full step has sagitta delta.
  for (size_t i = 0; i + 1 < steps.deviation_mm.size(); ++i)
    EXPECT_NEAR(steps.deviation_mm[i], opt.chord_tol_mm, 1e-9) << "segment " << i;
  const double step = 2 * std::sqrt(2 * 0.002 * r - 0.002 * 0.002);
  EXPECT_EQ(steps.points.size(), static_cast<size_t>(std::ceil(r / step * 0.999999)) + 1);
}

TEST(RowSteps, ConstantChordExceedsWhereCurvatureRisesVariableDoesNot) {
  const EllipseQuarter row(60.0, 12.0);  // curvature 0.0033 -> 0.42 per mm
  StepOptions constant;
  constant.method = ChordMethod::Constant;
  constant.guarantee_tolerance = false;
  const RowSteps c = plan_row_steps(row, constant);
  EXPECT_GT(c.max_deviation_mm, constant.chord_tol_mm * 1.05)
      << "eq. 17 assumes constant curvature; on a rising curvature it must overshoot";

  StepOptions variable;
  variable.method = ChordMethod::Variable;
  const RowSteps v = plan_row_steps(row, variable);
  EXPECT_LE(v.max_deviation_mm, variable.chord_tol_mm);
  for (double d : v.deviation_mm) EXPECT_LE(d, variable.chord_tol_mm);
  // Independent re-measurement of every emitted segment.
  for (size_t i = 0; i + 1 < v.t.size(); ++i)
    EXPECT_LE(chord_deviation(row, v.t[i], v.t[i + 1]), variable.chord_tol_mm * (1 + 1e-9));
  EXPECT_DOUBLE_EQ(v.t.back(), 1.0);
}

TEST(RowSteps, StraightRowUsesMaximumStep) {
  class Line : public Curve {
    CurveDerivs eval(double t) const override { return {Vec3(12 * t, 0, 0), Vec3(12, 0, 0), Vec3::Zero()}; }
  } line;
  StepOptions opt;
  opt.max_step_mm = 5.0;
  const RowSteps s = plan_row_steps(line, opt);
  ASSERT_EQ(s.points.size(), 4u);  // 0, 5, 10, 12
  EXPECT_NEAR(s.points[1].x(), 5.0, 1e-9);
  EXPECT_NEAR(s.points[3].x(), 12.0, 1e-12);
}

TEST(RowSteps, RejectsNonPositiveTolerance) {
  const Arc arc(10, 1);
  StepOptions opt;
  opt.chord_tol_mm = 0;
  EXPECT_THROW(plan_row_steps(arc, opt), ParameterError);
}

}  // namespace
}  // namespace bliskrun
