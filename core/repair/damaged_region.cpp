#include "core/repair/damaged_region.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Dense>

#include "core/common/error.h"
#include "core/common/progress.h"

namespace bliskrun {

namespace {

// Sutherland-Hodgman against one half-plane n . p + c > 0.
std::vector<Vec2> clip(const std::vector<Vec2>& poly, const Vec2& n, double c) {
  std::vector<Vec2> out;
  const size_t m = poly.size();
  for (size_t i = 0; i < m; ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % m];
    const double dp = n.dot(p) + c, dq = n.dot(q) + c;
    if (dp > 0) out.push_back(p);
    if ((dp > 0) != (dq > 0)) out.push_back(p + (q - p) * (dp / (dp - dq)));
  }
  return out;
}

double area(const std::vector<Vec2>& poly) {
  double twice = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % poly.size()];
    twice += p.x() * q.y() - p.y() * q.x();
  }
  return 0.5 * std::abs(twice);
}

constexpr int kVBins = 1024;  // v resolution of a gap's stretch, for the pairing

}  // namespace

double clipped_area(const std::vector<Vec2>& poly, const Vec2& n, double c) { return area(clip(poly, n, c)); }

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
  // Every gap of every completed section that is damage (header), with the
  // stretch of the rebuilt section it spans.
  std::vector<std::vector<std::vector<char>>> bins(sections_.size());
  for (const SectionGapFill& g : rebuilt.fills) {
    if (g.length_mm < min_gap_mm || g.sagitta_mm < g.spacing_mm) {
      ++skipped_;
      continue;
    }
    for (size_t k = 0; k < sections_.size(); ++k) {
      Section& s = sections_[k];
      if (std::abs(s.h - g.height_mm) > 1e-9) continue;
      Vec2 n(-(g.end_b - g.end_a).y(), (g.end_b - g.end_a).x());
      if (n.squaredNorm() == 0) continue;
      n.normalize();
      if (n.dot(g.arc_middle - g.end_a) < 0) n = -n;
      Gap gap;
      gap.a = g.end_a;
      gap.n = n;
      const std::vector<Vec2> poly = clamped_plane_section(rebuilt.loft, f, s.h, kVBins);
      auto nearest = [&](const Vec2& q) {
        int best = 0;
        for (int j = 1; j < kVBins; ++j)
          if ((poly[j] - q).squaredNorm() < (poly[best] - q).squaredNorm()) best = j;
        return best;
      };
      const int ja = nearest(g.end_a), jb = nearest(g.end_b), jm = nearest(g.arc_middle);
      const int ab = ((jb - ja) % kVBins + kVBins) % kVBins, am = ((jm - ja) % kVBins + kVBins) % kVBins;
      const int j0 = am <= ab ? ja : jb, len = am <= ab ? ab : kVBins - ab;
      gap.v0 = static_cast<double>(j0) / kVBins;
      gap.v1 = static_cast<double>((j0 + len) % kVBins) / kVBins;
      std::vector<char> mark(kVBins, 0);
      for (int d = -2; d <= len + 2; ++d) mark[((j0 + d) % kVBins + kVBins) % kVBins] = 1;
      for (const Vec2& q : poly) gap.depth = std::max(gap.depth, n.dot(q - gap.a));
      s.gaps.push_back(gap);
      bins[k].push_back(std::move(mark));
    }
  }
  // Pairs across neighbouring sections: the gap above with the most overlap.
  for (size_t k = 0; k < sections_.size(); ++k) {
    sections_[k].partner_up.assign(sections_[k].gaps.size(), -1);
    sections_[k].has_partner_down.assign(sections_[k].gaps.size(), 0);
  }
  for (size_t k = 0; k + 1 < sections_.size(); ++k) {
    Section& lo = sections_[k];
    Section& hi = sections_[k + 1];
    for (size_t i = 0; i < lo.gaps.size(); ++i) {
      int best = -1, best_overlap = 0;
      for (size_t j = 0; j < hi.gaps.size(); ++j) {
        if (hi.has_partner_down[j]) continue;
        int overlap = 0;
        for (int b = 0; b < kVBins; ++b) overlap += bins[k][i][b] && bins[k + 1][j][b];
        if (overlap > best_overlap) {
          best_overlap = overlap;
          best = static_cast<int>(j);
        }
      }
      if (best >= 0) {
        lo.partner_up[i] = best;
        hi.has_partner_down[best] = 1;
      }
    }
  }
}

