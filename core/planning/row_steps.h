#pragma once
// Step length along a tool-contact row (blisk paper §3.2).
//
// A row is a curve C(t) on the flank (an iso-u' line of the trimmed flank).
// Consecutive contact points are joined by straight moves; the chord error is
// the largest distance between the curve and that straight segment.
//
//  - Constant chord height (eq. 17): L_i = 2 sqrt(2 delta / k_i - delta^2),
//    k_i the curvature at p_i. Assumes the curvature does not change between
//    p_i and p_{i+1}, so where it rises the true error exceeds delta (Fig. 13).
//  - Variable chord height (eq. 18-19), as written: delta_{i+1} =
//    (k_i / k_{i+1}) delta_i, then eq. 17 with delta_{i+1}, and the next point
//    is where the chord |p_i p_{i+1}| equals L_i. The paper leaves open how
//    k_{i+1} is known before p_{i+1} is; we take it at the point eq. 17
//    predicts with the current delta (one predictor step). The paper calls
//    delta the allowed maximum, so delta never rises above chord_tol_mm.
//  - Guarantee (ours, not the paper's): with `guarantee_tolerance`, every
//    segment's *measured* chord deviation is checked and the step halved until
//    it is within chord_tol_mm. The variable method always uses it; the
//    constant method can be run without it to reproduce the paper's finding.
#include <string>
#include <vector>

#include "core/common/progress.h"
#include "core/geometry/curve.h"
#include "core/geometry/surface.h"

namespace bliskrun {

// The curve v -> S(u, v) for fixed u, on t = v in [0, 1].
class IsoUCurve : public Curve {
 public:
  IsoUCurve(const Surface& s, double u) : s_(s), u_(u) {}
  CurveDerivs eval(double t) const override;

 private:
  const Surface& s_;
  double u_;
};

// The curve u -> S(u, v) for fixed v, on t = u in [0, 1] (the edge region's
// rows run around the edge at constant v; core/planning/edge_finish.h).
class IsoVCurve : public Curve {
 public:
  IsoVCurve(const Surface& s, double v) : s_(s), v_(v) {}
  CurveDerivs eval(double t) const override;

 private:
  const Surface& s_;
  double v_;
};

// Curvature |C' x C''| / |C'|^3 of a space curve at t.
double curve_curvature(const Curve& c, double t);

// Largest distance between C(t), t in [t0, t1], and the segment C(t0)C(t1):
// dense sampling followed by golden-section refinement around the largest
// sample. This is a measurement of the actual curve, not an estimate from
// curvature.
double chord_deviation(const Curve& c, double t0, double t1);

//  - Larger curvature (belt paper §2.3, eq. 6): predict the next point with
//    the current curvature, take the larger of the current and the predicted
//    point's curvature, and recompute the step with it.
enum class ChordMethod { Constant, Variable, LargerCurvature };

struct StepOptions {
  ChordMethod method = ChordMethod::Variable;
  double chord_tol_mm = 0.002;   // allowed chord height delta
  bool guarantee_tolerance = true;
  double max_step_mm = 5.0;      // cap where the row is (nearly) straight
  double min_step_mm = 1e-4;     // below this the guarantee gives up: error
};

struct RowSteps {
  std::vector<double> t;             // parameters of the contact points
  std::vector<Vec3> points;
  std::vector<double> deviation_mm;  // measured chord deviation per segment
  double max_deviation_mm = 0;
  int halvings = 0;                  // steps shortened by the guarantee
};

// Steps from row.t_min() to row.t_max(); the last point is t_max().
RowSteps plan_row_steps(const Curve& row, const StepOptions& options);

// The part [t0, t1] of a curve, as a curve (a path trimmed at its ends).
class CurveSpan : public Curve {
 public:
  CurveSpan(const Curve& c, double t0, double t1) : c_(c), t0_(t0), t1_(t1) {}
  CurveDerivs eval(double t) const override { return c_.eval(t); }
  double t_min() const override { return t0_; }
  double t_max() const override { return t1_; }

 private:
  const Curve& c_;
  double t0_, t1_;
};

}  // namespace bliskrun
