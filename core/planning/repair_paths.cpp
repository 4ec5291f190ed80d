#include "core/planning/repair_paths.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "core/common/fixed_text.h"
#include "core/common/parallel.h"
#include "core/common/timing.h"
#include "core/geometry/differential.h"
#include "core/planning/belt_paths.h"

namespace bliskrun {

const char* repair_pattern_name(RepairPattern p) { return p == RepairPattern::Spiral ? "spiral" : "zigzag"; }

TiltSettings repair_tilt_defaults() {
  TiltSettings t;
  // axis_from_lead_tilt: λ = 90° is the normal; w = −90° leans the axis
  // towards +X_SL, the feed. λ0 = 80°: 10° of lead forward; raised through
  // the normal (90°) to 30° back (120°).
  t.lead0_rad = deg_to_rad(80);
  t.tilt0_rad = deg_to_rad(-90);
  t.lead_step_rad = deg_to_rad(2);
  t.lead_max_rad = deg_to_rad(120);
  t.allow_tilt = true;
  t.tilt_step_rad = deg_to_rad(10);
  t.tilt_range_rad = deg_to_rad(30);
  return t;
}

double ball_step_over(double scallop_mm, double ball_radius_mm, double curvature_across) {
  return belt_step_over_exact(scallop_mm, ball_radius_mm, curvature_across);
}

namespace {

// Sweep step of the cutting segments' gouge check (see plan_curve).
constexpr double kCutSweepMm = 0.15;

Vec3 outward(const SurfaceDerivs& d, bool flip) {
  const Vec3 n = d.pu.cross(d.pv);
  const double len = n.norm();
  if (!(len > 1e-14)) throw Error("repair paths: the design surface is singular (pu x pv = 0)");
  return flip ? Vec3(-n / len) : Vec3(n / len);
}

double wrap_unit(double v) { return v - std::floor(v); }

// §2.2, Fig. 19: the contacts of iso-u line u_j moved onto the slanted line
// from (u_j, 0) to (u_j+1, 1) of the parameter plane. t counts turns: turn
// j is t in [j, j + 1], v = t - j once around.
class SpiralCurve : public Curve {
 public:
  SpiralCurve(const Surface& s, std::vector<double> turn_u) : s_(s), u_(std::move(turn_u)) {}
  CurveDerivs eval(double t) const override {
    const int turns = static_cast<int>(u_.size()) - 1;
    const int j = std::clamp(static_cast<int>(std::floor(t)), 0, turns - 1);
    const double f = std::clamp(t - j, 0.0, 1.0);
    const double du = u_[j + 1] - u_[j];
    const SurfaceDerivs d = s_.eval(u_[j] + du * f, f);
    CurveDerivs c;
    c.p = d.p;
    c.dt = du * d.pu + d.pv;
    c.dtt = du * du * d.puu + 2 * du * d.puv + d.pvv;
    return c;
  }
  double t_max() const override { return static_cast<double>(u_.size() - 1); }
  // (u, v) of the contact at t.
  std::pair<double, double> uv(double t) const {
    const int turns = static_cast<int>(u_.size()) - 1;
    const int j = std::clamp(static_cast<int>(std::floor(t)), 0, turns - 1);
    const double f = std::clamp(t - j, 0.0, 1.0);
    return {u_[j] + (u_[j + 1] - u_[j]) * f, f};
  }

 private:
  const Surface& s_;
  std::vector<double> u_;
};

// The step in u across passes at iso-u line u for scallop h: the smallest
// over `samples` points of v in [v0, v1] of the closed-form step-over
// divided by |pu| there. Also the step-over in mm where it is smallest.
struct AcrossStep {
  double du = 0;
  double step_mm = 0;
};
AcrossStep across_step(const Surface& s, bool flip, double u, double v0, double v1, double h, double r,
                       int samples) {
  AcrossStep out;
  out.du = 1e300;
  out.step_mm = 1e300;
  for (int i = 0; i < samples; ++i) {
    const double v = v0 + (v1 - v0) * (i + 0.5) / samples;
    const SurfaceDerivs d = s.eval(u, v);
    // normal_curvature is signed by pu x pv; across the passes is along pu.
    // Convex (bending away from the tool, out of the material) is > 0 for
    // the step-over's convention.
    double k = -normal_curvature(d, d.pu);
    if (flip) k = -k;
    // A concave round tighter than the ball: no step leaves h there, and
    // the ball cannot touch it without cutting its sides — the gouge guard
    // refuses those contacts; the step is set where the ball fits.
    if (!(1 + r * k > 1e-6)) continue;
    const double step = ball_step_over(h, r, k);
    out.step_mm = std::min(out.step_mm, step);
    out.du = std::min(out.du, step / d.pu.norm());
  }
  if (out.du > 1e299) {  // nowhere: the flat's step
    const double step = ball_step_over(h, r, 0);
    out.step_mm = step;
    out.du = step / s.eval(u, 0.5 * (v0 + v1)).pu.norm();
  }
  return out;
}

struct RepairContact {
  double t = 0, u = 0, v = 0;
};

// A contact's frame on the layer's offset: the point offset along the
// outward normal, the tangent along the feed.
ContactFrame frame_at(const Surface& s, bool flip, const RepairContact& c, const Vec3& feed, double offset_mm,
                      Vec3& surface_point) {
  const SurfaceDerivs d = s.eval(c.u, c.v);
  ContactFrame f;
  f.normal = outward(d, flip);
  surface_point = d.p;
  f.point = d.p + offset_mm * f.normal;
  Vec3 t = feed - feed.dot(f.normal) * f.normal;
  if (!(t.norm() > 1e-12)) throw Error("repair paths: the feed is along the normal");
  f.tangent = t.normalized();
  return f;
}

struct RepairPlanner {
  const RepairPathRequest& rq;
  const ToolBody& body;
  const GougeGuard& guard;
  const Tool& tool;
  double ball_r = 0;
  double pose_allowed = 0;  // finishing: cut below the design a pose or cutting motion may make
  RepairPathResult& res;
  Progress& progress;

