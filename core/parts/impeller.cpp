#include "core/parts/impeller.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "core/common/error.h"
#include "core/common/fixed_text.h"
#include "core/geometry/interpolation.h"
#include "core/geometry/reparametrised.h"

namespace bliskrun {

namespace {

void require(bool ok, const std::string& name, const std::string& expected) {
  if (!ok) throw ParameterError(name, "expected " + expected);
}

void check_camber_list(const std::vector<CamberPoint>& pts, const std::string& name) {
  require(pts.size() >= 4, name, "at least 4 camber points, got " + std::to_string(pts.size()));
  for (size_t i = 0; i < pts.size(); ++i) {
    const CamberPoint& c = pts[i];
    require(c.p.allFinite() && std::isfinite(c.half_thickness_mm), name,
            "finite (x, y, z, h) at point " + std::to_string(i));
    require(c.half_thickness_mm > 0, name,
            "half thickness h > 0 at point " + std::to_string(i) + ", got " +
                short_text(c.half_thickness_mm));
    if (i > 0)
      require((c.p - pts[i - 1].p).norm() > 1e-9, name,
              "distinct consecutive points, points " + std::to_string(i - 1) + " and " +
                  std::to_string(i) + " coincide");
  }
}

struct CurveWithThickness {
  BSplineCurve curve, h;  // h as (h, 0, 0) at the curve's own parameters
};

std::vector<Vec3> points_of(const std::vector<CamberPoint>& pts) {
  std::vector<Vec3> xyz;
  for (const CamberPoint& c : pts) xyz.push_back(c.p);
  return xyz;
}

CurveWithThickness interpolate_camber(const std::vector<CamberPoint>& pts, const std::vector<double>& t) {
  std::vector<Vec3> hh;
  for (const CamberPoint& c : pts) hh.emplace_back(c.half_thickness_mm, 0.0, 0.0);
  return {interpolate_cubic(points_of(pts), t), interpolate_cubic(hh, t)};
}

// Eq. 11 in the SPEC orientation: u along the span, v along the chord.
class FaceSurface : public Surface {
 public:
  FaceSurface(RuledBlade blade, CamberSide side) : blade_(std::move(blade)), side_(side) {}

  SurfaceDerivs eval(double u, double v) const override {
    const double t = RuledBlade::chord_t(side_, v);
    const double dt_dv = side_ == CamberSide::kPlus ? -1.0 : 1.0;
    const RuledBlade::OffsetPoint a = blade_.hub_offset(t, side_);
    const RuledBlade::OffsetPoint b = blade_.shroud_offset(t, side_);
    // Second derivative along the chord: central difference of the analytic
    // tangents (one-sided at the ends of the domain).
    constexpr double kStep = 1e-5;
    const double t0 = std::max(0.0, t - kStep), t1 = std::min(1.0, t + kStep);
    const RuledBlade::OffsetPoint a0 = blade_.hub_offset(t0, side_);
    const RuledBlade::OffsetPoint a1 = blade_.hub_offset(t1, side_);
    const RuledBlade::OffsetPoint b0 = blade_.shroud_offset(t0, side_);
    const RuledBlade::OffsetPoint b1 = blade_.shroud_offset(t1, side_);
    const Vec3 att = (a1.dt - a0.dt) / (t1 - t0), btt = (b1.dt - b0.dt) / (t1 - t0);

    SurfaceDerivs d;
    d.p = a.p + (b.p - a.p) * u;
    d.pu = b.p - a.p;
    d.pv = (a.dt + (b.dt - a.dt) * u) * dt_dv;
    d.puu = Vec3::Zero();
    d.puv = (b.dt - a.dt) * dt_dv;
    d.pvv = att + (btt - att) * u;
    return d;
  }