void DamageFace::edge_half_planes(double h, std::vector<HalfPlane>& out) const {
  const size_t n = sections_.size();
  if (n < 2 || h < sections_.front().h || h > sections_.back().h) return;
  size_t k = 0;
  while (k + 2 < n && sections_[k + 1].h < h) ++k;
  const Section& lo = sections_[k];
  const Section& hi = sections_[k + 1];
  const double f = (h - lo.h) / (hi.h - lo.h);
  for (size_t i = 0; i < lo.gaps.size(); ++i) {
    const Gap& g = lo.gaps[i];
    if (lo.partner_up[i] >= 0) {
      const Gap& u = hi.gaps[lo.partner_up[i]];
      const Vec2 a = g.a + f * (u.a - g.a);
      const Vec2 nn = (g.n + f * (u.n - g.n)).normalized();
      out.push_back({nn, -nn.dot(a)});
    } else {
      out.push_back({g.n, -g.n.dot(g.a) - f * g.depth});
    }
  }
  for (size_t j = 0; j < hi.gaps.size(); ++j)
    if (!hi.has_partner_down[j]) out.push_back({hi.gaps[j].n, -hi.gaps[j].n.dot(hi.gaps[j].a) - (1 - f) * hi.gaps[j].depth});
}

std::vector<DamageFace::HalfPlane> DamageFace::half_planes(double h) const {
  std::vector<HalfPlane> out;
  const BladeFrame& f = rebuilt_.frame;
  // The break plane at height h: normal . (origin + h axis + x e1 + y e2) > offset.
  if (tip_) out.push_back({Vec2(normal_.dot(f.e1), normal_.dot(f.e2)), normal_.dot(f.origin) + h * normal_.dot(f.axis) - offset_});
  edge_half_planes(h, out);
  return out;
}

double DamageFace::thickness(const Vec3& p) const {
  const BladeFrame& f = rebuilt_.frame;
  double t = 0;
  if (tip_) t = std::max(t, normal_.dot(p) - offset_);
  std::vector<HalfPlane> edges;
  edge_half_planes(f.height(p), edges);
  const Vec2 xy = f.in_plane(p);
  for (const HalfPlane& e : edges) t = std::max(t, e.n.dot(xy) + e.c);
  return t;
}

