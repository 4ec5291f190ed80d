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
#include "core/geometry/mesh.h"
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
  PointMillFace f{*rq.face.surface, rq.face.flip_normal, along, 0, 1, 0, 1};
  // The hub-side boundary: u0 raised by hub_stop_mm along the face (the
  // smallest |pu| of the window's u0 edge, so every contact is at least
  // that far up).
  const double stop = rq.hub_stop_mm < 0 ? r : rq.hub_stop_mm;
  double min_pu = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= 16; ++i) min_pu = std::min(min_pu, rq.face.surface->eval(rq.u0, rq.v0 + (rq.v1 - rq.v0) * i / 16.0).pu.norm());
  const double u_start = rq.u0 + stop / std::max(min_pu, 1e-12);
  if (!(u_start < rq.u1)) throw ParameterError("hub_stop", "leaves nothing of the window to mill");
  res.first_row_u = u_start;
  if (along) f.a0 = u_start, f.a1 = rq.u1, f.b0 = rq.v0, f.b1 = rq.v1;
  else f.a0 = rq.v0, f.a1 = rq.v1, f.b0 = u_start, f.b1 = rq.u1;

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
  guards.guards.resize(guarded.size());
  guards.names.resize(guarded.size());
  CollisionWorld own_world;
  parallel_for_index(guarded.size() + 1, rq.threads, [&](size_t i) {
    if (i < guarded.size()) {
      const PointMillSurface& s = *guarded[i];
      guards.guards[i] = std::make_unique<GougeGuard>(*s.surface, link_guard_sampling(*s.surface, rq.guard_spacing_mm, s.flip_normal));
      guards.names[i] = s.name.empty() ? (i == 0 ? "the face" : "a neighbour") : s.name;
    } else if (!rq.world) {
      own_world = point_mill_world(rq);
    }
  });
  for (const auto& g : guards.guards) guards.margin = std::max(guards.margin, g->between_samples_mm(r));
  const CollisionWorld& world = rq.world ? *rq.world : own_world;
  const ToolBody body(*rq.tool, rq.tool_tol_mm);
  PointMillPlanner pl{rq, f, world, body, guards, r, res.taper_rad + 0.5 * kPi / 180,
                      rq.allowed_overcut_mm - guards.margin};
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

PointMillStrip measure_root_strip(const PointMillRequest& rq, const PointMillResult& res, int samples_u, int samples_v) {
  if (!rq.face.surface) throw ParameterError("face", "the face milled is required");
  if (samples_u < 2 || samples_v < 2) throw ParameterError("samples", "the root strip needs at least 2 x 2 samples");
  PointMillStrip st;
  st.u0 = rq.u0, st.u1 = res.first_row_u;
  const Surface& s = *rq.face.surface;
  // The strip's height along the face at each v: the u edge's arc length
  // (Simpson on |pu|, 16 panels: the faces are smooth over a few mm).
  st.height_min_mm = std::numeric_limits<double>::infinity();
  for (int j = 0; j < samples_v; ++j) {
    const double v = rq.v0 + (rq.v1 - rq.v0) * j / (samples_v - 1);
    double len = 0;
    const int n = 16;
    for (int i = 0; i <= n; ++i) {
      const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
      len += w * s.eval(st.u0 + (st.u1 - st.u0) * i / n, v).pu.norm();
    }
    len *= (st.u1 - st.u0) / n / 3;
    st.height_mm = std::max(st.height_mm, len);
    st.height_min_mm = std::min(st.height_min_mm, len);
  }
  if (!(st.u1 > st.u0)) {  // no strip: the rows start at the edge
    st.height_mm = st.height_min_mm = 0;
    return st;
  }
  // The ball centres' segments, every move of the program.
  const double r = res.ball_radius_mm;
  std::vector<std::pair<Vec3, Vec3>> segs;
  for (const std::vector<ToolPose>& pass : toolpath_passes(point_mill_moves(res)).passes)
    for (size_t i = 0; i < pass.size(); ++i) {
      const Vec3 c = pass[i].tip + r * pass[i].axis;
      const Vec3 b = i == 0 ? c : Vec3(pass[i - 1].tip + r * pass[i - 1].axis);
      segs.emplace_back(b, c);
    }
  // The strip sampled from u0 up to (not on) the first row.
  const int n = samples_u * samples_v;
  std::vector<double> dist(static_cast<size_t>(n), std::numeric_limits<double>::infinity());
  parallel_for_index(static_cast<size_t>(n), rq.threads, [&](size_t k) {
    const int i = static_cast<int>(k) / samples_v, j = static_cast<int>(k) % samples_v;
    const double u = st.u0 + (st.u1 - st.u0) * i / samples_u;
    const double v = rq.v0 + (rq.v1 - rq.v0) * j / (samples_v - 1);
    const Vec3 p = s.eval(u, v).p;
    double best = std::numeric_limits<double>::infinity();
    for (const auto& sg : segs) {
      const Vec3 d = sg.second - sg.first;
      const double dd = d.squaredNorm();
      const double t = dd > 0 ? std::clamp((p - sg.first).dot(d) / dd, 0.0, 1.0) : 0.0;
      best = std::min(best, (p - (sg.first + t * d)).norm());
    }
    dist[k] = best - r;
  });
  double sum = 0;
  st.material_max_mm = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < n; ++k) {
    sum += dist[static_cast<size_t>(k)];
    if (dist[static_cast<size_t>(k)] > st.material_max_mm) {
      st.material_max_mm = dist[static_cast<size_t>(k)];
      st.max_u = st.u0 + (st.u1 - st.u0) * (k / samples_v) / samples_u;
      st.max_v = rq.v0 + (rq.v1 - rq.v0) * (k % samples_v) / (samples_v - 1);
    }
  }
  st.material_mean_mm = sum / n;
  st.samples = n;
  return st;
}

}  // namespace bliskrun
