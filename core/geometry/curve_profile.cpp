#include "core/geometry/curve_profile.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/common/error.h"

namespace bliskrun {

namespace {

// 5-point Gauss–Legendre on [-1, 1].
constexpr double kGaussX[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                               0.9061798459386640};
constexpr double kGaussW[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                               0.2369268850561891};

double arc_length(const BSplineCurve& c, double a, double b) {
  double sum = 0;
  for (int g = 0; g < 5; ++g) sum += kGaussW[g] * c.eval(0.5 * (a + b) + 0.5 * (b - a) * kGaussX[g]).dt.norm();
  return 0.5 * (b - a) * sum;
}

}  // namespace

CurvatureProfile curvature_profile(const ClosedCurve& curve, int samples) {
  if (samples < 16) throw ParameterError("samples", "expected at least 16 samples, got " + std::to_string(samples));
  const BSplineCurve& spline = curve.spline();
  const std::vector<double>& knots = spline.knots();
  const double u0 = spline.t_min(), period = curve.period();
  // Cumulative arc length at the knots of one period, from u0.
  const int spans = static_cast<int>(spline.control_points().size()) - 3;
  std::vector<double> at_knot(spans + 1, 0.0);
  for (int k = 0; k < spans; ++k) at_knot[k + 1] = at_knot[k] + arc_length(spline, knots[k + 3], knots[k + 4]);
  const double length = at_knot.back();
  // Arc length from u0 to u (u in [u0, u0 + period]).
  const auto span_of = [&](double s) {
    const auto it = std::upper_bound(at_knot.begin(), at_knot.end(), s);
    return std::clamp(static_cast<int>(it - at_knot.begin()) - 1, 0, spans - 1);
  };
  const double start_u = u0 + std::fmod(curve.t_min() - u0, period);
  const double start_s = [&] {
    const auto it = std::upper_bound(knots.begin() + 3, knots.begin() + 3 + spans + 1, start_u);
    const int k = std::clamp(static_cast<int>(it - (knots.begin() + 3)) - 1, 0, spans - 1);
    return at_knot[k] + arc_length(spline, knots[k + 3], start_u);
  }();

  CurvatureProfile out;
  out.length_mm = length;
  out.period = period;
  std::vector<CurveDerivs> d(samples);
  for (int j = 0; j < samples; ++j) {
    const double s = std::fmod(start_s + length * j / samples, length);
    const int k = span_of(s);
    const double a = knots[k + 3], b = knots[k + 4];
    // Newton on the arc length within the span, from the linear guess.
    double u = a + (b - a) * (s - at_knot[k]) / std::max(at_knot[k + 1] - at_knot[k], 1e-300);
    for (int it = 0; it < 6; ++it) {
      const double speed = spline.eval(u).dt.norm();
      if (!(speed > 0)) break;
      const double next = std::clamp(u - (at_knot[k] + arc_length(spline, a, u) - s) / speed, a, b);
      const bool settled = std::abs(next - u) < 1e-12 * period;
      u = next;
      if (settled) break;
    }
    double t = u;
    while (t < curve.t_min()) t += period;
    while (t >= curve.t_max()) t -= period;
    out.t.push_back(t);
    d[j] = spline.eval(u);
  }
  std::vector<Vec3> points(samples);
  for (int j = 0; j < samples; ++j) points[j] = d[j].p;
  const Vec3 area = vector_area(points);
  const Vec3 normal = area.norm() > 0 ? Vec3(area.normalized()) : Vec3::Zero();
  out.curvature.reserve(samples);
  for (int j = 0; j < samples; ++j) {
    const double speed = d[j].dt.norm();
    out.curvature.push_back(speed > 0 ? d[j].dt.cross(d[j].dtt).dot(normal) / (speed * speed * speed) : 0.0);
  }
  return out;
}

Vec3 vector_area(const std::vector<Vec3>& loop) {
  if (loop.empty()) return Vec3::Zero();
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : loop) centre += p;
  centre /= static_cast<double>(loop.size());
  Vec3 area = Vec3::Zero();
  for (size_t i = 0; i < loop.size(); ++i)
    area += (loop[i] - centre).cross(loop[(i + 1) % loop.size()] - centre);
  return 0.5 * area;
}

}  // namespace bliskrun
