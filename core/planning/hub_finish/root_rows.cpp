// The root strip's rows on blade k closed around its section: the fillet
// row (at every v the ball touches the hub and the blade at once), then
// closed rows at constant height above the hub up to root_top_mm, spaced by
// the ball's scallop closed form shrunk by the blade's slope to the hub;
// each row's contacts stepped by chord height along its centres' path and
// the steps halved where the solved centres stand off their chord.
#include <algorithm>
#include <cmath>
#include <functional>

#include "core/common/parallel.h"
#include "core/geometry/differential.h"
#include "core/geometry/segment.h"
#include "core/planning/hub_finish/internal.h"
#include "core/planning/repair_paths.h"

namespace bliskrun::hub_detail {

RootGeometry::RootGeometry(const HubFinishRequest& rq, const ClosedRoot& blade, double r)
    : rq(rq),
      hub(*rq.hub),
      blade(blade),
      bs(*blade.surface),
      r(r),
      v_start(wrap01(0.5 * (blade.le_v + blade.te_v) + (blade.le_v > blade.te_v ? 0 : 0.5))),
      ns(rq.row_samples),
      du_per_mm(1.0 / std::max(1e-9, bs.eval(0.5, v_start).pu.norm())) {}

double RootGeometry::height(double u, double v) const { return hub.radial_offset(bs.point(u, v)); }

Vec3 RootGeometry::centre_of(double u, double v) const {
  const SurfaceDerivs d = bs.eval(u, v);
  return Vec3(d.p + r * unit_normal(d, false));
}

double RootGeometry::fillet_gap(double u, double v) const { return hub.radial_offset(centre_of(u, v)) - r; }

double RootGeometry::root_u(double v) const {
  const double x = wrap01(v) * static_cast<double>(blade.u.size());
  const size_t i = static_cast<size_t>(x) % blade.u.size(), j = (i + 1) % blade.u.size();
  return blade.u[i] + (x - std::floor(x)) * (blade.u[j] - blade.u[i]);
}

double RootGeometry::solve_u(bool fillet, double level, double v, double guess) const {
  const double vv = wrap01(v);
  if (fillet) return solve_near([&](double u) { return fillet_gap(u, vv); }, guess, 0.05 * du_per_mm, 0, 1, "the fillet row");
  // A constant-height row where it lies above the fillet row; the fillet
  // row where that is higher (the ball would dip into the hub below it).
  const double uh = solve_near([&](double u) { return height(u, vv) - level; }, guess, 0.05 * du_per_mm, 0, 1, "a root row");
  if (level > fillet_top) return uh;
  const double uf = solve_near([&](double u) { return fillet_gap(u, vv); }, uh, 0.05 * du_per_mm, 0, 1, "the fillet row");
  return std::max(uh, uf);
}

RootRow RootGeometry::make_row(bool fillet, double level) const {
  RootRow row;
  row.level = fillet ? -1 : level;
  std::vector<Vec3> centres;
  double u = 0;
  for (int i = 0; i < ns; ++i) {
    const double v = v_start + static_cast<double>(i) / ns;
    const double guess = i == 0 ? root_u(v) + (fillet ? r : level) * du_per_mm : u;
    u = solve_u(fillet, level, v, guess);
    row.v.push_back(v);
    row.u.push_back(u);
    centres.push_back(centre_of(u, wrap01(v)));
    row.height.push_back(fillet ? height(u, wrap01(v)) : level);
  }
  row.path = interpolate_closed_cubic(centres);
  row.cum.assign(1, 0.0);
  for (int i = 0; i < ns; ++i) row.cum.push_back(row.cum.back() + (centres[(i + 1) % ns] - centres[i]).norm());
  return row;
}

std::vector<RootRow> plan_root_rows(RootGeometry& geo, HubFinishResult& res) {
  const HubFinishRequest& rq = geo.rq;
  const Surface& bs = geo.bs;
  const double r = geo.r;
  const int ns = geo.ns;
  std::vector<RootRow> root_rows;
  RootRow fillet = geo.make_row(true, 0);
  res.fillet_min_mm = 1e300;
  res.fillet_max_mm = -1e300;
  for (double h : fillet.height) res.fillet_min_mm = std::min(res.fillet_min_mm, h), res.fillet_max_mm = std::max(res.fillet_max_mm, h);
  res.root_fillet_mm = r;
  geo.fillet_top = res.fillet_max_mm + 1e-6;
  // Height step: the scallop's step on the blade (its curvature along the
  // span) times the blade's slope to the hub, smallest over the row.
  double dh = 1e300, first = 1e300;
  res.root.step_min_mm = 1e300;
  for (int i = 0; i < ns; i += 5) {
    const double v = wrap01(fillet.v[i]);
    const SurfaceDerivs d = bs.eval(fillet.u[i], v);
    const Vec3 n = unit_normal(d, false);
    const double k = -normal_curvature(d, d.pu);  // > 0 convex along the span
    const double step = 1 + r * k > 1e-6 ? ball_step_over(rq.scallop_mm, r, k) : ball_step_over(rq.scallop_mm, r, 0);
    const double c = n.dot(geo.hub.offset_direction(d.p));
    const double slope = std::sqrt(std::max(1e-6, 1 - c * c));
    dh = std::min(dh, step * slope);
    first = std::min(first, fillet.height[i] + step * slope);
    res.root.step_min_mm = std::min(res.root.step_min_mm, step);
    res.root.step_max_mm = std::max(res.root.step_max_mm, step);
  }
  for (size_t i = 0; i < fillet.v.size(); ++i) {
    res.fillet_v.push_back(wrap01(fillet.v[i]));
    res.fillet_u.push_back(fillet.u[i]);
  }
  {  // v increasing for the simulation's lookup
    std::vector<size_t> idx(res.fillet_v.size());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return res.fillet_v[a] < res.fillet_v[b]; });
    std::vector<double> fv, fu;
    for (size_t i : idx) fv.push_back(res.fillet_v[i]), fu.push_back(res.fillet_u[i]);
    res.fillet_v.swap(fv);
    res.fillet_u.swap(fu);
  }
  root_rows.push_back(std::move(fillet));
  std::vector<double> levels;
  if (first < rq.root_top_mm) {
    const int n = std::max(1, static_cast<int>(std::ceil((rq.root_top_mm - first) / dh - 1e-9)));
    for (int j = 0; j <= n; ++j) levels.push_back(first + (rq.root_top_mm - first) * j / n);
  } else {
    levels.push_back(rq.root_top_mm);
  }
  res.first_height_mm = levels.front();
  res.top_height_mm = levels.back();
  std::vector<RootRow> more(levels.size());
  parallel_for_index(levels.size(), rq.threads, [&](size_t j) { more[j] = geo.make_row(false, levels[j]); });
  for (RootRow& rr : more) root_rows.push_back(std::move(rr));
  return root_rows;
}

