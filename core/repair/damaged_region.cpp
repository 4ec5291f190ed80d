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

constexpr int kVBins = 1024;  // v resolution of a damage's stretch, for the pairing

double region_cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// A closed polygon made counter-clockwise, with its bounding box.
struct CutRing {
  std::vector<Vec2> p;
  Vec2 lo = Vec2::Zero(), hi = Vec2::Zero();
  explicit CutRing(std::vector<Vec2> points) : p(std::move(points)) {
    double twice = 0;
    for (size_t i = 0; i < p.size(); ++i) twice += region_cross(p[i], p[(i + 1) % p.size()]);
    if (twice < 0) std::reverse(p.begin(), p.end());
    lo = hi = p.empty() ? Vec2::Zero() : p[0];
    for (const Vec2& q : p) {
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
  }
  bool box_holds(const Vec2& q) const { return q.x() >= lo.x() && q.x() <= hi.x() && q.y() >= lo.y() && q.y() <= hi.y(); }
  // Crossing number.
  bool holds(const Vec2& q) const {
    if (!box_holds(q)) return false;
    bool in = false;
    for (size_t i = 0, j = p.size() - 1; i < p.size(); j = i++)
      if ((p[i].y() > q.y()) != (p[j].y() > q.y()) &&
          q.x() < p[i].x() + (p[j].x() - p[i].x()) * (q.y() - p[i].y()) / (p[j].y() - p[i].y()))
        in = !in;
    return in;
  }
};

// Parameters t in (0, 1) where a + t (b - a) crosses an edge of r.
void cut_crossings(const Vec2& a, const Vec2& b, const CutRing& r, std::vector<double>& ts) {
  const Vec2 lo = a.cwiseMin(b), hi = a.cwiseMax(b);
  if (hi.x() < r.lo.x() || lo.x() > r.hi.x() || hi.y() < r.lo.y() || lo.y() > r.hi.y()) return;
  const Vec2 e = b - a;
  const size_t m = r.p.size();
  for (size_t i = 0; i < m; ++i) {
    const Vec2& c = r.p[i];
    const Vec2& d = r.p[(i + 1) % m];
    if (std::max(c.x(), d.x()) < lo.x() || std::min(c.x(), d.x()) > hi.x() || std::max(c.y(), d.y()) < lo.y() ||
        std::min(c.y(), d.y()) > hi.y())
      continue;
    const Vec2 f = d - c;
    const double den = region_cross(e, f);
    if (std::abs(den) < 1e-300) continue;
    const double t = region_cross(c - a, f) / den, u = region_cross(c - a, e) / den;
    if (t > 0 && t < 1 && u >= 0 && u <= 1) ts.push_back(t);
  }
}

// The first crossing of the ray q + s d (s > 0) with the edges of `poly`.
double cut_ray_exit(const Vec2& q, const Vec2& d, const std::vector<Vec2>& poly) {
  double best = std::numeric_limits<double>::infinity();
  const size_t m = poly.size();
  for (size_t k = 0; k < m; ++k) {
    const Vec2& a = poly[k];
    const Vec2 e = poly[(k + 1) % m] - a;
    const double den = region_cross(d, e);
    if (std::abs(den) < 1e-15) continue;
    const Vec2 w = a - q;
    const double s = region_cross(w, e) / den, t = region_cross(w, d) / den;
    if (t >= 0 && t < 1 && s > 0) best = std::min(best, s);
  }
  return best;
}

// `count` points at equal fractions of the polyline's length.
std::vector<Vec2> resample_floor(const std::vector<Vec2>& line, int count) {
  std::vector<double> at{0};
  for (size_t i = 1; i < line.size(); ++i) at.push_back(at.back() + (line[i] - line[i - 1]).norm());
  std::vector<Vec2> out;
  size_t i = 1;
  for (int k = 0; k < count; ++k) {
    const double s = at.back() * k / (count - 1);
    while (i + 1 < line.size() && at[i] < s) ++i;
    const double len = at[i] - at[i - 1];
    out.push_back(len > 0 ? Vec2(line[i - 1] + (line[i] - line[i - 1]) * std::clamp((s - at[i - 1]) / len, 0.0, 1.0))
                          : line[i]);
  }
  return out;
}

}  // namespace

double clipped_area(const std::vector<Vec2>& poly, const Vec2& n, double c) { return area(clip(poly, n, c)); }

