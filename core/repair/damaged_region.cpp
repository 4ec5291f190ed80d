#include "core/repair/damaged_region.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "core/common/error.h"
#include "core/common/progress.h"

namespace bliskrun {

double clipped_area(const std::vector<Vec2>& poly, const Vec2& n, double c) {
  // Sutherland-Hodgman against one half-plane, then the shoelace formula.
  std::vector<Vec2> out;
  const size_t m = poly.size();
  for (size_t i = 0; i < m; ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % m];
    const double dp = n.dot(p) + c, dq = n.dot(q) + c;
    if (dp > 0) out.push_back(p);
    if ((dp > 0) != (dq > 0)) out.push_back(p + (q - p) * (dp / (dp - dq)));
  }
  double twice = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    const Vec2& p = out[i];
    const Vec2& q = out[(i + 1) % out.size()];
    twice += p.x() * q.y() - p.y() * q.x();
  }
  return 0.5 * std::abs(twice);
}

DamageFace::DamageFace(const DamagedRebuild& rebuilt, const SectionMeasurement& measurement, double min_gap_mm)
    : rebuilt_(rebuilt) {
  const BladeFrame& f = rebuilt.frame;
  if (measurement.face.size() >= 3) {
    Vec3 c = Vec3::Zero();
    for (const Vec3& p : measurement.face) c += p / measurement.face.size();
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const Vec3& p : measurement.face) cov += (p - c) * (p - c).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    normal_ = eig.eigenvectors().col(0);
    if (normal_.dot(f.axis) < 0) normal_ = -normal_;
    offset_ = normal_.dot(c);
    face_points_ = static_cast<int>(measurement.face.size());
    face_rms_ = std::sqrt(std::max(eig.eigenvalues()[0], 0.0) / face_points_);
    tip_ = true;
  } else if (rebuilt.tip_extended) {
    normal_ = f.axis;
    offset_ = f.axis.dot(f.origin) + rebuilt.top_measured_mm;
    tip_ = true;
  }
  for (const DamagedSection& s : rebuilt.sections) {
    if (s.source == SectionSource::extended) continue;
    Section sec;
    sec.h = s.height_mm;
    sections_.push_back(sec);
  }
  // Each completed section's largest gap (fills are in section order).
  for (const SectionGapFill& g : rebuilt.fills) {
    if (g.length_mm < min_gap_mm) continue;
    for (Section& s : sections_) {
      if (std::abs(s.h - g.height_mm) > 1e-9) continue;
      Vec2 n(-(g.end_b - g.end_a).y(), (g.end_b - g.end_a).x());
      if (n.squaredNorm() == 0) continue;
      n.normalize();
      if (n.dot(g.arc_middle - g.end_a) < 0) n = -n;
      if (!s.gap || n.dot(g.arc_middle - g.end_a) > s.n.dot(g.arc_middle - s.a)) {
        s.gap = true;
        s.a = g.end_a;
        s.n = n;
      }
    }
  }
}

double DamageFace::edge_thickness(double h, const Vec2& xy) const {
  const size_t n = sections_.size();
  if (n == 0 || h < sections_.front().h || h > sections_.back().h) return 0;
  size_t k = 0;
  while (k + 2 < n && sections_[k + 1].h < h) ++k;
  const Section& lo = sections_[k];
  const Section& hi = sections_[k + 1];
  const double f = (h - lo.h) / (hi.h - lo.h);
  if (lo.gap && hi.gap) {
    const Vec2 a = lo.a + f * (hi.a - lo.a);
    const Vec2 nn = (lo.n + f * (hi.n - lo.n)).normalized();
    return std::max(0.0, nn.dot(xy - a));
  }
  if (lo.gap) return std::max(0.0, lo.n.dot(xy - lo.a) - f * lo.depth);
  if (hi.gap) return std::max(0.0, hi.n.dot(xy - hi.a) - (1 - f) * hi.depth);
  return 0;
}

double DamageFace::thickness(const Vec3& p) const {
  const BladeFrame& f = rebuilt_.frame;
  double t = 0;
  if (tip_) t = std::max(t, normal_.dot(p) - offset_);
  return std::max(t, edge_thickness(f.height(p), f.in_plane(p)));
}