 private:
  RuledBlade blade_;
  CamberSide side_;
};

}  // namespace

RuledBlade::RuledBlade(const BladeCamber& camber, const std::string& name) {
  check_camber_list(camber.shroud, name + ".shroud");
  check_camber_list(camber.hub, name + ".hub");
  // Pairing rule: hub point i and shroud point i lie on one ruling (the
  // paper joins "corresponding points", eq. 4), so the lists must be equally
  // long. Both curves take the average of the two lists' chord-length
  // parameters (eq. 3), as the grid kernel does across rows (eq. 4 of the
  // blisk paper), which puts data point i of each on the ruling t = t_i.
  // Lists of different lengths state no pairing: joining points at equal
  // chord fractions instead moved a face by 0.95 mm in an independent check
  // when 5 of 23 hub points were dropped, so they are refused.
  require(camber.hub.size() == camber.shroud.size(), name + ".hub",
          "as many points as " + name + ".shroud (" + std::to_string(camber.shroud.size()) +
              "): hub point i and shroud point i lie on one ruling; got " +
              std::to_string(camber.hub.size()));
  std::vector<double> ts = chord_length_parameters(points_of(camber.shroud));
  std::vector<double> th = chord_length_parameters(points_of(camber.hub));
  for (size_t i = 0; i < ts.size(); ++i) ts[i] = th[i] = 0.5 * (ts[i] + th[i]);
  CurveWithThickness s = interpolate_camber(camber.shroud, ts);
  CurveWithThickness h = interpolate_camber(camber.hub, th);
  shroud_ = std::move(s.curve);
  h_shroud_ = std::move(s.h);
  hub_ = std::move(h.curve);
  h_hub_ = std::move(h.h);
  // Eq. 5–8 need the rulings to cross the curves: a ruling along the
  // tangent gives no normal.
  for (int i = 0; i <= 64; ++i) {
    const double t = i / 64.0;
    const Vec3 d = shroud_.point(t) - hub_.point(t);
    for (const CurveDerivs& c : {shroud_.eval(t), hub_.eval(t)})
      require(c.dt.cross(d).norm() > 1e-9 * c.dt.norm() * std::max(d.norm(), 1e-12), name,
              "hub and shroud curves apart and not tangent to the rulings (t = " + short_text(t) + ")");
  }
}

Vec2 RuledBlade::shroud_half_thickness(double t) const {
  const CurveDerivs d = h_shroud_.eval(t);
  return {d.p.x(), d.dt.x()};
}

Vec2 RuledBlade::hub_half_thickness(double t) const {
  const CurveDerivs d = h_hub_.eval(t);
  return {d.p.x(), d.dt.x()};
}

Vec3 RuledBlade::camber_point(double t, double s) const {
  const Vec3 h = hub_.point(t);
  return h + (shroud_.point(t) - h) * s;
}

Vec3 RuledBlade::camber_normal(double t, bool at_shroud) const {
  const Vec3 d = shroud_.point(t) - hub_.point(t);
  const Vec3 tangent = at_shroud ? shroud_.eval(t).dt : hub_.eval(t).dt;
  return tangent.cross(d).normalized();
}

RuledBlade::OffsetPoint RuledBlade::offset(double t, CamberSide side, bool at_shroud) const {
  const CurveDerivs s = shroud_.eval(t), h = hub_.eval(t);
  const CurveDerivs& c = at_shroud ? s : h;
  const Vec3 d = s.p - h.p, d_t = s.dt - h.dt;
  const Vec3 n_raw = c.dt.cross(d);                            // eq. 5–6
  const Vec3 n_raw_t = c.dtt.cross(d) + c.dt.cross(d_t);       // full eq. 19–20
  const double len = n_raw.norm();
  const Vec3 n = n_raw / len;                                  // eq. 7–8
  const Vec3 n_t = n_raw_t / len - n_raw * (n_raw.dot(n_raw_t) / (len * len * len));  // eq. 17–18
  const Vec2 hh = at_shroud ? shroud_half_thickness(t) : hub_half_thickness(t);
  const double sign = side == CamberSide::kPlus ? 1.0 : -1.0;
  OffsetPoint o;
  o.p = c.p + sign * hh.x() * n;                               // eq. 9–10
  o.dt = c.dt + sign * (hh.y() * n + hh.x() * n_t);            // eq. 15–16
  return o;
}

RuledBlade::OffsetPoint RuledBlade::shroud_offset(double t, CamberSide side) const {
  return offset(t, side, true);
}

RuledBlade::OffsetPoint RuledBlade::hub_offset(double t, CamberSide side) const {
  return offset(t, side, false);
}

std::shared_ptr<const Surface> RuledBlade::face(CamberSide side) const {
  return std::make_shared<FaceSurface>(*this, side);
}

void validate(const ImpellerDefinition& d) {
  require(d.blade_count >= 2 && d.blade_count <= 200, "blades", "an integer in [2, 200]");
  require(d.splitter_offset_pitch > 0 && d.splitter_offset_pitch < 1, "splitter_offset",
          "a fraction of the pitch in (0, 1)");
  require(std::isfinite(d.hub_extension_mm) && d.hub_extension_mm >= 0, "hub_extension",
          "a length >= 0");
}

namespace {

// (z, r) of the main blade's hub curve from TE to LE (outlet -> inlet), so
// that SurfaceOfRevolution::radial_offset is > 0 on the channel side, with
// straight extensions along the end tangents.
std::vector<Vec2> hub_meridian_of(const RuledBlade& blade, double extension_mm) {
  constexpr int kSamples = 64;
  std::vector<Vec2> zr;
  auto at = [&](double t) {
    const Vec3 p = blade.hub_curve(t).p;
    return Vec2(p.z(), std::hypot(p.x(), p.y()));
  };
  // Unit (z, r) direction leaving the curve at its end `t` (0 or 1).
  auto outward = [&](double t) {
    const Vec2 d = at(t) - at(t == 0.0 ? 1e-6 : 1.0 - 1e-6);
    return Vec2(d / d.norm());
  };
  if (extension_mm > 0)
    for (double f : {1.0, 0.5}) zr.push_back(at(1.0) + outward(1.0) * (extension_mm * f));
  for (int i = kSamples; i >= 0; --i) zr.push_back(at(static_cast<double>(i) / kSamples));
  if (extension_mm > 0)
    for (double f : {0.5, 1.0}) zr.push_back(at(0.0) + outward(0.0) * (extension_mm * f));
  return zr;
}

// The hub's profile evaluated from the hub curve itself: (z, r, 0) of the
// main blade's hub camber curve, TE -> LE, between straight extensions of
// `extension_mm` along its end tangents. An interpolant through samples of
// it missed it by 2-4 um near the LE and ~11 um at the extensions' joints
// (the flank ball then sat 8.6 um inside the hub). Parameter tau in [0, 1]:
// [0, a] the TE extension, [a, 1 - b] the curve (t = 1 -> 0), [1 - b, 1]
// the LE extension, with a, b chosen so the speed |d(z, r)/dtau| is the
// same on both sides of each joint (the profile is C1 in tau there).
class HubProfile : public Curve {
 public:
  HubProfile(RuledBlade blade, double extension_mm) : blade_(std::move(blade)), e_(extension_mm) {
    const CurveDerivs te = zr(1.0), le = zr(0.0);
    const double l_te = te.dt.norm(), l_le = le.dt.norm();
    c_ = 1.0 / (1.0 + e_ * (1.0 / l_te + 1.0 / l_le));
    a_ = e_ * c_ / l_te;
    b_ = e_ * c_ / l_le;
    te_ = te.p;
    le_ = le.p;
    te_out_ = te.dt / l_te;   // t increases towards the TE
    le_out_ = -le.dt / l_le;
  }