double area_inside(const std::vector<Vec2>& polygon, const std::vector<std::vector<Vec2>>& cuts) {
  std::vector<CutRing> rings;
  rings.emplace_back(polygon);
  for (const std::vector<Vec2>& c : cuts)
    if (c.size() >= 3) rings.emplace_back(c);
  if (rings.size() < 2 || rings[0].p.size() < 3) return 0;
  // The boundary of polygon ∩ (∪ cuts): the polygon's pieces inside some
  // cut, and each cut's pieces inside the polygon and no other cut; the
  // area is the integral of (x dy - y dx) / 2 along it, counter-clockwise.
  double twice = 0;
  std::vector<double> ts;
  for (size_t i = 0; i < rings.size(); ++i) {
    const std::vector<Vec2>& p = rings[i].p;
    for (size_t k = 0; k < p.size(); ++k) {
      const Vec2& a = p[k];
      const Vec2& b = p[(k + 1) % p.size()];
      ts.assign({0.0, 1.0});
      for (size_t j = 0; j < rings.size(); ++j)
        if (j != i) cut_crossings(a, b, rings[j], ts);
      std::sort(ts.begin(), ts.end());
      for (size_t t = 0; t + 1 < ts.size(); ++t) {
        if (!(ts[t + 1] > ts[t])) continue;
        const Vec2 m = a + 0.5 * (ts[t] + ts[t + 1]) * (b - a);
        bool keep;
        if (i == 0) {
          keep = false;
          for (size_t j = 1; j < rings.size() && !keep; ++j) keep = rings[j].holds(m);
        } else {
          keep = rings[0].holds(m);
          for (size_t j = 1; j < rings.size() && keep; ++j)
            if (j != i && rings[j].holds(m)) keep = false;
        }
        if (keep) twice += region_cross(a + ts[t] * (b - a), a + ts[t + 1] * (b - a));
      }
    }
  }
  return 0.5 * twice;
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
  // Every gap of every completed section that is damage (header), and every
  // dent, with the stretch of the rebuilt section it spans.
  std::vector<std::vector<std::vector<char>>> bins(sections_.size());
  for (const SectionGapFill& g : rebuilt.fills) {
    const bool dent = !g.floor.empty();
    if (!dent && (g.length_mm < min_gap_mm || g.sagitta_mm < g.spacing_mm || g.bridged)) {
      ++skipped_;
      continue;
    }
    for (size_t k = 0; k < sections_.size(); ++k) {
      Section& s = sections_[k];
      if (std::abs(s.h - g.height_mm) > 1e-9) continue;
      Damage d;
      d.floor.push_back(g.edge_a);
      d.floor.insert(d.floor.end(), g.floor.begin(), g.floor.end());
      d.floor.push_back(g.edge_b);
      d.half_plane = !dent;
      Vec2 n(-(g.edge_b - g.edge_a).y(), (g.edge_b - g.edge_a).x());
      if (n.squaredNorm() == 0) continue;
      n.normalize();
      // Towards the missing material: a gap's arc; away from a dent's floor
      // (on a flat flank the arc lies on the line).
      if (dent) {
        Vec2 mid = Vec2::Zero();
        for (const Vec2& q : g.floor) mid += q / static_cast<double>(g.floor.size());
        if (n.dot(mid - g.edge_a) > 0) n = -n;
      } else if (n.dot(g.arc_middle - g.edge_a) < 0) {
        n = -n;
      }
      d.n = n;
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
      // Every floor runs the way v does (the sections were ordered each its
      // own way round), so paired floors are interpolated end to end.
      if (j0 == jb) std::reverse(d.floor.begin(), d.floor.end());
      d.v0 = static_cast<double>(j0) / kVBins;
      d.v1 = static_cast<double>((j0 + len) % kVBins) / kVBins;
      std::vector<char> mark(kVBins, 0);
      double out = -1e300, in = 1e300;
      for (int e = -2; e <= len + 2; ++e) {
        const int j = ((j0 + e) % kVBins + kVBins) % kVBins;
        mark[j] = 1;
        out = std::max(out, n.dot(poly[j]));
      }
      for (const Vec2& q : d.floor) in = std::min(in, n.dot(q));
      d.depth = std::max(0.0, out - in);
      s.damages.push_back(std::move(d));
      bins[k].push_back(std::move(mark));
    }
  }
  // Pairs across neighbouring sections: the damage above with the most overlap.
  for (size_t k = 0; k + 1 < sections_.size(); ++k) {
    Section& lo = sections_[k];
    Section& hi = sections_[k + 1];
    for (size_t i = 0; i < lo.damages.size(); ++i) {
      int best = -1, best_overlap = 0;
      for (size_t j = 0; j < hi.damages.size(); ++j) {
        if (hi.damages[j].partner_down >= 0) continue;
        int overlap = 0;
        for (int b = 0; b < kVBins; ++b) overlap += bins[k][i][b] && bins[k + 1][j][b];
        if (overlap > best_overlap) {
          best_overlap = overlap;
          best = static_cast<int>(j);
        }
      }
      if (best >= 0) {
        lo.damages[i].partner_up = best;
        hi.damages[best].partner_down = static_cast<int>(i);
      }
    }
  }
  // Where unpaired damage ends (header): its depth extrapolated from its
  // partner on the other side to zero, within the step to the neighbour.
  const int n = static_cast<int>(sections_.size());
  for (int k = 0; k < n; ++k) {
    for (size_t i = 0; i < sections_[k].damages.size(); ++i) {
      Damage& d = sections_[k].damages[i];
      const double h = sections_[k].h;
      if (d.partner_up < 0 && k + 1 < n) {
        d.end_up = sections_[k + 1].h;
        const Damage* below = d.partner_down >= 0 && k > 0 ? &sections_[k - 1].damages[d.partner_down] : nullptr;
        if (below && below->depth > d.depth)
          d.end_up = std::min(d.end_up, h + d.depth * (h - sections_[k - 1].h) / (below->depth - d.depth));
      }
      if (d.partner_down < 0 && k > 0) {
        d.end_down = sections_[k - 1].h;
        if (d.partner_up >= 0 && k + 1 < n) {
          const Damage& above = sections_[k + 1].damages[d.partner_up];
          if (above.depth > d.depth)
            d.end_down = std::max(d.end_down, h - d.depth * (sections_[k + 1].h - h) / (above.depth - d.depth));
        }
      }
    }
  }
}

