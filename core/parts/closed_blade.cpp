#include "core/parts/closed_blade.h"

#include <cmath>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/geometry/closed_curve.h"

namespace bliskrun {

namespace {

// Points strictly between a and b on the half circle through them that
// bulges along `out` (made perpendicular to b - a): a at phi = 0, b at pi.
void half_circle(const Vec3& a, const Vec3& b, Vec3 out, int samples, std::vector<Vec3>& loop) {
  const Vec3 c = 0.5 * (a + b);
  const double r = 0.5 * (a - b).norm();
  if (!(r > 1e-9)) throw Error("close_blade: the faces' edge points coincide at " + std::to_string(c.x()) + ", " +
                               std::to_string(c.y()) + ", " + std::to_string(c.z()));
  const Vec3 e1 = (a - c) / r;
  out -= out.dot(e1) * e1;
  if (!(out.norm() > 1e-9)) throw Error("close_blade: the faces' end tangents run along the edge's chord");
  out.normalize();
  for (int k = 1; k <= samples; ++k) {
    const double phi = kPi * k / (samples + 1);
    loop.push_back(c + r * (std::cos(phi) * e1 + std::sin(phi) * out));
  }
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
  const int m = o.face_samples;
  for (int i = 0; i < o.sections; ++i) {
    const double u = o.u0 + (o.u1 - o.u0) * i / (o.sections - 1);
    // Faces: pressure LE (v = 0) -> TE (v = 1), suction TE (v = 0) -> LE (v = 1).
    std::vector<Vec3> p(m), s(m);
    for (int j = 0; j < m; ++j) {
      const double v = static_cast<double>(j) / (m - 1);
      p[j] = pressure.point(u, v);
      s[j] = suction.point(u, v);
    }
    // Tangents into each face at its ends, away from the edge.
    const Vec3 t_p_le = pressure.eval(u, 0).pv, t_p_te = -pressure.eval(u, 1).pv;
    const Vec3 t_s_te = suction.eval(u, 0).pv, t_s_le = -suction.eval(u, 1).pv;
    // The loop from the TE apex: TE half circle (second half), suction TE ->
    // LE, LE half circle, pressure LE -> TE, TE half circle (first half).
    std::vector<Vec3> te;
    half_circle(p.back(), s.front(), -(t_p_te.normalized() + t_s_te.normalized()), 2 * o.edge_samples + 1, te);
    std::vector<Vec3> loop(te.begin() + o.edge_samples, te.end());
    te_apex.push_back(te[o.edge_samples]);
    loop.insert(loop.end(), s.begin(), s.end());
    std::vector<Vec3> le;
    half_circle(s.back(), p.front(), -(t_s_le.normalized() + t_p_le.normalized()), 2 * o.edge_samples + 1, le);
    le_apex.push_back(le[o.edge_samples]);
    loop.insert(loop.end(), le.begin(), le.end());
    loop.insert(loop.end(), p.begin(), p.end());
    loop.insert(loop.end(), te.begin(), te.begin() + o.edge_samples);
    sections.push_back(interpolate_closed_cubic(loop));
  }
  ClosedBlade out;
  out.loft = loft_sections(sections, o.loft);
  // The apexes' v on the middle section: nearest of a dense sampling, then
  // refined by golden section on the distance.
  const int mid = o.sections / 2;
  const double u_mid = out.loft.section_u[mid];
  auto nearest_v = [&](const Vec3& q) {
    constexpr int kN = 4000;
    int best = 0;
    double best_d = 1e300;
    for (int k = 0; k < kN; ++k) {
      const double d = (out.loft.surface.point(u_mid, static_cast<double>(k) / kN) - q).squaredNorm();
      if (d < best_d) best_d = d, best = k;
    }
    double a = (best - 1.0) / kN, b = (best + 1.0) / kN;
    auto f = [&](double v) { return (out.loft.surface.point(u_mid, v - std::floor(v)) - q).squaredNorm(); };
    const double g = 0.5 * (std::sqrt(5.0) - 1);
    for (int it = 0; it < 60; ++it) {
      const double x1 = b - g * (b - a), x2 = a + g * (b - a);
      if (f(x1) < f(x2)) b = x2; else a = x1;
    }
    const double v = 0.5 * (a + b);
    return v - std::floor(v);
  };
  out.le_v = nearest_v(le_apex[mid]);
  out.te_v = nearest_v(te_apex[mid]);
  const ClosedCurve& c = sections[mid];
  out.perimeter_mm = c.period();
  return out;
}

}  // namespace bliskrun