std::vector<Planner::Contact> root_contacts(const RootGeometry& geo, const RootRow& row, const TiltSettings& base,
                                            double& dev) {
  const HubFinishRequest& rq = geo.rq;
  const Surface& bs = geo.bs;
  const double r = geo.r;
  const int ns = geo.ns;
  // The point at arc length t of the row's centre path, its u solved
  // afresh (the path only interpolates the row's samples), and the ball's
  // centre there.
  struct At {
    double t = 0, v = 0;
    SurfaceDerivs d;
    Vec3 centre = Vec3::Zero();
  };
  auto at = [&](double t) {
    const auto it = std::upper_bound(row.cum.begin(), row.cum.end(), t);
    const size_t s = std::min<size_t>(static_cast<size_t>(std::max<long>(0, it - row.cum.begin() - 1)), ns - 1);
    const double f = std::clamp((t - row.cum[s]) / std::max(1e-12, row.cum[s + 1] - row.cum[s]), 0.0, 1.0);
    At x;
    x.t = t;
    x.v = row.v[s] + f / ns;
    const double ug = s + 1 < static_cast<size_t>(ns) ? row.u[s] + f * (row.u[s + 1] - row.u[s]) : row.u[s];
    x.d = bs.eval(geo.solve_u(row.level < 0, row.level, x.v, ug), wrap01(x.v));
    x.centre = x.d.p + r * unit_normal(x.d, false);
    return x;
  };
  // The contact there: its frame (the hub's normal says which way is up the
  // span) and tilt settings.
  auto contact_of = [&](const At& x) {
    Planner::Contact c;
    c.frame.point = x.d.p;
    c.frame.normal = unit_normal(x.d, false);
    c.centre = x.centre;
    c.t = wrap01(x.v);
    Vec3 tangent = row.path.eval(x.t).dt;
    tangent -= tangent.dot(c.frame.normal) * c.frame.normal;
    tangent.normalize();
    const Vec3 up = geo.hub.offset_direction(x.d.p);
    if (c.frame.normal.cross(tangent).dot(up) < 0) tangent = -tangent;  // Y = Z x X up the span
    c.frame.tangent = tangent;
    c.tilt = base;
    c.tilt.lead0_rad = rq.lean_rad;
    c.tilt.lead_max_rad = rq.lean_max_rad;
    c.tilt.tilt0_rad = 0;
    return c;
  };
  const RowSteps st = plan_row_steps(row.path, rq.steps);
  dev = st.max_deviation_mm;
  // The steps measure the chord against the interpolated path; the ball's
  // centre runs on the chord between the solved centres, which round an
  // edge on a tighter curve than the path through row_samples points does
  // (Rotor 67's: 1.07 um below the offset where the path measured 1.0, so
  // the motion cut the blade and split the row). A step is halved where a
  // solved centre a quarter, half or three quarters of the way lies farther
  // than the tolerance from the chord (v is not arc length around an edge:
  // the farthest centre need not be the middle one); at most kHalvings
  // times, the deviation reported the largest left. The quarter points of
  // a step are its halves' middles: solved once, passed down.
  constexpr int kHalvings = 4;
  std::vector<Planner::Contact> contacts;
  std::function<void(const At&, const At&, const At&, int)> between = [&](const At& a, const At& m, const At& b,
                                                                          int depth) {
    const At q1 = at(0.5 * (a.t + m.t)), q3 = at(0.5 * (m.t + b.t));
    double off = 0;
    for (const At* x : {&m, &q1, &q3}) off = std::max(off, distance_to_segment(x->centre, a.centre, b.centre));
    if (off <= rq.steps.chord_tol_mm || depth == kHalvings) {
      dev = std::max(dev, off);
      return;
    }
    between(a, q1, m, depth + 1);
    contacts.push_back(contact_of(m));
    between(m, q3, b, depth + 1);
  };
  At previous;
  for (size_t i = 0; i < st.t.size(); ++i) {
    const At here = at(st.t[i]);
    if (i > 0) between(previous, at(0.5 * (previous.t + here.t)), here, 0);
    contacts.push_back(contact_of(here));
    previous = here;
  }
  return contacts;
}

}  // namespace bliskrun::hub_detail
