// Point milling of a blade face (core/planning/point_milling.h): rows
// spaced by the measured scallop, stations by the measured chord of the
// ball centre's path, each contact tilted clear, the leans smoothed where
// the axis turns too fast per mm, the rows connected by the shared link
// builder. Reuses the hub finish's pieces (ball_cutter.h, row_steps.h,
// tilt.h, links.h, GougeGuard) rather than its code.
#include "core/planning/point_milling.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/common/error.h"
#include "core/common/parallel.h"
#include "core/common/timing.h"
#include "core/geometry/differential.h"
#include "core/geometry/interpolation.h"
#include "core/geometry/mesh.h"
#include "core/geometry/point_index.h"
#include "core/geometry/reparametrised.h"
#include "core/geometry/revolution_distance.h"
#include "core/planning/ball_cutter.h"
#include "core/planning/pass_moves.h"
#include "core/planning/repair_paths.h"
#include "core/sim/undercut.h"

namespace bliskrun {
namespace {

// Sweep step of a cutting motion's gouge check (as the hub finish's).
constexpr double kPointMillCutSweepMm = 0.15;
constexpr double kPointMillSweepTurnRad = 0.5 * kPi / 180;
// Samples across between two rows (fractions of the gap) where the scallop
// is measured, and their spacing along the rows.
constexpr int kPointMillAcross = 9;
constexpr double kPointMillAlongMm = 0.5;

// The face in row coordinates: a across the rows (the row's constant
// parameter), b along a row; the normal out of the material.
struct PointMillFace {
  const Surface& s;
  bool flip = false;
  bool along = true;  // rows along the flow: (u, v) = (a, b)
  double a0 = 0, a1 = 1, b0 = 0, b1 = 1;

  SurfaceDerivs eval(double a, double b) const { return along ? s.eval(a, b) : s.eval(b, a); }
  Vec3 normal(const SurfaceDerivs& d) const {
    const Vec3 n = d.pu.cross(d.pv);
    const double len = n.norm();
    if (!(len > 1e-14)) throw Error("point milling: the face is singular (pu x pv = 0)");
    return flip ? Vec3(-n / len) : Vec3(n / len);
  }
  Vec3 d_across(const SurfaceDerivs& d) const { return along ? d.pu : d.pv; }
  Vec3 d_along(const SurfaceDerivs& d) const { return along ? d.pv : d.pu; }
};

// The ball centre's path along a row (b -> S(a, b) + r n): derivatives by
// central differences (the face gives the normal, not its derivatives).
class PointMillCentreCurve : public Curve {
 public:
  PointMillCentreCurve(const PointMillFace& f, double a, double r) : f_(f), a_(a), r_(r) {}
  Vec3 at(double b) const {
    const SurfaceDerivs d = f_.eval(a_, b);
    return d.p + r_ * f_.normal(d);
  }
  CurveDerivs eval(double t) const override {
    constexpr double h = 1e-4;
    const double lo = std::max(f_.b0, t - h), hi = std::min(f_.b1, t + h), mid = 0.5 * (lo + hi);
    const Vec3 pl = at(lo), ph = at(hi), pm = at(mid);
    CurveDerivs c;
    c.p = at(t);
    c.dt = (ph - pl) / (hi - lo);
    const double hh = 0.5 * (hi - lo);
    c.dtt = (ph - 2 * pm + pl) / (hh * hh);
    return c;
  }
  double t_min() const override { return f_.b0; }
  double t_max() const override { return f_.b1; }

 private:
  const PointMillFace& f_;
  double a_, r_;
};

double point_mill_row_length(const PointMillFace& f, double a) {
  double len = 0;
  Vec3 prev = f.eval(a, f.b0).p;
  for (int i = 1; i <= 64; ++i) {
    const Vec3 p = f.eval(a, f.b0 + (f.b1 - f.b0) * i / 64.0).p;
    len += (p - prev).norm();
    prev = p;
  }
  return len;
}

// The row's centres every ~0.05 mm (for the scallop measurement).
std::vector<Vec3> point_mill_dense_centres(const PointMillFace& f, double a, double r) {
  const int n = std::max(50, static_cast<int>(std::ceil(point_mill_row_length(f, a) / 0.05)));
  std::vector<Vec3> out(static_cast<size_t>(n) + 1);
  const PointMillCentreCurve c(f, a, r);
  for (int i = 0; i <= n; ++i) out[static_cast<size_t>(i)] = c.at(f.b0 + (f.b1 - f.b0) * i / n);
  return out;
}

// The scallop between rows at a and a_next, measured.
double point_mill_scallop_between(const PointMillFace& f, double a, double a_next, double r, const std::vector<Vec3>& ca,
                       const std::vector<Vec3>& cb) {
  const int nb = std::max(40, static_cast<int>(std::ceil(point_mill_row_length(f, 0.5 * (a + a_next)) / kPointMillAlongMm)));
  std::vector<Vec3> pts, nrm;
  for (int j = 0; j <= nb; ++j) {
    const double b = f.b0 + (f.b1 - f.b0) * j / nb;
    for (int i = 1; i < kPointMillAcross; ++i) {
      const SurfaceDerivs d = f.eval(a + (a_next - a) * i / kPointMillAcross, b);
      pts.push_back(d.p);
      nrm.push_back(f.normal(d));
    }
  }
  return measured_scallop_mm(ca, cb, r, pts, nrm);
}

// The closed form's step (mm along the surface) from the row at a: the
// smallest over its stations (the face's normal curvature across the rows,
// > 0 convex), and the largest |dS/da| to turn it into a parameter step.
void point_mill_closed_form_step(const PointMillFace& f, double a, double h, double r, double& step_mm, double& da) {
  step_mm = std::numeric_limits<double>::infinity();
  double speed = 0;
  for (int i = 0; i <= 16; ++i) {
    const SurfaceDerivs d = f.eval(a, f.b0 + (f.b1 - f.b0) * i / 16.0);
    const Vec3 across = f.d_across(d);
    double k = -normal_curvature(d, across);
    if (f.flip) k = -k;
    const double s = 1 + r * k > 1e-6 ? ball_step_over(h, r, k) : ball_step_over(h, r, 0);
    step_mm = std::min(step_mm, s);
    speed = std::max(speed, across.norm());
  }
  da = step_mm / std::max(speed, 1e-12);
}

// The hub's meridian as a dense (z, rho) polyline with a signed distance:
// > 0 on the channel's side (the side of `channel`, a point known to be in
// it). Dense enough that its chords stand off the profile by well under a
// micron (2000 segments of a meridian some 100 mm long, curvature radii of
// millimetres and more), which is all the fillet line's solve needs.
class PointMillHubMeridian {
 public:
  PointMillHubMeridian(const SurfaceOfRevolution& hub, const Vec3& channel) {
    const Curve& c = hub.profile();
    constexpr int n = 2000;
    for (int i = 0; i <= n; ++i) {
      const double t = c.t_min() + (c.t_max() - c.t_min()) * i / n;
      const Vec3 p = c.eval(t).p;
      zr_.emplace_back(p.x(), p.y());
      t_.push_back(t);
    }
    for (size_t b = 0; b * kBlock < zr_.size() - 1; ++b) {
      Vec2 lo = zr_[b * kBlock], hi = lo;
      for (size_t i = b * kBlock; i <= std::min(zr_.size() - 1, (b + 1) * kBlock); ++i)
        lo = lo.cwiseMin(zr_[i]), hi = hi.cwiseMax(zr_[i]);
      lo_.push_back(lo), hi_.push_back(hi);
    }
    sign_ = 1;
    sign_ = signed_distance(channel) < 0 ? -1 : 1;
  }
  // Signed distance of q from the hub; `t` receives the meridian parameter
  // of the foot. The segments in blocks of kBlock with their boxes: a
  // block whose box is farther than the best so far is skipped (the
  // solves call this some hundred times per v).
  double signed_distance(const Vec3& q, double* t = nullptr) const {
    const Vec2 p(q.z(), std::hypot(q.x(), q.y()));
    double best = std::numeric_limits<double>::infinity(), side = 1, bt = 0;
    const size_t segs = zr_.size() - 1;
    // Blocks nearest first (by box distance), so the rest are mostly skipped.
    std::vector<std::pair<double, size_t>> order(lo_.size());
    for (size_t b = 0; b < lo_.size(); ++b) {
      const Vec2 d = (lo_[b] - p).cwiseMax(p - hi_[b]).cwiseMax(Vec2::Zero());
      order[b] = {d.norm(), b};
    }
    std::sort(order.begin(), order.end());
    for (const auto& [box, b] : order) {
      if (box >= best) break;
      for (size_t i = b * kBlock; i < std::min(segs, (b + 1) * kBlock); ++i) {
        const Vec2 a = zr_[i], d = zr_[i + 1] - a;
        const double dd = d.squaredNorm();
        const double s = dd > 0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
        const Vec2 e = p - (a + s * d);
        const double dist = e.norm();
        if (dist < best) {
          best = dist;
          side = d.x() * e.y() - d.y() * e.x() >= 0 ? 1 : -1;
          bt = t_[i] + s * (t_[i + 1] - t_[i]);
        }
      }
    }
    if (t) *t = bt;
    return sign_ * side * best;
  }

