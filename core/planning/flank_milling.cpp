#include "core/planning/flank_milling.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>

#include <unsupported/Eigen/NonLinearOptimization>

#include "core/common/error.h"
#include "core/common/fixed_text.h"
#include "core/geometry/projection.h"
#include "core/geometry/root_find.h"

namespace bliskrun {

namespace {

Vec3 face_normal(const SurfaceDerivs& d) { return d.pu.cross(d.pv).normalized(); }

// Root of g(s) = hub.radial_offset(p + s a) - r nearest s = 0: brackets
// grow outwards from 0 in both directions, then Illinois regula falsi.
std::optional<double> meet_hub_offset(const SurfaceOfRevolution& hub, double r, const Vec3& p,
                                      const Vec3& a, double reach_mm) {
  auto g = [&](double s) { return hub.radial_offset(p + s * a) - r; };
  const double g0 = g(0);
  if (g0 == 0) return 0.0;
  for (double step = 0.25; step <= reach_mm * 2; step *= 2) {
    for (double dir : {-1.0, 1.0}) {
      double a0 = dir * step / 2, b0 = dir * step;
      if (step == 0.25) a0 = 0;
      double ga = a0 == 0 ? g0 : g(a0), gb = g(b0);
      if ((ga > 0) == (gb > 0)) continue;
      return illinois_root(g, a0, b0, ga, gb, 1e-12);
    }
  }
  return std::nullopt;
}

// u where the ruling at v meets the hub (radial offset 0), searched in
// [-0.5, 0.5]; 0 when the face does not cross the hub there (a face that
// clamps its parameters outside [0, 1]).
double hub_parameter(const Surface& face, double v, const SurfaceOfRevolution& hub) {
  auto g = [&](double u) { return hub.radial_offset(face.point(u, v)); };
  double a = -0.5, b = 0.5, ga = g(a), gb = g(b);
  if ((ga > 0) == (gb > 0)) return 0.0;
  return illinois_root(g, a, b, ga, gb, 1e-14);
}

// A lead leaves the hub at this angle over its tangent plane.
constexpr double kLeadRiseRad = 45 * 3.14159265358979323846 / 180;
// How far the ball may come closer to the hub than its radius on a lead:
// the centre rides the hub offset to the root finder's precision.
constexpr double kHubToleranceMm = 1e-4;

// Unit normal of the hub's offset surfaces at q, pointing the way the
// signed radial offset grows, scaled to the channel side (where q is). From
// q's foot on the profile (SurfaceOfRevolution::offset_direction), not by
// differences of radial_offset: on a profile through dense, rounded data
// (Rotor 67's hub) those point anywhere.
Vec3 hub_normal(const SurfaceOfRevolution& hub, const Vec3& q) {
  const double channel = hub.radial_offset(q) >= 0 ? 1.0 : -1.0;
  return channel * hub.offset_direction(q);
}

}  // namespace

FlankCutter::FlankCutter(Tool tool, double ball_radius_mm) : tool_(std::move(tool)), r_(ball_radius_mm) {
  if (!(r_ > 0)) throw ParameterError("ball_radius", "expected a positive radius");
  // A ball end of radius r: the profile near the tip is that circle, and
  // the sphere of radius r at height r lies inside the cutter.
  const double z = 0.05 * r_;
  const double circle = std::sqrt(2 * r_ * z - z * z);
  const double inscribed = -tool_.signed_distance(Vec3(0, 0, r_), ToolPartId::Cutter);
  if (std::abs(tool_.radius_at(z) - circle) > 1e-6 * std::max(1.0, r_) ||
      std::abs(inscribed - r_) > 1e-6 * std::max(1.0, r_))
    throw ParameterError("ball_radius", "the tool (" + tool_.description() + ") has no ball end of radius " +
                                            short_text(r_) + " mm");
  top_ = tool_.cutter().z_max() - r_;
}

double FlankCutter::radius_at(double s_mm) const {
  // Heights are above the ball centre, which sits r_ - grow_ above the
  // real tool's tip.
  const double inside = -tool_.signed_distance(Vec3(0, 0, r_ - grow_ + s_mm), ToolPartId::Cutter);
  return inside > 0 ? inside + grow_ : 0.0;
}

FlankCutter FlankCutter::grown(double by_mm) const {
  if (!(by_mm >= 0)) throw ParameterError("stock", "expected a stock >= 0 in mm");
  FlankCutter g = *this;
  g.r_ += by_mm;
  g.grow_ += by_mm;
  return g;
}

FlankAxis flank_axis(const Surface& face, double v, const SurfaceOfRevolution* hub,
                     const FlankCutter& cutter) {
  FlankAxis ax;
  ax.v = v;
  // The hub contact: where the ruling meets the hub. The face's own hub
  // curve (the camber hub curve offset by h along the camber normal, eq. 10)
  // lies off the hub by up to h times the lean of the ruling: above it on
  // one face, inside it on the other. The ruled face is linear along the
  // ruling, so it is followed (or cut back) to the hub.
  ax.u_hub = hub ? hub_parameter(face, v, *hub) : 0.0;
  const SurfaceDerivs hub_side = face.eval(ax.u_hub, v), shroud_side = face.eval(1, v);
  ax.c1 = shroud_side.p;
  ax.c2 = hub_side.p;
  ax.n1 = face_normal(shroud_side);  // eq. 21
  ax.n2 = face_normal(hub_side);     // eq. 22
  const double r = cutter.ball_radius_mm();
  double rho1 = r, rho2 = r;
  Vec3 a = Vec3::UnitZ();
  for (ax.iterations = 1; ax.iterations <= 50; ++ax.iterations) {
    ax.d1 = ax.c1 + rho1 * ax.n1;  // eq. 23
    ax.d2 = ax.c2 + rho2 * ax.n2;  // eq. 24
    a = (ax.d1 - ax.d2).normalized();  // eq. 25, towards the shroud (up the tool)
    if (hub) {
      const double span = (ax.d1 - ax.d2).norm();
      // The channel is the side of the hub the shroud contact is on (a hub
      // meridian may run either way, flipping radial_offset's sign).
      const double channel = hub->radial_offset(ax.c1) >= 0 ? 1.0 : -1.0;
      const std::optional<double> s = meet_hub_offset(*hub, channel * r, ax.d2, a, span + 4 * r);
      if (!s)
        throw Error("flank_axis: the cutter axis at v = " + short_text(v) +
                    " does not meet the hub offset surface (ball radius " + short_text(r) + " mm)");
      ax.ball_centre = ax.d2 + *s * a;
    } else {
      ax.ball_centre = ax.d2;
    }
    ax.s1 = (ax.d1 - ax.ball_centre).dot(a);
    ax.s2 = (ax.d2 - ax.ball_centre).dot(a);
    if (ax.s1 > cutter.flute_top_mm())
      throw Error("flank_axis: at v = " + short_text(v) + " the shroud contact lies " + short_text(ax.s1) +
                  " mm above the ball centre, above the flutes (" + short_text(cutter.flute_top_mm()) +
                  " mm): use a longer cutter");
    // Below the ball centre the ball meets the hub, not the face: the hub
    // contact uses the ball radius there.
    const double new1 = cutter.radius_at(ax.s1), new2 = cutter.radius_at(std::max(0.0, ax.s2));
    const bool settled = std::abs(new1 - rho1) < 1e-12 && std::abs(new2 - rho2) < 1e-12;
    rho1 = new1;
    rho2 = new2;
    if (settled) break;
  }
  ax.pose.axis = a;
  ax.pose.tip = ax.ball_centre - r * a;
  return ax;
}

std::vector<double> flank_stations(const Surface& face, const StepOptions& steps) {
  std::vector<double> v;
  for (double u : {0.0, 1.0}) {
    const IsoUCurve row(face, u);
    const RowSteps rs = plan_row_steps(row, steps);
    v.insert(v.end(), rs.t.begin(), rs.t.end());
  }
  std::sort(v.begin(), v.end());
  std::vector<double> out;
  for (double x : v)
    if (out.empty() || x - out.back() > 1e-9) out.push_back(x);
  return out;
}

ResidualStats residual_stats(const std::vector<double>& values) {
  ResidualStats s;
  if (values.empty()) return s;
  s.samples = static_cast<int>(values.size());
  s.max_mm = *std::max_element(values.begin(), values.end());
  s.min_mm = *std::min_element(values.begin(), values.end());
  double sum = 0, sum2 = 0;
  for (double x : values) {
    sum += x;
    s.max_abs_mm = std::max(s.max_abs_mm, std::abs(x));
  }
  s.mean_mm = sum / s.samples;
  for (double x : values) sum2 += (x - s.mean_mm) * (x - s.mean_mm);
  s.std_mm = std::sqrt(sum2 / s.samples);
  return s;
}

FlankResidual flank_residual(const Surface& face, const std::vector<FlankAxis>& axes,
                             const FlankCutter& cutter, int points_per_axis) {
  if (points_per_axis < 2) throw ParameterError("points", "expected at least 2 points along each axis");
  FlankResidual out;
  out.axes = static_cast<int>(axes.size());
  out.points = points_per_axis;
  out.residual_mm.reserve(axes.size() * points_per_axis);
  ProjectionOptions opts;
  opts.tol_mm = 1e-10;
  for (const FlankAxis& ax : axes) {
    // From the hub contact's axis point, or the ball centre where that lies
    // above it (below the centre the ball meets the hub), to D1.
    const double s_lo = std::max(0.0, ax.s2), s_hi = ax.s1;
    std::optional<Eigen::Vector2d> seed;
    for (int k = 0; k < points_per_axis; ++k) {
      const double f = static_cast<double>(k) / (points_per_axis - 1);
      const double s = s_lo + (s_hi - s_lo) * f;
      const Vec3 p = ax.ball_centre + s * ax.pose.axis;
      // The foot lies near the same ruling: seed Newton there.
      opts.seed = seed ? seed : std::optional<Eigen::Vector2d>(Eigen::Vector2d(f, ax.v));
      const SurfaceProjection foot = project_to_surface(face, p, opts);  // eq. 33–35
      if (!foot.ok)
        throw Error("flank_residual: no foot on the face for the axis point at v = " + short_text(ax.v) +
                    ", height " + short_text(s) + " mm: " + foot.failure);
      seed = Eigen::Vector2d(foot.u, foot.v);
      // Signed by the face normal: an axis point behind the face (deep gouge)
      // counts its distance negative.
      const double side = (p - foot.point).dot(face_normal(face.eval(foot.u, foot.v))) < 0 ? -1.0 : 1.0;
      out.residual_mm.push_back(side * foot.distance - cutter.radius_at(s));  // eq. 36
      out.height_mm.push_back(s);
      out.foot.push_back(foot.point);
    }
  }
  out.stats = residual_stats(out.residual_mm);
  return out;
}

}  // namespace bliskrun

