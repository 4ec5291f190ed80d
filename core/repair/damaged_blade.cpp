#include "core/repair/damaged_blade.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <random>
#include <sstream>

#include "core/common/atomic_file.h"
#include "core/common/error.h"
#include "core/common/fixed_text.h"
#include "core/common/progress.h"
#include "core/geometry/closed_curve.h"
#include "core/io/data_lines.h"
#include "core/parts/builtin_blisk.h"
#include "core/repair/section_points.h"

namespace bliskrun {

namespace {

// Crossing number of the closed polygon.
bool inside_section_polygon(const Vec2& p, const std::vector<Vec2>& poly) {
  bool in = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < a.x() + (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y())) in = !in;
  }
  return in;
}

Vec3 centroid(const std::vector<Vec3>& loop) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : loop) c += p;
  return c / static_cast<double>(loop.size());
}

}  // namespace

BladeFrame blade_frame(const Vec3& origin, const Vec3& axis) {
  if (!(axis.norm() > 1e-12) || !axis.allFinite()) throw ParameterError("axis", "expected a non-zero stacking axis");
  BladeFrame f;
  f.origin = origin;
  f.axis = axis.normalized();
  Vec3 e1 = Vec3::UnitZ() - Vec3::UnitZ().dot(f.axis) * f.axis;
  if (e1.norm() < 1e-6) e1 = Vec3::UnitX() - Vec3::UnitX().dot(f.axis) * f.axis;
  f.e1 = e1.normalized();
  f.e2 = f.axis.cross(f.e1);
  return f;
}

DesignBlade design_blade(const std::vector<std::vector<Vec3>>& loops, int samples) {
  if (loops.size() < 2) throw ParameterError("loops", "a blade needs at least 2 section loops");
  const Vec3 first = centroid(loops.front()), last = centroid(loops.back());
  DesignBlade d;
  d.frame = blade_frame(first, last - first);
  const std::vector<OrientedSection> oriented = orient_sections(loops, d.frame.axis);
  std::vector<ClosedCurve> curves;
  for (const OrientedSection& o : oriented) curves.push_back(interpolate_closed_cubic(o.loop));
  SectionLoftOptions lo;
  lo.samples = samples;
  d.loft = loft_sections(curves, lo);
  // Every plane between the highest point of the first row and the lowest of
  // the last cuts each v line once (the loft rises along u).
  const PointGrid& g = d.loft.grid;
  d.h_lo = -1e300;
  d.h_hi = 1e300;
  for (int j = 0; j < g.cols; ++j) {
    d.h_lo = std::max(d.h_lo, d.frame.height(g.at(0, j)));
    d.h_hi = std::min(d.h_hi, d.frame.height(g.at(g.rows - 1, j)));
  }
  const double margin = 1e-3 * (d.h_hi - d.h_lo);
  d.h_lo += margin;
  d.h_hi -= margin;
  if (!(d.h_hi > d.h_lo))
    throw ParameterError("loops", "the sections do not stack along the axis from the first centroid to the last");
  return d;
}

DesignBlade builtin_design_blade(const BuiltinBlisk& blisk, int blade, int sections) {
  if (sections < 4) throw ParameterError("sections", "expected at least 4 design sections");
  std::vector<std::vector<Vec3>> loops;
  for (int k = 0; k < sections; ++k) {
    const double r = blisk.grid_radius_min_mm() +
                     (blisk.grid_radius_max_mm() - blisk.grid_radius_min_mm()) * k / (sections - 1);
    loops.push_back(blisk.section_loop(blade, r, 300));
  }
  return design_blade(loops);
}

DesignBlade design_blade(const BladeSections& blade, int samples) { return design_blade(blade.sections, samples); }