 private:
  static constexpr size_t kBlock = 16;
  std::vector<Vec2> zr_, lo_, hi_;
  std::vector<double> t_;
  double sign_ = 1;
};

// The face trimmed at the fillet line: p(u_f(v) + a (u1 - u_f(v)), v), u_f
// a cubic through the line's samples over the window [v0, v1] (derivatives
// by the chain rule, as TrimmedSurface's; its boundary is fitted over the
// whole [0, 1] and the window's line need not exist outside it).
class PointMillFilletFace : public Surface {
 public:
  PointMillFilletFace(std::shared_ptr<const Surface> base, const std::vector<double>& v, const std::vector<double>& u,
                      double u1)
      : base_(std::move(base)), v0_(v.front()), v1_(v.back()), u1_(u1) {
    std::vector<Vec3> pts;
    std::vector<double> t;
    for (size_t i = 0; i < v.size(); ++i) {
      pts.emplace_back(u[i], 0, 0);
      t.push_back((v[i] - v0_) / (v1_ - v0_));
    }
    fit_ = interpolate_cubic(pts, t);
  }
  // u_f(v), du_f/dv, d2u_f/dv2.
  void line(double v, double& u, double& du, double& ddu) const {
    const double w = v1_ - v0_;
    const CurveDerivs d = fit_.eval(std::clamp((v - v0_) / w, 0.0, 1.0));
    u = d.p.x(), du = d.dt.x() / w, ddu = d.dtt.x() / (w * w);
  }
  double base_u(double a, double v) const {
    double uf = 0, du = 0, ddu = 0;
    line(v, uf, du, ddu);
    return uf + a * (u1_ - uf);
  }
  SurfaceDerivs eval(double a, double v) const override {
    double lo = 0, dlo = 0, ddlo = 0;
    line(v, lo, dlo, ddlo);
    const double w = u1_ - lo, dw = -dlo, ddw = -ddlo;
    const double U = lo + a * w, Uv = dlo + a * dw, Uvv = ddlo + a * ddw;
    return chain_trimmed_u(base_->eval(U, v), w, dw, Uv, Uvv);
  }