namespace bliskrun {

namespace {

// The axis turned by `angle` about the hub contact normal through the ball
// centre; the ball centre and the axis heights stay.
FlankAxis tilted(const FlankAxis& ax, double angle_rad, double ball_radius) {
  FlankAxis t = ax;
  const Vec3 a = Eigen::AngleAxisd(angle_rad, ax.n2) * ax.pose.axis;
  t.pose.axis = a.normalized();
  t.pose.tip = ax.ball_centre - ball_radius * t.pose.axis;
  t.d1 = ax.ball_centre + ax.s1 * t.pose.axis;
  t.d2 = ax.ball_centre + ax.s2 * t.pose.axis;
  return t;
}

// The axis moved along the mean face normal to centre its residual band;
// with a hub, the ball then slides along the moved axis back onto the hub
// offset (the shift has a part along the hub normal on a leaning blade,
// which would press the ball a few um into the hub or lift it off).
FlankAxis balanced(const Surface& face, const FlankAxis& ax, const FlankCutter& cutter, int points,
                   const SurfaceOfRevolution* hub) {
  const ResidualStats st = flank_residual(face, {ax}, cutter, points).stats;
  const Vec3 m = (ax.n1 + ax.n2).normalized();
  const Vec3 shift = -0.5 * (st.max_mm + st.min_mm) * m;
  FlankAxis b = ax;
  b.pose.tip += shift;
  b.ball_centre += shift;
  b.d1 += shift;
  b.d2 += shift;
  if (hub) {
    const double r = cutter.ball_radius_mm();
    const Vec3 a = b.pose.axis;
    const double channel = hub->radial_offset(ax.ball_centre) >= 0 ? 1.0 : -1.0;
    if (const std::optional<double> s = meet_hub_offset(*hub, channel * r, b.ball_centre, a, 4 * r)) {
      b.ball_centre += *s * a;
      b.pose.tip += *s * a;
      b.s1 = (b.d1 - b.ball_centre).dot(a);
      b.s2 = (b.d2 - b.ball_centre).dot(a);
    }
  }
  return b;
}

// --- Axis fit (optimise_flank_axis) -----------------------------------------

// One trial axis of the fit: the line, its ball centre and the heights
// between which the residual is sampled.
struct FlankFitLine {
  bool ok = false;
  Vec3 centre = Vec3::Zero(), a = Vec3::UnitZ();
  double s_lo = 0, s_hi = 0;
  Vec3 point(int k, int n) const { return centre + height(k, n) * a; }
  double height(int k, int n) const { return s_lo + (s_hi - s_lo) * k / (n - 1); }
};

// The fit's unknowns x -> axis (see the header): x0, x1 move the mid point
// M of the start axis across it (e1 along the mean face normal, e2 = a0 x
// e1); x2, x3 turn it (as mm at half the span L: the tangent of the turn is
// x / L, saturated at tan(max correction) so the bound is hard); x4, without
// a hub and with a tapered cutter, slides the cutter along its axis.
class FlankFitModel {
 public:
  FlankFitModel(const Surface& face, const FlankAxis& start, const SurfaceOfRevolution* hub,
                const FlankCutter& cutter, const FlankFitOptions& o)
      : face_(face), start_(start), hub_(hub), cutter_(cutter), o_(o) {
    a0_ = start.pose.axis.normalized();
    Vec3 m = start.n1 + start.n2;
    m -= m.dot(a0_) * a0_;
    if (m.norm() < 1e-9) m = a0_.unitOrthogonal();
    e1_ = m.normalized();
    e2_ = a0_.cross(e1_);
    mid_ = 0.5 * (start.d1 + start.d2);
    half_ = std::max(1.0, 0.5 * (start.d1 - start.d2).norm());
    h_mid_ = (mid_ - start.ball_centre).dot(a0_);
    // A cylinder's slide along its axis changes nothing: no fifth unknown.
    slide_ = !hub && std::abs(cutter.radius_at(0) - cutter.radius_at(std::max(1.0, start.s1))) > 1e-9;
    tan_cap_ = std::tan(std::max(0.0, o.max_axis_correction_rad));
    if (hub_) {
      // The hub offset near the start's ball centre as its tangent plane:
      // trial lines move the centre by tens of um, where the plane is off
      // the offset surface by (tens of um)^2 / 2R, nothing against the
      // residual (the centre's height only moves rho(s) by sin(beta) times
      // it). The taken line meets the true offset (exact_centre); the
      // meridian projections of radial_offset were 90 % of the fit's time.
      channel_ = hub_->radial_offset(start.c1) >= 0 ? 1.0 : -1.0;
      hub_normal_ = hub_normal(*hub_, start.ball_centre);
      hub_gap_ = channel_ * hub_->radial_offset(start.ball_centre) - cutter.ball_radius_mm();
    }
  }
  // The taken line's ball centre on the true hub offset.
  std::optional<Vec3> exact_centre(const FlankFitLine& l) const {
    if (!hub_) return l.centre;
    const std::optional<double> s =
        meet_hub_offset(*hub_, channel_ * cutter_.ball_radius_mm(), l.centre, l.a, 4 * cutter_.ball_radius_mm());
    if (!s) return std::nullopt;
    return Vec3(l.centre + *s * l.a);
  }
  int unknowns() const { return slide_ ? 5 : 4; }

