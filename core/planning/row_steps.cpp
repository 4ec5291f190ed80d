#include "core/planning/row_steps.h"

#include <algorithm>
#include <cmath>

#include "core/common/error.h"
#include "core/geometry/segment.h"

namespace bliskrun {

CurveDerivs IsoUCurve::eval(double t) const {
  const SurfaceDerivs d = s_.eval(u_, t);
  return {d.p, d.pv, d.pvv};
}

CurveDerivs IsoVCurve::eval(double t) const {
  const SurfaceDerivs d = s_.eval(t, v_);
  return {d.p, d.pu, d.puu};
}

double curve_curvature(const Curve& c, double t) {
  const CurveDerivs d = c.eval(t);
  const double speed = d.dt.norm();
  if (speed < 1e-14) throw Error("curve_curvature: singular curve point at t = " + std::to_string(t));
  return d.dt.cross(d.dtt).norm() / (speed * speed * speed);
}

namespace {

// Parameter t > t0 where |C(t) - C(t0)| = length, or t_max if the rest of the
// curve is shorter. Chord length grows monotonically from t0 for the gently
// curved rows we plan (no row turns back on itself within one step).
double parameter_at_chord(const Curve& c, double t0, double length) {
  const Vec3 p0 = c.point(t0);
  const double t_end = c.t_max();
  // Bracket: grow the parameter step from a first-order guess. The end is
  // taken only when the bracket reaches it: a curve that comes back to
  // where it was (a closed loop, a spiral's last turn) has its end near p0
  // without the curve between being within `length`.
  const double speed = std::max(c.eval(t0).dt.norm(), 1e-12);
  double lo = t0, hi = std::min(t_end, t0 + length / speed);
  while ((c.point(hi) - p0).norm() < length) {
    if (hi >= t_end) return t_end;
    lo = hi;
    hi = std::min(t_end, t0 + 2 * (hi - t0));
  }
  for (int i = 0; i < 100 && hi - lo > 1e-15; ++i) {
    const double mid = 0.5 * (lo + hi);
    if ((c.point(mid) - p0).norm() < length) lo = mid; else hi = mid;
  }
  return 0.5 * (lo + hi);
}

// Eq. 17: chord length for chord height delta on a circle of curvature k.
double step_for_chord_height(double delta, double k, double max_step) {
  if (k * delta < 1e-15) return max_step;
  const double s = 2.0 * delta / k - delta * delta;
  return s > 0 ? std::min(max_step, 2.0 * std::sqrt(s)) : max_step;
}

}  // namespace

double chord_deviation(const Curve& c, double t0, double t1) {
  const Vec3 a = c.point(t0), b = c.point(t1);
  constexpr int kSamples = 32;
  int best = 0;
  double best_d = 0;
  for (int i = 1; i < kSamples; ++i) {
    const double t = t0 + (t1 - t0) * i / kSamples;
    const double d = distance_to_segment(c.point(t), a, b);
    if (d > best_d) { best_d = d; best = i; }
  }
  if (best == 0) return 0;
  // Golden-section search for the maximum in the bracket around the best sample.
  double lo = t0 + (t1 - t0) * (best - 1) / kSamples;
  double hi = t0 + (t1 - t0) * (best + 1) / kSamples;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = distance_to_segment(c.point(x1), a, b);
  double f2 = distance_to_segment(c.point(x2), a, b);
  for (int i = 0; i < 60; ++i) {
    if (f1 > f2) {
      hi = x2; x2 = x1; f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = distance_to_segment(c.point(x1), a, b);
    } else {
      lo = x1; x1 = x2; f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = distance_to_segment(c.point(x2), a, b);
    }
  }
  return std::max({best_d, f1, f2});
}

RowSteps plan_row_steps(const Curve& row, const StepOptions& options) {
  if (!(options.chord_tol_mm > 0)) throw ParameterError("chord_tol", "must be > 0");
  if (!(options.max_step_mm > options.min_step_mm) || !(options.min_step_mm > 0))
    throw ParameterError("max_step", "needs 0 < min_step < max_step");
  const double tol = options.chord_tol_mm;
  const bool guarantee = options.guarantee_tolerance || options.method == ChordMethod::Variable;
  // A step computed for exactly the tolerance measures it to rounding: not a
  // reason to halve it.
  const double tol_measured = tol * (1 + 1e-9);

  RowSteps out;
  double t = row.t_min();
  const double t_end = row.t_max();
  double delta = tol;  // current chord height (variable method)
  out.t.push_back(t);
  out.points.push_back(row.point(t));
  while (t < t_end) {
    const double k = curve_curvature(row, t);
    double step;
    if (options.method == ChordMethod::Constant) {
      step = step_for_chord_height(tol, k, options.max_step_mm);
    } else if (options.method == ChordMethod::LargerCurvature) {
      const double t_pred = parameter_at_chord(row, t, step_for_chord_height(tol, k, options.max_step_mm));
      step = step_for_chord_height(tol, std::max(k, curve_curvature(row, t_pred)), options.max_step_mm);
    } else {
      // Eq. 18 with the curvature at the point the current delta predicts.
      const double t_pred = parameter_at_chord(row, t, step_for_chord_height(delta, k, options.max_step_mm));
      const double k_next = curve_curvature(row, t_pred);
      if (k_next > 1e-15 && k > 1e-15) delta = delta * k / k_next;
      step = step_for_chord_height(delta, k, options.max_step_mm);
    }
    double t_next = parameter_at_chord(row, t, step);
    double dev = chord_deviation(row, t, t_next);
    while (guarantee && dev > tol_measured) {
      step *= 0.5;
      ++out.halvings;
      if (step < options.min_step_mm)
        throw Error("row step below " + std::to_string(options.min_step_mm) +
                    " mm at t = " + std::to_string(t) + ": chord tolerance cannot be met");
      t_next = parameter_at_chord(row, t, step);
      dev = chord_deviation(row, t, t_next);
    }
    if (options.method == ChordMethod::Variable && guarantee) {
      // Keep delta from drifting above what was actually achievable here.
      delta = std::min(delta, tol);
    }
    t = t_next;
    out.t.push_back(t);
    out.points.push_back(row.point(t));
    out.deviation_mm.push_back(dev);
    out.max_deviation_mm = std::max(out.max_deviation_mm, dev);
  }
  return out;
}

}  // namespace bliskrun