 private:
  std::shared_ptr<const Surface> base_;
  double v0_, v1_, u1_;
  BSplineCurve fit_;
};

Vec3 point_mill_unit_normal(const SurfaceDerivs& d, bool flip) {
  const Vec3 n = d.pu.cross(d.pv).normalized();
  return flip ? Vec3(-n) : n;
}

// The fillet line at v: the lowest u of [u_lo, u_hi] where the ball on the
// face (centre p + r n) is r from the hub — it touches both. Scanned up
// from u_lo in steps of ~r/8 along the face, then bisected; u_lo itself
// where the ball there is already clear of the hub.
double point_mill_fillet_u(const Surface& s, bool flip, double v, double r, const PointMillHubMeridian& hub,
                           double u_lo, double u_hi) {
  auto gap = [&](double u) {
    const SurfaceDerivs d = s.eval(u, v);
    return hub.signed_distance(d.p + r * point_mill_unit_normal(d, flip)) - r;
  };
  double a = u_lo, ga = gap(a);
  if (ga >= 0) return u_lo;
  while (a < u_hi) {
    const double step = 0.125 * r / std::max(s.eval(a, v).pu.norm(), 1e-12);
    const double b = std::min(u_hi, a + step), gb = gap(b);
    if (gb >= 0) {
      double lo = a, hi = b;
      for (int k = 0; k < 60 && hi - lo > 1e-12; ++k) {
        const double m = 0.5 * (lo + hi);
        (gap(m) >= 0 ? hi : lo) = m;
      }
      return hi;
    }
    a = b, ga = gb;
  }
  std::ostringstream os;
  os << "point milling: the ball (r " << r << " mm) does not clear the hub anywhere on the face between u " << u_lo
     << " and " << u_hi << " at v " << v << " (no fillet line: is the hub the face's?)";
  throw Error(os.str());
}

struct PointMillFillet {
  std::shared_ptr<const PointMillFilletFace> face;
  std::vector<double> v, u;  // the line's samples
};

PointMillFillet point_mill_fillet(const PointMillRequest& rq, double r) {
  const Surface& s = *rq.face.surface;
  const SurfaceDerivs top = s.eval(rq.u1, 0.5 * (rq.v0 + rq.v1));
  const PointMillHubMeridian hub(*rq.hub, top.p + r * point_mill_unit_normal(top, rq.face.flip_normal));
  auto solve = [&](double v) { return point_mill_fillet_u(s, rq.face.flip_normal, v, r, hub, rq.u0, rq.u1); };
  auto gap = [&](double u, double v) {
    const SurfaceDerivs d = s.eval(u, v);
    return hub.signed_distance(d.p + r * point_mill_unit_normal(d, rq.face.flip_normal)) - r;
  };
  PointMillFillet out;
  const int n = std::max(4, rq.fillet_samples);
  out.v.resize(static_cast<size_t>(n));
  out.u.resize(static_cast<size_t>(n));
  parallel_for_index(static_cast<size_t>(n), rq.threads, [&](size_t i) {
    out.v[i] = rq.v0 + (rq.v1 - rq.v0) * static_cast<double>(i) / (n - 1);
    out.u[i] = solve(out.v[i]);
  });
  // The cubic through the samples is measured between them: where its
  // ball stands off the hub by more than a fifth of the allowed overcut
  // (into it, or above it: material left in the strip), the midpoint is
  // solved and added, until none does (a real hub's fillet line turns
  // sharply near the edges: 41 samples put the HECC ball 17 um into it).
  const double tol = 0.2 * rq.allowed_overcut_mm;
  for (int round = 0; round < 12; ++round) {
    out.face = std::make_shared<const PointMillFilletFace>(rq.face.surface, out.v, out.u, rq.u1);
    const size_t m = out.v.size() - 1;
    std::vector<char> split(m, 0);
    std::vector<double> mid_u(m, 0);
    parallel_for_index(m, rq.threads, [&](size_t i) {
      for (double f : {0.25, 0.5, 0.75}) {
        const double v = out.v[i] + f * (out.v[i + 1] - out.v[i]);
        if (std::abs(gap(out.face->base_u(0, v), v)) > tol) split[i] = 1;
      }
      if (split[i]) mid_u[i] = solve(0.5 * (out.v[i] + out.v[i + 1]));
    });
    if (std::find(split.begin(), split.end(), 1) == split.end()) break;
    std::vector<double> nv{out.v.front()}, nu{out.u.front()};
    for (size_t i = 0; i < m; ++i) {
      if (split[i]) nv.push_back(0.5 * (out.v[i] + out.v[i + 1])), nu.push_back(mid_u[i]);
      nv.push_back(out.v[i + 1]), nu.push_back(out.u[i + 1]);
    }
    out.v = std::move(nv), out.u = std::move(nu);
    if (round == 11 || out.v.size() > 20000)
      throw Error("point milling: the fillet line does not settle to a cubic within " + std::to_string(tol * 1000) +
                  " um of the hub (" + std::to_string(out.v.size()) + " samples)");
  }
  return out;
}

// The hub's window along the fillet line, as a guarded surface: the hub
// turned about Z so that the window's middle angle is v = 1/2 (a surface of
// revolution turned about its axis is itself; the turn keeps the window off
// the seam at v = 0), its meridian window the feet of the fillet balls
// +- pad_mm, its angle window the same.
struct PointMillHubGuardSurface {
  std::shared_ptr<const Surface> surface;
  double u0 = 0, u1 = 1, v0 = 0, v1 = 1;
  bool flip = false;
};

PointMillHubGuardSurface point_mill_hub_guard(const PointMillRequest& rq, const PointMillFillet& fl, double r,
                                              double pad_mm) {
  const Surface& s = *rq.face.surface;
  const SurfaceDerivs top = s.eval(rq.u1, 0.5 * (rq.v0 + rq.v1));
  const PointMillHubMeridian hub(*rq.hub, top.p + r * point_mill_unit_normal(top, rq.face.flip_normal));
  std::vector<double> ts, angles;
  double rho_min = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < fl.v.size(); ++i) {
    const SurfaceDerivs d = s.eval(fl.u[i], fl.v[i]);
    const Vec3 c = d.p + r * point_mill_unit_normal(d, rq.face.flip_normal);
    double t = 0;
    hub.signed_distance(c, &t);
    ts.push_back(t);
    angles.push_back(std::atan2(c.y(), c.x()));
    rho_min = std::min(rho_min, std::hypot(c.x(), c.y()));
  }
  // The angles unwrapped about the first.
  for (double& a : angles) a = angles.front() + std::remainder(a - angles.front(), 2 * kPi);
  const double amin = *std::min_element(angles.begin(), angles.end()),
               amax = *std::max_element(angles.begin(), angles.end());
  const double mid = 0.5 * (amin + amax);
  PointMillHubGuardSurface g;
  // RotatedSurface turns p(u, v) by the angle: v = 1/2 (angle pi) lands on mid.
  g.surface = std::make_shared<const RotatedSurface>(rq.hub, mid - kPi);
  const double dv = (0.5 * (amax - amin) + pad_mm / std::max(rho_min - pad_mm, 1.0)) / (2 * kPi);
  g.v0 = std::max(0.0, 0.5 - dv), g.v1 = std::min(1.0, 0.5 + dv);
  const Curve& prof = rq.hub->profile();
  double speed = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= 32; ++i) {
    const double t = prof.t_min() + (prof.t_max() - prof.t_min()) * i / 32.0;
    speed = std::min(speed, prof.eval(t).dt.norm());
  }
  const double dt = pad_mm / std::max(speed, 1e-9);
  const double tmin = *std::min_element(ts.begin(), ts.end()), tmax = *std::max_element(ts.begin(), ts.end());
  g.u0 = std::max(prof.t_min(), tmin - dt), g.u1 = std::min(prof.t_max(), tmax + dt);
  // Out of the material: towards the first fillet ball's centre.
  const SurfaceDerivs d0 = s.eval(fl.u.front(), fl.v.front());
  const Vec3 c0 = d0.p + r * point_mill_unit_normal(d0, rq.face.flip_normal);
  double t0 = 0;
  hub.signed_distance(c0, &t0);
  const double a0 = angles.front() - (mid - kPi);
  const SurfaceDerivs h = g.surface->eval(t0, a0 / (2 * kPi));
  g.flip = h.pu.cross(h.pv).dot(c0 - h.p) < 0;
  return g;
}