namespace {

std::vector<Vec2> section_of_loft(const SectionLoft& loft, const BladeFrame& frame, double h, int samples, bool clamp) {
  if (samples < 16) throw ParameterError("samples", "expected at least 16 points per plane section");
  std::vector<Vec2> out(samples);
  for (int j = 0; j < samples; ++j) {
    const double v = static_cast<double>(j) / samples;
    double lo = 0, hi = 1;
    double g_lo = frame.height(loft.surface.point(lo, v)) - h;
    const double g_hi = frame.height(loft.surface.point(hi, v)) - h;
    if (g_lo > 0 || g_hi < 0) {
      if (!clamp)
        throw ParameterError("height", "the plane at height " + short_text(h) + " mm does not cut the blade all round (v = " +
                                           short_text(v) + ")");
      out[j] = frame.in_plane(loft.surface.point(g_lo > 0 ? 0.0 : 1.0, v));
      continue;
    }
    // Newton on u, kept inside the bracket (bisection where it leaves it).
    double u = g_lo / (g_lo - g_hi);
    SurfaceDerivs d;
    for (int it = 0; it < 60; ++it) {
      d = loft.surface.eval(u, v);
      const double g = frame.height(d.p) - h;
      if (std::abs(g) < 1e-11) break;
      if (g < 0) {
        lo = u;
        g_lo = g;
      } else {
        hi = u;
      }
      const double slope = d.pu.dot(frame.axis);
      double next = slope > 0 ? u - g / slope : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      u = next;
    }
    out[j] = frame.in_plane(d.p);
  }
  return out;
}

}  // namespace

std::vector<Vec2> plane_section(const SectionLoft& loft, const BladeFrame& frame, double h, int samples) {
  return section_of_loft(loft, frame, h, samples, false);
}

std::vector<Vec2> clamped_plane_section(const SectionLoft& loft, const BladeFrame& frame, double h, int samples) {
  return section_of_loft(loft, frame, h, samples, true);
}

DamagedBlade::DamagedBlade(DesignBlade design, const BladeDamage& d) : design_(std::move(design)), damage_(d) {
  auto fraction = [](double x, const char* name) {
    if (!(x >= 0 && x <= 1)) throw ParameterError(name, "expected a span fraction in [0, 1], got " + short_text(x));
  };
  fraction(d.deform_from, "deform_from");
  if (d.deform_from >= 1) throw ParameterError("deform_from", "expected a span below 1");
  if (!std::isfinite(d.twist_rad) || std::abs(d.twist_rad) > deg_to_rad(20))
    throw ParameterError("twist", "expected a twist within +-20 degrees");
  if (!std::isfinite(d.bend_mm) || std::abs(d.bend_mm) > 0.2 * (design_.h_hi - design_.h_lo))
    throw ParameterError("bend", "expected a bend within a fifth of the blade height");
  if (d.tip) {
    fraction(d.tip_span, "tip_span");
    if (!(std::abs(d.tip_tilt_rad) < deg_to_rad(45))) throw ParameterError("tip_tilt", "expected a tilt within +-45 degrees");
  }
  if (d.edge) {
    fraction(d.edge_from, "edge_from");
    fraction(d.edge_to, "edge_to");
    if (!(d.edge_to > d.edge_from)) throw ParameterError("edge_to", "expected a span above edge_from");
    if (!(d.edge_depth_mm > 0 && std::isfinite(d.edge_depth_mm)))
      throw ParameterError("edge_depth", "expected a positive depth, mm");
  }
  if (d.te_edge) {
    fraction(d.te_from, "te_from");
    fraction(d.te_to, "te_to");
    if (!(d.te_to > d.te_from)) throw ParameterError("te_to", "expected a span above te_from");
    if (!(d.te_depth_mm > 0 && std::isfinite(d.te_depth_mm))) throw ParameterError("te_depth", "expected a positive depth, mm");
  }
  if (d.dent) {
    fraction(d.dent_span, "dent_span");
    if (!(d.dent_chord > 0 && d.dent_chord < 1)) throw ParameterError("dent_chord", "expected a chord fraction in (0, 1)");
    if (d.dent_side != 1 && d.dent_side != -1) throw ParameterError("dent_side", "expected 1 (+e2) or -1 (-e2)");
    if (!(d.dent_radius_mm > 0 && std::isfinite(d.dent_radius_mm)))
      throw ParameterError("dent_radius", "expected a positive radius, mm");
    if (!(d.dent_depth_mm > 0 && d.dent_depth_mm < d.dent_radius_mm))
      throw ParameterError("dent_depth", "expected a depth > 0 and below the dent's radius, mm");
    // The flank point: where the line x = X crosses the deformed section on
    // the chosen side; the centre R - depth out along its outward normal.
    const double h = design_.span_height(d.dent_span);
    const std::vector<Vec2> s = deformed_section(h, 2048);
    double x_lo = 1e300, x_hi = -1e300, twice = 0;
    for (size_t j = 0; j < s.size(); ++j) {
      x_lo = std::min(x_lo, s[j].x());
      x_hi = std::max(x_hi, s[j].x());
      const Vec2& q = s[(j + 1) % s.size()];
      twice += s[j].x() * q.y() - s[j].y() * q.x();
    }
    const double x = x_lo + d.dent_chord * (x_hi - x_lo);
    double best_y = d.dent_side > 0 ? -1e300 : 1e300;
    Vec2 at = Vec2::Zero(), tangent = Vec2::Zero();
    for (size_t j = 0; j < s.size(); ++j) {
      const Vec2& a = s[j];
      const Vec2& b = s[(j + 1) % s.size()];
      if ((a.x() - x) * (b.x() - x) > 0 || a.x() == b.x()) continue;
      const Vec2 p = a + (b - a) * ((x - a.x()) / (b.x() - a.x()));
      if (d.dent_side > 0 ? p.y() > best_y : p.y() < best_y) {
        best_y = p.y();
        at = p;
        tangent = (b - a).normalized();
      }
    }
    // Outward: the tangent turned a quarter clockwise on a counter-clockwise loop.
    Vec2 out(tangent.y(), -tangent.x());
    if (twice < 0) out = -out;
    dent_centre_ = design_.frame.point(h, at + (d.dent_radius_mm - d.dent_depth_mm) * out);
  }
}