  FlankFitLine line(const Eigen::VectorXd& x) const {
    FlankFitLine l;
    const Vec3 m = mid_ + x[0] * e1_ + x[1] * e2_;
    Eigen::Vector2d t(x[2] / half_, x[3] / half_);
    const double tn = t.norm();
    if (tn > 0) t *= (tan_cap_ > 0 ? tan_cap_ * std::tanh(tn / tan_cap_) : 0.0) / tn;
    l.a = (a0_ + t[0] * e1_ + t[1] * e2_).normalized();
    if (hub_) {
      const double along = hub_normal_.dot(l.a);
      if (std::abs(along) < 1e-6) return l;  // the axis along the hub: no meeting
      l.centre = m + ((-hub_gap_ - hub_normal_.dot(m - start_.ball_centre)) / along) * l.a;
    } else {
      l.centre = m - h_mid_ * l.a + (slide_ ? x[4] : 0.0) * l.a;
    }
    l.s_hi = (start_.d1 - l.centre).dot(l.a);
    l.s_lo = std::max(0.0, (start_.d2 - l.centre).dot(l.a));
    l.ok = l.s_hi > l.s_lo;
    return l;
  }

  // Residuals of eq. 36 at the fit's points, and the gradient of each's
  // distance to the face (the unit normal at its foot, envelope theorem).
  // The same, remembered for the last x: Levenberg–Marquardt asks for the
  // Jacobian at the point it has just evaluated.
  bool residuals_at(const Eigen::VectorXd& x, FlankFitLine& l, std::vector<double>& r, std::vector<Vec3>& g) {
    if (cache_ok_ && x.size() == cache_x_.size() && x == cache_x_) {
      l = cache_line_;
      r = cache_r_;
      g = cache_g_;
      return true;
    }
    l = line(x);
    if (!l.ok || !residuals(l, r, g)) return false;
    cache_ok_ = true;
    cache_x_ = x;
    cache_line_ = l;
    cache_r_ = r;
    cache_g_ = g;
    return true;
  }
  bool residuals(const FlankFitLine& l, std::vector<double>& r, std::vector<Vec3>& g) {
    const int n = o_.points;
    r.resize(n);
    g.resize(n);
    seeds_.resize(n);
    ProjectionOptions po;
    po.tol_mm = 1e-10;
    for (int k = 0; k < n; ++k) {
      const double s = l.height(k, n);
      const Vec3 p = l.centre + s * l.a;
      po.seed = seeds_[k] ? seeds_[k] : std::optional<Eigen::Vector2d>(
                                            Eigen::Vector2d(static_cast<double>(k) / (n - 1), start_.v));
      const SurfaceProjection f = project_to_surface(face_, p, po);
      if (!f.ok) return false;
      seeds_[k] = Eigen::Vector2d(f.u, f.v);
      const Vec3 nf = face_normal(face_.eval(f.u, f.v));
      const Vec3 d = p - f.point;
      const double side = d.dot(nf) < 0 ? -1.0 : 1.0;
      r[k] = side * f.distance - cutter_.radius_at(s);
      g[k] = f.distance > 1e-9 ? Vec3(side * d / f.distance) : nf;
    }
    ++evaluations;
    return true;
  }
  // The weighted error the fit minimises: overcut counts overcut_weight times.
  double weighted(double r) const { return r < 0 ? o_.overcut_weight * r : r; }