struct PointMillGuards {
  std::vector<std::unique_ptr<GougeGuard>> guards;  // face first
  std::vector<std::string> names;
  double margin = 0;
};

struct PointMillPlanner {
  const PointMillRequest& rq;
  const PointMillFace& f;
  const CollisionWorld& world;
  const ToolBody& body;
  const PointMillGuards& g;
  double r = 0, lean_min = 0, pose_allowed = 0;
  StepOptions steps;
  const PointMillFilletFace* fillet = nullptr;  // following the fillet: f is the face trimmed there

  std::string gouge(const ToolPose& p) const {
    for (size_t i = 0; i < g.guards.size(); ++i) {
      const GougeGuard::Cut c = g.guards[i]->deepest_cut(*rq.tool, p, p, pose_allowed, true, true);
      if (c.depth_mm < 0) {
        std::ostringstream os;
        os << "the cutter cuts " << -c.depth_mm * 1000 << " um into " << g.names[i] << " at (" << c.point.x()
           << ", " << c.point.y() << ", " << c.point.z() << ")";
        return os.str();
      }
    }
    return "";
  }
  bool motion_dips(const ToolPose& a, const ToolPose& b) const {
    // The ball's centre runs on its chord (measured); what the turn of the
    // axis moves is the cone beside it, swept through the guards.
    if (PoseMotion(a, b).angle_rad() <= kPointMillSweepTurnRad) return false;
    for (const auto& gd : g.guards)
      if (gd->deepest_cut(*rq.tool, a, b, pose_allowed, false, false, kPointMillCutSweepMm).depth_mm < 0) return true;
    return false;
  }

  struct Contact {
    ContactFrame frame;
    Vec3 centre = Vec3::Zero();
    double u = 0, v = 0, s_mm = 0, lean0 = 0, tilt0 = 0;
  };

  std::vector<Contact> contacts(double a, bool reversed, double& dev, int& stations) const {
    const PointMillCentreCurve curve(f, a, r);
    const RowSteps st = plan_row_steps(curve, steps);
    dev = st.max_deviation_mm;
    stations = static_cast<int>(st.t.size());
    std::vector<double> ts = st.t;
    if (reversed) std::reverse(ts.begin(), ts.end());
    std::vector<Contact> out;
    double s = 0;
    for (size_t i = 0; i < ts.size(); ++i) {
      const SurfaceDerivs d = f.eval(a, ts[i]);
      Contact c;
      c.frame.point = d.p;
      c.frame.normal = f.normal(d);
      c.centre = d.p + r * c.frame.normal;
      c.u = f.along ? a : ts[i];
      c.v = f.along ? ts[i] : a;
      if (fillet) c.u = fillet->base_u(c.u, c.v);  // the face's own u
      // Y = Z x X up the span (the face's +u, towards the shroud side).
      Vec3 up = d.pu - d.pu.dot(c.frame.normal) * c.frame.normal;
      up.normalize();
      c.frame.tangent = up.cross(c.frame.normal);
      Vec3 feed = f.d_along(d) * (reversed ? -1.0 : 1.0);
      if (i > 0) s += (d.p - out.back().frame.point).norm();
      c.s_mm = s;
      // Positive lead tips the tool's top towards the feed.
      if (f.along) {
        c.lean0 = rq.lean_rad;
        c.tilt0 = feed.dot(c.frame.tangent) < 0 ? rq.lead_rad : -rq.lead_rad;
      } else {
        c.lean0 = std::max(lean_min, rq.lean_rad + (feed.dot(up) > 0 ? -rq.lead_rad : rq.lead_rad));
        c.tilt0 = 0;
      }
      out.push_back(c);
    }
    return out;
  }

  TiltSettings settings(const Contact& c, double lean0) const {
    TiltSettings t;
    t.lead0_rad = lean0;
    t.lead_step_rad = rq.lean_step_rad;
    t.lead_max_rad = std::max(lean0, rq.lean_max_rad);
    t.tilt0_rad = c.tilt0;
    t.allow_tilt = rq.side_tilt_rad > 0;
    t.tilt_step_rad = rq.side_step_rad;
    t.tilt_range_rad = rq.side_tilt_rad;
    t.clearances = rq.clearances;
    t.motion_tol_mm = rq.motion_tol_mm;
    t.axis_limit = rq.axis_limit;
    t.pose_filter = [this](const ToolPose& p) { return gouge(p); };
    return t;
  }

  // One row's contacts into passes (refusals and dipping motions split it).
  struct RowPlan {
    std::vector<PointMillPass> passes;
    std::vector<PointMillRefusal> refusals;
    std::vector<double> leans;  // per contact, NaN where refused
    int splits = 0;
  };
  RowPlan plan(int row, double level, bool reversed, const std::vector<Contact>& cs,
               const std::vector<double>& lean0, Progress& progress) const {
    RowPlan out;
    out.leans.assign(cs.size(), std::numeric_limits<double>::quiet_NaN());
    PointMillPass cur;
    cur.row = row;
    cur.level = level;
    cur.reversed = reversed;
    auto close = [&] {
      if (!cur.poses.empty()) out.passes.push_back(cur);
      cur.poses.clear();
    };
    for (size_t i = 0; i < cs.size(); ++i) {
      progress.check();
      const Contact& c = cs[i];
      const ToolPose* prev = cur.poses.empty() ? nullptr : &cur.poses.back().pose;
      const TiltOutcome o = tilt_until_clear(world, body, c.frame, static_cast<int>(i), settings(c, lean0[i]), prev);
      if (!o.accepted) {
        out.refusals.push_back({row, c.frame.point, o.refusal.reason});
        close();
        continue;
      }
      PointMillPose pp;
      pp.pose = o.pose.pose;
      pp.contact = c.frame.point;
      pp.normal = c.frame.normal;
      pp.centre = c.centre;
      pp.u = c.u;
      pp.v = c.v;
      pp.lean_rad = o.pose.lead_rad;
      pp.tilted = o.pose.tries > 1;
      out.leans[i] = o.pose.lead_rad;
      if (prev && motion_dips(*prev, pp.pose)) {
        ++out.splits;
        out.refusals.push_back({row, c.frame.point, "the cutting motion from the previous contact dips below the design: row split"});
        close();
      }
      cur.poses.push_back(pp);
    }
    close();
    return out;
  }
};