Vec2 DamagedBlade::deform(double h, const Vec2& xy) const {
  const double s = (h - design_.h_lo) / (design_.h_hi - design_.h_lo);
  const double w = std::clamp((s - damage_.deform_from) / (1 - damage_.deform_from), 0.0, 1.0);
  return rotate(xy, damage_.twist_rad * w * w) + Vec2(0, damage_.bend_mm * w * w);
}

std::vector<Vec2> DamagedBlade::deformed_section(double h, int samples) const {
  std::vector<Vec2> s = plane_section(design_.loft, design_.frame, h, samples);
  for (Vec2& p : s) p = deform(h, p);
  return s;
}

Vec3 DamagedBlade::break_normal() const {
  const BladeFrame& f = design_.frame;
  return std::cos(damage_.tip_tilt_rad) * f.axis + std::sin(damage_.tip_tilt_rad) * f.e1;
}

double DamagedBlade::break_offset() const {
  return break_normal().dot(design_.frame.point(design_.span_height(damage_.tip_span), Vec2::Zero()));
}

bool MissingInPlane::unseen(const Vec2& xy) const {
  if (tip && tip_n.dot(xy) + tip_c > 0) return true;
  if (le_depth >= 0 && (xy - le).dot(le_along) < le_depth) return true;
  if (te_depth >= 0 && (xy - te).dot(te_along) < te_depth) return true;
  return false;
}

