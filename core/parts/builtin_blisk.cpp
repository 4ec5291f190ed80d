#include "core/parts/builtin_blisk.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/common/error.h"
#include "core/common/fixed_text.h"
#include "core/common/progress.h"

namespace bliskrun {

namespace {

void require(bool ok, const char* name, const std::string& expected) {
  if (!ok) throw ParameterError(name, "expected " + expected);
}

double lerp(double a, double b, double w) { return a + (b - a) * w; }

// Central-difference derivatives of a point function on (u, v). The step is
// small enough for the truncation error and large enough for round-off at
// coordinates of ~100 mm (relative accuracy ~1e-7 for second derivatives).
template <class F>
SurfaceDerivs finite_difference_derivs(const F& f, double u, double v) {
  constexpr double h = 1e-4;
  SurfaceDerivs d;
  d.p = f(u, v);
  const Vec3 pu_p = f(u + h, v), pu_m = f(u - h, v);
  const Vec3 pv_p = f(u, v + h), pv_m = f(u, v - h);
  d.pu = (pu_p - pu_m) / (2 * h);
  d.pv = (pv_p - pv_m) / (2 * h);
  d.puu = (pu_p - 2 * d.p + pu_m) / (h * h);
  d.pvv = (pv_p - 2 * d.p + pv_m) / (h * h);
  d.puv = (f(u + h, v + h) - f(u + h, v - h) - f(u - h, v + h) + f(u - h, v - h)) / (4 * h * h);
  return d;
}

Vec3 rotate_z(const Vec3& p, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return Vec3(c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z());
}

}  // namespace

void validate(const BliskParams& p) {
  require(p.blade_count >= 2 && p.blade_count <= 400, "blade_count", "an integer in [2, 400]");
  require(std::isfinite(p.z_inlet_mm) && std::isfinite(p.z_outlet_mm) &&
              p.z_outlet_mm > p.z_inlet_mm,
          "z_outlet", "an axial position above z_inlet");
  require(p.hub_radius_inlet_mm > 0, "hub_radius_inlet", "a positive radius");
  require(p.hub_radius_outlet_mm > 0, "hub_radius_outlet", "a positive radius");
  require(p.casing_radius_inlet_mm > p.hub_radius_inlet_mm, "casing_radius_inlet",
          "a radius above hub_radius_inlet (" + short_text(p.hub_radius_inlet_mm) + ")");
  require(p.casing_radius_outlet_mm > p.hub_radius_outlet_mm, "casing_radius_outlet",
          "a radius above hub_radius_outlet (" + short_text(p.hub_radius_outlet_mm) + ")");
  require(p.chord_mm > 0, "chord", "a positive length");
  const double half_axial = 0.5 * p.chord_mm + p.le_radius_mm + p.te_radius_mm;
  require(-half_axial > p.z_inlet_mm && half_axial < p.z_outlet_mm, "chord",
          "a blade (centred at z = 0) inside [z_inlet, z_outlet]");
  for (auto [name, a] : {std::pair{"stagger_hub", p.stagger_hub_rad},
                         std::pair{"stagger_tip", p.stagger_tip_rad}})
    require(std::abs(a) < deg_to_rad(80), name, "an angle within (-80, 80) degrees");
  for (auto [name, a] : {std::pair{"camber_hub", p.camber_hub_rad},
                         std::pair{"camber_tip", p.camber_tip_rad}})
    require(a > deg_to_rad(0.5) && a < deg_to_rad(120), name,
            "a camber angle in (0.5, 120) degrees");
  require(p.le_radius_mm > 0, "le_radius", "a positive radius");
  require(p.te_radius_mm > 0, "te_radius", "a positive radius");
  for (auto [name, t] : {std::pair{"max_thickness_hub", p.max_thickness_hub_mm},
                         std::pair{"max_thickness_tip", p.max_thickness_tip_mm}}) {
    require(t > 2 * std::max(p.le_radius_mm, p.te_radius_mm), name,
            "a thickness above the edge diameters (2 * max(le_radius, te_radius))");
    require(t < 0.3 * p.chord_mm, name, "a thickness below 30% of the chord");
  }
  require(p.le_radius_mm + p.te_radius_mm < 0.25 * p.chord_mm, "le_radius",
          "edge radii summing to less than a quarter of the chord");
  require(p.grid_rows >= 4, "grid_rows", "at least 4 rows");
  require(p.grid_cols >= 4, "grid_cols", "at least 4 columns");
  require(p.span_extension_mm >= 0 && std::isfinite(p.span_extension_mm), "span_extension",
          "a length >= 0");
  require(std::min(p.hub_radius_inlet_mm, p.hub_radius_outlet_mm) - p.span_extension_mm >
              0.5 * p.chord_mm,
          "span_extension", "the grid's lowest radius to stay above half the chord");
}

BuiltinBlisk::BuiltinBlisk(const BliskParams& params) : params_(params) {
  validate(params_);
  r_lo_ = std::min(params_.hub_radius_inlet_mm, params_.hub_radius_outlet_mm) -
          params_.span_extension_mm;
  r_hi_ = std::max(params_.casing_radius_inlet_mm, params_.casing_radius_outlet_mm) +
          params_.span_extension_mm;
}

double BuiltinBlisk::hub_radius_at(double z) const {
  const BliskParams& p = params_;
  return lerp(p.hub_radius_inlet_mm, p.hub_radius_outlet_mm,
              (z - p.z_inlet_mm) / (p.z_outlet_mm - p.z_inlet_mm));
}

double BuiltinBlisk::casing_radius_at(double z) const {
  const BliskParams& p = params_;
  return lerp(p.casing_radius_inlet_mm, p.casing_radius_outlet_mm,
              (z - p.z_inlet_mm) / (p.z_outlet_mm - p.z_inlet_mm));
}

std::vector<Vec2> BuiltinBlisk::hub_meridian() const {
  const BliskParams& p = params_;
  return {Vec2(p.z_inlet_mm, p.hub_radius_inlet_mm), Vec2(p.z_outlet_mm, p.hub_radius_outlet_mm)};
}

std::vector<Vec2> BuiltinBlisk::casing_meridian() const {
  const BliskParams& p = params_;
  return {Vec2(p.z_inlet_mm, p.casing_radius_inlet_mm),
          Vec2(p.z_outlet_mm, p.casing_radius_outlet_mm)};
}

// The section of blade 0 at radius r in the unrolled (z, s = r theta) plane,
// see the header for the construction: the camber arc (radius R, angle phi
// from -camber/2 at the LE to +camber/2 at the TE, chord along local x centred
// at 0, bulging towards +y), the half thickness, the stagger.
struct BuiltinBlisk::Section {
  double R = 0, camber = 0, arc = 0, stagger = 0, t_max = 0, r_le = 0, r_te = 0;