double point_mill_turn_per_mm(const PointMillPose& a, const PointMillPose& b) {
  const double d = (b.contact - a.contact).norm();
  const double ang = std::acos(std::clamp(a.pose.axis.dot(b.pose.axis), -1.0, 1.0));
  return d > 1e-9 ? ang / d : (ang > 1e-9 ? std::numeric_limits<double>::infinity() : 0.0);
}

LinkEnd point_mill_end(const PointMillPose& p) { return LinkEnd{p.pose, p.normal}; }

}  // namespace

double measured_scallop_mm(const std::vector<Vec3>& row_a, const std::vector<Vec3>& row_b, double r,
                           const std::vector<Vec3>& samples, const std::vector<Vec3>& normals, double step_mm) {
  if (samples.size() != normals.size()) throw ParameterError("normals", "one per sample");
  std::vector<Vec3> balls;
  for (const std::vector<Vec3>* row : {&row_a, &row_b}) {
    for (size_t i = 0; i < row->size(); ++i) {
      if (i == 0) {
        balls.push_back((*row)[0]);
        continue;
      }
      const Vec3 a = (*row)[i - 1], b = (*row)[i];
      const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step_mm)));
      for (int k = 1; k <= n; ++k) balls.push_back(a + (b - a) * (static_cast<double>(k) / n));
    }
  }
  const double r2 = r * r;
  double worst = 0;
  for (size_t s = 0; s < samples.size(); ++s) {
    const Vec3& p = samples[s];
    const Vec3& n = normals[s];
    double low = std::numeric_limits<double>::infinity();
    for (const Vec3& c : balls) {
      const Vec3 d = c - p;
      const double along = d.dot(n);
      const double perp2 = d.squaredNorm() - along * along;
      if (perp2 >= r2) continue;
      low = std::min(low, along - std::sqrt(r2 - perp2));
    }
    worst = std::max(worst, low);
  }
  return worst;
}

CollisionWorld point_mill_world(const PointMillRequest& rq) {
  if (!rq.face.surface) throw ParameterError("face", "the face milled is required");
  CollisionWorld w;
  PartMask no_cutter;
  no_cutter.cutter = false;
  w.add(rq.face.name.empty() ? "face (shank)" : rq.face.name + " (shank)", tessellate(*rq.face.surface, 0.05),
        CheckSurfaceOptions{no_cutter, 0.05});
  for (const PointMillSurface& n : rq.neighbours) {
    if (!n.surface) throw ParameterError("neighbours", "a neighbour has no surface");
    w.add(n.name, tessellate(*n.surface, rq.mesh_tol_mm));
  }
  // The hub, analytically: following the fillet the ball touches it by
  // design (the planner's hub guard proves the cutter), so the shank and
  // holder only; else every part.
  if (rq.hub) {
    PartMask mask;
    mask.cutter = !rq.follow_fillet;
    w.add("hub", std::make_shared<const RevolutionDistance>(*rq.hub, 1e-3), CheckSurfaceOptions{mask, 0});
  }
  return w;
}