  int evaluations = 0;

 private:
  const Surface& face_;
  const FlankAxis& start_;
  const SurfaceOfRevolution* hub_;
  const FlankCutter& cutter_;
  FlankFitOptions o_;
  Vec3 a0_, e1_, e2_, mid_;
  double half_ = 1, h_mid_ = 0, tan_cap_ = 0, channel_ = 1, hub_gap_ = 0;
  Vec3 hub_normal_ = Vec3::UnitZ();
  bool slide_ = false;
  std::vector<std::optional<Eigen::Vector2d>> seeds_;
  bool cache_ok_ = false;
  Eigen::VectorXd cache_x_;
  FlankFitLine cache_line_;
  std::vector<double> cache_r_;
  std::vector<Vec3> cache_g_;
};

// Eigen's Levenberg–Marquardt functor: sqrt(weight_k) * weighted(r_k).
struct FlankFitFunctor {
  using Scalar = double;
  FlankFitModel* model;
  const std::vector<double>* weights;
  int n_points;
  int values() const { return n_points; }
  int inputs() const { return model->unknowns(); }
  // Out of reach (no hub meeting, no foot): a large constant error, so the
  // step is rejected and LM shrinks it.
  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
    FlankFitLine l;
    f.resize(n_points);
    std::vector<double> r;
    std::vector<Vec3> g;
    if (!model->residuals_at(x, l, r, g)) {
      f.setConstant(1e3);
      return 0;
    }
    for (int k = 0; k < n_points; ++k) f[k] = std::sqrt((*weights)[k]) * model->weighted(r[k]);
    return 0;
  }
  int df(const Eigen::VectorXd& x, Eigen::MatrixXd& J) const {
    const int m = inputs();
    J.setZero(n_points, m);
    FlankFitLine l;
    std::vector<double> r;
    std::vector<Vec3> g;
    if (!model->residuals_at(x, l, r, g)) return 0;
    // d r_k / dx_j = g_k . dP_k/dx_j - d rho(s_k)/dx_j, the axis points
    // differenced (no projection: the foot's motion is second order).
    constexpr double h = 1e-5;
    for (int j = 0; j < m; ++j) {
      Eigen::VectorXd xh = x;
      xh[j] += h;
      const FlankFitLine lh = model->line(xh);
      if (!lh.ok) continue;
      for (int k = 0; k < n_points; ++k) {
        const double s = l.height(k, n_points), sh = lh.height(k, n_points);
        const double dr = g[k].dot(lh.point(k, n_points) - l.point(k, n_points)) / h -
                          (model_radius(sh) - model_radius(s)) / h;
        J(k, j) = std::sqrt((*weights)[k]) * (r[k] < 0 ? overcut_weight : 1.0) * dr;
      }
    }
    return 0;
  }
  double model_radius(double s) const { return cutter->radius_at(s); }
  const FlankCutter* cutter;
  double overcut_weight = 1;
};

FlankAxis flank_axis_from_line(const FlankAxis& start, const FlankFitLine& l, double r) {
  FlankAxis ax = start;
  ax.pose.axis = l.a;
  ax.ball_centre = l.centre;
  ax.pose.tip = l.centre - r * l.a;
  // D1, D2: the axis points nearest the start's (the paper's offsets of the
  // contacts, moved with the axis).
  ax.s1 = (start.d1 - l.centre).dot(l.a);
  ax.s2 = (start.d2 - l.centre).dot(l.a);
  ax.d1 = l.centre + ax.s1 * l.a;
  ax.d2 = l.centre + ax.s2 * l.a;
  return ax;
}

double flank_fit_score(const ResidualStats& s, double overcut_weight) {
  return std::max(s.max_mm, -overcut_weight * s.min_mm);
}

}  // namespace