DamageFace::Cuts DamageFace::cuts(double h, double reach) const {
  Cuts out;
  const BladeFrame& f = rebuilt_.frame;
  // The break plane at height h: normal . (origin + h axis + x e1 + y e2) > offset.
  if (tip_) {
    out.tip = true;
    out.tip_n = Vec2(normal_.dot(f.e1), normal_.dot(f.e2));
    out.tip_c = normal_.dot(f.origin) + h * normal_.dot(f.axis) - offset_;
  }
  const size_t n = sections_.size();
  if (n < 2 || h < sections_.front().h || h > sections_.back().h) return out;
  size_t k = 0;
  while (k + 2 < n && sections_[k + 1].h < h) ++k;
  const Section& lo = sections_[k];
  const Section& hi = sections_[k + 1];
  const double t = (h - lo.h) / (hi.h - lo.h);
  // The cut of a floor with normal nn: a gap's half-plane as a quadrilateral,
  // a dent's strip out from its floor.
  auto polygon = [&](std::vector<Vec2> floor, const Vec2& nn, bool half_plane) {
    if (half_plane) {
      const Vec2 a = floor.front(), b = floor.back();
      const Vec2 along = (b - a).normalized();
      return std::vector<Vec2>{a - reach * along, b + reach * along, b + reach * (along + nn), a + reach * (nn - along)};
    }
    const Vec2 a = floor.front(), b = floor.back();
    floor.push_back(b + reach * nn);
    floor.push_back(a + reach * nn);
    return floor;
  };
  auto shifted = [](const Damage& d, double by) {
    std::vector<Vec2> floor = d.floor;
    for (Vec2& q : floor) q += by * d.n;
    return floor;
  };
  for (const Damage& d : lo.damages) {
    if (d.partner_up >= 0) {
      const Damage& u = hi.damages[d.partner_up];
      // The pair's partners below and above, for the cubic's slopes.
      const Damage* below = d.partner_down >= 0 && k > 0 ? &sections_[k - 1].damages[d.partner_down] : nullptr;
      const Damage* above = u.partner_up >= 0 && k + 2 < n ? &sections_[k + 2].damages[u.partner_up] : nullptr;
      size_t most = std::max(d.floor.size(), u.floor.size());
      if (below) most = std::max(most, below->floor.size());
      if (above) most = std::max(most, above->floor.size());
      const int count = std::min<int>(256, static_cast<int>(most));
      const std::vector<Vec2> a = resample_floor(d.floor, count), b = resample_floor(u.floor, count);
      const std::vector<Vec2> p = below ? resample_floor(below->floor, count) : std::vector<Vec2>();
      const std::vector<Vec2> q = above ? resample_floor(above->floor, count) : std::vector<Vec2>();
      // Cubic Hermite over [lo.h, hi.h], slopes by central differences.
      const double dh = hi.h - lo.h;
      const double h00 = (1 + 2 * t) * (1 - t) * (1 - t), h10 = t * (1 - t) * (1 - t), h01 = t * t * (3 - 2 * t),
                   h11 = t * t * (t - 1);
      std::vector<Vec2> floor(count);
      for (int i = 0; i < count; ++i) {
        const Vec2 ma = below ? Vec2((b[i] - p[i]) / (hi.h - sections_[k - 1].h)) : Vec2((b[i] - a[i]) / dh);
        const Vec2 mb = above ? Vec2((q[i] - a[i]) / (sections_[k + 2].h - lo.h)) : Vec2((b[i] - a[i]) / dh);
        floor[i] = h00 * a[i] + h10 * dh * ma + h01 * b[i] + h11 * dh * mb;
      }
      const Vec2 nn = (d.n + t * (u.n - d.n)).normalized();
      out.polygons.push_back(polygon(std::move(floor), nn, d.half_plane && u.half_plane));
    } else if (h < d.end_up) {
      out.polygons.push_back(polygon(shifted(d, d.depth * (h - lo.h) / (d.end_up - lo.h)), d.n, d.half_plane));
    }
  }
  for (const Damage& d : hi.damages)
    if (d.partner_down < 0 && h > d.end_down)
      out.polygons.push_back(polygon(shifted(d, d.depth * (hi.h - h) / (hi.h - d.end_down)), d.n, d.half_plane));
  return out;
}