PointMillResult plan_point_milling(const PointMillRequest& rq, Progress& progress) {
  const auto t0 = SteadyClock::now();
  if (!rq.face.surface) throw ParameterError("face", "the face milled is required");
  if (!rq.tool) throw ParameterError("tool", "a ball or tapered ball end is required");
  if (rq.tool->kind() != ToolKind::BallEndMill && rq.tool->kind() != ToolKind::TaperedBallEndMill)
    throw ParameterError("tool", "point milling needs a ball or tapered ball end");
  if (!(rq.scallop_mm > 0)) throw ParameterError("scallop", "must be > 0 mm");
  if (!(rq.steps.chord_tol_mm > 0)) throw ParameterError("chord_tol", "must be > 0 mm");
  if (!(rq.u0 < rq.u1) || !(rq.v0 < rq.v1) || rq.u0 < 0 || rq.v0 < 0 || rq.u1 > 1 || rq.v1 > 1)
    throw ParameterError("window", "needs 0 <= u0 < u1 <= 1 and 0 <= v0 < v1 <= 1");
  if (!(rq.max_turn_rad_per_mm > 0)) throw ParameterError("max_turn", "must be > 0 deg/mm");
  PointMillResult res;
  const double r = ball_radius(*rq.tool);
  res.ball_radius_mm = r;
  res.taper_rad = rq.tool->kind() == ToolKind::TaperedBallEndMill ? taper_rad(*rq.tool) : 0.0;
  if (!(rq.lean_rad > res.taper_rad))
    throw ParameterError("lean", "must exceed the taper's half angle (the cone would lie on the face)");

  const bool along = rq.rows == PointMillRows::AlongFlow;
  // Following the fillet, the rows are planned on the face trimmed at the
  // fillet line (window u [0, 1]); else on the face from the hub stop up.
  PointMillFillet fillet;
  double u_start = 0, u_top = rq.u1;
  if (rq.hub && rq.follow_fillet) {
    fillet = point_mill_fillet(rq, r);
    res.follows_fillet = true;
    res.fillet_u_min = *std::min_element(fillet.u.begin(), fillet.u.end());
    res.fillet_u_max = *std::max_element(fillet.u.begin(), fillet.u.end());
    if (!(res.fillet_u_max < rq.u1)) throw ParameterError("u", "the fillet line reaches the window's top: nothing to mill");
    res.first_row_u = res.fillet_u_min;
    res.milled_surface = fillet.face;
    u_start = 0, u_top = 1;
  } else {
    // The hub-side boundary: u0 raised by hub_stop_mm along the face (the
    // smallest |pu| of the window's u0 edge, so every contact is at least
    // that far up).
    const double stop = rq.hub_stop_mm < 0 ? r : rq.hub_stop_mm;
    double min_pu = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= 16; ++i) min_pu = std::min(min_pu, rq.face.surface->eval(rq.u0, rq.v0 + (rq.v1 - rq.v0) * i / 16.0).pu.norm());
    u_start = rq.u0 + stop / std::max(min_pu, 1e-12);
    if (!(u_start < rq.u1)) throw ParameterError("hub_stop", "leaves nothing of the window to mill");
    res.first_row_u = u_start;
    res.milled_surface = rq.face.surface;
  }
  res.milled_u0 = u_start, res.milled_u1 = u_top;
  PointMillFace f{*res.milled_surface, rq.face.flip_normal, along, 0, 1, 0, 1};
  if (along) f.a0 = u_start, f.a1 = u_top, f.b0 = rq.v0, f.b1 = rq.v1;
  else f.a0 = rq.v0, f.a1 = rq.v1, f.b0 = u_start, f.b1 = u_top;

  // ---- rows: the closed form, then measured and tightened ----
  std::vector<double> levels{f.a0};
  res.rows.push_back(PointMillRow{f.a0});
  std::vector<Vec3> prev_c = point_mill_dense_centres(f, f.a0, r);
  while (levels.back() < f.a1) {
    progress.check();
    const double a = levels.back();
    double step_mm = 0, da = 0;
    point_mill_closed_form_step(f, a, rq.scallop_mm, r, step_mm, da);
    PointMillRow row;
    row.closed_form_step_mm = step_mm;
    double next = 0, measured = 0;
    std::vector<Vec3> next_c;
    for (int tries = 0;; ++tries) {
      next = std::min(a + da, f.a1);
      next_c = point_mill_dense_centres(f, next, r);
      measured = point_mill_scallop_between(f, a, next, r, prev_c, next_c);
      if (measured <= rq.scallop_mm) break;
      if (tries > 30) throw Error("point milling: the scallop between rows does not close (rows " +
                                  std::to_string(a) + ")");
      da *= std::clamp(0.95 * std::sqrt(rq.scallop_mm / measured), 0.3, 0.95);
    }
    row.level = next;
    row.scallop_mm = measured;
    double speed = 0;
    for (int i = 0; i <= 8; ++i) speed += f.d_across(f.eval(0.5 * (a + next), f.b0 + (f.b1 - f.b0) * i / 8.0)).norm() / 9;
    row.step_mm = (next - a) * speed;
    res.scallop_max_mm = std::max(res.scallop_max_mm, measured);
    // The closed form's scallop at the step taken: h = r - sqrt(r^2 - s^2/4) on a plane.
    const double half = 0.5 * row.step_mm;
    res.scallop_closed_form_mm = std::max(res.scallop_closed_form_mm, r - std::sqrt(std::max(0.0, r * r - half * half)));
    levels.push_back(next);
    res.rows.push_back(row);
    prev_c = std::move(next_c);
  }

  // ---- what is proved against ----
  PointMillGuards guards;
  std::vector<const PointMillSurface*> guarded{&rq.face};
  for (const PointMillSurface& n : rq.neighbours) guarded.push_back(&n);
  // Following the fillet the ball touches the hub: its window along the
  // fillet line guarded as the face is (3 r and 2 mm beyond the balls' feet).
  PointMillHubGuardSurface hub_guard;
  if (res.follows_fillet) hub_guard = point_mill_hub_guard(rq, fillet, r, 3 * r + 2);
  const size_t n_guards = guarded.size() + (res.follows_fillet ? 1 : 0);
  guards.guards.resize(n_guards);
  guards.names.resize(n_guards);
  CollisionWorld own_world;
  parallel_for_index(n_guards + 1, rq.threads, [&](size_t i) {
    if (i < guarded.size()) {
      const PointMillSurface& s = *guarded[i];
      guards.guards[i] = std::make_unique<GougeGuard>(*s.surface, link_guard_sampling(*s.surface, rq.guard_spacing_mm, s.flip_normal));
      guards.names[i] = s.name.empty() ? (i == 0 ? "the face" : "a neighbour") : s.name;
    } else if (i < n_guards) {
      UndercutOptions o = guard_sampling(*hub_guard.surface, rq.guard_spacing_mm, hub_guard.u0, hub_guard.u1,
                                         hub_guard.v0, hub_guard.v1);
      o.flip_normal = hub_guard.flip;
      o.search_below_mm = 0.02;  // as link_guard_sampling's
      o.sweep_step_mm = 0.02;
      o.threads = 1;
      guards.guards[i] = std::make_unique<GougeGuard>(*hub_guard.surface, o);
      guards.names[i] = "the hub";
    } else if (!rq.world) {
      own_world = point_mill_world(rq);
    }
  });
  for (const auto& g : guards.guards) guards.margin = std::max(guards.margin, g->between_samples_mm(r));
  const CollisionWorld& world = rq.world ? *rq.world : own_world;
  const ToolBody body(*rq.tool, rq.tool_tol_mm);
  PointMillPlanner pl{rq, f, world, body, guards, r, res.taper_rad + 0.5 * kPi / 180,
                      rq.allowed_overcut_mm - guards.margin, rq.steps, fillet.face.get()};
  if (!(pl.pose_allowed > 0))
    throw ParameterError("guard_spacing", "the guards' samples miss more than the allowed overcut: sample closer");
  // On a convex face the centre's chord runs inside its path: the ball cuts
  // up to the chord deviation below the design between poses, so the steps
  // keep it under what a cutting motion may cut.
  pl.steps = rq.steps;
  pl.steps.chord_tol_mm = std::min(rq.steps.chord_tol_mm, 0.9 * pl.pose_allowed);
  res.chord_tol_mm = pl.steps.chord_tol_mm;

  // ---- rows into passes, on the workers ----
  const size_t n_rows = levels.size();
  std::vector<PointMillPlanner::RowPlan> plans(n_rows);
  std::vector<int> smoothed(n_rows, 0), stations(n_rows, 0);
  std::vector<double> devs(n_rows, 0);
  run_parallel(n_rows, rq.threads, progress, "point milling rows", [&](size_t k, Progress& own) {
    const bool reversed = k % 2 == 1;  // zigzag
    const std::vector<PointMillPlanner::Contact> cs = pl.contacts(levels[k], reversed, devs[k], stations[k]);
    std::vector<double> lean0(cs.size());
    for (size_t i = 0; i < cs.size(); ++i) lean0[i] = cs[i].lean0;
    PointMillPlanner::RowPlan p = pl.plan(static_cast<int>(k), levels[k], reversed, cs, lean0, own);
    // Smoothness: where the axis turns faster than allowed per mm, raise
    // the leans to their envelope and plan the row again from them.
    bool fast = false;
    for (const PointMillPass& pass : p.passes)
      for (size_t i = 1; i < pass.poses.size(); ++i)
        if (point_mill_turn_per_mm(pass.poses[i - 1], pass.poses[i]) > rq.max_turn_rad_per_mm) fast = true;
    if (fast) {
      std::vector<double> env(cs.size());
      for (size_t i = 0; i < cs.size(); ++i) {
        env[i] = lean0[i];
        for (size_t j = 0; j < cs.size(); ++j)
          if (!std::isnan(p.leans[j]))
            env[i] = std::max(env[i], p.leans[j] - rq.max_turn_rad_per_mm * std::abs(cs[i].s_mm - cs[j].s_mm));
      }
      p = pl.plan(static_cast<int>(k), levels[k], reversed, cs, env, own);
      smoothed[k] = 1;
    }
    plans[k] = std::move(p);
  });
  for (size_t k = 0; k < n_rows; ++k) {
    res.rows[k].max_deviation_mm = devs[k];
    res.rows[k].stations = stations[k];
    res.max_deviation_mm = std::max(res.max_deviation_mm, devs[k]);
    res.smoothed_rows += smoothed[k];
    res.gouge_splits += plans[k].splits;
    for (PointMillPass& p : plans[k].passes) res.passes.push_back(std::move(p));
    for (PointMillRefusal& x : plans[k].refusals) res.refusals.push_back(std::move(x));
  }
  for (const PointMillPass& p : res.passes) {
    res.poses += static_cast<int>(p.poses.size());
    for (size_t i = 0; i < p.poses.size(); ++i) {
      res.tilted += p.poses[i].tilted;
      if (i > 0) res.max_turn_rad_per_mm = std::max(res.max_turn_rad_per_mm, point_mill_turn_per_mm(p.poses[i - 1], p.poses[i]));
    }
  }

  // ---- steps, links and leads ----
  LinkChecks checks;
  checks.world = &world;
  checks.body = &body;
  checks.clearances = rq.clearances;
  checks.motion_tol_mm = rq.motion_tol_mm;
  checks.guard = guards.guards[0].get();
  checks.guard_margin_mm = guards.margin;
  for (size_t i = 1; i < guards.guards.size(); ++i) checks.more_guards.push_back({guards.guards[i].get(), guards.margin});
  LinkOptions lo = rq.links;
  lo.allowed_overcut_mm = rq.allowed_overcut_mm;
  const int np = static_cast<int>(res.passes.size());
  if (np > 0) {
    res.connections.resize(static_cast<size_t>(np) + 1);
    auto departure = [&](const PointMillPose& p, int from, int to) {
      PointMillConnection c;
      c.kind = PointMillConnection::Kind::Departure;
      c.from_pass = from;
      c.to_pass = to;
      const PlannedDeparture d = plan_departure(point_mill_end(p), checks, lo);
      c.clear = d.clear;
      if (d.clear) c.poses = {d.away}, c.motion = {from < 0 ? "start" : "retract"};
      else c.reason = std::string(from < 0 ? "lead-in: " : "lead-out: ") + d.reason;
      return c;
    };
    res.connections.front() = departure(res.passes.front().poses.front(), -1, 0);
    res.connections.back() = departure(res.passes.back().poses.back(), np - 1, -1);
    parallel_for_index(static_cast<size_t>(np - 1), rq.threads, [&](size_t pi) {
      progress.check();
      const PointMillPass &a = res.passes[pi], &b = res.passes[pi + 1];
      PointMillConnection c;
      c.from_pass = static_cast<int>(pi);
      c.to_pass = static_cast<int>(pi) + 1;
      // Consecutive rows of the zigzag: a straight step along the face,
      // cutting, proved as a link's legs are.
      if (b.row == a.row + 1 && (b.poses.front().centre - a.poses.back().centre).norm() < 4 * r) {
        const ChainProof proof = prove_chain({a.poses.back().pose, b.poses.front().pose}, checks,
                                             rq.allowed_overcut_mm, true, true);
        if (proof.clear) {
          c.kind = PointMillConnection::Kind::Step;
          c.clear = true;
          res.connections[pi + 1] = std::move(c);
          return;
        }
      }
      c.kind = PointMillConnection::Kind::Link;
      const PlannedLink link = plan_link(point_mill_end(a.poses.back()), point_mill_end(b.poses.front()), checks, lo);
      c.clear = link.clear;
      if (link.clear) {
        c.poses = link.via;
        for (size_t i = 0; i < link.via.size(); ++i) c.motion.push_back(link_leg_name(link.legs[i]));
      } else {
        c.reason = "link from pass " + std::to_string(pi) + " to " + std::to_string(pi + 1) + ": " + link.reason;
      }
      res.connections[pi + 1] = std::move(c);
    });
    for (const PointMillConnection& c : res.connections) {
      if (!c.clear) ++res.refused_connections;
      else if (c.kind == PointMillConnection::Kind::Step) ++res.steps;
      else if (c.kind == PointMillConnection::Kind::Link) ++res.links;
    }
  }
  res.seconds = seconds_since(t0);
  return res;
}