double root_corner_material(const FlankAxis& axis, const FlankCutter& cutter) {
  const Vec3 a = axis.pose.axis.normalized();
  const Vec3 d = axis.c2 - (axis.pose.tip + cutter.grown_by_mm() * a);
  const double along = d.dot(a);
  return cutter.tool().signed_distance(Vec3((d - along * a).norm(), 0, along));
}


FlankAxisFit optimise_flank_axis(const Surface& face, const FlankAxis& start, const SurfaceOfRevolution* hub,
                                 const FlankCutter& cutter, const FlankFitOptions& options) {
  if (options.points < 3) throw ParameterError("fit points", "expected at least 3 points along the axis");
  if (!(options.overcut_weight >= 1)) throw ParameterError("overcut_weight", "expected a weight >= 1");
  FlankAxisFit fit;
  fit.axis = start;
  fit.before = flank_residual(face, {start}, cutter, options.check_points).stats;
  fit.after = fit.before;
  // Nothing to gain (a developable face's two-contact axis is exact).
  if (flank_fit_score(fit.before, options.overcut_weight) < 1e-7) return fit;
  FlankFitModel model(face, start, hub, cutter, options);
  const int n = options.points, m = model.unknowns();
  std::vector<double> weights(n, 1.0);
  FlankFitFunctor functor{&model, &weights, n, &cutter, options.overcut_weight};
  Eigen::VectorXd x = Eigen::VectorXd::Zero(m), best_x = x;
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> r;
  std::vector<Vec3> g;
  int stalls = 0;
  for (int round = 0; round <= options.minimax_rounds; ++round) {
    Eigen::LevenbergMarquardt<FlankFitFunctor> lm(functor);
    // Parameters are mm of axis motion: 1e-7 of relative change is far
    // below the residual's um; each reweighted round starts where the last
    // ended, so a few steps suffice.
    lm.parameters.maxfev = round == 0 ? 40 : 15;
    lm.parameters.xtol = 1e-7;
    lm.parameters.ftol = 1e-8;
    lm.minimize(x);
    FlankFitLine l;
    if (!model.residuals_at(x, l, r, g)) break;
    double worst = 0, sum = 0;
    for (double v : r) worst = std::max(worst, std::abs(model.weighted(v)));
    // Lawson's rounds converge slowly once the band is nearly levelled:
    // stop when a round gains less than 1 % twice running.
    if (worst < best) {
      stalls = worst > 0.99 * best ? stalls + 1 : 0;
      best = worst;
      best_x = x;
    } else {
      ++stalls;
    }
    if (stalls >= 2) break;
    // Lawson: each weight grows with its point's error, renormalised; a
    // floor keeps every point in play.
    for (int k = 0; k < n; ++k) {
      weights[k] *= std::max(std::abs(model.weighted(r[k])), 1e-3 * worst);
      sum += weights[k];
    }
    if (!(sum > 0)) break;
    for (double& w : weights) w *= n / sum;
  }
  fit.evaluations = model.evaluations;
  FlankFitLine l = model.line(best_x);
  if (!l.ok) return fit;
  const std::optional<Vec3> centre = model.exact_centre(l);
  if (!centre) return fit;
  l.centre = *centre;
  const FlankAxis cand = flank_axis_from_line(start, l, cutter.ball_radius_mm());
  const ResidualStats after = flank_residual(face, {cand}, cutter, options.check_points).stats;
  // Taken only for a real gain (0.1 nm): an exact start (a developable
  // face) keeps its axis bit for bit, and so do the programs posted from it.
  if (flank_fit_score(after, options.overcut_weight) < flank_fit_score(fit.before, options.overcut_weight) - 1e-7) {
    fit.axis = cand;
    fit.after = after;
    fit.improved = true;
    fit.correction_rad = std::acos(std::clamp(cand.pose.axis.dot(start.pose.axis.normalized()), -1.0, 1.0));
  }
  return fit;
}