  // A contact on its curve with the feed direction (dC/dt, negated when
  // the curve is run backwards).
  template <class ContactOf>
  std::vector<RepairPass> plan_curve(const Curve& curve, const ContactOf& contact_of, std::vector<double> ts,
                                     bool reversed, int layer, double offset_mm, bool finishing, double pass_u,
                                     const RowSteps& steps) {
    std::vector<RepairPass> pieces;
    auto make_pose = [&](double t, RepairPose& rp, ToolPose& lead_pose, double lift_mm) {
      const RepairContact c = contact_of(t);
      Vec3 feed = curve.eval(t).dt;
      if (reversed) feed = -feed;
      Vec3 sp;
      const ContactFrame f = frame_at(*rq.design, rq.flip_normal, c, feed, offset_mm + lift_mm, sp);
      rp.contact = sp;
      rp.normal = f.normal;
      rp.tangent = f.tangent;
      rp.u = c.u;
      rp.v = wrap_unit(c.v);
      rp.t = t;
      rp.lift_mm = lift_mm;
      lead_pose = place_tool(tool, f, axis_from_lead_tilt(f, rq.tilt.lead0_rad, rq.tilt.tilt0_rad));
      return f;
    };
    if (reversed) std::reverse(ts.begin(), ts.end());
    std::vector<char> refused(ts.size(), 0);
    std::vector<std::string> why(ts.size());
    std::vector<double> lift(ts.size(), 0.0);
    // Finishing only: the ball at a pose against the whole design surface
    // (the undamaged blade around the region).
    auto gouge_of = [&](const ToolPose& p) { return guard.deepest_cut(tool, p, p, pose_allowed, true, true); };
    // Whether the cutting motion a -> b, swept at kCutSweepMm, dips below
    // the design deeper than allowed (its ends are the contacts' own).
    auto cuts = [&](const ToolPose& a, const ToolPose& b) {
      return guard.deepest_cut(tool, a, b, pose_allowed, false, false, kCutSweepMm).depth_mm < 0;
    };
    // The pose at t, lifted off along the normal until the ball no longer
    // cuts the design deeper than allowed: on a trough narrower than the
    // ball (a ripple of a lofted edge, a concave round tighter than it)
    // the ball rides over it and leaves its depth. The least such lift
    // is bracketed between 0 (cuts) and max_lift_mm (must clear, else the
    // contact is refused: refusal non-empty) and found to 0.2 um: a
    // Newton step from the cutting side — lifting the centre c by δ along
    // n moves it from the cut point p by about δ n·(c − p)/|c − p|, so a
    // steep wall beside the contact needs more lift than its depth —,
    // bisection where that step leaves the bracket.
    auto settle = [&](double t, ToolPose& pose, double& lifted_mm, std::string& refusal) {
      RepairPose rp;
      lifted_mm = 0;
      refusal.clear();
      make_pose(t, rp, pose, 0);
      GougeGuard::Cut cut = gouge_of(pose);
      if (cut.depth_mm >= 0) return;
      ToolPose top = pose;
      GougeGuard::Cut top_cut = cut;
      if (rq.max_lift_mm > 0) {
        make_pose(t, rp, top, rq.max_lift_mm);
        top_cut = gouge_of(top);
      }
      if (top_cut.depth_mm < 0) {
        std::ostringstream os;
        os << "the ball cuts " << -cut.depth_mm * 1000 << " um into the design at (" << cut.point.x() << ", "
           << cut.point.y() << ", " << cut.point.z() << ") (allowed " << pose_allowed * 1000
           << " um; lifted off by " << rq.max_lift_mm * 1000 << " um it still cuts " << -top_cut.depth_mm * 1000
           << " um)";
        refusal = os.str();
        return;
      }
      double lo = 0, hi = rq.max_lift_mm;
      ToolPose lo_pose = pose, hi_pose = top;
      for (int round = 0; round < 40 && hi - lo > 2e-4; ++round) {
        const Vec3 to_centre = lo_pose.tip + ball_r * lo_pose.axis - cut.point;
        const double gain = rp.normal.dot(to_centre) / std::max(1e-9, to_centre.norm());
        double next = gain > 1e-3 ? lo + (-cut.depth_mm - pose_allowed) / gain + 1e-5 : hi;
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        ToolPose p;
        make_pose(t, rp, p, next);
        const GougeGuard::Cut c = gouge_of(p);
        if (c.depth_mm < 0) {
          lo = next, lo_pose = p, cut = c;
        } else {
          hi = next, hi_pose = p;
        }
      }
      pose = hi_pose;
      lifted_mm = hi;
    };
    if (finishing) {
      // Each contact settled, each cutting segment swept through the guard
      // and halved where it dips below.
      // The measured chord deviation of the step of `steps` holding [a, b].
      auto chord_of = [&](double a, double b) {
        const double lo = std::min(a, b);
        const auto it = std::upper_bound(steps.t.begin(), steps.t.end(), lo + 1e-12);
        const size_t k = it == steps.t.begin() ? 0 : static_cast<size_t>(it - steps.t.begin()) - 1;
        return k < steps.deviation_mm.size() ? steps.deviation_mm[k] : steps.max_deviation_mm;
      };
      // Contacts and segments are independent of each other here: settled
      // and swept on the request's threads, each into its own slot.
      std::vector<ToolPose> lp(ts.size());
      parallel_for_index(ts.size(), rq.threads, [&](size_t i) { settle(ts[i], lp[i], lift[i], why[i]); });
      for (size_t i = 0; i < ts.size(); ++i) {
        refused[i] = !why[i].empty();
        res.gouge_refusals += refused[i];
      }
      for (int round = 0; round < 8; ++round) {
        // Only segments whose estimate (the measured chord deviation plus
        // what the axis turn can add, R θ²/8) reaches half the tolerance
        // are swept: on the flanks the axis hardly turns and the chord is
        // far below it; around an edge both are large.
        // The sweep step bounds the motion of the fastest tool point, the
        // flutes' top when the axis turns round an edge; near the design
        // only the ball cuts, whose points move about a third of that.
        // 0.15 mm (three times faster than 0.05) can miss a few tenths of
        // a um between positions (the recipe's simulation read 0.26 um
        // more material left at 0.15 than at 0.05); the independent
        // simulation of the program, at 0.05, measures what is left.
        std::vector<char> dips(ts.size(), 0);
        parallel_for_index(ts.size(), rq.threads, [&](size_t i) {
          if (i + 1 == ts.size() || refused[i] || refused[i + 1]) return;
          const double theta = axis_angle_rad(lp[i].axis, lp[i + 1].axis);
          if (chord_of(ts[i], ts[i + 1]) + ball_r * theta * theta / 8 < 0.5 * rq.steps.chord_tol_mm) return;
          dips[i] = cuts(lp[i], lp[i + 1]);
        });
        std::vector<size_t> at;
        for (size_t i = 0; i < ts.size(); ++i)
          if (dips[i]) at.push_back(i);
        if (at.empty()) break;
        // A contact halfway along each segment that dips below.
        std::vector<double> mt(at.size()), ml(at.size());
        std::vector<ToolPose> mp(at.size());
        std::vector<std::string> mw(at.size());
        parallel_for_index(at.size(), rq.threads, [&](size_t k) {
          mt[k] = 0.5 * (ts[at[k]] + ts[at[k] + 1]);
          settle(mt[k], mp[k], ml[k], mw[k]);
        });
        std::vector<double> nt;
        std::vector<ToolPose> np;
        std::vector<char> nr;
        std::vector<std::string> nw;
        std::vector<double> nl;
        for (size_t i = 0, k = 0; i < ts.size(); ++i) {
          nt.push_back(ts[i]);
          np.push_back(lp[i]);
          nr.push_back(refused[i]);
          nw.push_back(why[i]);
          nl.push_back(lift[i]);
          if (k < at.size() && at[k] == i) {
            nt.push_back(mt[k]);
            np.push_back(mp[k]);
            nr.push_back(!mw[k].empty());
            nw.push_back(mw[k].empty() ? "" : "between contacts, " + mw[k]);
            nl.push_back(ml[k]);
            res.gouge_refusals += !mw[k].empty();
            ++res.gouge_splits;
            ++k;
          }
        }
        ts.swap(nt);
        lp.swap(np);
        refused.swap(nr);
        why.swap(nw);
        lift.swap(nl);
      }
    }
    // The tool axis: lead, tilted until the shank and holder are clear of
    // the world, the motion from the previous pose too.
    RepairPass cur;
    cur.layer = layer;
    cur.u = pass_u;
    cur.reversed = reversed;
    cur.max_deviation_mm = steps.max_deviation_mm;
    auto close_piece = [&] {
      if (!cur.poses.empty()) pieces.push_back(cur);
      cur.poses.clear();
    };
    auto accept = [&](const RepairPose& rp) {
      if (rp.lift_mm > 0) {
        ++res.lifted;
        res.max_lift_mm = std::max(res.max_lift_mm, rp.lift_mm);
      }
      cur.poses.push_back(rp);
    };
    // Contacts between a and b (finishing) whose motions all sweep clear of
    // the design, in order, into `out`; false where a contact is refused or
    // `depth` halvings do not clear a motion.
    std::function<bool(const RepairPose&, const RepairPose&, int, int, std::vector<RepairPose>&)> fill_between =
        [&](const RepairPose& a, const RepairPose& b, int depth, int index, std::vector<RepairPose>& out) {
          if (depth == 0) return false;
          const double tm = 0.5 * (a.t + b.t);
          ToolPose settled;
          double lm = 0;
          std::string refusal;
          settle(tm, settled, lm, refusal);
          if (!refusal.empty()) return false;
          RepairPose m;
          ToolPose lead_pose;
          const ContactFrame f = make_pose(tm, m, lead_pose, lm);
          const TiltOutcome o = tilt_until_clear(*rq.world, body, f, index, rq.tilt, &a.pose);
          if (!o.accepted) return false;
          m.pose = o.pose.pose;
          m.tilted = o.pose.tries > 1;
          if (cuts(a.pose, m.pose) && !fill_between(a, m, depth - 1, index, out)) return false;
          out.push_back(m);
          return !cuts(m.pose, b.pose) || fill_between(m, b, depth - 1, index, out);
        };
    for (size_t i = 0; i < ts.size(); ++i) {
      progress.check();
      RepairPose rp;
      ToolPose lead_pose;
      const ContactFrame f = make_pose(ts[i], rp, lead_pose, lift[i]);
      if (refused[i]) {
        res.refusals.push_back({layer, rp.u, rp.v, rp.contact, why[i]});
        close_piece();
        continue;
      }
      const ToolPose* prev = cur.poses.empty() ? nullptr : &cur.poses.back().pose;
      const TiltOutcome o = tilt_until_clear(*rq.world, body, f, static_cast<int>(i), rq.tilt, prev);
      if (!o.accepted) {
        res.refusals.push_back({layer, rp.u, rp.v, rp.contact, o.refusal.reason});
        close_piece();
        continue;
      }
      rp.pose = o.pose.pose;
      rp.tilted = o.pose.tries > 1;
      // A tilted axis moves the swept ball between poses a little: the
      // segment is swept again, and where it now dips below the design
      // contacts are put in between (each settled and tilted like any
      // other, each new motion swept), halving up to four times; only
      // where that does not clear it is the pass split (the pieces are
      // joined by a proved link).
      if (finishing && prev && (rp.tilted || cur.poses.back().tilted) && cuts(*prev, rp.pose)) {
        std::vector<RepairPose> between;
        if (fill_between(cur.poses.back(), rp, 4, static_cast<int>(i), between)) {
          res.tilt_fills += static_cast<int>(between.size());
          for (const RepairPose& m : between) accept(m);
        } else {
          close_piece();
          res.refusals.push_back({layer, rp.u, rp.v, rp.contact,
                                  "the tilted motion from the previous contact cuts into the design, also with "
                                  "contacts put in between: pass split"});
        }
      }
      accept(rp);
    }
    close_piece();
    return pieces;
  }
};

// The arc leaving a pass at pose e (§2.1 (2)): in the plane of the end
// tangent and the normal, tangent to the pass, turning away from the
// surface; the axis of e throughout. `into`: the arc reaching a pass's
// first pose instead, returned in the order the tool runs it.
std::vector<ToolPose> lead_arc(const RepairPose& e, double radius, double angle, int segments, bool into) {
  std::vector<ToolPose> out;
  for (int k = 1; k <= segments; ++k) {
    const double phi = angle * k / segments;
    const double along = into ? -std::sin(phi) : std::sin(phi);
    out.push_back(ToolPose{e.pose.tip + radius * (along * e.tangent + (1 - std::cos(phi)) * e.normal), e.pose.axis});
  }
  if (into) std::reverse(out.begin(), out.end());
  return out;
}

// The bridge (§2.1 (3)): a cubic Hermite curve from the end a of one arc to
// the start b of the next, leaving a along da and reaching b along db
// (unit), the axis turned on the great circle uniformly with the length.
std::vector<ToolPose> bridge(const ToolPose& a, const Vec3& da, const ToolPose& b, const Vec3& db, double radius,
                             int segments) {
  const double len = std::max((b.tip - a.tip).norm(), radius);
  std::vector<Vec3> pts;
  for (int k = 1; k < segments; ++k) {
    const double s = static_cast<double>(k) / segments, s2 = s * s, s3 = s2 * s;
    pts.push_back((2 * s3 - 3 * s2 + 1) * a.tip + (s3 - 2 * s2 + s) * len * da + (-2 * s3 + 3 * s2) * b.tip +
                  (s3 - s2) * len * db);
  }
  std::vector<double> cum{0};
  Vec3 prev = a.tip;
  for (const Vec3& p : pts) cum.push_back(cum.back() + (p - prev).norm()), prev = p;
  const double total = cum.back() + (b.tip - prev).norm();
  const PoseMotion turn(a, b);
  std::vector<ToolPose> out;
  for (size_t k = 0; k < pts.size(); ++k) out.push_back(ToolPose{pts[k], turn.pose_at(cum[k + 1] / total).axis});
  return out;
}

void validate(const RepairPathRequest& rq) {
  if (!rq.design) throw ParameterError("design", "a design surface is required");
  if (!rq.tool) throw ParameterError("tool", "a ball-end mill is required");
  if (rq.tool->kind() != ToolKind::BallEndMill)
    throw ParameterError("tool", "expected a ball-end mill, got " + rq.tool->description());
  if (!rq.world) throw ParameterError("world", "a collision world (blade, fixture) is required");
  if (!(rq.u0 >= 0 && rq.u1 <= 1 && rq.u1 > rq.u0)) throw ParameterError("u", "expected 0 <= u0 < u1 <= 1");
  // A window from v0 round through v = 0 to v1 (v0 > v1) crosses the
  // surface's seam: the spiral goes all the way round and ignores v, the
  // zigzag's passes run along v from v0 to v1 and are not planned across it
  // (issue 43: refused only where the pattern needs v).
  if (rq.pattern == RepairPattern::Zigzag && rq.v0 > rq.v1 && rq.v0 <= 1 && rq.v1 >= 0)
    throw ParameterError("v", "the region crosses the surface's seam (v from " + short_text(rq.v0) + " round through 0 to " +
                                  short_text(rq.v1) + "): the zigzag's passes run along v and are not planned across "
                                  "the seam; re-seam the surface away from the region, or use the spiral (which goes "
                                  "all the way round and needs no v window)");
  if (rq.pattern == RepairPattern::Zigzag && !(rq.v0 >= 0 && rq.v1 <= 1 && rq.v1 > rq.v0))
    throw ParameterError("v", "expected 0 <= v0 < v1 <= 1");
  if (!(rq.scallop_mm > 0 && rq.scallop_mm < rq.tool->cutter().max_radius()))
    throw ParameterError("scallop", "expected a height > 0 and below the ball radius");
  if (!(rq.rough_scallop_mm > 0 && rq.rough_scallop_mm < rq.tool->cutter().max_radius()))
    throw ParameterError("rough_scallop", "expected a height > 0 and below the ball radius");
  if (!(rq.layer_mm > 0)) throw ParameterError("layer", "expected a depth of cut > 0");
  if (!(rq.stock_mm >= 0)) throw ParameterError("stock", "expected >= 0");
  if (!(rq.deposit_mm >= rq.stock_mm)) throw ParameterError("deposit", "expected at least the stock");
  if (!(rq.rough_chord_tol_mm > 0)) throw ParameterError("rough_chord_tol", "expected > 0");
  if (!(rq.arc_radius_mm > 0)) throw ParameterError("arc_radius", "expected > 0");
  if (!(rq.arc_angle_rad > 0 && rq.arc_angle_rad <= kPi)) throw ParameterError("arc_angle", "expected (0, 180] deg");
  if (rq.arc_segments < 1 || rq.bridge_segments < 2) throw ParameterError("arc_segments", "expected >= 1 (bridges >= 2)");
  if (!(rq.guard_spacing_mm > 0)) throw ParameterError("guard_spacing", "expected > 0");
  if (!(rq.max_lift_mm >= 0)) throw ParameterError("max_lift", "expected >= 0 mm");
  if (rq.across_samples < 2) throw ParameterError("across_samples", "expected >= 2");
  if (rq.threads < 1) throw ParameterError("threads", "expected >= 1");
}

}  // namespace

RepairPathResult plan_repair_paths(const RepairPathRequest& rq, Progress& progress) {
  validate(rq);
  RepairPathResult res;
  res.pattern = rq.pattern;
  const Surface& s = *rq.design;
  const Tool& tool = *rq.tool;
  const double ball_r = tool.cutter().max_radius();
  const ToolBody body(tool, rq.tool_tol_mm);
  auto t0 = SteadyClock::now();
  const GougeGuard guard(s, link_guard_sampling(s, rq.guard_spacing_mm, rq.flip_normal));
  res.guard_spacing_mm = guard.spacing_mm();
  const double margin = guard.between_samples_mm(ball_r);
  const double pose_allowed = std::max(0.0, rq.steps.chord_tol_mm - margin);

  // Offsets: stock + k layer below the deposit, outside first; then 0.
  std::vector<double> offsets;
  for (int k = 0; rq.stock_mm + k * rq.layer_mm < rq.deposit_mm - 1e-9; ++k)
    offsets.push_back(rq.stock_mm + k * rq.layer_mm);
  std::reverse(offsets.begin(), offsets.end());
  offsets.push_back(0);

  auto scallop_of = [&](size_t L) { return L + 1 == offsets.size() ? rq.scallop_mm : rq.rough_scallop_mm; };
  // Zigzag: each layer's iso-u lines (u0 upwards) and the step-over from
  // each to the next. Each layer starts on the side of the region where the
  // one before ended (its last pass's end), so the link between layers stays
  // on one side of the blade instead of crossing round the edge. That
  // depends only on the pass counts before it, so the layers themselves can
  // be planned apart.
  struct ZigzagLines {
    std::vector<double> u, step_mm;
    bool start_reversed = false;
  };
  std::vector<ZigzagLines> zigzag(offsets.size());
  if (rq.pattern == RepairPattern::Zigzag) {
    bool next = false;
    for (size_t L = 0; L < offsets.size(); ++L) {
      ZigzagLines& z = zigzag[L];
      z.u.assign(1, rq.u0);
      while (z.u.back() < rq.u1 - 1e-12) {
        const AcrossStep a =
            across_step(s, rq.flip_normal, z.u.back(), rq.v0, rq.v1, scallop_of(L), ball_r, rq.across_samples);
        z.step_mm.push_back(a.step_mm);
        z.u.push_back(std::min(rq.u1, z.u.back() + a.du));
      }
      z.start_reversed = next;
      next = !(((z.u.size() - 1) % 2 == 1) != next);
    }
  }

  // One layer into its own result (passes, refusals, counts): the layers
  // are independent (every pose and motion is checked against the design
  // and the world, never against another layer), so they are planned on
  // the request's threads and joined in order; the plan does not depend on
  // the thread count.
  auto plan_layer = [&](size_t L, RepairPlanner& planner, RepairPathResult& part) {
    const bool finishing = L + 1 == offsets.size();
    RepairLayer layer;
    layer.offset_mm = offsets[L];
    layer.finishing = finishing;
    layer.scallop_mm = scallop_of(L);
    StepOptions so = rq.steps;
    if (!finishing) so.chord_tol_mm = rq.rough_chord_tol_mm;
    layer.chord_tol_mm = so.chord_tol_mm;
    layer.step_over_min_mm = 1e300;
    const bool upward = L % 2 == 0;  // layers alternate: shorter links
    if (rq.pattern == RepairPattern::Zigzag) {
      std::vector<double> us = zigzag[L].u;
      const std::vector<double>& step_mm = zigzag[L].step_mm;
      for (double m : step_mm) {
        layer.step_over_min_mm = std::min(layer.step_over_min_mm, m);
        layer.step_over_max_mm = std::max(layer.step_over_max_mm, m);
      }
      if (!upward) std::reverse(us.begin(), us.end());
      for (size_t k = 0; k < us.size(); ++k) {
        const IsoUCurve iso(s, us[k]);
        const CurveSpan span(iso, rq.v0, rq.v1);
        const RowSteps st = plan_row_steps(span, so);
        const double u = us[k];
        auto contact_of = [&](double t) { return RepairContact{t, u, t}; };
        std::vector<RepairPass> pieces =
            planner.plan_curve(span, contact_of, st.t, (k % 2 == 1) != zigzag[L].start_reversed,
                               static_cast<int>(L), layer.offset_mm, finishing, u, st);
        layer.max_deviation_mm = std::max(layer.max_deviation_mm, st.max_deviation_mm);
        for (RepairPass& p : pieces) {
          const size_t sk = upward ? k : us.size() - 2 - k;
          p.step_over_mm = k + 1 < us.size() && sk < step_mm.size() ? step_mm[sk] : 0;
          part.passes.push_back(std::move(p));
        }
      }
    } else {
      // Turns: one flat at u0, slanted turns each up by the step across,
      // one flat at u1.
      std::vector<double> turn_u{rq.u0, rq.u0};
      while (turn_u.back() < rq.u1 - 1e-12) {
        const AcrossStep a =
            across_step(s, rq.flip_normal, turn_u.back(), 0, 1, layer.scallop_mm, ball_r, rq.across_samples);
        layer.step_over_min_mm = std::min(layer.step_over_min_mm, a.step_mm);
        layer.step_over_max_mm = std::max(layer.step_over_max_mm, a.step_mm);
        turn_u.push_back(std::min(rq.u1, turn_u.back() + a.du));
      }
      turn_u.push_back(rq.u1);
      layer.turns = static_cast<int>(turn_u.size()) - 1;
      const SpiralCurve spiral(s, turn_u);
      const RowSteps st = plan_row_steps(spiral, so);
      auto contact_of = [&](double t) {
        const auto [u, v] = spiral.uv(t);
        return RepairContact{t, u, v};
      };
      std::vector<RepairPass> pieces = planner.plan_curve(spiral, contact_of, st.t, !upward, static_cast<int>(L),
                                                          layer.offset_mm, finishing, rq.u0, st);
      layer.max_deviation_mm = st.max_deviation_mm;
      for (RepairPass& p : pieces) part.passes.push_back(std::move(p));
    }
    if (layer.step_over_min_mm > 1e299) layer.step_over_min_mm = 0;
    layer.passes = static_cast<int>(part.passes.size());
    for (const RepairPass& p : part.passes) {
      layer.poses += static_cast<int>(p.poses.size());
      for (const RepairPose& rp : p.poses) layer.tilted += rp.tilted;
    }
    layer.refusals = static_cast<int>(part.refusals.size());
    return layer;
  };
  std::vector<RepairPathResult> parts(offsets.size());
  std::vector<RepairLayer> layers(offsets.size());
  // The finishing layer first: it costs the most (the gouge guard, the
  // finer steps), and started last it would run alone at the end.
  run_parallel(offsets.size(), rq.threads, progress, "repair layers", [&](size_t k, Progress& own) {
    const size_t L = offsets.size() - 1 - k;
    RepairPlanner planner{rq, body, guard, tool, ball_r, pose_allowed, parts[L], own};
    layers[L] = plan_layer(L, planner, parts[L]);
  });
  for (size_t L = 0; L < offsets.size(); ++L) {
    RepairPathResult& part = parts[L];
    RepairLayer& layer = layers[L];
    layer.first_pass = static_cast<int>(res.passes.size());
    for (RepairPass& p : part.passes) res.passes.push_back(std::move(p));
    res.refusals.insert(res.refusals.end(), part.refusals.begin(), part.refusals.end());
    res.gouge_refusals += part.gouge_refusals;
    res.gouge_splits += part.gouge_splits;
    res.tilt_fills += part.tilt_fills;
    res.lifted += part.lifted;
    res.max_lift_mm = std::max(res.max_lift_mm, part.max_lift_mm);
    if (layer.finishing) res.max_deviation_mm = layer.max_deviation_mm;
    res.layers.push_back(layer);
  }
  res.paths_seconds = seconds_since(t0);

  // Connections: arcs and bridges between the passes of a layer (zigzag),
  // the shared link elsewhere, departures at the ends.
  t0 = SteadyClock::now();
  LinkChecks checks;
  checks.world = rq.world;
  checks.body = &body;
  checks.clearances = rq.tilt.clearances;
  checks.motion_tol_mm = rq.tilt.motion_tol_mm;
  checks.guard = &guard;
  checks.guard_margin_mm = margin;
  if (rq.world) checks.traverse_world = rq.world->unchecked_pairs();  // the blade being machined, for the cutter
  const double link_allowed = rq.links.allowed_overcut_mm;  // the guard's margin comes off in the proof
  auto end_of = [](const RepairPose& p) { return LinkEnd{p.pose, p.normal}; };
  auto link = [&](int from, int to) {
    RepairConnection c;
    c.kind = RepairConnection::Kind::Link;
    c.from_pass = from;
    c.to_pass = to;
    c.rapid = true;
    const PlannedLink pl = plan_link(end_of(res.passes[from].poses.back()), end_of(res.passes[to].poses.front()),
                                     checks, rq.links);
    c.clear = pl.clear;
    if (pl.clear) {
      c.poses = pl.via;
      for (size_t i = 0; i < pl.via.size(); ++i) c.motion.push_back(link_leg_name(pl.legs[i]));
    } else {
      c.reason = "link from pass " + std::to_string(from) + " to pass " + std::to_string(to) + ": " + pl.reason;
    }
    return c;
  };
  const int n = static_cast<int>(res.passes.size());
  if (n > 0) {
    auto departure = [&](const RepairPose& p, int from, int to, const char* what) {
      RepairConnection c;
      c.kind = RepairConnection::Kind::Departure;
      c.from_pass = from;
      c.to_pass = to;
      c.rapid = true;
      const PlannedDeparture d = plan_departure(end_of(p), checks, rq.links);
      c.clear = d.clear;
      if (d.clear) {
        c.poses = {d.away};
        c.motion = {from < 0 ? "start" : "retract"};
      } else {
        c.reason = std::string(what) + ": " + d.reason;
      }
      return c;
    };
    res.connections.push_back(departure(res.passes.front().poses.front(), -1, 0, "lead-in"));
    for (int p = 0; p + 1 < n; ++p) {
      progress.check();
      const RepairPass &a = res.passes[p], &b = res.passes[p + 1];
      RepairConnection c;
      bool done = false;
      if (rq.pattern == RepairPattern::Zigzag && a.layer == b.layer) {
        const RepairPose &e = a.poses.back(), &st = b.poses.front();
        const std::vector<ToolPose> out = lead_arc(e, rq.arc_radius_mm, rq.arc_angle_rad, rq.arc_segments, false);
        const std::vector<ToolPose> in = lead_arc(st, rq.arc_radius_mm, rq.arc_angle_rad, rq.arc_segments, true);
        const double phi = rq.arc_angle_rad;
        const Vec3 da = std::cos(phi) * e.tangent + std::sin(phi) * e.normal;
        const Vec3 db = std::cos(phi) * st.tangent - std::sin(phi) * st.normal;
        const std::vector<ToolPose> br = bridge(out.back(), da, in.front(), db, rq.arc_radius_mm, rq.bridge_segments);
        std::vector<ToolPose> chain{e.pose};
        c.kind = RepairConnection::Kind::Bridge;
        c.from_pass = p;
        c.to_pass = p + 1;
        for (const ToolPose& q : out) c.poses.push_back(q), c.motion.push_back("lead-out");
        for (const ToolPose& q : br) c.poses.push_back(q), c.motion.push_back("bridge");
        for (const ToolPose& q : in) c.poses.push_back(q), c.motion.push_back("lead-in");
        chain.insert(chain.end(), c.poses.begin(), c.poses.end());
        chain.push_back(st.pose);
        const ChainProof proof = prove_chain(chain, checks, link_allowed, true, true);
        if (proof.clear) {
          c.clear = true;
          done = true;
          ++res.bridges;
        }
      }
      if (!done) {
        c = link(p, p + 1);
        if (c.clear) ++res.links;
      }
      if (!c.clear) ++res.refused_connections;
      res.connections.push_back(std::move(c));
    }
    res.connections.push_back(departure(res.passes.back().poses.back(), n - 1, -1, "lead-out"));
    for (const RepairConnection& c : {res.connections.front(), res.connections.back()})
      if (!c.clear) ++res.refused_connections;
  }
  res.connect_seconds = seconds_since(t0);
  return res;
}

RepairMoves repair_moves(const RepairPathResult& r) {
  RepairMoves out;
  auto add = [&](Move::Kind kind, const ToolPose& pose, int row, const std::string& motion, int layer,
                 const std::string& reason = "") {
    Move m;
    m.kind = kind;
    m.pose = pose;
    m.row = row;
    m.motion = motion;
    m.reason = reason;
    out.moves.push_back(std::move(m));
    out.layer_of.push_back(layer);
  };
  if (r.passes.empty()) return out;
  // connections[0] leads in, connections[p + 1] joins pass p to p + 1, the
  // last leads out.
  std::string reach = "approach";
  for (size_t p = 0; p <= r.passes.size(); ++p) {
    const RepairConnection& c = r.connections[p];
    const int layer = r.passes[std::min(p, r.passes.size() - 1)].layer;
    if (!c.clear) {
      add(Move::Kind::Stop, ToolPose{}, static_cast<int>(p), "stop", layer, c.reason);
    } else {
      for (size_t i = 0; i < c.poses.size(); ++i)
        add(c.rapid ? Move::Kind::Rapid : Move::Kind::Feed, c.poses[i], static_cast<int>(p),
            c.motion[i], layer);
    }
    reach = c.kind == RepairConnection::Kind::Bridge ? "lead-in" : "approach";
    if (p == r.passes.size()) break;
    const RepairPass& pass = r.passes[p];
    for (size_t i = 0; i < pass.poses.size(); ++i)
      add(Move::Kind::Feed, pass.poses[i].pose, static_cast<int>(p), i == 0 ? reach : "cut", pass.layer);
  }
  return out;
}

std::vector<ToolPass> repair_passes(const RepairPathResult& r, int first_layer) {
  const RepairMoves m = repair_moves(r);
  Toolpath layers;
  for (size_t i = 0; i < m.moves.size(); ++i)
    if (m.layer_of[i] >= first_layer) layers.push_back(m.moves[i]);
  return toolpath_passes(layers).passes;
}

}  // namespace bliskrun