double normal_thickness(const DamageFace& face, const Vec3& p, const Vec3& outward, std::vector<Vec2>& section,
                        int section_samples) {
  const BladeFrame& f = face.rebuilt().frame;
  const double h = f.height(p);
  const std::vector<DamageFace::HalfPlane> hp = face.half_planes(h);
  const Vec2 xy = f.in_plane(p);
  const Vec2 n_ip(outward.dot(f.e1), outward.dot(f.e2));
  const double inf = std::numeric_limits<double>::infinity();
  // Along p - s outward: each half-space the point is in is left at s_i (never
  // when the ray moves deeper into it); the union at the largest.
  double leave = -1;
  bool tip = face.has_tip();
  for (const DamageFace::HalfPlane& q : hp) {
    const double value = q.n.dot(xy) + q.c;
    // The tip's plane is tilted out of the section's plane: its rate along
    // the ray is its 3-D normal's, not the in-plane part's.
    const double rate = tip ? face.break_normal().dot(outward) : q.n.dot(n_ip);
    const double value3 = tip ? face.break_normal().dot(p) - face.break_offset() : value;
    tip = false;
    if (!(value3 > 0)) continue;
    leave = std::max(leave, rate > 0 ? value3 / rate : inf);
  }
  if (leave < 0) return 0;
  // The blade's other side, in the section's plane.
  const double len = n_ip.norm();
  if (!(len > 1e-9)) return std::isfinite(leave) ? leave : 0;
  if (section.empty()) section = clamped_plane_section(face.rebuilt().loft, f, h, section_samples);
  const Vec2 d = -n_ip / len;
  double through = inf;
  const size_t m = section.size();
  for (size_t k = 0; k < m; ++k) {
    const Vec2& a = section[k];
    const Vec2 e = section[(k + 1) % m] - a;
    const double den = d.x() * e.y() - d.y() * e.x();
    if (std::abs(den) < 1e-15) continue;
    const Vec2 w = a - xy;
    const double s = (w.x() * e.y() - w.y() * e.x()) / den;
    const double t = (w.x() * d.y() - w.y() * d.x()) / den;
    if (t >= 0 && t < 1 && s > 0.02) through = std::min(through, s);
  }
  const double blade = through / len;  // in-plane length to the 3-D length along the normal
  const double t = std::min(leave, blade);
  return std::isfinite(t) ? t : 0;
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
  out.skipped_gaps = face.skipped_;
  for (const DamageFace::Section& s : face.sections_) {
    if (!s.gaps.empty()) ++out.nicked_sections;
    out.nicks += static_cast<int>(s.gaps.size());
  }

  // The heights where anything is missing: between two sections either of
  // which has a gap, and from where the break plane enters the blade to the
  // top of the loft.
  std::vector<std::pair<double, double>> ranges;
  for (size_t k = 0; k + 1 < face.sections_.size(); ++k)
    if (!face.sections_[k].gaps.empty() || !face.sections_[k + 1].gaps.empty())
      ranges.emplace_back(face.sections_[k].h, face.sections_[k + 1].h);
  const double h_bottom = rebuilt.sections.front().height_mm, h_top = rebuilt.sections.back().height_mm;
  if (face.tip_) {
    const Vec3& nrm = face.normal_;
    const double na = nrm.dot(fr.axis);
    const Vec2 nxy(nrm.dot(fr.e1), nrm.dot(fr.e2));
    const double no = nrm.dot(fr.origin);
    double reach = 0;
    for (const Vec2& q : clamped_plane_section(loft, fr, std::min(rebuilt.top_measured_mm, h_top), 256))
      reach = std::max(reach, -nxy.dot(q));
    const double h_start = std::max(h_bottom, (face.offset_ - no - reach - 0.5) / na);
    if (h_top > h_start) ranges.emplace_back(h_start, h_top);
  }
  std::sort(ranges.begin(), ranges.end());
  std::vector<std::pair<double, double>> merged;
  for (const auto& r : ranges) {
    if (!merged.empty() && r.first <= merged.back().second) merged.back().second = std::max(merged.back().second, r.second);
    else merged.push_back(r);
  }
  double total = 0;
  for (const auto& r : merged) total += r.second - r.first;
  // One volume: the missing area of each slice (midpoint rule), tip and
  // edges together so that where they meet nothing is counted twice.
  for (const auto& r : merged) {
    const int slices = std::max(8, static_cast<int>(std::ceil(o.slices * (r.second - r.first) / total)));
    const double dh = (r.second - r.first) / slices;
    for (int i = 0; i < slices; ++i) {
      cancellation_point();
      const double h = r.first + (i + 0.5) * dh;
      const std::vector<Vec2> poly = clamped_plane_section(loft, fr, h, o.section_samples);
      const std::vector<DamageFace::HalfPlane> hp = face.half_planes(h);
      std::vector<Vec2> kept = poly;
      for (const DamageFace::HalfPlane& p : hp) kept = clip(kept, -p.n, -p.c);
      out.volume_mm3 += dh * (area(poly) - area(kept));
      if (face.tip_) out.tip_volume_mm3 += dh * clipped_area(poly, hp[0].n, hp[0].c);
    }
  }
  out.edge_volume_mm3 = out.volume_mm3 - out.tip_volume_mm3;

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
    std::vector<Vec2> row_section;  // the rebuilt section at the row's first damaged sample, for the rays
    for (int j = 0; j < o.samples_v; ++j) {
      const double u = i * du, v = j * dv;
      const SurfaceDerivs d = loft.surface.eval(u, v);
      const Vec3 cross = d.pu.cross(d.pv);
      const Vec3 n = cross.normalized();
      const double t = normal_thickness(face, d.p, n, row_section, o.section_samples);
      if (!(t > 0)) continue;
      out.thickness_map[static_cast<size_t>(i) * o.samples_v + j] = t;
      row_hit[i] = col_hit[j] = 1;
      out.max_thickness_mm = std::max(out.max_thickness_mm, t);
      const double h = fr.height(d.p);
      out.height_from_mm = std::min(out.height_from_mm, h);
      out.height_to_mm = std::max(out.height_to_mm, h);
      out.area_mm2 += cross.norm() * du * dv * ((i == 0 || i == o.samples_u - 1) ? 0.5 : 1.0);
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