MissingInPlane DamagedBlade::missing(double h, const std::vector<Vec2>& section) const {
  MissingInPlane m;
  const BladeFrame& f = design_.frame;
  if (damage_.tip) {
    // n . (origin + h axis + x e1 + y e2) > offset.
    const Vec3 n = break_normal();
    m.tip = true;
    m.tip_n = Vec2(n.dot(f.e1), n.dot(f.e2));
    m.tip_c = n.dot(f.origin) + h * n.dot(f.axis) - break_offset();
  }
  const double s = (h - design_.h_lo) / (design_.h_hi - design_.h_lo);
  const bool le = damage_.edge && s > damage_.edge_from && s < damage_.edge_to;
  const bool te = damage_.te_edge && s > damage_.te_from && s < damage_.te_to;
  if ((le || te) && !section.empty()) {
    const auto [lo, hi] = std::minmax_element(section.begin(), section.end(),
                                              [](const Vec2& a, const Vec2& b) { return a.x() < b.x(); });
    const Vec2 chord = (*hi - *lo).normalized();
    if (le) {
      m.le = *lo;
      m.le_along = chord;
      m.le_depth = damage_.edge_depth_mm * std::sin(kPi * (s - damage_.edge_from) / (damage_.edge_to - damage_.edge_from));
    }
    if (te) {
      m.te = *hi;
      m.te_along = -chord;
      m.te_depth = damage_.te_depth_mm * std::sin(kPi * (s - damage_.te_from) / (damage_.te_to - damage_.te_from));
    }
  }
  if (damage_.dent) {
    const double dh = h - f.height(dent_centre_);
    const double r2 = damage_.dent_radius_mm * damage_.dent_radius_mm - dh * dh;
    if (r2 > 0) {
      m.dent_centre = f.in_plane(dent_centre_);
      m.dent_radius = std::sqrt(r2);
    }
  }
  return m;
}

bool DamagedBlade::removed(double h, const Vec2& xy, const std::vector<Vec2>& section) const {
  return missing(h, section).removed(xy);
}