Toolpath point_mill_moves(const PointMillResult& r) { return passes_to_moves(r.passes, r.connections); }

namespace {

// The nearest ball of a program's moves: the ball centre's segments cut
// into pieces no longer than kPointMillStripPieceMm, their midpoints in a
// PointIndex. The distance to a piece is at most the distance to its
// midpoint, and a piece nearer than d has its midpoint within d + half the
// longest piece: so the nearest midpoint bounds the search box, and every
// piece in it is measured exactly.
constexpr double kPointMillStripPieceMm = 0.5;

class PointMillBallDistance {
 public:
  explicit PointMillBallDistance(const Toolpath& moves, double r) {
    std::vector<Vec3> mids;
    for (const std::vector<ToolPose>& pass : toolpath_passes(moves).passes)
      for (size_t i = 0; i < pass.size(); ++i) {
        const Vec3 c = pass[i].tip + r * pass[i].axis;
        const Vec3 b = i == 0 ? c : Vec3(pass[i - 1].tip + r * pass[i - 1].axis);
        const int n = std::max(1, static_cast<int>(std::ceil((c - b).norm() / kPointMillStripPieceMm)));
        for (int k = 0; k < n; ++k) {
          const Vec3 p = b + (c - b) * (static_cast<double>(k) / n), q = b + (c - b) * (static_cast<double>(k + 1) / n);
          pieces_.emplace_back(p, q);
          mids.push_back(0.5 * (p + q));
          half_ = std::max(half_, 0.5 * (q - p).norm());
        }
      }
    if (!mids.empty()) index_ = std::make_unique<PointIndex>(std::move(mids), kPointMillStripPieceMm);
  }
  // Distance from p to the nearest centre segment (infinity without moves).
  double centre_distance(const Vec3& p) const {
    if (!index_) return std::numeric_limits<double>::infinity();
    const int k = index_->nearest(p, 1e9);
    if (k < 0) return std::numeric_limits<double>::infinity();
    double best = (p - index_->points()[static_cast<size_t>(k)]).norm();
    const Vec3 reach = Vec3::Constant(best + half_);
    index_->for_each_in_box(p - reach, p + reach, [&](int i) {
      const auto& sg = pieces_[static_cast<size_t>(i)];
      const Vec3 d = sg.second - sg.first;
      const double dd = d.squaredNorm();
      const double t = dd > 0 ? std::clamp((p - sg.first).dot(d) / dd, 0.0, 1.0) : 0.0;
      best = std::min(best, (p - (sg.first + t * d)).norm());
    });
    return best;
  }

