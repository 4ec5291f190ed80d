#include "core/parts/edge_region.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/common/error.h"
#include "core/geometry/interpolation.h"
#include "core/geometry/point_grid.h"

namespace bliskrun {
namespace {

Vec3 unit_normal(const SurfaceDerivs& d) { return d.pu.cross(d.pv).normalized(); }

// Arc length along a flank's section from its edge end, as a table of
// (v, s) walked in small steps: where each flank carries its half of the
// round (flanks that meet at the edge point), the region's points are spaced
// by arc length through it, and the round's end is found on the walk.
struct ArcTable {
  std::vector<double> v, s;  // s[0] = 0 at the edge end, increasing
  double v_at(double arc) const {
    const size_t k = std::min<size_t>(std::upper_bound(s.begin(), s.end(), arc) - s.begin(), s.size() - 1);
    const size_t k0 = k == 0 ? 0 : k - 1;
    const double w = s[k] > s[k0] ? std::clamp((arc - s[k0]) / (s[k] - s[k0]), 0.0, 1.0) : 0.0;
    return v[k0] + w * (v[k] - v[k0]);
  }
};

// The construction at one span: flank A's last overlap, the round, flank B's
// first overlap, as a function of arc length s in [0, length]. Either the
// flanks end where the round starts and the round is the circle tangent to
// both ends (the built-in blisk), or they meet at the edge point and carry
// the round themselves (blades lofted with edge_margin 0: the data's own
// round), and the region is their last stretch on either side.
struct SpanSection {
  const Surface* a = nullptr;
  const Surface* b = nullptr;
  double span_u = 0;  // on flank A
  double span_b = 0;  // on flank B: the same section (below)
  double dv_a = 0, dv_b = 0;      // flank v extent of the overlaps
  double len_a = 0, len_b = 0;    // their arc lengths (measured)
  Vec3 centre = Vec3::Zero();
  double radius = 0, sweep = 0;   // round radius and angle (circle construction)
  Vec3 e1 = Vec3::Zero(), e2 = Vec3::Zero(), out_of_plane = Vec3::Zero();
  double misfit = 0;              // circle centres apart, or the meeting flank ends apart
  bool meeting = false;           // the flanks carry the round
  double round_in_a = 0, round_in_b = 0;  // meeting: arc of the round on each flank
  double crease_deg = 0;          // meeting: angle between the flanks' normals at the edge point
  double round_radius = 0;        // the round's radius: the circle's, or (meeting) its mean
  ArcTable arc_a, arc_b;          // meeting: arc length from the edge end on each flank

  double length() const { return len_a + radius * sweep + len_b; }
  double round_start() const { return len_a - round_in_a; }
  double round_end() const { return len_a + radius * sweep + round_in_b; }