SectionMeasurement measure_sections(const DamagedBlade& blade, const MeasurementOptions& o) {
  if (o.sections < 2) throw ParameterError("sections", "expected at least 2 measured sections");
  if (!(o.span_from >= 0 && o.span_to <= 1 && o.span_to > o.span_from))
    throw ParameterError("span_from", "expected 0 <= span_from < span_to <= 1");
  if (o.points < 16) throw ParameterError("points", "expected at least 16 points per section");
  if (!(o.noise_mm >= 0 && o.noise_mm < 0.1)) throw ParameterError("noise", "expected a sigma in [0, 0.1) mm");
  if (!(o.outlier_fraction >= 0 && o.outlier_fraction <= 0.1))
    throw ParameterError("outliers", "expected a fraction in [0, 0.1]");
  if (!(o.unseen_arc_mm >= 0 && std::isfinite(o.unseen_arc_mm))) throw ParameterError("unseen_arc", "expected a length >= 0 mm");
  if (o.face_points < 0) throw ParameterError("face_points", "expected a count >= 0");

  const DesignBlade& design = blade.design();
  SectionMeasurement m;
  m.frame = design.frame;
  m.has_frame = true;
  // The plan's top is stated even when a broken tip leaves its sections
  // unmeasured: that is how the rebuild tells a break from the plan's margin.
  m.planned_top_mm = design.span_height(o.span_to);
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> unit(0, 1);
  std::normal_distribution<double> gauss(0, 1);

  for (int k = 0; k < o.sections; ++k) {
    cancellation_point();
    const double s = o.span_from + (o.span_to - o.span_from) * k / (o.sections - 1);
    const double h = design.span_height(s);
    const std::vector<Vec2> section = blade.deformed_section(h, 2048);
    std::vector<Vec3> loop3;
    for (const Vec2& p : section) loop3.emplace_back(p.x(), p.y(), 0);
    const ClosedCurve curve = interpolate_closed_cubic(loop3);
    // The unseen arc: centred where the section reaches furthest along -e2.
    double unseen_t = 0;
    {
      int lowest = 0;
      for (int j = 1; j < static_cast<int>(section.size()); ++j)
        if (section[j].y() < section[lowest].y()) lowest = j;
      unseen_t = curve.t_min() + curve.period() * lowest / section.size();
    }
    MeasuredSection ms;
    ms.index = k + 1;
    ms.height_mm = h;
    const MissingInPlane missing = blade.missing(h, section);
    const double offset = unit(rng);
    for (int i = 0; i < o.points; ++i) {
      const double t = curve.t_min() + (i + offset + 0.5 * (unit(rng) - 0.5)) / o.points * curve.period();
      const double noise = gauss(rng);
      const bool outlier = unit(rng) < o.outlier_fraction;
      const double side = unit(rng) < 0.5 ? -1 : 1;
      const double stray = std::max(10 * o.noise_mm, 0.02) + unit(rng) * 0.3;
      double dt = std::abs(t - unseen_t);
      dt = std::min(dt, curve.period() - dt);
      if (o.unseen_arc_mm > 0 && dt < 0.5 * o.unseen_arc_mm) continue;
      const CurveDerivs c = curve.eval(t);
      const Vec2 at(c.p.x(), c.p.y());
      if (missing.removed(at)) continue;
      const Vec2 normal = Vec2(c.dt.y(), -c.dt.x()).normalized();
      const Vec2 q = at + normal * (outlier ? side * stray : o.noise_mm * noise);
      ms.points.push_back(design.frame.point(h, q));
    }
    if (missing.dent_radius > 0) {
      // The dent's floor: the circle's arcs inside the section, probed at the
      // profile's step (from a random start, jittered a quarter step), noise
      // along the radius; none where the probe finds no surface (unseen).
      const double step = curve.period() / o.points, r = missing.dent_radius;
      const int n = std::max(64, static_cast<int>(std::ceil(2 * kPi * r / (0.05 * step))));
      std::vector<char> inside(n);
      for (int j = 0; j < n; ++j)
        inside[j] = inside_section_polygon(missing.dent_centre + r * Vec2(std::cos(2 * kPi * j / n), std::sin(2 * kPi * j / n)), section);
      const double start = unit(rng) * step;
      for (double arc = start; arc < 2 * kPi * r; arc += step) {
        const double a = (arc + 0.5 * step * (unit(rng) - 0.5)) / r;
        const double noise = gauss(rng);
        const int j = static_cast<int>(std::floor(a / (2 * kPi) * n + n)) % n;
        if (!inside[j]) continue;
        const Vec2 radial(std::cos(a), std::sin(a));
        const Vec2 at = missing.dent_centre + r * radial;
        if (missing.unseen(at)) continue;
        ms.points.push_back(design.frame.point(h, at + radial * (o.noise_mm * noise)));
      }
    }
    if (static_cast<int>(ms.points.size()) * 2 < o.points) continue;  // the probe finds no section here
    std::shuffle(ms.points.begin(), ms.points.end(), rng);
    m.sections.push_back(std::move(ms));
  }

  const BladeDamage& dmg = blade.damage();
  if (dmg.tip && o.face_points > 0) {
    // On the break plane, inside the deformed blade: along the e1 extent of
    // the section at the break's axis point, each point's height where the
    // plane meets that x, then a y inside that height's section.
    const double H = design.span_height(dmg.tip_span);
    const std::vector<Vec2> at_break = blade.deformed_section(std::min(H, design.h_hi), 512);
    double x_lo = 1e300, x_hi = -1e300;
    for (const Vec2& p : at_break) {
      x_lo = std::min(x_lo, p.x());
      x_hi = std::max(x_hi, p.x());
    }
    const Vec3 n = blade.break_normal();
    const double tan_tilt = std::tan(dmg.tip_tilt_rad);
    for (int i = 0; i < o.face_points; ++i) {
      const double x = x_lo + (0.1 + 0.8 * (i + 0.5) / o.face_points) * (x_hi - x_lo);
      const double h = H - tan_tilt * x;
      if (h < design.h_lo || h > design.h_hi) continue;
      const std::vector<Vec2> sec = blade.deformed_section(h, 256);
      // The section's extent in y at this x (its two crossings of the line).
      double y_lo = 1e300, y_hi = -1e300;
      for (size_t j = 0; j < sec.size(); ++j) {
        const Vec2& a = sec[j];
        const Vec2& b = sec[(j + 1) % sec.size()];
        if ((a.x() - x) * (b.x() - x) > 0 || a.x() == b.x()) continue;
        const double y = a.y() + (b.y() - a.y()) * (x - a.x()) / (b.x() - a.x());
        y_lo = std::min(y_lo, y);
        y_hi = std::max(y_hi, y);
      }
      if (!(y_hi > y_lo)) continue;
      const double y = y_lo + (0.15 + 0.7 * unit(rng)) * (y_hi - y_lo);
      m.face.push_back(design.frame.point(h, Vec2(x, y)) + n * (o.noise_mm * gauss(rng)));
    }
  }
  return m;
}

