#include "core/planning/belt_paths.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/common/error.h"
#include "core/planning/row_steps.h"

namespace bliskrun {

double belt_step_over(double scallop_mm, double wheel_radius_mm, double curvature_across) {
  const double fit = 1 + wheel_radius_mm * curvature_across;
  if (!(fit > 0))
    throw ParameterError("wheel radius", "the wheel (r = " + std::to_string(wheel_radius_mm) +
                                             " mm) does not fit a concave face of radius " +
                                             std::to_string(1 / std::abs(curvature_across)) + " mm");
  return 2 * std::sqrt(2 * wheel_radius_mm * scallop_mm / fit);
}

double belt_step_over_exact(double h, double r, double k) {
  if (std::abs(k) < 1e-12) return 2 * std::sqrt(2 * r * h - h * h);
  // Eq. 3: contacts θ apart on the face's circle of radius R; the wheel
  // centres at R ± r, the cusp at R ± h on the bisector, one wheel radius
  // from each centre. The step-over is the arc between the contacts.
  const double big_r = 1 / std::abs(k);
  const double centre = k > 0 ? big_r + r : big_r - r, cusp = k > 0 ? big_r + h : big_r - h;
  if (!(centre > 0)) throw ParameterError("wheel radius", "the wheel does not fit the concave face");
  const double c = (centre * centre + cusp * cusp - r * r) / (2 * centre * cusp);
  return big_r * 2 * std::acos(std::clamp(c, -1.0, 1.0));
}

namespace {

// The face seen in (across, along) parameters: for AlongV paths, across = u
// and along = v.
struct FaceView {
  const Surface& face;
  bool along_v;
  double sign;  // +1: the wheel on the side of pu x pv