  Vec3 at(double s) const {
    if (meeting) {
      if (s <= len_a) return a->point(span_u, arc_a.v_at(len_a - s));
      return b->point(span_b, arc_b.v_at(s - len_a));
    }
    if (s <= len_a) {  // flank A, v from dv_a down to 0 (towards its edge end)
      const double f = len_a > 0 ? s / len_a : 1.0;
      return a->point(span_u, dv_a * (1.0 - f));
    }
    if (s >= round_end()) {  // flank B, v from 1 down to 1 - dv_b
      const double f = len_b > 0 ? (s - round_end()) / len_b : 0.0;
      return b->point(span_b, 1.0 - dv_b * f);
    }
    const double alpha = (s - len_a) / radius;
    const Vec3 dir = (std::cos(alpha) * e1 + std::sin(alpha) * e2 + (alpha / sweep) * out_of_plane).normalized();
    return centre + radius * dir;
  }
};

double polyline_length(const Surface& s, double u, double v0, double v1, int n) {
  double len = 0;
  Vec3 prev = s.point(u, v0);
  for (int i = 1; i <= n; ++i) {
    const Vec3 p = s.point(u, v0 + (v1 - v0) * i / n);
    len += (p - prev).norm();
    prev = p;
  }
  return len;
}

// Flank B's span parameter whose edge end lies in the plane through flank A's
// edge end across its edge line (normal to A's pu there): two lofted flanks
// carry their own span parametrisation (each grid's chord-length parameters
// averaged over its own columns), and the same u on both is up to 0.003 of
// the span apart on Rotor 67 — half a millimetre along the edge, where two
// flanks lofted to the edge point meet within a micrometre.
double matching_span(const Surface& a, const Surface& b, double span_u) {
  const SurfaceDerivs da = a.eval(span_u, 0.0);
  const Vec3 t = da.pu.normalized();
  double u = span_u;
  for (int it = 0; it < 30; ++it) {
    const SurfaceDerivs db = b.eval(u, 1.0);
    const double g = (db.p - da.p).dot(t), dg = db.pu.dot(t);
    if (std::abs(dg) < 1e-12) break;
    const double step = g / dg;
    u = std::clamp(u - step, 0.0, 1.0);
    if (std::abs(step) < 1e-13) break;
  }
  return u;
}

// Flank ends closer than this meet: the flanks carry the round.
constexpr double kMeetingMm = 0.01;

// Walks a flank's section from its edge end (v = from) towards v = from +
// dir * 0.5 in steps of ~`step_mm` of arc, until `arc_mm` is reached or, with
// stop_on_round, the round ends first: the section's curvature (normal turn
// per arc) falls below half the edge point's. Returns the table; the round's
// arc length in *round_mm.
ArcTable walk_from_edge(const Surface& f, double span_u, double from, double dir, double arc_mm, double* round_mm) {
  constexpr double kStepMm = 0.005;
  constexpr double kFrontMm = 0.02;  // the edge point's curvature: the largest over the first 20 um
  ArcTable t;
  t.v.push_back(from);
  t.s.push_back(0);
  SurfaceDerivs prev = f.eval(span_u, from);
  Vec3 n_prev = unit_normal(prev);
  double kappa_front = -1;
  bool round_found = false;
  *round_mm = 0;
  double v = from;
  while (std::abs(v - from) < 0.5) {
    const double dv = kStepMm / std::max(prev.pv.norm(), 1e-9);
    v = from + dir * std::min(std::abs(v - from) + dv, 0.5);
    const SurfaceDerivs d = f.eval(span_u, v);
    const Vec3 n = unit_normal(d);
    const double ds = (d.p - prev.p).norm();
    const double kappa = ds > 0 ? std::acos(std::clamp(n.dot(n_prev), -1.0, 1.0)) / ds : 0.0;
    t.v.push_back(v);
    t.s.push_back(t.s.back() + ds);
    if (t.s.back() <= kFrontMm) kappa_front = std::max(kappa_front, kappa);
    else if (!round_found && kappa < 0.5 * kappa_front) {
      round_found = true;
      *round_mm = t.s.back();
    }
    prev = d;
    n_prev = n;
    if (round_found && t.s.back() >= *round_mm + arc_mm) break;
  }
  if (!round_found) *round_mm = t.s.back();
  return t;
}

// The stretch of each flank a meeting section takes: the round as found on
// it and `overlap_mm` past; its radius as its mean curvature (the turn of
// the normal over it).
void settle_meeting(SpanSection& sec, double overlap_mm) {
  sec.len_a = std::min(sec.arc_a.s.back(), sec.round_in_a + overlap_mm);
  sec.len_b = std::min(sec.arc_b.s.back(), sec.round_in_b + overlap_mm);
  sec.dv_a = sec.arc_a.v_at(sec.len_a);
  sec.dv_b = 1.0 - sec.arc_b.v_at(sec.len_b);
  const SurfaceDerivs ea = sec.a->eval(sec.span_u, sec.arc_a.v_at(sec.round_in_a));
  const SurfaceDerivs eb = sec.b->eval(sec.span_b, sec.arc_b.v_at(sec.round_in_b));
  const double turn = std::acos(std::clamp(unit_normal(ea).dot(unit_normal(eb)), -1.0, 1.0));
  sec.round_radius = turn > 1e-9 ? (sec.round_in_a + sec.round_in_b) / turn : 0.0;
}

// The flanks walked a millimetre past overlap_mm beyond the round: room for
// the rounds' lengths to be smoothed along the span (build_edge_region).
constexpr double kWalkPastMm = 1.0;

SpanSection meeting_section(SpanSection sec, const SurfaceDerivs& da, const SurfaceDerivs& db, double overlap_mm) {
  sec.meeting = true;
  sec.misfit = (da.p - db.p).norm();
  sec.crease_deg = std::acos(std::clamp(unit_normal(da).dot(unit_normal(db)), -1.0, 1.0)) * 180 / kPi;
  sec.arc_a = walk_from_edge(*sec.a, sec.span_u, 0.0, +1, overlap_mm + kWalkPastMm, &sec.round_in_a);
  sec.arc_b = walk_from_edge(*sec.b, sec.span_b, 1.0, -1, overlap_mm + kWalkPastMm, &sec.round_in_b);
  settle_meeting(sec, overlap_mm);
  return sec;  // radius and sweep 0: no constructed arc, length() is the flanks' stretches
}

// The rounds' lengths on each flank smoothed along the span (a running
// median of 9 stations, then a mean of 5): where one station's walk ends
// the round early and the next late, the region's u would jump along v —
// on Rotor 67's LE near section 11 the front's normal swung by 30 degrees
// over 2 % of the span and 380 contacts there found no clear axis.
void smooth_rounds(std::vector<SpanSection>& secs, double overlap_mm) {
  const int n = static_cast<int>(secs.size());
  for (double SpanSection::*len : {&SpanSection::round_in_a, &SpanSection::round_in_b}) {
    std::vector<double> raw(n), med(n);
    for (int j = 0; j < n; ++j) raw[j] = secs[j].*len;
    for (int j = 0; j < n; ++j) {
      std::vector<double> w;
      for (int k = std::max(0, j - 4); k <= std::min(n - 1, j + 4); ++k) w.push_back(raw[k]);
      std::nth_element(w.begin(), w.begin() + w.size() / 2, w.end());
      med[j] = w[w.size() / 2];
    }
    for (int j = 0; j < n; ++j) {
      double sum = 0;
      int count = 0;
      for (int k = std::max(0, j - 2); k <= std::min(n - 1, j + 2); ++k, ++count) sum += med[k];
      secs[j].*len = sum / count;
    }
  }
  for (SpanSection& sec : secs) settle_meeting(sec, overlap_mm);
}

SpanSection section_at(const Surface& a, const Surface& b, double span_u, double overlap_mm) {
  SpanSection sec;
  sec.a = &a;
  sec.b = &b;
  sec.span_u = span_u;
  // Flanks that meet: each carries its own span parametrisation, so B is
  // taken at the span that meets A. Otherwise both at span_u (the circle's
  // ends must be one section of the blade, which flanks of one parametrisation
  // give, as the built-in blisk's do).
  const SurfaceDerivs da = a.eval(span_u, 0.0);
  sec.span_b = matching_span(a, b, span_u);
  const SurfaceDerivs dm = b.eval(sec.span_b, 1.0);
  if ((da.p - dm.p).norm() < kMeetingMm) return meeting_section(sec, da, dm, overlap_mm);
  sec.span_b = span_u;
  const SurfaceDerivs db = b.eval(span_u, 1.0);
  const Vec3 na3 = unit_normal(da), nb3 = unit_normal(db);
  // The round lies in the section: the plane of flank A's section tangent at
  // its end and the chord to flank B's end (a circle's two tangents and its
  // chord are coplanar). In that plane each flank's end normal is the
  // in-plane perpendicular of its section tangent, on the side of its 3-D
  // normal. The surface normals themselves tilt out of the section where the
  // edge leans along the span, so they would not share a centre.
  const Vec3 ta = -da.pv.normalized(), tb = db.pv.normalized();  // towards the edge
  Vec3 plane_normal = ta.cross(db.p - da.p);
  if (plane_normal.squaredNorm() < 1e-20)
    throw Error("edge region: the flank ends at span u = " + std::to_string(span_u) + " do not bound a round");
  plane_normal.normalize();
  Vec3 na = plane_normal.cross(ta).normalized();
  if (na.dot(na3) < 0) na = -na;
  const Vec3 tb_in = (tb - tb.dot(plane_normal) * plane_normal).normalized();
  Vec3 nb = plane_normal.cross(tb_in).normalized();
  if (nb.dot(nb3) < 0) nb = -nb;
  const Vec3 dn = na - nb;
  if (dn.squaredNorm() < 1e-12)
    throw Error("edge region: the flank ends at span u = " + std::to_string(span_u) +
                " have parallel normals; they do not bound an edge round");
  // Centre c = P_a - rho n_a = P_b - rho n_b in the least-squares sense.
  sec.radius = (da.p - db.p).dot(dn) / dn.squaredNorm();
  sec.round_radius = sec.radius;
  if (!(sec.radius > 0))
    throw Error("edge region: the flank ends at span u = " + std::to_string(span_u) +
                " do not bound a convex round (radius " + std::to_string(sec.radius) + " mm)");
  const Vec3 ca = da.p - sec.radius * na, cb = db.p - sec.radius * nb;
  sec.centre = 0.5 * (ca + cb);
  sec.misfit = (ca - cb).norm();
  // The round turns from n_a towards flank A's direction off its edge end.
  sec.e1 = na;
  sec.e2 = (ta - ta.dot(na) * na).normalized();
  const Vec3 pn = sec.e1.cross(sec.e2);
  sec.sweep = std::atan2(nb.dot(sec.e2), nb.dot(sec.e1));
  if (sec.sweep <= 0) sec.sweep += 2 * kPi;
  sec.out_of_plane = nb.dot(pn) * pn;
  // The arc runs from the common centre; its ends miss P_a and P_b by half
  // the misfit, which is reported.
  sec.dv_a = std::min(0.5, overlap_mm / std::max(da.pv.norm(), 1e-9));
  sec.dv_b = std::min(0.5, overlap_mm / std::max(db.pv.norm(), 1e-9));
  sec.len_a = polyline_length(a, span_u, sec.dv_a, 0.0, 32);
  sec.len_b = polyline_length(b, sec.span_b, 1.0, 1.0 - sec.dv_b, 32);
  return sec;
}

}  // namespace

EdgeRegion build_edge_region(const EdgeRegionRequest& rq) {
  if (!rq.first || !rq.second) throw ParameterError("flanks", "edge region needs both flank surfaces");
  if (!(rq.overlap_mm >= 0)) throw ParameterError("overlap_mm", "must be >= 0");
  if (!(rq.span_u0 >= 0 && rq.span_u1 <= 1 && rq.span_u0 < rq.span_u1))
    throw ParameterError("span_u0/span_u1", "expected 0 <= span_u0 < span_u1 <= 1");
  if (rq.samples_around < 8) throw ParameterError("samples_around", "must be >= 8");
  if (rq.samples_span < 4) throw ParameterError("samples_span", "must be >= 4");

  const int na = rq.samples_around, ns = rq.samples_span;
  // Grid rows along the surface's u (around), columns along v (span).
  PointGrid grid(na, ns);
  EdgeRegion out;
  out.round_u0 = 1;
  out.round_u1 = 0;
  out.overlap_mm = std::numeric_limits<double>::infinity();
  out.radius_min_mm = std::numeric_limits<double>::infinity();
  std::vector<SpanSection> sections;
  sections.reserve(ns);
  for (int j = 0; j < ns; ++j) {
    const double su = rq.span_u0 + (rq.span_u1 - rq.span_u0) * j / (ns - 1);
    sections.push_back(section_at(*rq.first, *rq.second, su, rq.overlap_mm));
    if (sections.back().meeting != sections.front().meeting)
      throw Error("edge region: the flank ends meet at some spans and not at others (span u = " + std::to_string(su) +
                  "): loft both flanks with the same edge_margin");
  }
  out.flanks_meet = sections.front().meeting;
  if (out.flanks_meet) smooth_rounds(sections, rq.overlap_mm);
  for (int j = 0; j < ns; ++j) {
    const SpanSection& sec = sections[j];
    const double len = sec.length();
    for (int i = 0; i < na; ++i) grid.at(i, j) = sec.at(len * i / (na - 1));
    out.round_u0 = std::min(out.round_u0, sec.round_start() / len);
    out.round_u1 = std::max(out.round_u1, sec.round_end() / len);
    out.overlap_mm = std::min({out.overlap_mm, sec.len_a - sec.round_in_a, sec.len_b - sec.round_in_b});
    out.radius_min_mm = std::min(out.radius_min_mm, sec.round_radius);
    out.radius_max_mm = std::max(out.radius_max_mm, sec.round_radius);
    out.circle_misfit_mm = std::max(out.circle_misfit_mm, sec.misfit);
    out.crease_deg = std::max(out.crease_deg, sec.crease_deg);
  }
  // Uniform parameters: the grid is uniform in arc length around and in span.
  GridParameters params;
  for (int i = 0; i < na; ++i) params.u.push_back(static_cast<double>(i) / (na - 1));
  for (int j = 0; j < ns; ++j) params.v.push_back(static_cast<double>(j) / (ns - 1));
  auto spline = std::make_shared<BSplineSurface>(interpolate_grid(grid, params));
  // Deviation between samples: mid-points around at every sampled span (the
  // round's curvature jump at its ends is where a cubic rings).
  for (int j = 0; j < ns; ++j) {
    const double len = sections[j].length();
    const double v = static_cast<double>(j) / (ns - 1);
    for (int i = 0; i + 1 < na; ++i) {
      const double f = (i + 0.5) / (na - 1);
      out.fit_deviation_mm = std::max(out.fit_deviation_mm, (spline->point(f, v) - sections[j].at(len * f)).norm());
    }
  }
  out.surface = spline;
  return out;
}

}  // namespace bliskrun