// ---- files ----

SectionMeasurement parse_section_measurement(const std::string& text, const std::string& file) {
  using io_detail::DataLines;
  DataLines lines(text, file);
  SectionMeasurement m;
  double scale = 1;
  enum { kNone, kSection, kFace } block = kNone;
  bool csv = false, first = true;
  std::map<long, size_t> csv_sections;  // section key -> index in m.sections
  bool csv_by_z = false;
  int csv_first_line = 0;
  auto csv_section = [&](long key, double height) -> MeasuredSection& {
    auto it = csv_sections.find(key);
    if (it == csv_sections.end()) {
      it = csv_sections.emplace(key, m.sections.size()).first;
      MeasuredSection s;
      s.index = static_cast<int>(key);
      s.height_mm = height;
      s.line = lines.line();
      m.sections.push_back(s);
    }
    return m.sections[it->second];
  };
  while (!lines.at_end()) {
    const std::string& line = lines.take("a line");
    const size_t hash = line.find('#');
    const std::string body = hash == std::string::npos ? line : line.substr(0, hash);
    std::vector<std::string> f = DataLines::fields(body);
    if (f.empty()) continue;
    if (first) {
      first = false;
      csv = body.find(',') != std::string::npos;
      if (csv) {
        const std::vector<std::string> c = DataLines::fields(body, ',');
        char* end = nullptr;
        std::strtod(c[0].c_str(), &end);
        if (end == c[0].c_str()) continue;  // a header line of column names
      }
    }
    if (csv) {
      const std::vector<double> v = lines.numbers(body, -1, "x,y,z or x,y,z,section", ',');
      if (v.size() != 3 && v.size() != 4)
        lines.fail("expected 3 or 4 comma-separated numbers (x,y,z or x,y,z,section), got " + std::to_string(v.size()));
      if (v.size() == 4 && v[3] != std::floor(v[3])) lines.fail("expected a whole section number in column 4, got " + short_text(v[3]));
      if (csv_first_line == 0) {
        csv_first_line = lines.line();
        csv_by_z = v.size() == 3;
      }
      if (csv_by_z != (v.size() == 3))
        lines.fail("expected " + std::string(csv_by_z ? "3" : "4") + " columns on every line, as on line " +
                   std::to_string(csv_first_line));
      const long key = v.size() == 4 ? static_cast<long>(v[3]) : std::lround(v[2] * 1000);
      csv_section(key, v[2]).points.emplace_back(v[0], v[1], v[2]);
      continue;
    }
    const std::string& key = f[0];
    if (key == "units") {
      if (f.size() != 2 || (f[1] != "mm" && f[1] != "inch")) lines.fail("expected 'units mm' or 'units inch'");
      if (!m.sections.empty() || !m.face.empty() || std::isfinite(m.planned_top_mm))
        lines.fail("expected the units before the first point and the planned top");
      scale = f[1] == "inch" ? 25.4 : 1;
      m.units = "mm";
    } else if (key == "axis") {
      const std::vector<double> v = lines.numbers(body.substr(body.find("axis") + 4), 6, "axis ox oy oz ax ay az");
      const Vec3 axis(v[3], v[4], v[5]);
      if (!(axis.norm() > 1e-12)) lines.fail("expected a non-zero axis direction");
      m.frame = blade_frame(scale * Vec3(v[0], v[1], v[2]), axis);
      m.has_frame = true;
    } else if (key == "section") {
      const std::vector<double> v = lines.numbers(body.substr(body.find("section") + 7), 2, "section <number> <height>");
      if (v[0] != std::floor(v[0]) || v[0] < 1) lines.fail("expected a section number >= 1, got " + short_text(v[0]));
      MeasuredSection s;
      s.index = static_cast<int>(v[0]);
      s.height_mm = scale * v[1];
      s.line = lines.line();
      if (!m.sections.empty() && s.height_mm <= m.sections.back().height_mm)
        lines.fail("expected sections in increasing height, section " + short_text(v[0]) + " at " + short_text(s.height_mm) +
                   " mm is not above the previous one");
      m.sections.push_back(s);
      block = kSection;
    } else if (key == "planned_top") {
      const std::vector<double> v = lines.numbers(body.substr(body.find("planned_top") + 11), 1, "planned_top <height>");
      if (!std::isfinite(m.planned_top_mm)) {
        m.planned_top_mm = scale * v[0];
      } else {
        lines.fail("expected one 'planned_top' line, found a second");
      }
    } else if (key == "face") {
      if (f.size() != 1) lines.fail("expected 'face' alone on its line");
      block = kFace;
    } else {
      const std::vector<double> v = lines.numbers(body, 3, "x y z of a point");
      const Vec3 p = scale * Vec3(v[0], v[1], v[2]);
      if (block == kSection)
        m.sections.back().points.push_back(p);
      else if (block == kFace)
        m.face.push_back(p);
      else
        lines.fail("expected 'section <number> <height>' or 'face' before the first point");
    }
  }
  if (csv && csv_by_z) {
    // Grouped by Z: right only for sections measured at constant Z. A blade
    // stacked along another axis (radially, on a rotor) has its points each
    // at their own Z — thousands of one-point "sections" (issue 43) — so
    // refuse rather than guess the axis.
    size_t small = 0;
    for (const MeasuredSection& s : m.sections) small += s.points.size() < 10;
    if (small > 0)
      throw DataError(file, csv_first_line,
                      "points without a section column are grouped by Z (sections measured at constant Z), but " +
                          std::to_string(small) + " of the " + std::to_string(m.sections.size()) +
                          " Z values have fewer than 10 points: the sections are not at constant Z (a blade not "
                          "stacked along Z?); add a 4th column, x,y,z,section, with each point's section number");
  }
  if (csv) {
    // Heights: mean z of each section (a CMM export measures at constant Z).
    for (MeasuredSection& s : m.sections) {
      double z = 0;
      for (const Vec3& p : s.points) z += p.z();
      s.height_mm = z / s.points.size();
    }
    std::sort(m.sections.begin(), m.sections.end(),
              [](const MeasuredSection& a, const MeasuredSection& b) { return a.height_mm < b.height_mm; });
  }
  if (m.sections.empty()) throw DataError(file, lines.line(), "expected at least one section of points, found none");
  for (const MeasuredSection& s : m.sections)
    if (s.points.empty()) throw DataError(file, lines.line(), "section " + std::to_string(s.index) + " has no point");
  if (!m.has_frame) m.frame = blade_frame(Vec3::Zero(), Vec3::UnitZ());
  m.file = file;
  return m;
}