FlankFacePlan plan_flank_face(const FlankFaceRequest& rq) {
  if (!rq.face) throw ParameterError("face", "expected a face to machine");
  if (!rq.cutter) throw ParameterError("tool", "expected a cutter");
  if (rq.world && !rq.body) throw ParameterError("world", "a collision world needs the tool body");
  if (!(rq.tilt_step_rad > 0) || rq.max_tilt_rad < 0)
    throw ParameterError("tilt_step", "expected a positive tilt step and a max tilt >= 0");
  FlankFacePlan plan;
  const std::vector<double> stations = flank_stations(*rq.face, rq.steps);
  plan.stations = static_cast<int>(stations.size());
  plan.min_margin_mm = std::numeric_limits<double>::infinity();
  const double r = rq.cutter->ball_radius_mm();
  const Surface& design = rq.design ? *rq.design : *rq.face;
  std::vector<FlankAxis> unbalanced, before;
  for (double v : stations) {
    FlankAxis ax;
    try {
      ax = flank_axis(*rq.face, v, rq.hub, *rq.cutter);
    } catch (const Error& e) {
      plan.refusals.push_back({v, e.what()});
      continue;
    }
    // The fit of the untilted pose (from the balanced axis when balancing).
    std::optional<FlankAxisFit> fitted;
    auto fit_of = [&](const FlankAxis& from) {
      if (!rq.optimise) return;
      FlankFitOptions fo = rq.fit;
      fo.check_points = rq.residual_points;
      try {
        FlankAxisFit f = optimise_flank_axis(design, from, rq.hub, *rq.cutter, fo);
        if (f.improved) fitted = std::move(f);
      } catch (const Error&) {
        // No foot for a trial point: the unfitted axis stands (it is proved
        // and measured as before).
      }
    };
    if (!rq.world) {
      unbalanced.push_back(ax);
      if (rq.balance_residual) {
        ax = balanced(design, ax, *rq.cutter, rq.residual_points, rq.hub);
        ++plan.balanced;
      }
      before.push_back(ax);
      fit_of(ax);
      plan.correction_rad.push_back(fitted ? fitted->correction_rad : 0.0);
      if (fitted) {
        ax = fitted->axis;
        ++plan.optimised;
      }
      plan.axes.push_back(ax);
      plan.tilt_rad.push_back(0);
      continue;
    }
    // Tilts in the order 0, +step, -step, +2 step, ...
    std::string why;
    bool done = false;
    const int n = static_cast<int>(std::floor(rq.max_tilt_rad / rq.tilt_step_rad + 1e-9));
    for (int i = 0; i <= 2 * n && !done; ++i) {
      const double angle = (i == 0 ? 0.0 : ((i + 1) / 2) * rq.tilt_step_rad * (i % 2 ? 1.0 : -1.0));
      const FlankAxis plain = angle == 0 ? ax : tilted(ax, angle, r);
      std::vector<FlankAxis> tries;
      if (rq.balance_residual) tries.push_back(balanced(design, plain, *rq.cutter, rq.residual_points, rq.hub));
      tries.push_back(plain);
      // Untilted: the fitted pose first (its start is tries[0]).
      int fit_index = -1;
      if (i == 0) {
        fit_of(tries.front());
        if (fitted) {
          tries.insert(tries.begin(), fitted->axis);
          fit_index = 0;
        }
      }
      for (size_t k = 0; k < tries.size() && !done; ++k) {
        const FlankAxis& cand = tries[k];
        const PoseCheck pc = rq.world->check(*rq.body, cand.pose, rq.clearances, 0.0);
        if (!pc.clear) {
          if (i == 0) why = "pose: " + describe(pc, *rq.world);
          continue;
        }
        if (!plan.axes.empty()) {
          const MotionCheck mc = rq.world->check_motion(*rq.body, plan.axes.back().pose, cand.pose,
                                                        rq.clearances, rq.motion_tol_mm);
          if (!mc.clear) {
            why = "motion from the previous pose: " + describe(mc.at, *rq.world) +
                  (mc.undecided ? " (undecided)" : "");
            continue;
          }
        }
        plan.axes.push_back(cand);
        unbalanced.push_back(plain);
        const bool is_fit = static_cast<int>(k) == fit_index;
        before.push_back(is_fit ? tries[1] : cand);
        plan.correction_rad.push_back(is_fit ? fitted->correction_rad : 0.0);
        if (is_fit) ++plan.optimised;
        plan.tilt_rad.push_back(angle);
        if (angle != 0) ++plan.tilted;
        // Balanced: the balanced axis itself, or the fit started from it.
        if (rq.balance_residual && static_cast<int>(k) <= fit_index + 1) ++plan.balanced;
        done = true;
      }
    }
    if (!done)
      plan.refusals.push_back({v, why + "; no tilt up to " + std::to_string(rad_to_deg(rq.max_tilt_rad)) +
                                      " deg clears it"});
  }
  if (plan.axes.empty()) {
    plan.min_margin_mm = 0;
    return plan;
  }
  if (rq.world) {
    for (const FlankAxis& a : plan.axes)
      plan.min_margin_mm =
          std::min(plan.min_margin_mm, rq.world->check(*rq.body, a.pose, rq.clearances, kMarginHorizonMm).min_margin_mm);
    LinkChecks checks;
    checks.world = rq.world;
    checks.body = rq.body;
    checks.clearances = rq.clearances;
    checks.motion_tol_mm = rq.motion_tol_mm;
    if (rq.world) checks.traverse_world = rq.world->unchecked_pairs();  // the face being machined, for the cutter
    const double r = rq.cutter->ball_radius_mm();
    auto end_normal = [&](const FlankAxis& a) {
      // Out of the material at mid-span of the ruling, and off the hub: a
      // leaning blade's normal points partly into the hub, and the ball that
      // rides the hub would follow it in (found by simulating the job:
      // 0.5 mm deep at the built-in impeller's splitter). Its part into the
      // hub is dropped and the lead rises at kLeadRiseRad over the hub, more
      // than a concave meridian's sag over the lead's length.
      const SurfaceDerivs d = rq.face->eval(0.5, a.v);
      Vec3 n = d.pu.cross(d.pv).normalized();
      if (!rq.hub) return n;
      const Vec3 up = hub_normal(*rq.hub, a.ball_centre);
      n -= std::min(0.0, n.dot(up)) * up;
      const Vec3 along = (n - n.dot(up) * up).normalized();
      return Vec3((along + std::tan(kLeadRiseRad) * up).normalized());
    };
    // The collision world holds the hub for the shank and holder only (the
    // ball rides it): the ball's own clearance of the hub over a lead is
    // proved here, its centre at least r from the hub all along.
    auto prove_off_hub = [&](PlannedDeparture& lead, const FlankAxis& a) {
      if (!rq.hub || !lead.clear) return;
      const double channel = rq.hub->radial_offset(a.ball_centre) >= 0 ? 1.0 : -1.0;
      const Vec3 from = a.ball_centre, to = lead.away.tip + r * lead.away.axis.normalized();
      const int n = std::max(2, static_cast<int>(std::ceil((to - from).norm() / 0.05)));
      double deepest = 0;
      for (int k = 1; k <= n; ++k)
        deepest = std::min(deepest, channel * rq.hub->radial_offset(from + (to - from) * (double(k) / n)) - r);
      if (deepest < -kHubToleranceMm) {
        lead.clear = false;
        lead.reason = "the ball would dip " + short_text(-deepest) + " mm into the hub";
      }
    };
    plan.lead_in = plan_departure({plan.axes.front().pose, end_normal(plan.axes.front())}, checks, rq.lead);
    plan.lead_out = plan_departure({plan.axes.back().pose, end_normal(plan.axes.back())}, checks, rq.lead);
    prove_off_hub(plan.lead_in, plan.axes.front());
    prove_off_hub(plan.lead_out, plan.axes.back());
    // The leads are motions the tool makes beside the neighbours too: the
    // built-in splitter's lead-out passed 0.81 mm from one while the poses
    // alone reported 2.99 mm.
    plan.pose_min_margin_mm = plan.min_margin_mm;
    plan.lead_min_margin_mm = std::numeric_limits<double>::infinity();
    for (const auto& [lead, at] : {std::pair{&plan.lead_in, &plan.axes.front()}, std::pair{&plan.lead_out, &plan.axes.back()}})
      if (lead->clear)
        plan.lead_min_margin_mm = std::min(
            plan.lead_min_margin_mm, rq.world->motion_min_margin(*rq.body, at->pose, lead->away, rq.clearances, kLeadMarginTolMm));
    plan.min_margin_mm = std::min(plan.pose_min_margin_mm, plan.lead_min_margin_mm);
  } else {
    plan.min_margin_mm = 0;
    plan.lead_min_margin_mm = std::numeric_limits<double>::infinity();
  }
  if (rq.hub) {
    for (const FlankAxis& a : plan.axes) plan.root_corner_mm.push_back(root_corner_material(a, *rq.cutter));
    plan.root_corner = residual_stats(plan.root_corner_mm);
  }
  plan.residual = flank_residual(design, plan.axes, *rq.cutter, rq.residual_points);
  plan.residual_before = plan.optimised > 0 ? flank_residual(design, before, *rq.cutter, rq.residual_points).stats
                                            : plan.residual.stats;
  plan.residual_unbalanced = !rq.balance_residual ? plan.residual_before
                             : flank_residual(design, unbalanced, *rq.cutter, rq.residual_points).stats;
  return plan;
}

std::string flank_face_apt(const FlankFacePlan& plan, const std::string& part_name,
                           const std::string& tool_description) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(6);
  s << "PARTNO/" << part_name << "\n";
  s << "$$ bliskrun flank milling (impeller paper 4.3): tip x,y,z and unit axis i,j,k per pose\n";
  s << "$$ tool: " << tool_description << "\n";
  s << "$$ poses " << plan.axes.size() << ", refused " << plan.refusals.size() << ", tilted " << plan.tilted
    << "\n";
  auto go = [&](const ToolPose& p) {
    s << "GOTO/" << p.tip.x() << "," << p.tip.y() << "," << p.tip.z() << "," << p.axis.x() << ","
      << p.axis.y() << "," << p.axis.z() << "\n";
  };
  if (plan.lead_in.clear) {
    s << "RAPID\n";
    go(plan.lead_in.away);
  }
  for (const FlankAxis& a : plan.axes) go(a.pose);
  if (plan.lead_out.clear) go(plan.lead_out.away);
  s << "END\n";
  return s.str();
}

}  // namespace bliskrun