  SurfaceDerivs eval(double across, double along) const {
    return along_v ? face.eval(across, along) : face.eval(along, across);
  }
  Vec3 normal(const SurfaceDerivs& d) const { return sign * d.pu.cross(d.pv).normalized(); }
  const Vec3& d_along(const SurfaceDerivs& d) const { return along_v ? d.pv : d.pu; }
  const Vec3& d_across(const SurfaceDerivs& d) const { return along_v ? d.pu : d.pv; }
};

// Local frame of a contact: unit normal (wheel side), path tangent, and the
// direction across the path in the tangent plane (towards increasing
// `across`), with the face's convex curvature in that direction
// (second fundamental form; > 0 where the face bends away from the wheel)
// and the parameter speed across.
struct Contact {
  Vec3 p, n, t, d;
  double curvature_across = 0;
  double across_speed = 0;  // d(arc)/d(across) in direction d
};

Contact contact_at(const FaceView& f, double across, double along) {
  const SurfaceDerivs s = f.eval(across, along);
  Contact c;
  c.p = s.p;
  c.n = f.normal(s);
  c.t = f.d_along(s).normalized();
  c.d = c.n.cross(c.t);
  if (c.d.dot(f.d_across(s)) < 0) c.d = -c.d;
  // d = α pu + β pv, from the tangent-plane basis.
  const double e = s.pu.dot(s.pu), ff = s.pu.dot(s.pv), g = s.pv.dot(s.pv);
  const double du = c.d.dot(s.pu), dv = c.d.dot(s.pv);
  const double det = e * g - ff * ff;
  const double alpha = (g * du - ff * dv) / det, beta = (e * dv - ff * du) / det;
  const double second = alpha * alpha * s.puu.dot(c.n) + 2 * alpha * beta * s.puv.dot(c.n) +
                        beta * beta * s.pvv.dot(c.n);
  c.curvature_across = -second;  // |d| = 1: the first fundamental form is 1
  c.across_speed = f.d_across(s).dot(c.d);
  return c;
}

// Distance from q to the wheel through a contact (the cylinder of radius r
// about the axis through p + r n along t), positive outside.
double wheel_gap(const Contact& c, double r, const Vec3& q) {
  const Vec3 w = q - (c.p + r * c.n);
  return (w - w.dot(c.t) * c.t).norm() - r;
}

// The scallop between two neighbouring paths at one position along them:
// the material left on the face between the contacts, i.e. the largest
// over the cross-section of the distance to the nearer wheel. The gap to
// the first wheel grows across, to the second shrinks: the largest of their
// minimum is where they are equal (bisection), or at a sample.
double scallop_between(const FaceView& f, double r, double c0, double c1, double along, int samples) {
  const Contact a = contact_at(f, c0, along), b = contact_at(f, c1, along);
  auto gaps = [&](double x) {
    const Vec3 q = f.eval(x, along).p;
    return std::make_pair(wheel_gap(a, r, q), wheel_gap(b, r, q));
  };
  double best = 0;
  double lo = c0, hi = c1;
  for (int k = 1; k < samples; ++k) {
    const double x = c0 + (c1 - c0) * k / samples;
    const auto [ga, gb] = gaps(x);
    best = std::max(best, std::min(ga, gb));
    if (ga < gb) lo = x; else if (hi == c1) hi = x;
  }
  for (int it = 0; it < 60 && hi - lo > 1e-14; ++it) {
    const double m = 0.5 * (lo + hi);
    const auto [ga, gb] = gaps(m);
    best = std::max(best, std::min(ga, gb));
    if (ga < gb) lo = m; else hi = m;
  }
  return best;
}

double path_scallop(const FaceView& f, double r, const BeltPath& path, double c1, int samples) {
  double worst = 0;
  for (double along : path.along) worst = std::max(worst, scallop_between(f, r, path.across, c1, along, samples));
  return worst;
}

// Arc length of the path curve from t = 0, sampled (for trimming by w/2).
struct PathArcTable {
  std::vector<double> t, s;
  double at_length(double len) const {
    const auto it = std::lower_bound(s.begin(), s.end(), len);
    if (it == s.begin()) return t.front();
    if (it == s.end()) return t.back();
    const size_t i = it - s.begin();
    const double f = (len - s[i - 1]) / (s[i] - s[i - 1]);
    return t[i - 1] + f * (t[i] - t[i - 1]);
  }
};

PathArcTable arc_table(const Curve& c, int n) {
  PathArcTable a;
  a.t.push_back(0);
  a.s.push_back(0);
  Vec3 prev = c.point(0);
  for (int i = 1; i <= n; ++i) {
    const double t = static_cast<double>(i) / n;
    const Vec3 p = c.point(t);
    a.t.push_back(t);
    a.s.push_back(a.s.back() + (p - prev).norm());
    prev = p;
  }
  return a;
}

std::string where(const FaceView& f, double across, double along) {
  const double u = f.along_v ? across : along, v = f.along_v ? along : across;
  return "(u, v) = (" + std::to_string(u) + ", " + std::to_string(v) + ")";
}

BeltPath plan_path(const FaceView& f, const ContactWheel& wheel, const BeltPathOptions& o, double across,
                   BeltPlan& plan) {
  IsoUCurve along_v(f.face, across);
  IsoVCurve along_u(f.face, across);
  const Curve& curve = f.along_v ? static_cast<const Curve&>(along_v) : static_cast<const Curve&>(along_u);
  const PathArcTable arc = arc_table(curve, 2000);
  const double length = arc.s.back();
  if (length <= wheel.width_mm)
    throw Error("belt path at " + where(f, across, 0.5) + ": the face is " + std::to_string(length) +
                " mm long along the path, not longer than the wheel width " + std::to_string(wheel.width_mm) +
                " mm");
  // Trim by half the wheel width at both ends (Fig. 2).
  const CurveSpan span(curve, arc.at_length(0.5 * wheel.width_mm), arc.at_length(length - 0.5 * wheel.width_mm));
  StepOptions steps;
  steps.method = o.paper_correction ? ChordMethod::LargerCurvature : ChordMethod::Constant;
  steps.chord_tol_mm = o.chord_tol_mm;
  steps.guarantee_tolerance = o.guarantee;
  steps.max_step_mm = o.max_step_mm;
  RowSteps rs;
  try {
    rs = plan_row_steps(span, steps);
  } catch (const Error& e) {
    throw Error("belt path at " + where(f, across, 0.5) + ": " + e.what());
  }
  plan.step_halvings += rs.halvings;

  BeltPath path;
  path.across = across;
  path.along = rs.t;
  path.points = rs.points;
  path.chord_mm = rs.deviation_mm;
  path.chord_max_mm = rs.max_deviation_mm;
  path.length_mm = length - wheel.width_mm;
  for (double along : path.along) {
    const Contact c = contact_at(f, across, along);
    path.normals.push_back(c.n);
    path.tangents.push_back(c.t);
    double step_over;
    try {
      step_over = belt_step_over(o.scallop_mm, wheel.radius_mm, c.curvature_across);
      if (o.paper_correction) {
        // Eq. 6 for the step-over: the curvature where the next path would
        // be; the smaller step-over of the two (see the header on concave).
        const double next = across + step_over / std::max(c.across_speed, 1e-12);
        if (next <= 1) {
          const Contact p = contact_at(f, next, along);
          step_over = std::min(step_over, belt_step_over(o.scallop_mm, wheel.radius_mm, p.curvature_across));
        }
      }
    } catch (const ParameterError& e) {
      throw Error("belt path at " + where(f, across, along) + ": " + e.what());
    }
    path.step_over_mm.push_back(step_over);
  }
  return path;
}

}  // namespace

BeltPlan plan_belt_paths(const Surface& face, const ContactWheel& wheel, const BeltPathOptions& o,
                         Progress& progress) {
  if (!(wheel.radius_mm > 0) || !std::isfinite(wheel.radius_mm))
    throw ParameterError("wheel radius", "expected a radius > 0 in mm");
  if (!(wheel.width_mm > 0) || !std::isfinite(wheel.width_mm))
    throw ParameterError("wheel width", "expected a width > 0 in mm");
  if (!(o.chord_tol_mm > 0)) throw ParameterError("chord_tol", "expected a chord error > 0 in mm");
  if (!(o.scallop_mm > 0) || !(o.scallop_mm < wheel.radius_mm))
    throw ParameterError("scallop", "expected a scallop height > 0 and below the wheel radius");
  if (o.scallop_samples < 4) throw ParameterError("scallop_samples", "expected at least 4");

  const FaceView f{face, o.direction == BeltPathDirection::AlongV, o.normal_along_pu_x_pv ? 1.0 : -1.0};
  BeltPlan plan;
  double across = 0;
  progress.begin("belt paths", 100);
  for (;;) {
    progress.check();
    BeltPath path = plan_path(f, wheel, o, across, plan);
    // The next path at the smallest step-over along this one.
    double step = 1e300;
    for (size_t i = 0; i < path.along.size(); ++i) {
      const Contact c = contact_at(f, across, path.along[i]);
      step = std::min(step, path.step_over_mm[i] / std::max(c.across_speed, 1e-12));
    }
    const bool last = across >= 1;
    double next = std::min(1.0, across + step);
    if (!last) {
      double scallop = path_scallop(f, wheel.radius_mm, path, next, o.scallop_samples);
      // The formulas are approximations: shorten a step-over whose measured
      // scallop exceeds h (the scallop grows with the square of the step).
      while (o.guarantee && scallop > o.scallop_mm) {
        next = across + (next - across) * 0.995 * std::sqrt(o.scallop_mm / scallop);
        ++plan.step_over_shrinks;
        if (next - across < 1e-9) throw Error("belt paths: the scallop height cannot be met at " + where(f, across, 0.5));
        scallop = path_scallop(f, wheel.radius_mm, path, next, o.scallop_samples);
      }
      path.scallop_max_mm = scallop;
    }
    plan.points += static_cast<long>(path.points.size());
    plan.chord_max_mm = std::max(plan.chord_max_mm, path.chord_max_mm);
    plan.scallop_max_mm = std::max(plan.scallop_max_mm, path.scallop_max_mm);
    plan.paths.push_back(std::move(path));
    progress.step(static_cast<long>(100 * std::min(1.0, next)));
    if (last) break;
    across = next;  // on the far edge (1) when the next path would leave the face
  }
  progress.end();
  return plan;
}

}  // namespace bliskrun