double normal_thickness(const DamageFace& face, const Vec3& p, const Vec3& outward, std::vector<Vec2>& section,
                        int section_samples) {
  const BladeFrame& f = face.rebuilt().frame;
  const double h = f.height(p);
  const DamageFace::Cuts cuts = face.cuts(h);
  const Vec2 xy = f.in_plane(p);
  const Vec2 n_ip(outward.dot(f.e1), outward.dot(f.e2));
  const double len = n_ip.norm();
  const double inf = std::numeric_limits<double>::infinity();
  // Along p - s outward: each cut the point is in is left at s_i (never when
  // the ray moves deeper into it); the union at the largest.
  double leave = -1;
  if (cuts.tip) {
    // The tip's plane is tilted out of the section's plane: its rate along
    // the ray is its 3-D normal's, not the in-plane part's.
    const double value = face.break_normal().dot(p) - face.break_offset();
    const double rate = face.break_normal().dot(outward);
    if (value > 0) leave = std::max(leave, rate > 0 ? value / rate : inf);
  }
  const Vec2 d = len > 1e-9 ? Vec2(-n_ip / len) : Vec2::Zero();
  for (const std::vector<Vec2>& c : cuts.polygons) {
    if (!CutRing(c).holds(xy)) continue;
    // In-plane length to the 3-D length along the normal: / len.
    leave = std::max(leave, len > 1e-9 ? cut_ray_exit(xy, d, c) / len : inf);
  }
  if (leave < 0) return 0;
  // The blade's other side, in the section's plane.
  if (!(len > 1e-9)) return std::isfinite(leave) ? leave : 0;
  if (section.empty()) section = clamped_plane_section(face.rebuilt().loft, f, h, section_samples);
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
    if (!s.damages.empty()) ++out.nicked_sections;
    out.nicks += static_cast<int>(s.damages.size());
    for (const DamageFace::Damage& d : s.damages) out.dents += !d.half_plane;
  }

  // The heights where anything is missing: between two sections either of
  // which has a gap, and from where the break plane enters the blade to the
  // top of the loft.
  std::vector<std::pair<double, double>> ranges;
  for (size_t k = 0; k + 1 < face.sections_.size(); ++k)
    if (!face.sections_[k].damages.empty() || !face.sections_[k + 1].damages.empty())
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
      // The cuts reach well beyond the section (its size, ten times over).
      double size = 0;
      for (const Vec2& q : poly) size = std::max(size, q.norm());
      const DamageFace::Cuts cuts = face.cuts(h, 10 * size + 10);
      std::vector<std::vector<Vec2>> all = cuts.polygons;
      if (cuts.tip) {
        // The tip's half-plane as a quadrilateral reaching as far; a plane
        // that misses the section takes all of it or nothing.
        const double r = 10 * size + 10, norm = cuts.tip_n.norm();
        const Vec2 nn = norm > 0 ? Vec2(cuts.tip_n / norm) : Vec2::UnitX(), along(-nn.y(), nn.x());
        const double c = norm > 0 ? cuts.tip_c / norm : (cuts.tip_c > 0 ? 1e300 : -1e300);
        if (c > 2 * size) {
          all.push_back({Vec2(-r, -r), Vec2(r, -r), Vec2(r, r), Vec2(-r, r)});
        } else if (c >= -2 * size) {
          const Vec2 on = -c * nn;
          all.push_back({on - r * along, on + r * along, on + r * (along + nn), on + r * (nn - along)});
        }
        out.tip_volume_mm3 += dh * clipped_area(poly, cuts.tip_n, cuts.tip_c);
      }
      out.volume_mm3 += dh * area_inside(poly, all);
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
