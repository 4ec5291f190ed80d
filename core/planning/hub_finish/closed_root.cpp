// Each blade closed around its section (close_blade, core/parts/
// closed_blade.h): its root on the hub, its angular extent and the
// mid-line between its two sides; and the signed distance from it.
#include <algorithm>
#include <memory>
#include <utility>

#include "core/geometry/projection.h"
#include "core/parts/closed_blade.h"
#include "core/planning/hub_finish/internal.h"

namespace bliskrun::hub_detail {
namespace {

// The blade's section at `level` above the hub (v samples around), its
// extent and the mid-line between its two sides (split at the edges'
// apexes le_v, te_v) as theta(z).
void section_at(const Surface& s, const SurfaceOfRevolution& hub, double level, double ref_angle, ClosedRoot& out) {
  out.v.clear();
  out.u.clear();
  out.points.clear();
  constexpr int kRoot = 720;
  double u = 0.5;
  bool first = true;
  Vec3 sum = Vec3::Zero();
  for (int i = 0; i < kRoot; ++i) {
    const double v = static_cast<double>(i) / kRoot;
    auto g = [&](double uu) { return hub.radial_offset(s.point(uu, v)) - level; };
    u = first ? solve_near(g, 0.5, 0.5, 0, 1, "the hub") : solve_near(g, u, 0.005, 0, 1, "the hub");
    first = false;
    out.v.push_back(v);
    out.u.push_back(u);
    out.points.push_back(s.point(u, v));
    sum += out.points.back();
  }
  out.theta_centroid = wrap_near(angle_of(sum), ref_angle);
  // The two sides split at the edges' apexes; the mid-line at common z.
  std::vector<double> za, ta, zb, tb;
  out.theta_min = 1e300, out.theta_max = -1e300;
  out.z_min = 1e300, out.z_max = -1e300;
  const double lo = std::min(out.le_v, out.te_v), hi = std::max(out.le_v, out.te_v);
  for (int i = 0; i < kRoot; ++i) {
    const Vec3& p = out.points[i];
    const double th = wrap_near(angle_of(p), out.theta_centroid);
    out.theta_min = std::min(out.theta_min, th);
    out.theta_max = std::max(out.theta_max, th);
    out.z_min = std::min(out.z_min, p.z());
    out.z_max = std::max(out.z_max, p.z());
    if (out.v[i] > lo && out.v[i] < hi) za.push_back(p.z()), ta.push_back(th);
    else zb.push_back(p.z()), tb.push_back(th);
  }
  auto sorted = [](std::vector<double>& z, std::vector<double>& t) {
    std::vector<size_t> idx(z.size());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return z[a] < z[b]; });
    std::vector<double> z2, t2;
    for (size_t i : idx) z2.push_back(z[i]), t2.push_back(t[i]);
    z.swap(z2), t.swap(t2);
  };
  sorted(za, ta);
  sorted(zb, tb);
  auto at = [](const std::vector<double>& z, const std::vector<double>& t, double x) {
    const auto it = std::lower_bound(z.begin(), z.end(), x);
    if (it == z.begin()) return t.front();
    if (it == z.end()) return t.back();
    const size_t k = static_cast<size_t>(it - z.begin());
    const double f = (x - z[k - 1]) / std::max(1e-12, z[k] - z[k - 1]);
    return t[k - 1] + f * (t[k] - t[k - 1]);
  };
  const double z0 = std::max(za.front(), zb.front()), z1 = std::min(za.back(), zb.back());
  std::vector<double> zm, tm, wm;
  for (int i = 0; i <= 100; ++i) {
    const double z = z0 + (z1 - z0) * (0.02 + 0.96 * i / 100.0);
    zm.push_back(z);
    tm.push_back(0.5 * (at(za, ta, z) + at(zb, tb, z)));
    wm.push_back(1);
  }
  // Through the edges' apexes (the lowest and highest z of the root).
  for (int i = 0; i < kRoot; ++i) {
    const Vec3& p = out.points[i];
    if (p.z() == out.z_min || p.z() == out.z_max) {
      zm.push_back(p.z());
      tm.push_back(wrap_near(angle_of(p), out.theta_centroid));
      wm.push_back(10);
    }
  }
  out.mid = fit_poly3(zm, tm, wm);
  out.mid.z_lo = out.z_min;
  out.mid.z_hi = out.z_max;
}

}  // namespace

ClosedRoot close_root(const BladeFaces& faces, const SurfaceOfRevolution& hub, int sections, double ref_angle,
                      double top_level) {
  ClosedBladeOptions co;
  co.sections = sections;
  ClosedBlade b = close_blade(*faces.pressure, *faces.suction, co);
  ClosedRoot out;
  out.surface = std::make_shared<const BSplineSurface>(std::move(b.loft.surface));
  out.le_v = b.le_v;
  out.te_v = b.te_v;
  out.edge_kink_deg = b.edge_kink_deg;
  section_at(*out.surface, hub, 0, ref_angle, out);
  ClosedRoot top = out;
  section_at(*out.surface, hub, top_level, ref_angle, top);
  out.mid_top = top.mid;
  return out;
}

double blade_signed_distance(const Surface& s, const std::vector<double>& su, const std::vector<double>& sv,
                             const std::vector<Vec3>& sp, double lift_u, const Vec3& q) {
  size_t best = 0;
  double bd = 1e300;
  for (size_t i = 0; i < sp.size(); i += 2) {
    const double d = (sp[i] - q).squaredNorm();
    if (d < bd) bd = d, best = i;
  }
  ProjectionOptions po;
  po.seed = Eigen::Vector2d(std::min(1.0, su[best] + lift_u), sv[best]);
  SurfaceProjection pr = project_to_surface(s, q, po);
  if (!pr.ok) {
    ProjectionOptions grid;
    grid.seed_samples_u = 40;
    grid.seed_samples_v = 160;
    pr = project_to_surface(s, q, grid);
  }
  if (!pr.ok) return -1.0;
  const Vec3 nn = unit_normal(s.eval(pr.u, pr.v), false);
  return (q - pr.point).dot(nn) >= 0 ? pr.distance : -pr.distance;
}

}  // namespace bliskrun::hub_detail