  Section(const BliskParams& p, double r) {
    const double r_hub = 0.5 * (p.hub_radius_inlet_mm + p.hub_radius_outlet_mm);
    const double r_tip = 0.5 * (p.casing_radius_inlet_mm + p.casing_radius_outlet_mm);
    const double w = (r - r_hub) / (r_tip - r_hub);
    stagger = lerp(p.stagger_hub_rad, p.stagger_tip_rad, w);
    camber = lerp(p.camber_hub_rad, p.camber_tip_rad, w);
    t_max = lerp(p.max_thickness_hub_mm, p.max_thickness_tip_mm, w);
    R = p.chord_mm / (2 * std::sin(0.5 * camber));
    arc = R * camber;
    r_le = p.le_radius_mm;
    r_te = p.te_radius_mm;
  }
  // Camber point at arc length a from the LE end, its unit normal n (towards
  // +y, the suction side) and unit tangent d (LE -> TE).
  void camber_at(double a, Vec2& c, Vec2& n, Vec2& d) const {
    const double phi = -0.5 * camber + a / R;
    n = Vec2(std::sin(phi), std::cos(phi));
    d = Vec2(std::cos(phi), -std::sin(phi));
    c = Vec2(R * n.x(), R * n.y() - R * std::cos(0.5 * camber));
  }
  // Flank point at chord fraction t (0 at the LE circle's tangent point, 1 at
  // the TE circle's).
  Vec2 flank(FlankSide side, double t) const {
    Vec2 c, n, d;
    camber_at(r_le + t * (arc - r_le - r_te), c, n, d);
    const double smooth = t * t * (3 - 2 * t);
    const double bump = std::sin(kPi * t);
    const double h = r_le * (1 - smooth) + r_te * smooth + (0.5 * t_max - 0.5 * (r_le + r_te)) * bump * bump;
    return c + (side == FlankSide::kSuction ? h : -h) * n;
  }
  // Stagger in the unrolled plane, then wrap on the cylinder of radius r.
  Vec3 wrap(const Vec2& q, double r) const {
    const double cg = std::cos(stagger), sg = std::sin(stagger);
    const double z = q.x() * cg - q.y() * sg;
    const double s = q.x() * sg + q.y() * cg;
    return Vec3(r * std::cos(s / r), r * std::sin(s / r), z);
  }
};

Vec3 BuiltinBlisk::flank_point(FlankSide side, double r, double t) const {
  const Section s(params_, r);
  return s.wrap(s.flank(side, t), r);
}

std::vector<Vec3> BuiltinBlisk::section_loop(int blade, double r, int points_per_flank) const {
  if (blade < 0 || blade >= blade_count())
    throw ParameterError("blade", "expected an index in [0, " + std::to_string(blade_count() - 1) +
                                      "], got " + std::to_string(blade));
  if (!(r > 0.5 * params_.chord_mm && std::isfinite(r)))
    throw ParameterError("radius", "expected a radius above half the chord, got " + short_text(r));
  if (points_per_flank < 8) throw ParameterError("points", "expected at least 8 per flank");
  const Section s(params_, r);
  const double angle = 2 * kPi * blade / blade_count();
  // Points per edge half circle: about the flanks' spacing, at least 8.
  const double spacing = s.arc / points_per_flank;
  const int le_n = std::max(8, static_cast<int>(std::ceil(kPi * s.r_le / spacing)));
  const int te_n = std::max(8, static_cast<int>(std::ceil(kPi * s.r_te / spacing)));
  std::vector<Vec2> loop;
  Vec2 c, n, d;
  // Pressure flank LE -> TE, TE half circle, suction flank TE -> LE, LE half circle.
  for (int i = 0; i < points_per_flank; ++i) loop.push_back(s.flank(FlankSide::kPressure, static_cast<double>(i) / points_per_flank));
  s.camber_at(s.arc - s.r_te, c, n, d);
  for (int i = 0; i < te_n; ++i) {
    const double psi = kPi * i / te_n;  // from the pressure side (-n) through +d to the suction side (+n)
    loop.push_back(c + s.r_te * (-std::cos(psi) * n + std::sin(psi) * d));
  }
  for (int i = 0; i < points_per_flank; ++i) loop.push_back(s.flank(FlankSide::kSuction, 1 - static_cast<double>(i) / points_per_flank));
  s.camber_at(s.r_le, c, n, d);
  for (int i = 0; i < le_n; ++i) {
    const double psi = kPi * i / le_n;  // from the suction side (+n) through -d to the pressure side (-n)
    loop.push_back(c + s.r_le * (std::cos(psi) * n - std::sin(psi) * d));
  }
  std::vector<Vec3> out;
  out.reserve(loop.size());
  for (const Vec2& q : loop) out.push_back(rotate_z(s.wrap(q, r), angle));
  return out;
}

class FlankSurface : public Surface {
 public:
  FlankSurface(const BuiltinBlisk& blisk, int blade, FlankSide side)
      : blisk_(blisk.params()), side_(side),
        angle_(2 * kPi * blade / blisk.blade_count()) {}

