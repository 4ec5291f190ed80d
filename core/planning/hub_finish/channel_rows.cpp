// The channel floor's rows between blade k and k+1: circles of the hub at
// constant z, the ball's centre on the hub offset by r, each row the
// longest run where the ball fits between both blades; rows spaced by the
// ball's scallop closed form on the meridian; each row's contacts with the
// axis aimed at the channel's middle above the hub.
#include <algorithm>
#include <cmath>

#include "core/common/parallel.h"
#include "core/geometry/differential.h"
#include "core/planning/hub_finish/internal.h"
#include "core/planning/repair_paths.h"

namespace bliskrun::hub_detail {

FloorGeometry::FloorGeometry(const HubFinishRequest& rq, const ClosedRoot& blade, const ClosedRoot& next, double r,
                             double pitch, double lift_u)
    : rq(rq), blade(blade), next(next), r(r), pitch(pitch), lift_u(lift_u) {
  off = std::make_unique<SurfaceOfRevolution>(hub_offset_out(*rq.hub, r));
  zo0 = std::min(off->point(0, 0).z(), off->point(1, 0).z());
  zo1 = std::max(off->point(0, 0).z(), off->point(1, 0).z());
}

double FloorGeometry::signed_distance(const ClosedRoot& b, const Vec3& q) const {
  return blade_signed_distance(*b.surface, b.u, b.v, b.points, lift_u, q);
}

FloorRow FloorGeometry::row_at(double z) const {
  FloorRow fr;
  fr.z = z;
  fr.radius = off->radius_at(fr.z);
  const double e = 1e-4;
  const double za = std::max(zo0, fr.z - e), zb = std::min(zo1, fr.z + e);
  const double slope = (off->radius_at(zb) - off->radius_at(za)) / (zb - za);
  fr.normal_zr = Vec3(-slope, 1, 0).normalized();
  const double a = blade.mid(fr.z);
  const double b = a + pitch;
  fr.cell0 = a;
  fr.cell1 = b;
  auto centre = [&](double th) { return Vec3(fr.radius * std::cos(th), fr.radius * std::sin(th), fr.z); };
  // The ball's gap to each blade along the row, every 0.1 mm; the row is
  // the longest run where it fits between both, its ends found by
  // bisection to 0.1 um against the blade that ends it.
  auto gap = [&](const ClosedRoot& bl, double th) {
    const Vec3 q = centre(th);
    double near = 1e300;
    for (const Vec3& p : bl.points) near = std::min(near, (p - q).squaredNorm());
    if (near > (3 * r + 2) * (3 * r + 2)) return 1.0;  // far from this blade's root
    return signed_distance(bl, q) - r;
  };
  const int m = std::max(8, static_cast<int>(std::ceil((b - a) * fr.radius / 0.1)));
  std::vector<char> fits(static_cast<size_t>(m) + 1);
  std::vector<double> gk(fits.size()), gn(fits.size());
  for (int i = 0; i <= m; ++i) {
    const double th = a + (b - a) * i / m;
    gk[i] = gap(blade, th);
    gn[i] = gap(next, th);
    fits[i] = gk[i] >= 0 && gn[i] >= 0;
  }
  int best = -1, best_len = 0;
  for (int i = 0; i <= m;) {
    if (!fits[i]) { ++i; continue; }
    int j = i;
    while (j + 1 <= m && fits[j + 1]) ++j;
    if (j - i + 1 > best_len) best_len = j - i + 1, best = i;
    i = j + 1;
  }
  if (best < 0) {
    fr.theta0 = fr.theta1 = a;
    return fr;
  }
  const int i0 = best, i1 = best + best_len - 1;
  auto refine = [&](double inside, double outside) {
    auto ok = [&](double th) { return gap(blade, th) >= 0 && gap(next, th) >= 0; };
    for (int k = 0; k < 40 && std::abs(outside - inside) * fr.radius > 1e-7; ++k) {
      const double mid = 0.5 * (inside + outside);
      (ok(mid) ? inside : outside) = mid;
    }
    return inside;
  };
  const double t0 = a + (b - a) * i0 / m, t1 = a + (b - a) * i1 / m;
  fr.theta0 = i0 > 0 ? refine(t0, a + (b - a) * (i0 - 1) / m) : t0;
  fr.theta1 = i1 < m ? refine(t1, a + (b - a) * (i1 + 1) / m) : t1;
  return fr;
}

// Exact distances: projections on the blades, the hub's meridian.
double FloorGeometry::ball_dip(const Vec3& ca, const Vec3& cb) const {
  const SurfaceOfRevolution& hub = *rq.hub;
  double dip = 0;
  for (int k = 0; k <= 8; ++k) {
    const Vec3 q = ca + (cb - ca) * (k / 8.0);
    dip = std::max(dip, r - hub.radial_offset(q));
    for (const ClosedRoot* bl : {&blade, &next}) {
      double near = 1e300;
      for (const Vec3& p : bl->points) near = std::min(near, (p - q).squaredNorm());
      if (near < (3 * r + 2) * (3 * r + 2)) dip = std::max(dip, r - signed_distance(*bl, q));
    }
  }
  return dip;
}

std::vector<FloorRow> plan_floor_rows(const FloorGeometry& geo, double z_in, double z_out, HubFinishResult& res) {
  const HubFinishRequest& rq = geo.rq;
  const SurfaceOfRevolution& hub = *rq.hub;
  const double r = geo.r;
  const double zo0 = geo.zo0, zo1 = geo.zo1;
  const double zh0 = hub.point(0, 0).z(), zh1 = hub.point(1, 0).z();
  std::vector<FloorRow> floor_rows;
  // Centre z range: the hub's ends moved as the offset moved them.
  const double zc0 = std::max(zo0, z_in + (zo0 - std::min(zh0, zh1))) + 1e-6;
  const double zc1 = std::min(zo1, z_out + (zo1 - std::max(zh0, zh1))) - 1e-6;
  // Step along z: the scallop's step on the meridian (its curvature)
  // shrunk by the meridian's slope.
  double dz = 1e300;
  res.channel.step_min_mm = 1e300;
  for (int i = 0; i <= 20; ++i) {
    const double u = i / 20.0;
    const SurfaceDerivs d = hub.eval(u, 0);
    const bool inward = d.pu.cross(d.pv).dot(Vec3(d.p.x(), d.p.y(), 0)) < 0;
    double curv = -normal_curvature(d, d.pu);  // > 0 convex (bending away from the tool)
    if (inward) curv = -curv;
    const double slope = std::abs(d.pu.z()) > 1e-12 ? std::hypot(d.pu.x(), d.pu.y()) / std::abs(d.pu.z()) : 1e6;
    const double step = 1 + r * curv > 1e-6 ? ball_step_over(rq.scallop_mm, r, curv) : ball_step_over(rq.scallop_mm, r, 0);
    // The centres' path lies r further out: its spacing is (1 + r k) the contacts'.
    dz = std::min(dz, step * (1 + r * std::max(0.0, curv)) / std::sqrt(1 + slope * slope));
    res.channel.step_min_mm = std::min(res.channel.step_min_mm, step);
    res.channel.step_max_mm = std::max(res.channel.step_max_mm, step);
  }
  const int n = std::max(1, static_cast<int>(std::ceil((zc1 - zc0) / dz - 1e-9)));
  floor_rows.resize(static_cast<size_t>(n) + 1);
  parallel_for_index(floor_rows.size(), rq.threads,
                     [&](size_t j) { floor_rows[j] = geo.row_at(zc0 + (zc1 - zc0) * static_cast<double>(j) / n); });
  for (const FloorRow& fr : floor_rows) {
    res.floor_z.push_back(fr.z);
    res.floor_theta0.push_back(fr.theta0);
    res.floor_theta1.push_back(fr.theta1);
    res.floor_cell0.push_back(fr.cell0);
    res.floor_cell1.push_back(fr.cell1);
  }
  return floor_rows;
}

std::vector<Planner::Contact> floor_contacts(const FloorGeometry& geo, const FloorRow& fr, size_t j,
                                             const TiltSettings& base, double& dev) {
  const HubFinishRequest& rq = geo.rq;
  const SurfaceOfRevolution& hub = *rq.hub;
  const ClosedRoot& blade = geo.blade;
  const ClosedRoot& next = geo.next;
  const double r = geo.r;
  const double zh0 = hub.point(0, 0).z(), zh1 = hub.point(1, 0).z();
  std::vector<Planner::Contact> contacts;
  const ArcCurve arc(fr.radius, fr.z, fr.theta0, fr.theta1);
  const RowSteps st = plan_row_steps(arc, rq.steps);
  dev = st.max_deviation_mm;
  const bool reversed = j % 2 == 1;
  std::vector<double> ts = st.t;
  if (reversed) std::reverse(ts.begin(), ts.end());
  for (double t : ts) {
    const double th = fr.theta0 + t * (fr.theta1 - fr.theta0);
    const Vec3 radial(std::cos(th), std::sin(th), 0);
    const Vec3 n = (fr.normal_zr.y() * radial + fr.normal_zr.x() * Vec3::UnitZ()).normalized();
    Planner::Contact c;
    c.centre = arc.point(t);
    c.frame.normal = n;
    c.frame.point = c.centre - r * n;
    Vec3 x(-std::sin(th), std::cos(th), 0);  // +theta, towards blade k+1
    x -= x.dot(n) * n;
    c.frame.tangent = x.normalized();
    c.t = t;
    // The axis points at the channel's middle kTargetHeightMm above the
    // hub (between both blades' mid-lines there, at this z): it leans
    // away from the nearer blade and follows the twist. Where that is
    // not clear the lean is taken down through the normal and on to
    // the other side, then (second search) further out.
    const double th_t = 0.5 * (blade.mid_top(fr.z) + next.mid_top(fr.z));
    const double r_t = hub.radius_at(std::clamp(fr.z, std::min(zh0, zh1), std::max(zh0, zh1))) + kTargetHeightMm;
    const Vec3 target(r_t * std::cos(th_t), r_t * std::sin(th_t), fr.z);
    Vec3 a = (target - c.centre).normalized();
    if (a.dot(n) < std::cos(rq.lean_max_rad)) {  // no more than lean_max from the normal
      const Vec3 side = (a - a.dot(n) * n).normalized();
      a = std::cos(rq.lean_max_rad) * n + std::sin(rq.lean_max_rad) * side;
    }
    const Vec3 y = n.cross(c.frame.tangent);
    c.tilt = base;
    c.tilt.lead0_rad = std::asin(std::clamp(a.dot(n), -1.0, 1.0));
    c.tilt.tilt0_rad = std::atan2(-a.dot(c.frame.tangent), a.dot(y));
    c.tilt.lead_step_rad = rq.lean_step_rad;
    c.tilt.lead_max_rad = kPi / 2 + rq.lean_max_rad;
    c.second = c.tilt;
    c.second.lead_step_rad = -rq.lean_step_rad;
    c.second.lead_max_rad = kPi / 2 - rq.lean_max_rad;
    c.has_second = c.second.lead_max_rad < c.tilt.lead0_rad;
    contacts.push_back(std::move(c));
  }
  return contacts;
}

}  // namespace bliskrun::hub_detail
