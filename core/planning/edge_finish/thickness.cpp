// The edge's thickness after machining against the design, measured on the
// simulation's map of material left (edge_thickness, edge_finish.h).
#include <algorithm>
#include <cmath>
#include <string>

#include "core/common/error.h"
#include "core/planning/edge_finish.h"

namespace bliskrun {
namespace {

// Where the polyline pts[from], pts[from + step], ... first falls to height
// h along t, walking out from the front; false if it does not, or an
// unknown point comes first.
bool crossing(const std::vector<Vec3>& pts, const std::vector<bool>& known, const Vec3& t, double h, int from,
              int step, Vec3& at) {
  const int n = static_cast<int>(pts.size());
  if (!known[from] || pts[from].dot(t) < h) return false;
  for (int i = from; i + step >= 0 && i + step < n; i += step) {
    if (!known[i + step]) return false;
    const double a = pts[i].dot(t) - h, b = pts[i + step].dot(t) - h;
    if (b <= 0) {
      const double f = a / (a - b);
      at = pts[i] + f * (pts[i + step] - pts[i]);
      return true;
    }
  }
  return false;
}

}  // namespace

std::vector<EdgeThickness> edge_thickness(const Surface& edge, const UndercutResult& sim, const UndercutOptions& o,
                                          const std::vector<double>& spans_v, const std::vector<double>& behind_mm) {
  const int nu = sim.samples_u, nv = sim.samples_v;
  if (nu < 3 || nv < 2 || sim.residual_mm.size() != static_cast<size_t>(nu) * nv || nu != o.samples_u ||
      nv != o.samples_v)
    throw ParameterError("simulation", "a residual map of options.samples_u x samples_v (>= 3 x 2) samples");
  for (double d : behind_mm)
    if (!(d >= 0)) throw ParameterError("behind", "distances behind the front must be >= 0 mm");
  std::vector<EdgeThickness> out;
  for (double v : spans_v) {
    if (!(v >= o.v0 - 1e-12 && v <= o.v1 + 1e-12))
      throw ParameterError("spans", "span v = " + std::to_string(v) + " outside the simulated window [" +
                                        std::to_string(o.v0) + ", " + std::to_string(o.v1) + "]");
    const double fv = o.v1 > o.v0 ? (v - o.v0) / (o.v1 - o.v0) * (nv - 1) : 0.0;
    const int j0 = std::clamp(static_cast<int>(std::floor(fv)), 0, nv - 2);
    const double f = std::clamp(fv - j0, 0.0, 1.0);
    std::vector<Vec3> design(nu), machined(nu);
    std::vector<bool> all(nu, true), known(nu, true);
    for (int i = 0; i < nu; ++i) {
      const SurfaceDerivs d = edge.eval(o.u0 + (o.u1 - o.u0) * i / (nu - 1), v);
      Vec3 n = d.pu.cross(d.pv).normalized();
      if (o.flip_normal) n = -n;
      const double r0 = sim.residual_mm[static_cast<size_t>(i) * nv + j0];
      const double r1 = sim.residual_mm[static_cast<size_t>(i) * nv + j0 + 1];
      design[i] = d.p;
      known[i] = std::isfinite(r0) && std::isfinite(r1);
      machined[i] = known[i] ? Vec3(d.p + ((1 - f) * r0 + f * r1) * n) : d.p;
    }
    const Vec3 mid = 0.5 * (design.front() + design.back());
    int front = 0;
    for (int i = 1; i < nu; ++i)
      if ((design[i] - mid).norm() > (design[front] - mid).norm()) front = i;
    const Vec3 t = (design[front] - mid).normalized();
    for (int i = 0; i < nu; ++i)
      if (design[i].dot(t) > design[front].dot(t)) front = i;
    const double top = design[front].dot(t);
    for (double d : behind_mm) {
      EdgeThickness th;
      th.v = v;
      th.behind_mm = d;
      Vec3 a, b, ma, mb;
      if (crossing(design, all, t, top - d, front, -1, a) && crossing(design, all, t, top - d, front, +1, b) &&
          crossing(machined, known, t, top - d, front, -1, ma) && crossing(machined, known, t, top - d, front, +1, mb)) {
        th.measured = true;
        th.design_mm = (a - b).norm();
        th.machined_mm = (ma - mb).norm();
      }
      out.push_back(th);
    }
  }
  return out;
}

}  // namespace bliskrun
