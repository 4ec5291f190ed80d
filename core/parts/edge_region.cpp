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

// The construction at one span: flank A's last overlap, the round, flank B's
// first overlap, as a function of arc length s in [0, length].
struct SpanSection {
  const Surface* a = nullptr;
  const Surface* b = nullptr;
  double span_u = 0;
  double dv_a = 0, dv_b = 0;      // flank v extent of the overlaps
  double len_a = 0, len_b = 0;    // their arc lengths (measured)
  Vec3 centre = Vec3::Zero();
  double radius = 0, sweep = 0;   // round radius and angle
  Vec3 e1 = Vec3::Zero(), e2 = Vec3::Zero(), out_of_plane = Vec3::Zero();
  double misfit = 0;

  double length() const { return len_a + radius * sweep + len_b; }
  double round_start() const { return len_a; }
  double round_end() const { return len_a + radius * sweep; }

  Vec3 at(double s) const {
    if (s <= len_a) {  // flank A, v from dv_a down to 0 (towards its edge end)
      const double f = len_a > 0 ? s / len_a : 1.0;
      return a->point(span_u, dv_a * (1.0 - f));
    }
    if (s >= round_end()) {  // flank B, v from 1 down to 1 - dv_b
      const double f = len_b > 0 ? (s - round_end()) / len_b : 0.0;
      return b->point(span_u, 1.0 - dv_b * f);
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

SpanSection section_at(const Surface& a, const Surface& b, double span_u, double overlap_mm) {
  SpanSection sec;
  sec.a = &a;
  sec.b = &b;
  sec.span_u = span_u;
  const SurfaceDerivs da = a.eval(span_u, 0.0), db = b.eval(span_u, 1.0);
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
  sec.len_b = polyline_length(b, span_u, 1.0, 1.0 - sec.dv_b, 32);
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
    SpanSection sec = section_at(*rq.first, *rq.second, su, rq.overlap_mm);
    const double len = sec.length();
    for (int i = 0; i < na; ++i) grid.at(i, j) = sec.at(len * i / (na - 1));
    out.round_u0 = std::min(out.round_u0, sec.round_start() / len);
    out.round_u1 = std::max(out.round_u1, sec.round_end() / len);
    out.overlap_mm = std::min({out.overlap_mm, sec.len_a, sec.len_b});
    out.radius_min_mm = std::min(out.radius_min_mm, sec.radius);
    out.radius_max_mm = std::max(out.radius_max_mm, sec.radius);
    out.circle_misfit_mm = std::max(out.circle_misfit_mm, sec.misfit);
    sections.push_back(sec);
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
