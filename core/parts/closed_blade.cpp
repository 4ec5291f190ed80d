#include "core/parts/closed_blade.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/geometry/closed_curve.h"

namespace bliskrun {

namespace {

// Faces whose end points are closer than this meet at the edge: they carry
// the edge's round themselves (a blade model lofted with edge_margin 0) and
// are joined directly, with no half circle between them. Two faces lofted
// through the same edge points at their own span parameters meet within
// 0.7 um between the sections (Rotor 67).
constexpr double kMeetMm = 0.002;

// The parameter of the point of a curve `at` nearest q: the nearest of the
// samples at k / n, k = 0 .. last, refined by golden section between its
// neighbours (`at` wraps or clamps the parameter as its curve needs).
template <class At>
double nearest_parameter(const At& at, const Vec3& q, int n, int last) {
  int best = 0;
  double best_d = 1e300;
  for (int k = 0; k <= last; ++k) {
    const double d = (at(static_cast<double>(k) / n) - q).squaredNorm();
    if (d < best_d) best_d = d, best = k;
  }
  double a = (best - 1.0) / n, b = (best + 1.0) / n;
  auto f = [&](double x) { return (at(x) - q).squaredNorm(); };
  const double g = 0.5 * (std::sqrt(5.0) - 1);
  for (int it = 0; it < 60; ++it) {
    const double x1 = b - g * (b - a), x2 = a + g * (b - a);
    if (f(x1) < f(x2)) b = x2; else a = x1;
  }
  return 0.5 * (a + b);
}

// The suction face's span parameter whose section meets the pressure face's
// section u at both edges (both faces carry the edge's round: a blade model
// lofted with edge_margin 0), or -1 where they do not meet. Each face is
// interpolated along the span at its own averaged chord-length parameters,
// so the same u is a slightly different height on each (0.4 mm apart on
// Rotor 67): the suction face's u is found on its leading edge.
double meeting_suction_u(const Surface& pressure, const Surface& suction, double u) {
  const Vec3 le = pressure.point(u, 0);
  auto clamp = [](double x) { return std::clamp(x, 0.0, 1.0); };
  const double us = clamp(nearest_parameter([&](double x) { return suction.point(clamp(x), 1); }, le, 400, 400));
  if ((suction.point(us, 1) - le).norm() > kMeetMm || (suction.point(us, 0) - pressure.point(u, 1)).norm() > kMeetMm)
    return -1;
  return us;
}

double angle_deg(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / kPi;
}

// The edge between the face ending at `a` (arriving along `t_a`) and the
// face starting at `b` (leaving along `t_b`), appended to `loop` without a
// and b: nothing where they meet, else the 2 k + 1 points strictly between
// them on the half circle through them that bulges along the faces' mean
// end tangent (made perpendicular to b - a), a at phi = 0, b at pi. Returns
// the apex (the meeting point, or the half circle's middle) and raises
// `kink_deg` to the largest turn of the tangent where the edge meets a face.
Vec3 close_edge(const Vec3& a, const Vec3& t_a, const Vec3& b, const Vec3& t_b, int k, std::vector<Vec3>& loop,
                double& kink_deg) {
  const Vec3 c = 0.5 * (a + b);
  const double r = 0.5 * (a - b).norm();
  if (2 * r <= kMeetMm) {
    kink_deg = std::max(kink_deg, angle_deg(t_a, t_b));
    return c;
  }
  const Vec3 e1 = (a - c) / r;
  Vec3 out = t_a.normalized() - t_b.normalized();
  out -= out.dot(e1) * e1;
  if (!(out.norm() > 1e-9)) throw Error("close_blade: the faces' end tangents run along the edge's chord");
  out.normalize();
  // The circle leaves a along `out` and arrives at b along -out.
  kink_deg = std::max({kink_deg, angle_deg(t_a, out), angle_deg(-out, t_b)});
  const int samples = 2 * k + 1;
  for (int i = 1; i <= samples; ++i) {
    const double phi = kPi * i / (samples + 1);
    loop.push_back(c + r * (std::cos(phi) * e1 + std::sin(phi) * out));
  }
  return loop[loop.size() - k - 1];
}

}  // namespace

ClosedBlade close_blade(const Surface& pressure, const Surface& suction, const ClosedBladeOptions& o) {
  if (!(o.u0 >= 0 && o.u0 <= 1)) throw ParameterError("u0", "expected a span parameter in [0, 1]");
  if (!(o.u1 > o.u0 && o.u1 <= 1)) throw ParameterError("u1", "expected a span parameter in (u0, 1]");
  if (o.sections < 2) throw ParameterError("sections", "expected at least 2");
  if (o.face_samples < 8) throw ParameterError("face_samples", "expected at least 8");
  if (o.edge_samples < 3) throw ParameterError("edge_samples", "expected at least 3");
  std::vector<ClosedCurve> sections;
  std::vector<Vec3> le_apex, te_apex;
  double kink_deg = 0;
  const int m = o.face_samples;
  for (int i = 0; i < o.sections; ++i) {
    const double u = o.u0 + (o.u1 - o.u0) * i / (o.sections - 1);
    // Faces: pressure LE (v = 0) -> TE (v = 1), suction TE (v = 0) -> LE (v = 1).
    const double meet = meeting_suction_u(pressure, suction, u);
    const double us = meet < 0 ? u : meet;
    std::vector<Vec3> p(m), s(m);
    for (int j = 0; j < m; ++j) {
      const double v = static_cast<double>(j) / (m - 1);
      p[j] = pressure.point(u, v);
      s[j] = suction.point(us, v);
    }
    // The loop runs suction TE -> LE, pressure LE -> TE: each face's tangent
    // along the loop at its ends.
    const Vec3 p_le = pressure.eval(u, 0).pv, p_te = pressure.eval(u, 1).pv;
    const Vec3 s_te = suction.eval(us, 0).pv, s_le = suction.eval(us, 1).pv;
    // TE (pressure's end -> suction's start), then suction, LE, pressure;
    // the loop starts at the TE apex: the TE's second half first.
    std::vector<Vec3> te;
    te_apex.push_back(close_edge(p.back(), p_te, s.front(), s_te, o.edge_samples, te, kink_deg));
    const size_t te_half = te.size() / 2;  // the apex's index; 0 where the faces meet
    std::vector<Vec3> loop(te.begin() + static_cast<std::ptrdiff_t>(te_half), te.end());
    loop.insert(loop.end(), s.begin(), s.end());
    std::vector<Vec3> le;
    le_apex.push_back(close_edge(s.back(), s_le, p.front(), p_le, o.edge_samples, le, kink_deg));
    loop.insert(loop.end(), le.begin(), le.end());
    // Where the faces meet, pressure's end points are suction's: left out.
    loop.insert(loop.end(), p.begin() + (le.empty() ? 1 : 0), p.end() - (te.empty() ? 1 : 0));
    loop.insert(loop.end(), te.begin(), te.begin() + static_cast<std::ptrdiff_t>(te_half));
    sections.push_back(interpolate_closed_cubic(loop));
  }
  ClosedBlade out;
  out.loft = loft_sections(sections, o.loft);
  // The apexes' v on the middle section: nearest of a dense sampling, then
  // refined by golden section on the distance.
  const int mid = o.sections / 2;
  const double u_mid = out.loft.section_u[mid];
  auto nearest_v = [&](const Vec3& q) {
    const double v = nearest_parameter([&](double x) { return out.loft.surface.point(u_mid, x - std::floor(x)); }, q,
                                       4000, 3999);
    return v - std::floor(v);
  };
  out.le_v = nearest_v(le_apex[mid]);
  out.te_v = nearest_v(te_apex[mid]);
  const ClosedCurve& c = sections[mid];
  out.perimeter_mm = c.period();
  out.edge_kink_deg = kink_deg;
  return out;
}

}  // namespace bliskrun