  Vec3 at(double u, double v) const {
    const double r = blisk_.grid_radius_min_mm() +
                     u * (blisk_.grid_radius_max_mm() - blisk_.grid_radius_min_mm());
    const double t = side_ == FlankSide::kSuction ? 1 - v : v;
    return rotate_z(blisk_.flank_point(side_, r, t), angle_);
  }

  SurfaceDerivs eval(double u, double v) const override {
    return finite_difference_derivs([this](double a, double b) { return at(a, b); }, u, v);
  }

 private:
  BuiltinBlisk blisk_;  // a copy: the surface may outlive the caller's blisk
  FlankSide side_;
  double angle_;
};

std::shared_ptr<const Surface> BuiltinBlisk::flank_surface(int blade, FlankSide side) const {
  if (blade < 0 || blade >= blade_count())
    throw ParameterError("blade", "expected an index in [0, " + std::to_string(blade_count() - 1) +
                                      "], got " + std::to_string(blade));
  return std::make_shared<FlankSurface>(*this, blade, side);
}

PointGrid BuiltinBlisk::flank_grid(int blade, FlankSide side) const {
  const auto surface = flank_surface(blade, side);
  const auto& flank = static_cast<const FlankSurface&>(*surface);
  PointGrid grid(params_.grid_rows, params_.grid_cols);
  for (int i = 0; i < grid.rows; ++i) {
    cancellation_point();
    for (int j = 0; j < grid.cols; ++j)
      grid.at(i, j) = flank.at(static_cast<double>(i) / (grid.rows - 1),
                               static_cast<double>(j) / (grid.cols - 1));
  }
  return grid;
}

double BuiltinBlisk::narrowest_passage_mm() const {
  // The closed-form points: the surfaces' eval adds finite-difference
  // derivatives the search does not need.
  const FlankSurface suction(*this, 0, FlankSide::kSuction);
  const FlankSurface pressure(*this, 1 % blade_count(), FlankSide::kPressure);
  return narrowest_span_passage([&](double u, double v) { return suction.at(u, v); },
                                [&](double u, double v) { return pressure.at(u, v); },
                                [&](double z) { return hub_radius_at(z); },
                                [&](double z) { return casing_radius_at(z); });
}

std::shared_ptr<const SurfaceOfRevolution> BuiltinBlisk::hub() const {
  return std::make_shared<const SurfaceOfRevolution>(hub_meridian());
}

std::shared_ptr<const SurfaceOfRevolution> BuiltinBlisk::casing() const {
  return std::make_shared<const SurfaceOfRevolution>(casing_meridian());
}

std::string BuiltinBlisk::description() const {
  const BliskParams& p = params_;
  std::ostringstream s;
  s << "bliskrun.Blisk(" << p.blade_count << " blades, hub r " << p.hub_radius_inlet_mm << "->"
    << p.hub_radius_outlet_mm << " mm, casing r " << p.casing_radius_inlet_mm << "->"
    << p.casing_radius_outlet_mm << " mm, chord " << p.chord_mm << " mm, grid " << p.grid_rows
    << "x" << p.grid_cols << ")";
  return s.str();
}

}  // namespace bliskrun