  CurveDerivs eval(double tau) const override {
    tau = std::clamp(tau, 0.0, 1.0);
    CurveDerivs d;
    if (e_ > 0 && tau < a_) {
      d.p = te_ + te_out_ * (e_ * (1 - tau / a_));
      d.dt = -te_out_ * (e_ / a_);
      d.dtt = Vec3::Zero();
    } else if (e_ > 0 && tau > 1 - b_) {
      d.p = le_ + le_out_ * (e_ * (tau - (1 - b_)) / b_);
      d.dt = le_out_ * (e_ / b_);
      d.dtt = Vec3::Zero();
    } else {
      const CurveDerivs m = zr(std::clamp(1 - (tau - a_) / c_, 0.0, 1.0));
      d.p = m.p;
      d.dt = -m.dt / c_;
      d.dtt = m.dtt / (c_ * c_);
    }
    return d;
  }

  // The curve as (z, r, 0) against its own t, with exact derivatives of
  // r = |(x, y)|.
  CurveDerivs zr(double t) const {
    const CurveDerivs h = blade_.hub_curve(t);
    const double x = h.p.x(), y = h.p.y(), r = std::hypot(x, y);
    const double xx = x * h.dt.x() + y * h.dt.y();  // r r'
    const double r_t = xx / r;
    const double r_tt = (h.dt.x() * h.dt.x() + h.dt.y() * h.dt.y() + x * h.dtt.x() + y * h.dtt.y()) / r -
                        xx * xx / (r * r * r);
    CurveDerivs d;
    d.p = Vec3(h.p.z(), r, 0);
    d.dt = Vec3(h.dt.z(), r_t, 0);
    d.dtt = Vec3(h.dtt.z(), r_tt, 0);
    return d;
  }