 private:
  std::vector<std::pair<Vec3, Vec3>> pieces_;
  double half_ = 0;
  std::unique_ptr<PointIndex> index_;
};

}  // namespace

PointMillStrip measure_root_strip(const PointMillRequest& rq, const PointMillResult& res, int samples_u, int samples_v) {
  if (!rq.face.surface) throw ParameterError("face", "the face milled is required");
  if (samples_u < 2 || samples_v < 2) throw ParameterError("samples", "the root strip needs at least 2 x 2 samples");
  PointMillStrip st;
  const Surface& s = *rq.face.surface;
  const double r = res.ball_radius_mm;
  // The band's top: the hub stop (a stopping plan's first row), as the
  // planner takes it.
  const double stop = rq.hub_stop_mm < 0 ? r : rq.hub_stop_mm;
  double min_pu = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= 16; ++i) min_pu = std::min(min_pu, s.eval(rq.u0, rq.v0 + (rq.v1 - rq.v0) * i / 16.0).pu.norm());
  const double top = std::min(rq.u1, rq.u0 + stop / std::max(min_pu, 1e-12));
  // The lower edge per v: the fillet line with the hub, else u0.
  std::vector<double> vs(static_cast<size_t>(samples_v)), lower(static_cast<size_t>(samples_v), rq.u0);
  for (int j = 0; j < samples_v; ++j) vs[static_cast<size_t>(j)] = rq.v0 + (rq.v1 - rq.v0) * j / (samples_v - 1);
  st.from_fillet = rq.hub != nullptr;
  if (st.from_fillet) {
    const SurfaceDerivs t = s.eval(rq.u1, 0.5 * (rq.v0 + rq.v1));
    const PointMillHubMeridian hub(*rq.hub, t.p + r * point_mill_unit_normal(t, rq.face.flip_normal));
    parallel_for_index(vs.size(), rq.threads, [&](size_t j) {
      lower[j] = std::min(top, point_mill_fillet_u(s, rq.face.flip_normal, vs[j], r, hub, rq.u0, rq.u1));
    });
  }
  st.u0 = *std::min_element(lower.begin(), lower.end());
  st.u1 = top;
  st.v = vs, st.lower_u = lower;
  // The band's height along the face at each v: the u edge's arc length
  // (Simpson on |pu|, 16 panels: the faces are smooth over a few mm).
  auto arc = [&](double ua, double ub, double v) {
    double len = 0;
    const int n = 16;
    for (int i = 0; i <= n; ++i) {
      const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
      len += w * s.eval(ua + (ub - ua) * i / n, v).pu.norm();
    }
    return len * (ub - ua) / n / 3;
  };
  st.height_min_mm = std::numeric_limits<double>::infinity();
  for (size_t j = 0; j < vs.size(); ++j) {
    const double len = arc(lower[j], top, vs[j]);
    st.height_mm = std::max(st.height_mm, len);
    st.height_min_mm = std::min(st.height_min_mm, len);
  }
  if (!(st.height_mm > 0)) {  // no band: the rows start at its top
    st.height_mm = st.height_min_mm = 0;
    return st;
  }
  const PointMillBallDistance balls(point_mill_moves(res), r);
  // The band sampled from its lower edge up to (not on) the top, and the
  // corner below a fillet line from u0 up to (not on) the line.
  const int n = samples_u * samples_v;
  const int nc = st.from_fillet ? n : 0;
  std::vector<double> dist(static_cast<size_t>(n + nc), -std::numeric_limits<double>::infinity());
  std::vector<double> us(static_cast<size_t>(n + nc), 0);
  parallel_for_index(static_cast<size_t>(n + nc), rq.threads, [&](size_t k) {
    const bool corner = static_cast<int>(k) >= n;
    const int kk = static_cast<int>(k) - (corner ? n : 0);
    const int i = kk / samples_v, j = kk % samples_v;
    const double lo = corner ? rq.u0 : lower[static_cast<size_t>(j)], hi = corner ? lower[static_cast<size_t>(j)] : top;
    if (!(hi > lo)) return;  // an empty column (the band or the corner)
    const double u = lo + (hi - lo) * i / samples_u;
    us[k] = u;
    dist[k] = balls.centre_distance(s.eval(u, vs[static_cast<size_t>(j)]).p) - r;
  });
  double sum = 0;
  int counted = 0;
  st.material_max_mm = st.corner_max_mm = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < n + nc; ++k) {
    const double d = dist[static_cast<size_t>(k)];
    if (d == -std::numeric_limits<double>::infinity()) continue;
    const double v = vs[static_cast<size_t>(k % samples_v)];
    if (k >= n) {
      ++st.corner_samples;
      if (d > st.corner_max_mm) st.corner_max_mm = d, st.corner_u = us[static_cast<size_t>(k)], st.corner_v = v;
      continue;
    }
    sum += d;
    ++counted;
    if (d > st.material_max_mm) st.material_max_mm = d, st.max_u = us[static_cast<size_t>(k)], st.max_v = v;
  }
  if (st.corner_samples == 0) st.corner_max_mm = 0;
  st.material_mean_mm = counted ? sum / counted : 0;
  st.samples = counted;
  return st;
}

}  // namespace bliskrun