DamagedRegion damaged_region(const DamagedRebuild& rebuilt, const SectionMeasurement& measurement,
                             const DamagedRegionOptions& o) {
  if (o.samples_u < 4 || o.samples_v < 8) throw ParameterError("samples", "expected at least 4 x 8 map samples");
  if (o.slices < 4) throw ParameterError("slices", "expected at least 4 slices");
  if (!(o.layer_mm > 0 && std::isfinite(o.layer_mm))) throw ParameterError("layer", "expected a positive layer thickness, mm");
  if (o.layers < 0 || o.layers > 1000) throw ParameterError("layers", "expected a count in [0, 1000]");
  if (!(o.min_gap_mm >= 0)) throw ParameterError("min_gap", "expected a length >= 0 mm");
  DamageFace face(rebuilt, measurement, o.min_gap_mm);
  const BladeFrame& fr = rebuilt.frame;
  const SectionLoft& loft = rebuilt.loft;
  DamagedRegion out;
  out.tip = face.tip_;
  out.break_normal = face.normal_;
  out.break_offset = face.offset_;
  out.face_points = face.face_points_;
  out.face_rms_mm = face.face_rms_;

  // Edge: each nicked section's cut area and depth; trapezoid over the sections.
  double previous_area = 0;
  for (size_t k = 0; k < face.sections_.size(); ++k) {
    DamageFace::Section& s = face.sections_[k];
    double area = 0;
    if (s.gap) {
      ++out.nicked_sections;
      const std::vector<Vec2> poly = plane_section(loft, fr, s.h, o.section_samples);
      area = clipped_area(poly, s.n, -s.n.dot(s.a));
      for (const Vec2& q : poly) s.depth = std::max(s.depth, s.n.dot(q - s.a));
    }
    if (k > 0) out.edge_volume_mm3 += 0.5 * (area + previous_area) * (s.h - face.sections_[k - 1].h);
    previous_area = area;
  }

  // Tip: slices from where the break plane enters the blade to the top.
  if (face.tip_) {
    const double h_top = rebuilt.sections.back().height_mm;
    const Vec3& nrm = face.normal_;
    const double na = nrm.dot(fr.axis);
    const Vec2 nxy(nrm.dot(fr.e1), nrm.dot(fr.e2));
    const double no = nrm.dot(fr.origin);
    double reach = 0;
    for (const Vec2& q : plane_section(loft, fr, std::min(rebuilt.top_measured_mm, h_top), 256))
      reach = std::max(reach, -nxy.dot(q));
    const double h_start = std::max(rebuilt.sections.front().height_mm, (face.offset_ - no - reach - 0.5) / na);
    if (h_top > h_start) {
      const double dh = (h_top - h_start) / o.slices;
      for (int i = 0; i < o.slices; ++i) {
        cancellation_point();
        const double h = h_start + (i + 0.5) * dh;
        const std::vector<Vec2> poly = plane_section(loft, fr, h, o.section_samples);
        out.tip_volume_mm3 += dh * clipped_area(poly, nxy, na * h + no - face.offset_);
      }
    }
  }
  out.volume_mm3 = out.tip_volume_mm3 + out.edge_volume_mm3;

  // Thickness map, extent, area, layers.
  out.map_u = o.samples_u;
  out.map_v = o.samples_v;
  out.thickness_map.assign(static_cast<size_t>(o.samples_u) * o.samples_v, 0.0);
  std::vector<char> row_hit(o.samples_u, 0), col_hit(o.samples_v, 0);
  out.height_from_mm = 1e300;
  out.height_to_mm = -1e300;
  out.layers.resize(o.layers);
  for (int k = 0; k < o.layers; ++k) out.layers[k].offset_mm = (k + 1) * o.layer_mm;
  const double du = 1.0 / (o.samples_u - 1), dv = 1.0 / o.samples_v;
  for (int i = 0; i < o.samples_u; ++i) {
    cancellation_point();
    for (int j = 0; j < o.samples_v; ++j) {
      const double u = i * du, v = j * dv;
      const SurfaceDerivs d = loft.surface.eval(u, v);
      const double t = face.thickness(d.p);
      if (!(t > 0)) continue;
      out.thickness_map[static_cast<size_t>(i) * o.samples_v + j] = t;
      row_hit[i] = col_hit[j] = 1;
      out.max_thickness_mm = std::max(out.max_thickness_mm, t);
      const double h = fr.height(d.p);
      out.height_from_mm = std::min(out.height_from_mm, h);
      out.height_to_mm = std::max(out.height_to_mm, h);
      const Vec3 cross = d.pu.cross(d.pv);
      out.area_mm2 += cross.norm() * du * dv * ((i == 0 || i == o.samples_u - 1) ? 0.5 : 1.0);
      const Vec3 n = cross.normalized();
      for (OffsetLayer& l : out.layers) {
        l.points.push_back(d.p + l.offset_mm * n);
        l.uv.emplace_back(u, v);
      }
    }
  }
  out.empty = out.max_thickness_mm <= 0;
  if (out.empty) {
    out.height_from_mm = out.height_to_mm = 0;
    return out;
  }
  const int first_row = static_cast<int>(std::find(row_hit.begin(), row_hit.end(), 1) - row_hit.begin());
  const int last_row = o.samples_u - 1 - static_cast<int>(std::find(row_hit.rbegin(), row_hit.rend(), 1) - row_hit.rbegin());
  out.u_from = first_row * du;
  out.u_to = last_row * du;
  // v: the complement of the longest circular run of columns without damage.
  int best_len = 0, best_start = 0;
  for (int j = 0; j < o.samples_v; ++j) {
    if (col_hit[j] || !col_hit[(j + o.samples_v - 1) % o.samples_v]) continue;  // runs start after a hit
    int len = 0;
    while (len < o.samples_v && !col_hit[(j + len) % o.samples_v]) ++len;
    if (len > best_len) {
      best_len = len;
      best_start = j;
    }
  }
  if (best_len == 0) {
    out.v_from = 0;
    out.v_to = 1;
  } else {
    out.v_from = ((best_start + best_len) % o.samples_v) * dv;
    out.v_to = ((best_start + o.samples_v - 1) % o.samples_v) * dv;
  }
  return out;
}

}  // namespace bliskrun