 private:
  RuledBlade blade_;
  double e_, a_ = 0, b_ = 0, c_ = 1;
  Vec3 te_, le_, te_out_, le_out_;
};

}  // namespace

Impeller::Impeller(ImpellerDefinition definition)
    : def_((validate(definition), std::move(definition))), main_(def_.main, "main") {
  if (def_.splitter) splitter_.emplace(*def_.splitter, "splitter");
  hub_meridian_ = hub_meridian_of(main_, def_.hub_extension_mm);
  hub_ = std::make_shared<SurfaceOfRevolution>(
      std::make_shared<const HubProfile>(main_, def_.hub_extension_mm),
      static_cast<int>(hub_meridian_.size()));
}

const RuledBlade& Impeller::blade(BladeKind kind) const {
  if (kind == BladeKind::kSplitter) {
    if (!splitter_) throw Error("this impeller has no splitter blades");
    return *splitter_;
  }
  return main_;
}

double Impeller::blade_angle_rad(BladeKind kind, int k) const {
  const double offset = kind == BladeKind::kSplitter ? def_.splitter_offset_pitch : 0.0;
  return 2 * kPi * (k + offset) / def_.blade_count;
}

std::shared_ptr<const Surface> Impeller::face(BladeKind kind, int k, CamberSide side) const {
  if (k < 0 || k >= def_.blade_count)
    throw ParameterError("blade", "expected an index in [0, " + std::to_string(def_.blade_count - 1) +
                                      "], got " + std::to_string(k));
  return std::make_shared<RotatedSurface>(blade(kind).face(side), blade_angle_rad(kind, k));
}

double Impeller::outer_radius_mm() const {
  double r = 0;
  for (const RuledBlade* b : {&main_, splitter_ ? &*splitter_ : nullptr}) {
    if (!b) continue;
    for (int i = 0; i <= 400; ++i)
      for (CamberSide side : {CamberSide::kPlus, CamberSide::kMinus})
        for (const RuledBlade::OffsetPoint& o :
             {b->hub_offset(i / 400.0, side), b->shroud_offset(i / 400.0, side)})
          r = std::max(r, std::hypot(o.p.x(), o.p.y()));
  }
  return r;
}

// ---------------------------------------------------------------------------
// Built-in impeller.

void validate(const BuiltinImpellerParams& p) {
  require(p.blade_count >= 2 && p.blade_count <= 200, "blades", "an integer in [2, 200]");
  require(p.splitter_start > 0 && p.splitter_start < 0.9, "splitter_start",
          "a fraction of the meridional length in (0, 0.9)");
  require(p.outlet_radius_mm > 0, "outlet_radius", "a positive radius");
  require(p.outlet_width_mm > 0, "outlet_width", "a positive length");
  require(p.inlet_z_mm > p.outlet_width_mm, "inlet_z",
          "an inlet plane above the outlet width (" + short_text(p.outlet_width_mm) + " mm)");
  require(p.hub_inlet_radius_mm > 0, "hub_inlet_radius", "a positive radius");
  require(p.shroud_inlet_radius_mm > p.hub_inlet_radius_mm &&
              p.shroud_inlet_radius_mm < p.outlet_radius_mm,
          "shroud_inlet_radius", "a radius between hub_inlet_radius and outlet_radius");
  for (auto [name, b] : {std::pair{"beta_inlet", p.beta_inlet_rad},
                         std::pair{"beta_outlet", p.beta_outlet_rad}})
    require(std::isfinite(b) && std::abs(b) < deg_to_rad(75), name, "an angle in (-75, 75) degrees");
  for (auto [name, h] : {std::pair{"half_thickness_le", p.half_thickness_le_mm},
                         std::pair{"half_thickness_te", p.half_thickness_te_mm},
                         std::pair{"half_thickness_max_hub", p.half_thickness_max_hub_mm},
                         std::pair{"half_thickness_max_shroud", p.half_thickness_max_shroud_mm}})
    require(std::isfinite(h) && h > 0 && h < 20, name, "a half thickness in (0, 20) mm");
  require(p.camber_points >= 6 && p.camber_points <= 1000, "camber_points",
          "an integer in [6, 1000]");
}

namespace {

// One meridian curve (quarter ellipse from the inlet to the outlet) with the
// wrap angle integrated along it, sampled finely.
struct MeridianWrap {
  std::vector<double> s;            // normalised meridional length, 0 .. 1
  std::vector<double> z, r, theta;
};

MeridianWrap wrap_along(double r_in, double z_in, double r_out, double z_out, double beta_in,
                        double beta_out) {
  constexpr int kSteps = 4000;
  MeridianWrap w;
  auto zr = [&](double phi) {
    return Vec2(z_out + (z_in - z_out) * (1 - std::sin(phi)),
                r_in + (r_out - r_in) * (1 - std::cos(phi)));
  };
  std::vector<double> m(1, 0.0);
  for (int i = 1; i <= kSteps; ++i)
    m.push_back(m.back() + (zr(0.5 * kPi * i / kSteps) - zr(0.5 * kPi * (i - 1) / kSteps)).norm());
  double theta = 0;
  for (int i = 0; i <= kSteps; ++i) {
    const Vec2 p = zr(0.5 * kPi * i / kSteps);
    const double s = m[i] / m.back();
    if (i > 0) {
      // Trapezoid on dtheta/dm = -tan(beta)/r.
      const Vec2 q = zr(0.5 * kPi * (i - 1) / kSteps);
      const double s0 = m[i - 1] / m.back();
      auto slope = [&](double ss, double r) {
        return -std::tan(beta_in + (beta_out - beta_in) * ss) / r;
      };
      theta += 0.5 * (slope(s0, q.y()) + slope(s, p.y())) * (m[i] - m[i - 1]);
    }
    w.s.push_back(s);
    w.z.push_back(p.x());
    w.r.push_back(p.y());
    w.theta.push_back(theta);
  }
  return w;
}

Vec3 wrap_point(const MeridianWrap& w, double s) {
  const auto it = std::lower_bound(w.s.begin(), w.s.end(), s);
  const size_t i = std::clamp<size_t>(it - w.s.begin(), 1, w.s.size() - 1);
  const double f = (s - w.s[i - 1]) / (w.s[i] - w.s[i - 1]);
  auto lerp = [&](const std::vector<double>& x) { return x[i - 1] + (x[i] - x[i - 1]) * f; };
  const double r = lerp(w.r), th = lerp(w.theta);
  return {r * std::cos(th), r * std::sin(th), lerp(w.z)};
}

BladeCamber camber_between(const MeridianWrap& hub, const MeridianWrap& shroud,
                           const BuiltinImpellerParams& p, double s0) {
  BladeCamber c;
  for (int i = 0; i < p.camber_points; ++i) {
    // Cosine spacing: design data crowd near the edges.
    const double f = 0.5 * (1 - std::cos(kPi * i / (p.camber_points - 1)));
    const double s = s0 + (1 - s0) * f;
    auto h = [&](double h_max) {
      const double sn = std::sin(kPi * s);
      return p.half_thickness_le_mm + (p.half_thickness_te_mm - p.half_thickness_le_mm) * s +
             (h_max - 0.5 * (p.half_thickness_le_mm + p.half_thickness_te_mm)) * sn * sn;
    };
    c.hub.push_back({wrap_point(hub, s), h(p.half_thickness_max_hub_mm)});
    c.shroud.push_back({wrap_point(shroud, s), h(p.half_thickness_max_shroud_mm)});
  }
  return c;
}

}  // namespace

ImpellerDefinition builtin_impeller_definition(const BuiltinImpellerParams& p) {
  validate(p);
  const MeridianWrap shroud =
      wrap_along(p.shroud_inlet_radius_mm, p.inlet_z_mm, p.outlet_radius_mm, p.outlet_width_mm,
                 p.beta_inlet_rad, p.beta_outlet_rad);
  // The hub at the same meridional fractions, with the shroud's wrap: the
  // rulings lie in meridional planes (beta only feeds the shroud's theta).
  MeridianWrap hub = wrap_along(p.hub_inlet_radius_mm, p.inlet_z_mm, p.outlet_radius_mm, 0.0, 0.0, 0.0);
  for (size_t i = 0; i < hub.s.size(); ++i) {
    const auto it = std::lower_bound(shroud.s.begin(), shroud.s.end(), hub.s[i]);
    const size_t k = std::clamp<size_t>(it - shroud.s.begin(), 1, shroud.s.size() - 1);
    const double f = (hub.s[i] - shroud.s[k - 1]) / (shroud.s[k] - shroud.s[k - 1]);
    hub.theta[i] = shroud.theta[k - 1] + (shroud.theta[k] - shroud.theta[k - 1]) * f;
  }
  ImpellerDefinition d;
  d.blade_count = p.blade_count;
  d.main = camber_between(hub, shroud, p, 0.0);
  if (p.splitters) d.splitter = camber_between(hub, shroud, p, p.splitter_start);
  return d;
}

}  // namespace bliskrun