SectionMeasurement read_section_measurement(const std::string& path) {
  return parse_section_measurement(io_detail::read_text_file(path), path);
}

std::string format_section_measurement(const SectionMeasurement& m) {
  std::ostringstream s;
  s << std::setprecision(17);
  s << "# bliskrun section measurement: 'section <number> <height>' then 'x y z' per point; 'face' then\n"
       "# points on a broken tip's fracture face. Heights along the axis from its origin.\n";
  s << "units mm\n";
  if (m.has_frame) {
    const Vec3& o = m.frame.origin;
    const Vec3& a = m.frame.axis;
    s << "axis " << o.x() << ' ' << o.y() << ' ' << o.z() << ' ' << a.x() << ' ' << a.y() << ' ' << a.z() << '\n';
  }
  if (std::isfinite(m.planned_top_mm)) s << "planned_top " << m.planned_top_mm << '\n';
  for (const MeasuredSection& sec : m.sections) {
    s << "section " << sec.index << ' ' << sec.height_mm << '\n';
    for (const Vec3& p : sec.points) s << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  }
  if (!m.face.empty()) {
    s << "face\n";
    for (const Vec3& p : m.face) s << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  }
  return s.str();
}

void write_section_measurement(const std::string& path, const SectionMeasurement& m) {
  write_file_atomic(path, format_section_measurement(m));
}

}  // namespace bliskrun
