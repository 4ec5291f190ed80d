#include "core/planning/hub_finish.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>

#include "core/common/error.h"
#include "core/common/parallel.h"
#include "core/geometry/closed_curve.h"
#include "core/geometry/differential.h"
#include "core/geometry/mesh.h"
#include "core/geometry/revolution_distance.h"
#include "core/geometry/root_find.h"
#include "core/parts/closed_blade.h"
#include "core/planning/repair_paths.h"

namespace bliskrun {

const char* hub_finish_op_name(HubFinishOp op) { return op == HubFinishOp::Root ? "root" : "channel"; }

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Sweep step of the cutting segments' gouge check (as the repair paths'):
// the independent simulation, at 0.05 mm, measures what is left.
constexpr double kCutSweepMm = 0.15;
constexpr double kSweepTurnRad = 0.5 * kPi / 180;
// The floor's initial axes point at the channel's middle this high above
// the hub (two thirds of the built-in blade): they follow the blades' twist.
constexpr double kTargetHeightMm = 20.0;

// The hub between two angles: (u, v) -> the hub at meridian u, angle
// theta0 + v (theta1 - theta0). A window of a surface of revolution that may
// straddle angle 0 (the built-in blisk's blade 1 does), which its own v in
// [0, 1] cannot.
class HubSector : public Surface {
 public:
  HubSector(std::shared_ptr<const SurfaceOfRevolution> hub, double theta0, double theta1)
      : hub_(std::move(hub)), v0_(theta0 / (2 * kPi)), dv_((theta1 - theta0) / (2 * kPi)) {}
  SurfaceDerivs eval(double u, double v) const override {
    SurfaceDerivs d = hub_->eval(u, v0_ + dv_ * v);
    d.pv *= dv_;
    d.puv *= dv_;
    d.pvv *= dv_ * dv_;
    return d;
  }

 private:
  std::shared_ptr<const SurfaceOfRevolution> hub_;
  double v0_, dv_;
};

// The circle of radius r at height z between two angles, t in [0, 1].
class ArcCurve : public Curve {
 public:
  ArcCurve(double r, double z, double theta0, double theta1) : r_(r), z_(z), a_(theta0), d_(theta1 - theta0) {}
  CurveDerivs eval(double t) const override {
    const double a = a_ + d_ * t, c = std::cos(a), s = std::sin(a);
    CurveDerivs out;
    out.p = Vec3(r_ * c, r_ * s, z_);
    out.dt = Vec3(-r_ * s, r_ * c, 0) * d_;
    out.dtt = Vec3(-r_ * c, -r_ * s, 0) * (d_ * d_);
    return out;
  }

 private:
  double r_, z_, a_, d_;
};

Vec3 unit_normal(const SurfaceDerivs& d, bool flip) {
  const Vec3 n = d.pu.cross(d.pv);
  const double len = n.norm();
  if (!(len > 1e-14)) throw Error("hub finish: a design surface is singular (pu x pv = 0)");
  return flip ? Vec3(-n / len) : Vec3(n / len);
}

double angle_of(const Vec3& p) { return std::atan2(p.y(), p.x()); }
double wrap_near(double a, double ref) { return a - 2 * kPi * std::round((a - ref) / (2 * kPi)); }

// The hub offset by d out of the material (radial_offset d; d < 0: into
// it), whichever way the meridian runs.
SurfaceOfRevolution hub_offset_out(const SurfaceOfRevolution& hub, double d) {
  SurfaceOfRevolution a = hub.offset(d);
  if ((hub.radial_offset(a.point(0.5, 0)) > 0) == (d > 0)) return a;
  return hub.offset(-d);
}

// A root of g between lo and hi around a guess: the bracket grows from
// +-step until g changes sign (or [lo, hi] is exhausted).
template <class F>
double solve_near(F&& g, double guess, double step, double lo, double hi, const char* what) {
  for (double w = step; w < 4 * (hi - lo); w *= 4) {
    const double a = std::max(lo, guess - w), b = std::min(hi, guess + w);
    const double ga = g(a), gb = g(b);
    if ((ga <= 0) != (gb <= 0)) return illinois_root(g, a, b, ga, gb, 1e-12, 200);
    if (a == lo && b == hi) break;
  }
  throw Error(std::string("hub finish: ") + what + " not found on the blade's span");
}

// Least-squares polynomial (degree 3) theta(z), centred on z_c.
// Beyond [z_lo, z_hi] (the blade's apexes) it continues along its end
// tangents: a cubic extrapolated past the blade would bend away.
struct Poly3 {
  double zc = 0, z_lo = -1e300, z_hi = 1e300;
  double a[4] = {0, 0, 0, 0};
  double inside(double z) const {
    const double x = z - zc;
    return a[0] + x * (a[1] + x * (a[2] + x * a[3]));
  }
  double slope(double z) const {
    const double x = z - zc;
    return a[1] + x * (2 * a[2] + x * 3 * a[3]);
  }
  double operator()(double z) const {
    if (z < z_lo) return inside(z_lo) + (z - z_lo) * slope(z_lo);
    if (z > z_hi) return inside(z_hi) + (z - z_hi) * slope(z_hi);
    return inside(z);
  }
};
Poly3 fit_poly3(const std::vector<double>& z, const std::vector<double>& y, const std::vector<double>& w) {
  Poly3 p;
  double s = 0;
  for (double v : z) s += v;
  p.zc = s / static_cast<double>(z.size());
  Eigen::MatrixXd A(z.size(), 4);
  Eigen::VectorXd b(z.size());
  for (size_t i = 0; i < z.size(); ++i) {
    const double x = z[i] - p.zc;
    A(i, 0) = w[i], A(i, 1) = w[i] * x, A(i, 2) = w[i] * x * x, A(i, 3) = w[i] * x * x * x;
    b(i) = w[i] * y[i];
  }
  const Eigen::Vector4d c = A.colPivHouseholderQr().solve(b);
  for (int k = 0; k < 4; ++k) p.a[k] = c(k);
  return p;
}

// One blade closed around its section, with its root on the hub.
struct ClosedRoot {
  std::shared_ptr<const BSplineSurface> surface;
  double le_v = 0, te_v = 0;
  std::vector<double> v, u;  // the root (height 0) at v samples
  std::vector<Vec3> points;
  double theta_min = 0, theta_max = 0, theta_centroid = 0;
  Poly3 mid;                 // the mid-line between the two sides, theta(z)
  Poly3 mid_top;             // the same at the channel axes' target height
  double z_min = 0, z_max = 0;
};

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

ClosedRoot close_root(const BladeFaces& faces, const SurfaceOfRevolution& hub, int sections, double ref_angle,
                      double top_level) {
  ClosedBladeOptions co;
  co.sections = sections;
  ClosedBlade b = close_blade(*faces.pressure, *faces.suction, co);
  ClosedRoot out;
  out.surface = std::make_shared<const BSplineSurface>(std::move(b.loft.surface));
  out.le_v = b.le_v;
  out.te_v = b.te_v;
  section_at(*out.surface, hub, 0, ref_angle, out);
  ClosedRoot top = out;
  section_at(*out.surface, hub, top_level, ref_angle, top);
  out.mid_top = top.mid;
  return out;
}

// Signed distance of q from a closed blade surface (> 0 outside), by its
// nearest point: Newton from the nearest of the given samples (u raised by
// `lift_u`, towards the ball's height), else from a coarse grid. -1 when no
// foot is found (near the medial axis, inside): callers take that as "does
// not fit", which is safe.
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

struct Guards {
  std::unique_ptr<GougeGuard> blade, next, hub;
  double margin = 0;
};

}  // namespace

CollisionWorld hub_finish_world(const HubFinishRequest& rq, const std::vector<NamedMesh>& extra) {
  if (!rq.hub) throw ParameterError("hub", "the hub (a surface of revolution) is required");
  CollisionWorld w;
  auto add_faces = [&](const BladeFaces& f, const std::string& name, bool cutter) {
    if (!f.pressure || !f.suction) return;
    PartMask parts;
    parts.cutter = cutter;
    const double tol = cutter ? rq.mesh_tol_mm : 0.05;
    const CheckSurfaceOptions opt{parts, cutter ? 0.0 : tol};
    w.add(name + " pressure", tessellate(*f.pressure, tol), opt);
    w.add(name + " suction", tessellate(*f.suction, tol), opt);
  };
  add_faces(rq.previous, "blade k-1", true);
  add_faces(rq.blade, "blade k (shank)", false);
  add_faces(rq.next, "blade k+1 (shank)", false);
  PartMask no_cutter;
  no_cutter.cutter = false;
  w.add("hub (shank)", std::make_shared<const RevolutionDistance>(*rq.hub, 1e-4), CheckSurfaceOptions{no_cutter, 0});
  PartMask cutter_only;
  cutter_only.shank = cutter_only.holder = false;
  // The cutter meets the hub by design: checked against the hub 0.2 mm
  // inside it, a guard against gross errors (the gouge guard measures what
  // it cuts). Closer, a motion along the hub would be proved in steps of a
  // few um (conservative advancement steps by the distance).
  const SurfaceOfRevolution inset = hub_offset_out(*rq.hub, -0.2);
  w.add("hub (cutter)", std::make_shared<const RevolutionDistance>(inset, 1e-5), CheckSurfaceOptions{cutter_only, 0});
  for (const NamedMesh& m : extra) w.add(m.name, m.mesh);
  return w;
}

namespace {

// The ball's radius: the tip's radius of curvature (R^2 = 2 r z - z^2 on
// the ball; a tapered ball's cutter is wider above it).
double ball_radius(const Tool& tool) {
  const double z = 1e-3 * tool.cutter().z_max();
  const double R = tool.cutter().radius_at(z);
  return (R * R + z * z) / (2 * z);
}

// The taper's half angle: the cone's slope near the top of the flute (0 for
// a plain ball end's cylinder).
double taper_rad(const Tool& tool) {
  const Profile& p = tool.cutter();
  const double z1 = p.z_min() + 0.8 * (p.z_max() - p.z_min()), z2 = p.z_min() + 0.9 * (p.z_max() - p.z_min());
  return std::atan2(p.radius_at(z2) - p.radius_at(z1), z2 - z1);
}

void validate(const HubFinishRequest& rq) {
  if (!rq.blade.pressure || !rq.blade.suction) throw ParameterError("blade", "blade k's pressure and suction faces are required");
  if (!rq.next.pressure || !rq.next.suction) throw ParameterError("next", "blade k+1's pressure and suction faces are required");
  if (!rq.hub) throw ParameterError("hub", "the hub (a surface of revolution) is required");
  if (!rq.tool) throw ParameterError("tool", "a ball or tapered ball-end mill is required");
  if (rq.tool->kind() != ToolKind::BallEndMill && rq.tool->kind() != ToolKind::TaperedBallEndMill)
    throw ParameterError("tool", "expected a ball or tapered ball-end mill, got " + rq.tool->description());
  if (!rq.root && !rq.channel) throw ParameterError("root", "nothing to plan: root and channel are both off");
  if (!(rq.scallop_mm > 0 && rq.scallop_mm < 0.5 * ball_radius(*rq.tool)))
    throw ParameterError("scallop", "expected a height > 0 and below half the ball radius");
  if (!(rq.steps.chord_tol_mm > 0)) throw ParameterError("chord_tol", "expected > 0");
  if (!(rq.allowed_overcut_mm > 0)) throw ParameterError("allowed_overcut", "expected > 0");
  if (!(rq.root_top_mm > 0 && rq.root_top_mm < 50)) throw ParameterError("top", "expected a height in (0, 50) mm");
  if (rq.z_inlet_mm != rq.z_outlet_mm && !(rq.z_inlet_mm < rq.z_outlet_mm))
    throw ParameterError("z", "expected z_inlet < z_outlet");
  if (!(rq.lean_rad > 0 && rq.lean_rad < kPi / 3)) throw ParameterError("lean", "expected (0, 60) degrees");
  if (!(rq.lean_step_rad > 0)) throw ParameterError("lean_step", "expected > 0");
  if (!(rq.lean_max_rad >= rq.lean_rad && rq.lean_max_rad < kPi / 2))
    throw ParameterError("lean_max", "expected at least the lean and below 90 degrees");
  if (!(rq.side_tilt_rad >= 0) || !(rq.side_step_rad > 0)) throw ParameterError("side_tilt", "expected >= 0 (step > 0)");
  if (!(rq.guard_spacing_mm > 0)) throw ParameterError("guard_spacing", "expected > 0");
  if (rq.closed_sections < 4) throw ParameterError("closed_sections", "expected >= 4");
  if (rq.row_samples < 64) throw ParameterError("row_samples", "expected >= 64");
  if (rq.threads < 1) throw ParameterError("threads", "expected >= 1");
  if (!(rq.links.retract_mm > 0) || !(rq.links.min_retract_mm > 0 && rq.links.min_retract_mm <= rq.links.retract_mm))
    throw ParameterError("retract", "expected 0 < min_retract <= retract");
  // The cone above the ball must stand off the blade: the lean is the
  // angle between the axis and the blade.
  if (!(rq.lean_rad > taper_rad(*rq.tool)))
    throw ParameterError("lean", "expected more than the taper's half angle, " +
                                     std::to_string(taper_rad(*rq.tool) * 180 / kPi) + " degrees");
}

// The row of contacts at one level of the root, as the ball centre's closed
// path (interpolated through row_samples points) and the v and u of each.
struct RootRow {
  double level = 0;  // height above the hub; -1 for the fillet row
  std::vector<double> v, u;  // v unwrapped from v_start, increasing
  std::vector<double> cum;   // the centre path's chord-length knots
  ClosedCurve path;
  std::vector<double> height;  // contact height above the hub per sample
};

struct Planner {
  const HubFinishRequest& rq;
  const CollisionWorld& world;
  const ToolBody& body;
  const Guards& guards;
  double pose_allowed = 0;
  const Tool& short_tool;
  double flute_from_mm = 0, flute_top_mm = 0;
  const ToolBody* flute_body;  // null: no flute above 2 r (a short ball end)
  const CollisionWorld& flute_world;
  Clearances flute_clearance;

  // The operation's test of a pose, cheap enough for every axis the
  // interference loop tries: the bottom of the cutter (the ball and the
  // cone up to `short_tool`'s flute length) through the gouge guards of the
  // design surfaces, the flute above it (`flute`, a conical body from there
  // up) against both blades' closed surfaces meshed, where nothing may touch.
  // The whole cutter against the guards would trace every sample the long
  // flute passes near a neighbouring blade.
  std::string gouge(const ToolPose& p) const {
    const struct {
      const GougeGuard* g;
      const char* name;
    } all[] = {{guards.blade.get(), "blade k"}, {guards.next.get(), "blade k+1"}, {guards.hub.get(), "the hub"}};
    for (const auto& a : all) {
      if (!a.g) continue;
      const GougeGuard::Cut c = a.g->deepest_cut(short_tool, p, p, pose_allowed, true, true);
      if (c.depth_mm < 0) {
        std::ostringstream os;
        os << "the cutter cuts " << -c.depth_mm * 1000 << " um into " << a.name << " at (" << c.point.x() << ", "
           << c.point.y() << ", " << c.point.z() << ")";
        return os.str();
      }
    }
    if (!flute_body) return "";
    const PoseCheck fc = flute_world.check(*flute_body, flute_pose(p), flute_clearance, 0);
    if (!fc.clear) return "the flute above the ball: " + describe(fc, flute_world);
    return "";
  }
  ToolPose flute_pose(const ToolPose& p) const { return ToolPose{p.tip + flute_from_mm * p.axis, p.axis}; }
  // The flute's margin over its clearance at a pose, resolved up to 1 mm.
  double flute_margin(const ToolPose& p) const {
    return flute_body ? flute_world.check(*flute_body, flute_pose(p), flute_clearance, 1.0).min_margin_mm : 1e300;
  }
  // Whether the cutting motion a -> b cuts the design or brings the flute
  // to the blades. The ball's centre runs on the chord of its path, whose
  // deviation the steps measured: the ball alone cannot dip deeper. What
  // the axis turn moves is the cone beside the ball: the bottom is swept
  // through the guards where the axis turns more than kSweepTurnRad, and the
  // flute proved against the blades unless its margins at both ends exceed
  // how far any of its points moves (|d tip| + turn * reach).
  bool motion_dips(const ToolPose& a, double margin_a, const ToolPose& b, double margin_b) const {
    const PoseMotion motion(a, b);
    if (motion.angle_rad() > kSweepTurnRad)
      for (const GougeGuard* g : {guards.blade.get(), guards.next.get(), guards.hub.get()})
        if (g && g->deepest_cut(short_tool, a, b, pose_allowed, false, false, kCutSweepMm).depth_mm < 0) return true;
    if (!flute_body || std::min(margin_a, margin_b) > motion.max_point_speed(flute_top_mm)) return false;
    return !flute_world.check_motion(*flute_body, flute_pose(a), flute_pose(b), flute_clearance, rq.motion_tol_mm).clear;
  }

  // Each contact tilted until clear (its own settings), the motion from the
  // previous accepted pose too; refusals and dipping motions split the row.
  struct Contact {
    ContactFrame frame;
    Vec3 centre = Vec3::Zero();
    double t = 0;
    TiltSettings tilt;
    TiltSettings second;  // tried when `tilt` finds no clear axis
    bool has_second = false;
  };
  void plan_row(HubFinishOp op, int row, double level, bool reversed, const std::vector<Contact>& contacts,
                double max_dev, std::vector<HubFinishPass>& out, std::vector<HubFinishRefusal>& refusals,
                int& gouge_splits, Progress& progress) const {
    HubFinishPass cur;
    cur.op = op;
    cur.row = row;
    cur.level = level;
    cur.reversed = reversed;
    cur.max_deviation_mm = max_dev;
    auto close = [&] {
      if (!cur.poses.empty()) out.push_back(cur);
      cur.poses.clear();
    };
    double prev_margin = 0;
    for (size_t i = 0; i < contacts.size(); ++i) {
      progress.check();
      const Contact& c = contacts[i];
      const ToolPose* prev = cur.poses.empty() ? nullptr : &cur.poses.back().pose;
      TiltOutcome o = tilt_until_clear(world, body, c.frame, static_cast<int>(i), c.tilt, prev);
      if (!o.accepted && c.has_second) {
        const TiltOutcome o2 = tilt_until_clear(world, body, c.frame, static_cast<int>(i), c.second, prev);
        if (o2.accepted) o = o2;
        else o.refusal.reason += "; and leaning further: " + o2.refusal.reason;
      }
      if (!o.accepted) {
        refusals.push_back({op, row, c.frame.point, o.refusal.reason});
        close();
        continue;
      }
      HubFinishPose hp;
      hp.pose = o.pose.pose;
      hp.contact = c.frame.point;
      hp.normal = c.frame.normal;
      hp.centre = c.centre;
      hp.t = c.t;
      hp.tilted = o.pose.tries > 1;
      const double margin = flute_margin(hp.pose);
      if (prev && motion_dips(*prev, prev_margin, hp.pose, margin)) {
        ++gouge_splits;
        refusals.push_back({op, row, c.frame.point,
                            "the cutting motion from the previous contact dips below the design: row split"});
        close();
      }
      cur.poses.push_back(hp);
      prev_margin = margin;
    }
    close();
  }
};

// The channel's route for the join: the pose nearest the middle of each
// channel row (t = 0.5), `lift_mm` up its axis, from the row nearest
// z_from to the one nearest z_to, rows at least `spacing_mm` apart in z
// (the first and last always).
std::vector<ToolPose> channel_waypoints(const HubFinishPart& channel, double z_from, double z_to, double lift_mm,
                                        double spacing_mm) {
  struct Mid {
    double level = 0, off = 1e300;
    const HubFinishPose* pose = nullptr;
  };
  std::vector<Mid> rows;  // by row, in the channel's row order
  for (const HubFinishPass& pass : channel.passes) {
    if (pass.row >= static_cast<int>(rows.size())) rows.resize(static_cast<size_t>(pass.row) + 1);
    Mid& m = rows[static_cast<size_t>(pass.row)];
    m.level = pass.level;
    for (const HubFinishPose& p : pass.poses)
      if (std::abs(p.t - 0.5) < m.off) m.off = std::abs(p.t - 0.5), m.pose = &p;
  }
  std::vector<const Mid*> have;
  for (const Mid& m : rows)
    if (m.pose) have.push_back(&m);
  if (have.empty()) return {};
  std::sort(have.begin(), have.end(), [](const Mid* a, const Mid* b) { return a->level < b->level; });
  auto nearest = [&](double z) {
    size_t best = 0;
    for (size_t i = 1; i < have.size(); ++i)
      if (std::abs(have[i]->level - z) < std::abs(have[best]->level - z)) best = i;
    return best;
  };
  const long from = static_cast<long>(nearest(z_from)), to = static_cast<long>(nearest(z_to));
  const long step = to >= from ? 1 : -1;
  std::vector<ToolPose> out;
  double last = 0;
  for (long i = from;; i += step) {
    const Mid& m = *have[static_cast<size_t>(i)];
    if (i == from || i == to || std::abs(m.level - last) >= spacing_mm) {
      const ToolPose& p = m.pose->pose;
      out.push_back({p.tip + lift_mm * unit_axis(p.axis), p.axis});
      last = m.level;
    }
    if (i == to) break;
  }
  return out;
}

// How close the tool comes to the part between the join's two retracted
// poses (the legs that leave and reach the cutting poses touch it by
// design): the whole tool against the world and both blades' closed
// surfaces (which the proofs see the cutter against through the guards
// only), at poses along the legs no tool point moves more than 0.5 mm
// between, resolved up to 2 mm. Returns the margin and what it is against.
std::pair<double, std::string> join_clearance(const std::vector<ToolPose>& via, const LinkChecks& checks,
                                              const CollisionWorld& blades) {
  constexpr double kStepMm = 0.5, kHorizonMm = 2;
  std::pair<double, std::string> out{kHorizonMm, "nothing within " + std::to_string(kHorizonMm) + " mm"};
  const double reach = checks.body->tool().reach();
  for (size_t i = 0; i + 1 < via.size(); ++i) {
    const PoseMotion motion(via[i], via[i + 1]);
    const int n = std::max(1, static_cast<int>(std::ceil(motion.max_point_speed(reach) / kStepMm)));
    for (int k = 0; k <= n; ++k) {
      const ToolPose pose = motion.pose_at(static_cast<double>(k) / n);
      for (const CollisionWorld* w : {checks.world, &blades}) {
        const PoseCheck pc = w->check(*checks.body, pose, checks.clearances, kHorizonMm);
        if (pc.min_margin_mm < out.first) out = {pc.min_margin_mm, describe(pc, *w)};
      }
    }
  }
  return out;
}

// HubFinishResult::join: plan_link from the root's last pose to the
// channel's first by each route in turn (see hub_finish.h), the first that
// proves kept.
void plan_join(HubFinishResult& res, const LinkChecks& checks, const LinkOptions& lo, double ball_r,
               const CollisionWorld& flute_world) {
  HubFinishConnection& join = res.join;
  join.kind = HubFinishConnection::Kind::Link;
  if (res.root.passes.empty() || res.channel.passes.empty()) {
    join.reason = "nothing to join: the plan has only one part";
    return;
  }
  const auto t0 = Clock::now();
  const HubFinishPose& a = res.root.passes.back().poses.back();
  const HubFinishPose& b = res.channel.passes.front().poses.front();
  join.from_pass = static_cast<int>(res.root.passes.size()) - 1;
  join.to_pass = 0;
  const LinkEnd from{a.pose, a.normal}, to{b.pose, b.normal};

  // Over the blades: both ends far enough up their axes that the tool's
  // ball is outside the blades' tips by 1 mm more than the chord between
  // the two raised tips sags towards the axis.
  double tip_radius = 0;
  for (const Surface* s : {res.blade_closed.get(), res.next_closed.get()})
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; j < 360; ++j) {
        const Vec3 p = s->point(0.9 + 0.01 * i, j / 360.0);
        tip_radius = std::max(tip_radius, std::hypot(p.x(), p.y()));
      }
  const double turn = std::abs(wrap_near(angle_of(a.pose.tip) - angle_of(b.pose.tip), 0));
  const double high_radius = tip_radius * (2 - std::cos(0.5 * turn)) + ball_r + 1;
  double rise_mm = 0;
  bool can_rise = true;
  for (const ToolPose* p : {&a.pose, &b.pose}) {
    const Vec3 radial = Vec3(p->tip.x(), p->tip.y(), 0).normalized();
    const double outward = unit_axis(p->axis).dot(radial);
    if (outward < 0.2) can_rise = false;
    else rise_mm = std::max(rise_mm, (high_radius - p->tip.dot(radial)) / outward - lo.min_retract_mm);
  }

  struct Route {
    const char* name;
    LinkOptions options;
    std::vector<ToolPose> via;
  };
  std::vector<Route> routes;
  routes.push_back({"through the channel", lo,
                    channel_waypoints(res.channel, a.centre.z(), res.channel.passes.front().level, lo.retract_mm, 3.0)});
  routes.push_back({"straight", lo, {}});
  std::string reasons;
  if (can_rise) {
    LinkOptions high = lo;
    high.axis_retract_mm = std::max(0.0, rise_mm);
    routes.push_back({"over the blades", high, {}});
  } else {
    reasons = "over the blades: an axis leans too far from radial to rise over the tips";
  }
  for (const Route& route : routes) {
    const PlannedLink pl = plan_link(from, to, checks, route.options, route.via);
    if (!pl.clear) {
      reasons += (reasons.empty() ? "" : "; ") + std::string(route.name) + ": " + pl.reason;
      continue;
    }
    join.clear = true;
    join.poses = pl.via;
    for (size_t i = 0; i < pl.via.size(); ++i) join.motion.push_back(link_leg_name(pl.legs[i]));
    res.join_route = route.name;
    res.join_offset_mm = pl.offset_mm;
    res.join_deepest_cut_mm = pl.deepest_cut_mm;
    CollisionWorld own;
    if (flute_world.size() == 0) {  // a short ball end: no flute world to reuse
      own.add("blade k", tessellate(*res.blade_closed, 0.05), {PartMask{}, 0.05});
      own.add("blade k+1", tessellate(*res.next_closed, 0.05), {PartMask{}, 0.05});
    }
    std::tie(res.join_margin_mm, res.join_margin_at) =
        join_clearance(pl.via, checks, flute_world.size() ? flute_world : own);
    break;
  }
  if (!join.clear) join.reason = "root to channel: no route proved (" + reasons + ")";
  res.join_seconds = seconds_since(t0);
}

}  // namespace

HubFinishResult plan_hub_finish(const HubFinishRequest& rq, Progress& progress) {
  validate(rq);
  HubFinishResult res;
  const auto t_setup = Clock::now();
  const Tool& tool = *rq.tool;
  const double r = ball_radius(tool);
  const SurfaceOfRevolution& hub = *rq.hub;
  const double ref_angle = angle_of(rq.blade.pressure->point(0.5, 0.5));
  // Both blades closed on the workers (blade k+1's angles read near blade
  // k's turned forward, so that the pitch comes out positive).
  ClosedRoot closed[2];
  parallel_for_index(2, rq.threads, [&](size_t i) {
    closed[i] = close_root(i == 0 ? rq.blade : rq.next, hub, rq.closed_sections, ref_angle + (i == 0 ? 0 : 0.3),
                           kTargetHeightMm);
  });
  const ClosedRoot& blade = closed[0];
  const ClosedRoot& next = closed[1];
  res.blade_closed = blade.surface;
  res.next_closed = next.surface;
  res.pitch_rad = next.theta_centroid - blade.theta_centroid;
  if (res.pitch_rad <= 0) res.pitch_rad += 2 * kPi;
  const double pitch = res.pitch_rad;
  // The hub around both blades, 4 mm beyond their roots either way.
  const double r_mid = std::hypot(blade.points[0].x(), blade.points[0].y());
  const double th0 = blade.theta_min - 4 / r_mid;
  const double th1 = wrap_near(next.theta_max, blade.theta_centroid + pitch) + 4 / r_mid;
  const auto sector = std::make_shared<const HubSector>(rq.hub, th0, th1);
  res.hub_sector = sector;
  {
    const SurfaceDerivs d = sector->eval(0.5, 0.5);
    res.hub_sector_flip = d.pu.cross(d.pv).dot(Vec3(d.p.x(), d.p.y(), 0)) < 0;
  }
  const double zh0 = hub.point(0, 0).z(), zh1 = hub.point(1, 0).z();
  const double z_in = rq.z_inlet_mm != rq.z_outlet_mm ? rq.z_inlet_mm : std::min(zh0, zh1);
  const double z_out = rq.z_inlet_mm != rq.z_outlet_mm ? rq.z_outlet_mm : std::max(zh0, zh1);
  res.z_inlet_mm = z_in;
  res.z_outlet_mm = z_out;

  Guards guards;
  CollisionWorld own_world;
  parallel_for_index(4, rq.threads, [&](size_t i) {
    if (i == 0)
      guards.blade = std::make_unique<GougeGuard>(*blade.surface, link_guard_sampling(*blade.surface, rq.guard_spacing_mm, false));
    else if (i == 1)
      guards.next = std::make_unique<GougeGuard>(*next.surface, link_guard_sampling(*next.surface, rq.guard_spacing_mm, false));
    else if (i == 2)
      guards.hub = std::make_unique<GougeGuard>(*sector, link_guard_sampling(*sector, rq.guard_spacing_mm, res.hub_sector_flip));
    else if (!rq.world)
      own_world = hub_finish_world(rq);
  });
  res.guard_spacing_mm = std::max({guards.blade->spacing_mm(), guards.next->spacing_mm(), guards.hub->spacing_mm()});
  guards.margin = std::max({guards.blade->between_samples_mm(r), guards.next->between_samples_mm(r),
                            guards.hub->between_samples_mm(r)});
  const double pose_allowed = std::max(0.0, rq.allowed_overcut_mm - guards.margin);

  const CollisionWorld& world = rq.world ? *rq.world : own_world;
  const ToolBody body(tool, rq.tool_tol_mm);
  // The cutter split for the pose checks (Planner::gouge): the ball and
  // 2 r of cone, and the flute above as a conical body (a conical drum
  // wheel of a barrel radius so large that it bulges outward by < 0.01 um:
  // it encloses the cone).
  const double beta = taper_rad(tool);
  const double flute_from = 2 * r;
  const double flute_top = tool.cutter().z_max();
  const Tool short_tool = Tool::tapered_ball_end_mill({r, beta, flute_from, {}, {}});
  std::unique_ptr<ToolBody> flute_body;
  CollisionWorld flute_world;
  if (flute_top > flute_from + 0.1) {
    const double rf0 = tool.cutter().radius_at(flute_from), rf1 = tool.cutter().radius_at(flute_top - 1e-9);
    const Tool flute_tool =
        Tool::conical_drum_wheel({2 * rf0 + 2e-5, 2 * rf1 + 2e-5, 1e7, flute_top - flute_from, {}, {}});
    flute_body = std::make_unique<ToolBody>(flute_tool, 0.005);
    constexpr double kFluteMeshMm = 0.05;  // with that as margin: the flute keeps off the blades
    flute_world.add("blade k", tessellate(*blade.surface, kFluteMeshMm), {PartMask{}, kFluteMeshMm});
    flute_world.add("blade k+1", tessellate(*next.surface, kFluteMeshMm), {PartMask{}, kFluteMeshMm});
  }
  Clearances flute_clearance;
  flute_clearance.cutter_mm = 0.02;  // the flute stands off the finished blades
  Planner planner{rq,         world,      body,      guards,     pose_allowed,   short_tool,
                  flute_from, flute_top, flute_body.get(), flute_world, flute_clearance};
  res.setup_seconds = seconds_since(t_setup);

  TiltSettings base;
  base.lead_step_rad = rq.lean_step_rad;
  base.allow_tilt = rq.side_tilt_rad > 0;
  base.tilt_step_rad = rq.side_step_rad;
  base.tilt_range_rad = rq.side_tilt_rad;
  base.clearances = rq.clearances;
  base.motion_tol_mm = rq.motion_tol_mm;
  base.pose_filter = [&planner](const ToolPose& p) { return planner.gouge(p); };

  // ---- root rows ----------------------------------------------------------
  const Surface& bs = *blade.surface;
  // Height of a contact above the hub; the fillet's condition: the centre
  // r from the hub.
  auto height = [&](double u, double v) { return hub.radial_offset(bs.point(u, v)); };
  auto centre_of = [&](double u, double v) {
    const SurfaceDerivs d = bs.eval(u, v);
    return Vec3(d.p + r * unit_normal(d, false));
  };
  auto fillet_gap = [&](double u, double v) { return hub.radial_offset(centre_of(u, v)) - r; };
  auto wrap01 = [](double v) { return v - std::floor(v); };
  // Start the rows in the middle of one flank (away from the edges).
  const double v_start = wrap01(0.5 * (blade.le_v + blade.te_v) + (blade.le_v > blade.te_v ? 0 : 0.5));
  const int ns = rq.row_samples;
  // u of the root at v (seed for the row solves).
  auto root_u = [&](double v) {
    const double x = wrap01(v) * static_cast<double>(blade.u.size());
    const size_t i = static_cast<size_t>(x) % blade.u.size(), j = (i + 1) % blade.u.size();
    return blade.u[i] + (x - std::floor(x)) * (blade.u[j] - blade.u[i]);
  };
  const double du_per_mm = 1.0 / std::max(1e-9, bs.eval(0.5, v_start).pu.norm());
  double fillet_top = 1e300;  // the fillet row's highest contact, once known
  auto solve_u = [&](bool fillet, double level, double v, double guess) {
    const double vv = wrap01(v);
    if (fillet) return solve_near([&](double u) { return fillet_gap(u, vv); }, guess, 0.05 * du_per_mm, 0, 1, "the fillet row");
    // A constant-height row where it lies above the fillet row; the fillet
    // row where that is higher (the ball would dip into the hub below it).
    const double uh = solve_near([&](double u) { return height(u, vv) - level; }, guess, 0.05 * du_per_mm, 0, 1, "a root row");
    if (level > fillet_top) return uh;
    const double uf = solve_near([&](double u) { return fillet_gap(u, vv); }, uh, 0.05 * du_per_mm, 0, 1, "the fillet row");
    return std::max(uh, uf);
  };
  auto make_root_row = [&](bool fillet, double level) {
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
  };
  // The hub's normal at the foot of p (gradient of the distance).
  auto hub_normal_at = [&](const Vec3& p) {
    const double e = 1e-4;
    Vec3 g;
    for (int k = 0; k < 3; ++k) {
      Vec3 d = Vec3::Zero();
      d[k] = e;
      g[k] = (hub.radial_offset(p + d) - hub.radial_offset(p - d)) / (2 * e);
    }
    return Vec3(g.normalized());
  };

  std::vector<RootRow> root_rows;
  if (rq.root) {
    RootRow fillet = make_root_row(true, 0);
    res.fillet_min_mm = 1e300;
    res.fillet_max_mm = -1e300;
    for (double h : fillet.height) res.fillet_min_mm = std::min(res.fillet_min_mm, h), res.fillet_max_mm = std::max(res.fillet_max_mm, h);
    res.root_fillet_mm = r;
    fillet_top = res.fillet_max_mm + 1e-6;
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
      const double c = n.dot(hub_normal_at(d.p));
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
    parallel_for_index(levels.size(), rq.threads, [&](size_t j) { more[j] = make_root_row(false, levels[j]); });
    for (RootRow& rr : more) root_rows.push_back(std::move(rr));
  }

  // ---- channel rows --------------------------------------------------------
  // Signed distance of a point from a closed blade (its nearest point,
  // seeded from the nearest root sample).
  auto signed_distance = [&](const ClosedRoot& b, const Vec3& q) {
    return blade_signed_distance(*b.surface, b.u, b.v, b.points, r * du_per_mm, q);
  };
  struct FloorRow {
    double z = 0, radius = 0, theta0 = 0, theta1 = 0, cell0 = 0, cell1 = 0;
    Vec3 normal_zr = Vec3::Zero();  // the hub normal in the meridian plane (n_z, n_r)
  };
  std::vector<FloorRow> floor_rows;
  std::unique_ptr<SurfaceOfRevolution> off;
  // The floor row at centre height z: the ball on the hub's offset, between
  // where it touches blade k and blade k+1 (or the cell's mid-lines).
  std::function<FloorRow(double)> floor_row_at;
  if (rq.channel) {
    off = std::make_unique<SurfaceOfRevolution>(hub_offset_out(hub, r));
    const double zo0 = std::min(off->point(0, 0).z(), off->point(1, 0).z());
    const double zo1 = std::max(off->point(0, 0).z(), off->point(1, 0).z());
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
    floor_row_at = [&, zo0, zo1](double z) {
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
    };
    parallel_for_index(floor_rows.size(), rq.threads,
                       [&](size_t j) { floor_rows[j] = floor_row_at(zc0 + (zc1 - zc0) * static_cast<double>(j) / n); });
    for (const FloorRow& fr : floor_rows) {
      res.floor_z.push_back(fr.z);
      res.floor_theta0.push_back(fr.theta0);
      res.floor_theta1.push_back(fr.theta1);
      res.floor_cell0.push_back(fr.cell0);
      res.floor_cell1.push_back(fr.cell1);
    }
  }

  // ---- contacts and poses, row by row on the workers -----------------------
  const size_t n_root = root_rows.size(), n_floor = floor_rows.size();
  std::vector<std::vector<HubFinishPass>> pieces(n_root + n_floor);
  std::vector<std::vector<HubFinishRefusal>> refusals(n_root + n_floor);
  std::vector<int> splits(n_root + n_floor, 0);
  std::vector<double> devs(n_root + n_floor, 0.0);
  auto t_rows = Clock::now();
  run_parallel(n_root + n_floor, rq.threads, progress, "hub finish rows", [&](size_t k, Progress& own) {
    std::vector<Planner::Contact> contacts;
    double dev = 0;
    if (k < n_root) {
      const RootRow& row = root_rows[k];
      const RowSteps st = plan_row_steps(row.path, rq.steps);
      dev = st.max_deviation_mm;
      for (size_t i = 0; i < st.t.size(); ++i) {
        const double t = st.t[i];
        const auto it = std::upper_bound(row.cum.begin(), row.cum.end(), t);
        const size_t s = std::min<size_t>(static_cast<size_t>(std::max<long>(0, it - row.cum.begin() - 1)), ns - 1);
        const double f = std::clamp((t - row.cum[s]) / std::max(1e-12, row.cum[s + 1] - row.cum[s]), 0.0, 1.0);
        const double v = row.v[s] + f / ns;
        const double ug = s + 1 < static_cast<size_t>(ns) ? row.u[s] + f * (row.u[s + 1] - row.u[s]) : row.u[s];
        const double u = solve_u(row.level < 0, row.level, v, ug);
        const SurfaceDerivs d = bs.eval(u, wrap01(v));
        Planner::Contact c;
        c.frame.point = d.p;
        c.frame.normal = unit_normal(d, false);
        c.centre = d.p + r * c.frame.normal;
        c.t = wrap01(v);
        Vec3 x = row.path.eval(t).dt;
        x -= x.dot(c.frame.normal) * c.frame.normal;
        x.normalize();
        const Vec3 up = hub_normal_at(d.p);
        if (c.frame.normal.cross(x).dot(up) < 0) x = -x;  // Y = Z x X up the span
        c.frame.tangent = x;
        c.tilt = base;
        c.tilt.lead0_rad = rq.lean_rad;
        c.tilt.lead_max_rad = rq.lean_max_rad;
        c.tilt.tilt0_rad = 0;
        contacts.push_back(std::move(c));
      }
      planner.plan_row(HubFinishOp::Root, static_cast<int>(k), row.level, false, contacts, dev, pieces[k],
                       refusals[k], splits[k], own);
    } else {
      const size_t j = k - n_root;
      const FloorRow& fr = floor_rows[j];
      if (!(fr.theta1 > fr.theta0)) {
        refusals[k].push_back({HubFinishOp::Channel, static_cast<int>(j), Vec3(0, 0, fr.z),
                               "the ball does not fit between the blades at this z"});
        return;
      }
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
      planner.plan_row(HubFinishOp::Channel, static_cast<int>(j), fr.z, reversed, contacts, dev, pieces[k],
                       refusals[k], splits[k], own);
    }
    devs[k] = dev;
  });
  auto fill_part = [&](HubFinishPart& part, HubFinishOp op, size_t first, size_t count) {
    part.op = op;
    part.rows = static_cast<int>(count);
    for (size_t k = first; k < first + count; ++k) {
      for (HubFinishPass& p : pieces[k]) part.passes.push_back(std::move(p));
      for (HubFinishRefusal& f : refusals[k]) res.refusals.push_back(std::move(f)), ++part.refusals;
      part.gouge_splits += splits[k];
      part.max_deviation_mm = std::max(part.max_deviation_mm, devs[k]);
    }
    for (const HubFinishPass& p : part.passes) {
      part.poses += static_cast<int>(p.poses.size());
      for (const HubFinishPose& hp : p.poses) part.tilted += hp.tilted;
    }
    if (part.step_min_mm > 1e299) part.step_min_mm = 0;
  };
  fill_part(res.root, HubFinishOp::Root, 0, n_root);
  fill_part(res.channel, HubFinishOp::Channel, n_root, n_floor);
  const double rows_seconds = seconds_since(t_rows);

  // How far the ball whose centre runs straight from ca to cb cuts below
  // blade k, blade k+1 and the hub, measured at 9 points of the segment
  // (exact distances: projections on the blades, the hub's meridian).
  auto ball_dip = [&](const Vec3& ca, const Vec3& cb) {
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
  };

  // ---- connections: steps along the fillet / blade, links, departures -------
  LinkChecks checks;
  checks.world = &world;
  checks.body = &body;
  checks.clearances = rq.clearances;
  checks.motion_tol_mm = rq.motion_tol_mm;
  checks.guard = guards.blade.get();
  checks.guard_margin_mm = guards.margin;
  checks.more_guards = {{guards.next.get(), guards.margin}, {guards.hub.get(), guards.margin}};
  checks.traverse_world = world.unchecked_pairs();  // the blades either side of the channel and the hub, for the ball
  LinkOptions lo = rq.links;
  lo.allowed_overcut_mm = rq.allowed_overcut_mm;
  auto end_of = [](const HubFinishPose& p) { return LinkEnd{p.pose, p.normal}; };
  auto connect_part = [&](HubFinishPart& part, Progress& own) {
    const auto t0 = Clock::now();
    const int n = static_cast<int>(part.passes.size());
    if (n == 0) return;
    part.connections.resize(static_cast<size_t>(n) + 1);
    auto departure = [&](const HubFinishPose& p, int from, int to, const char* what) {
      HubFinishConnection c;
      c.kind = HubFinishConnection::Kind::Departure;
      c.from_pass = from;
      c.to_pass = to;
      const PlannedDeparture d = plan_departure(end_of(p), checks, lo);
      c.clear = d.clear;
      if (d.clear) {
        c.poses = {d.away};
        c.motion = {from < 0 ? "start" : "retract"};
      } else {
        c.reason = std::string(hub_finish_op_name(part.op)) + " " + what + ": " + d.reason;
      }
      return c;
    };
    part.connections.front() = departure(part.passes.front().poses.front(), -1, 0, "lead-in");
    part.connections.back() = departure(part.passes.back().poses.back(), n - 1, -1, "lead-out");
    parallel_for_index(static_cast<size_t>(n - 1), rq.threads, [&](size_t pi) {
      own.check();
      const int p = static_cast<int>(pi);
      const HubFinishPass &a = part.passes[p], &b = part.passes[p + 1];
      HubFinishConnection c;
      c.from_pass = p;
      c.to_pass = p + 1;
      // Consecutive rows: a straight step from the end of one to the start
      // of the next (along the blade / the fillet), a cutting move proved
      // as a link's legs are.
      const Vec3 gap = b.poses.front().centre - a.poses.back().centre;
      if (b.row == a.row + 1 && gap.norm() < 4 * std::max(part.step_max_mm, 0.05)) {
        std::vector<ToolPose> chain{a.poses.back().pose};
        if (part.op == HubFinishOp::Channel) {
          // Along the fillet: the ball's centre on the straight segment
          // between two rows' ends cuts the corner of a tight round (the
          // TE's, r_e + r round) deeper than the guards' samples see;
          // ends of rows between are put in until the segment's dip,
          // measured on the blades themselves, is within the chord
          // tolerance.
          const bool high_end = !a.reversed;  // the row ended at theta1
          std::function<void(const ToolPose&, const Vec3&, double, const ToolPose&, const Vec3&, double, int)> fill =
              [&](const ToolPose& pa, const Vec3& ca, double za, const ToolPose& pb, const Vec3& cb, double zb,
                  int depth) {
                if (depth == 0 || ball_dip(ca, cb) <= rq.steps.chord_tol_mm) {
                  chain.push_back(pb);
                  return;
                }
                const double zm = 0.5 * (za + zb);
                const FloorRow fr = floor_row_at(zm);
                const double th = high_end ? fr.theta1 : fr.theta0;
                const Vec3 cm(fr.radius * std::cos(th), fr.radius * std::sin(th), zm);
                const Vec3 axis = PoseMotion(pa, pb).pose_at(0.5).axis;
                const ToolPose pm{cm - r * axis, axis};
                fill(pa, ca, za, pm, cm, zm, depth - 1);
                fill(pm, cm, zm, pb, cb, zb, depth - 1);
              };
          fill(a.poses.back().pose, a.poses.back().centre, a.level, b.poses.front().pose, b.poses.front().centre,
               b.level, 6);
        } else {
          chain.push_back(b.poses.front().pose);
        }
        const ChainProof proof = prove_chain(chain, checks, rq.allowed_overcut_mm, true, true);
        if (proof.clear) {
          c.kind = HubFinishConnection::Kind::Step;
          c.clear = true;
          for (size_t i = 1; i + 1 < chain.size(); ++i) c.poses.push_back(chain[i]), c.motion.push_back("step");
          part.connections[pi + 1] = std::move(c);
          return;
        }
      }
      c.kind = HubFinishConnection::Kind::Link;
      const PlannedLink pl = plan_link(end_of(a.poses.back()), end_of(b.poses.front()), checks, lo);
      c.clear = pl.clear;
      if (pl.clear) {
        c.poses = pl.via;
        for (size_t i = 0; i < pl.via.size(); ++i) c.motion.push_back(link_leg_name(pl.legs[i]));
      } else {
        c.reason = std::string(hub_finish_op_name(part.op)) + " link from pass " + std::to_string(p) + " to " +
                   std::to_string(p + 1) + ": " + pl.reason;
      }
      part.connections[pi + 1] = std::move(c);
    });
    for (const HubFinishConnection& c : part.connections) {
      if (!c.clear) ++part.refused_connections;
      else if (c.kind == HubFinishConnection::Kind::Step) ++part.steps;
      else if (c.kind == HubFinishConnection::Kind::Link) ++part.links;
    }
    part.seconds += seconds_since(t0);
  };
  connect_part(res.root, progress);
  connect_part(res.channel, progress);
  plan_join(res, checks, lo, r, flute_world);
  // Rows' time shared by the poses each part planned.
  const double total_poses = std::max(1, res.root.poses + res.channel.poses);
  res.root.seconds += rows_seconds * res.root.poses / total_poses;
  res.channel.seconds += rows_seconds * res.channel.poses / total_poses;
  return res;
}

namespace {

// One part's program (hub_finish_moves(part)), without its lead-in or its
// lead-out where the join replaces them.
std::vector<DrumFinishMove> part_moves(const HubFinishPart& part, bool lead_in, bool lead_out) {
  std::vector<DrumFinishMove> out;
  auto add = [&](DrumFinishMove::Kind kind, const ToolPose& pose, int row, const std::string& motion,
                 const std::string& reason = "") {
    DrumFinishMove m;
    m.kind = kind;
    m.pose = pose;
    m.row = row;
    m.motion = motion;
    m.reason = reason;
    out.push_back(std::move(m));
  };
  if (part.passes.empty()) return out;
  for (size_t p = 0; p <= part.passes.size(); ++p) {
    const HubFinishConnection& c = part.connections[p];
    const int row = part.passes[std::min(p, part.passes.size() - 1)].row;
    std::string reach = "approach";
    if ((p == 0 && !lead_in) || (p == part.passes.size() && !lead_out)) {
      // the join's
    } else if (!c.clear) {
      add(DrumFinishMove::Kind::Stop, ToolPose{}, row, "stop", c.reason);
    } else {
      const DrumFinishMove::Kind kind =
          c.kind == HubFinishConnection::Kind::Step ? DrumFinishMove::Kind::Feed : DrumFinishMove::Kind::Rapid;
      for (size_t i = 0; i < c.poses.size(); ++i) add(kind, c.poses[i], row, c.motion[i]);
      if (c.kind == HubFinishConnection::Kind::Step) reach = "step";
    }
    if (p == part.passes.size()) break;
    const HubFinishPass& pass = part.passes[p];
    for (size_t i = 0; i < pass.poses.size(); ++i)
      add(DrumFinishMove::Kind::Feed, pass.poses[i].pose, pass.row, i == 0 ? reach : "cut");
  }
  return out;
}

// The whole program in three pieces: the root, the join (its rapids, or a
// Stop), the channel.
struct Program {
  std::vector<DrumFinishMove> root, join, channel;
};
Program program_of(const HubFinishResult& r) {
  Program p;
  const bool both = !r.root.passes.empty() && !r.channel.passes.empty();
  const bool joined = both && r.join.clear;
  p.root = part_moves(r.root, true, !joined);
  p.channel = part_moves(r.channel, !joined, true);
  if (!both) return p;
  const int row = r.channel.passes.front().row;
  if (joined) {
    for (const ToolPose& pose : r.join.poses) {
      DrumFinishMove m;
      m.kind = DrumFinishMove::Kind::Rapid;
      m.pose = pose;
      m.row = row;
      m.motion = "link";
      p.join.push_back(std::move(m));
    }
  } else {
    DrumFinishMove stop;
    stop.kind = DrumFinishMove::Kind::Stop;
    stop.row = row;
    stop.motion = "stop";
    stop.reason = r.join.reason;
    p.join.push_back(std::move(stop));
  }
  return p;
}

}  // namespace

std::vector<DrumFinishMove> hub_finish_moves(const HubFinishPart& part) { return part_moves(part, true, true); }

std::vector<DrumFinishMove> hub_finish_moves(const HubFinishResult& r) {
  Program p = program_of(r);
  std::vector<DrumFinishMove> out = std::move(p.root);
  out.insert(out.end(), p.join.begin(), p.join.end());
  out.insert(out.end(), p.channel.begin(), p.channel.end());
  return out;
}

namespace {

HubFinishRegionStats region_stats(const UndercutResult& u, const std::vector<char>& in_region) {
  HubFinishRegionStats s;
  double sum = 0;
  int reached = 0;
  for (size_t i = 0; i < u.residual_mm.size(); ++i) {
    const double x = u.residual_mm[i];
    if (std::isfinite(x)) s.overcut_mm = std::min(s.overcut_mm, x);
    if (!in_region[i]) continue;
    ++s.samples;
    if (!std::isfinite(x)) {
      ++s.unreached;
      continue;
    }
    ++reached;
    if (x > s.left_max_mm || s.left_max_sample < 0) s.left_max_mm = std::max(s.left_max_mm, x), s.left_max_sample = static_cast<long>(i);
    sum += std::max(0.0, x);
  }
  s.left_mean_mm = reached ? sum / reached : 0;
  return s;
}

double interp(const std::vector<double>& x, const std::vector<double>& y, double at) {
  const auto it = std::lower_bound(x.begin(), x.end(), at);
  if (it == x.begin()) return y.front();
  if (it == x.end()) return y.back();
  const size_t k = static_cast<size_t>(it - x.begin());
  const double f = (at - x[k - 1]) / std::max(1e-15, x[k] - x[k - 1]);
  return y[k - 1] + f * (y[k] - y[k - 1]);
}

}  // namespace

HubFinishRegions hub_finish_regions(const HubFinishResult& result, const HubFinishRequest& rq,
                                    const HubFinishSimOptions& options) {
  if (!rq.tool || !rq.hub) throw ParameterError("tool", "the request's tool and hub are required");
  if (options.root_samples_u < 2 || options.root_samples_v < 2 || options.floor_samples_u < 2 ||
      options.floor_samples_v < 2)
    throw ParameterError("samples", "expected at least 2 samples each way");
  const SurfaceOfRevolution& hub = *rq.hub;
  HubFinishRegions regions;
  UndercutOptions base;
  base.sweep_step_mm = options.sweep_step_mm;
  base.threads = options.threads;
  base.search_above_mm = 0.1;
  base.search_below_mm = 0.1;
  if (rq.root && result.blade_closed && !result.fillet_v.empty()) {
    const Surface& bs = *result.blade_closed;
    // u window: from below the lowest root point to above the top row's highest.
    double ulo = 1, uhi = 0;
    for (size_t i = 0; i < result.fillet_u.size(); i += 8) {
      const double v = result.fillet_v[i];
      auto g = [&](double u) { return hub.radial_offset(bs.point(u, v)); };
      const double du = 1.0 / std::max(1e-9, bs.eval(result.fillet_u[i], v).pu.norm());
      ulo = std::min(ulo, result.fillet_u[i] - (g(result.fillet_u[i]) + 0.3) * du);
      uhi = std::max(uhi, result.fillet_u[i] + (result.top_height_mm + 0.5 - g(result.fillet_u[i])) * du);
    }
    UndercutOptions& o = regions.root;
    o = base;
    o.u0 = std::max(0.0, ulo);
    o.u1 = std::min(1.0, uhi);
    o.samples_u = options.root_samples_u;
    o.samples_v = options.root_samples_v;
    regions.blade = result.blade_closed;
    std::vector<char>& strip = regions.strip;
    std::vector<char>& fillet = regions.fillet;
    strip.assign(static_cast<size_t>(o.samples_u) * o.samples_v, 0);
    fillet.assign(strip.size(), 0);
    for (int i = 0; i < o.samples_u; ++i) {
      const double u = o.u0 + (o.u1 - o.u0) * i / (o.samples_u - 1);
      for (int j = 0; j < o.samples_v; ++j) {
        const double v = o.v0 + (o.v1 - o.v0) * j / (o.samples_v - 1);
        const double h = hub.radial_offset(bs.point(u, v));
        if (h < 0 || h > result.top_height_mm) continue;
        const size_t k = static_cast<size_t>(i) * o.samples_v + j;
        (u >= interp(result.fillet_v, result.fillet_u, v) ? strip : fillet)[k] = 1;
      }
    }
  }
  if (rq.channel && result.hub_sector && !result.floor_z.empty()) {
    UndercutOptions& o = regions.floor;
    o = base;
    o.flip_normal = result.hub_sector_flip;
    o.samples_u = options.floor_samples_u;
    o.samples_v = options.floor_samples_v;
    // The meridian u of the inlet and outlet planes.
    auto u_at_z = [&](double z) {
      double lo = 0, hi = 1;
      const bool rising = hub.point(1, 0).z() > hub.point(0, 0).z();
      for (int i = 0; i < 60; ++i) {
        const double m = 0.5 * (lo + hi);
        if ((hub.point(m, 0).z() < z) == rising) lo = m; else hi = m;
      }
      return 0.5 * (lo + hi);
    };
    const double ua = u_at_z(result.z_inlet_mm), ub = u_at_z(result.z_outlet_mm);
    o.u0 = std::min(ua, ub);
    o.u1 = std::max(ua, ub);
    // Floor: between the rows' ends at the sample's z (the row ends are ball
    // centres; the contact below is at the same angle, z moved by the
    // normal's tilt, which the row interpolation in z absorbs).
    regions.hub = result.hub_sector;
    std::vector<char>& floor = regions.channel_floor;
    std::vector<char>& middle = regions.channel_middle;
    floor.assign(static_cast<size_t>(o.samples_u) * o.samples_v, 0);
    middle.assign(floor.size(), 0);
    const double zmin = result.floor_z.front(), zmax = result.floor_z.back();
    constexpr double kExactMm = 0.6;
    const double r = ball_radius(*rq.tool);
    std::vector<Vec3> seeds;
    for (size_t k = 0; k < result.fillet_u.size(); ++k)
      seeds.push_back(result.blade_closed->point(result.fillet_u[k], result.fillet_v[k]));
    std::vector<Vec3> seeds_next;
    for (size_t k = 0; k < result.fillet_u.size(); ++k)
      seeds_next.push_back(result.next_closed->point(result.fillet_u[k], result.fillet_v[k]));
    auto fits = [&](const Vec3& c) {
      const struct {
        const Surface* s;
        const std::vector<Vec3>* pts;
      } blades[] = {{result.blade_closed.get(), &seeds}, {result.next_closed.get(), &seeds_next}};
      for (const auto& b : blades) {
        double near = 1e300;
        for (const Vec3& q : *b.pts) near = std::min(near, (q - c).squaredNorm());
        if (near > (3 * r + 2) * (3 * r + 2)) continue;
        if (blade_signed_distance(*b.s, result.fillet_u, result.fillet_v, *b.pts, 0, c) < r - 1e-4) return false;
      }
      return true;
    };
    for (int i = 0; i < o.samples_u; ++i) {
      const double u = o.u0 + (o.u1 - o.u0) * i / (o.samples_u - 1);
      for (int j = 0; j < o.samples_v; ++j) {
        const double v = o.v0 + (o.v1 - o.v0) * j / (o.samples_v - 1);
        const SurfaceDerivs d = result.hub_sector->eval(u, v);
        const Vec3& p = d.p;
        // The ball resting on the hub here: its centre (the rows' z is the centre's).
        const Vec3 c = p + r * unit_normal(d, result.hub_sector_flip);
        const double zc = c.z();
        if (zc < zmin || zc > zmax) continue;
        const double t0 = interp(result.floor_z, result.floor_theta0, zc);
        const double t1 = interp(result.floor_z, result.floor_theta1, zc);
        const double th = wrap_near(angle_of(p), t0);
        const double radius = std::hypot(p.x(), p.y());
        if (th < t0 - kExactMm / radius || th > t1 + kExactMm / radius) continue;
        // The cell's own: beyond its mid-lines the next channel's rows cut.
        if (th < interp(result.floor_z, result.floor_cell0, zc) || th > interp(result.floor_z, result.floor_cell1, zc))
          continue;
        bool in = th >= t0 && th <= t1;
        // Near the rows' ends (a round's end moves fast from row to row):
        // whether the ball resting on the hub here fits, measured.
        if (std::min(std::abs(th - t0), std::abs(th - t1)) * radius < kExactMm) in = fits(c);
        if (in) floor[static_cast<size_t>(i) * o.samples_v + j] = 1;
        if (th > t0 + 1.0 / radius && th < t1 - 1.0 / radius) middle[static_cast<size_t>(i) * o.samples_v + j] = 1;
      }
    }
  }
  return regions;
}

HubFinishSimulation simulate_hub_finish(const HubFinishResult& result, const HubFinishRequest& rq,
                                        const HubFinishSimOptions& options, Progress& progress) {
  if (!(options.sweep_step_mm > 0)) throw ParameterError("sweep_step", "expected > 0");
  const HubFinishRegions regions = hub_finish_regions(result, rq, options);
  const auto t0 = Clock::now();
  HubFinishSimulation sim;
  // Every move of the plan, root and channel: either can cut the other's region.
  // The plan is blade k's and channel k's; the blisk is periodic and a job
  // turns the plan onto every blade, so the neighbours' copies cut here too:
  // channel k - 1 reaches blade k's pressure-side fillet, blade k + 1's root
  // rows and channel k + 1 the floor's far side.
  auto turned = [&](const std::vector<ToolPass>& in, double angle) {
    const Eigen::AngleAxisd rot(angle, Vec3::UnitZ());
    std::vector<ToolPass> out = in;
    for (ToolPass& pass : out)
      for (ToolPose& p : pass) p = ToolPose{rot * p.tip, rot * p.axis};
    return out;
  };
  auto join = [](std::vector<ToolPass> a, const std::vector<ToolPass>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  };
  // Only what can reach a window's samples: the stretches of each pass
  // whose poses come within the tool's reach of the window's box, with the
  // pose before and after (the motion from or to a far pose can still cut).
  auto near_window = [&](const std::vector<ToolPass>& in, const Surface& s, const UndercutOptions& o) {
    Eigen::AlignedBox3d box;
    for (int i = 0; i <= 16; ++i)
      for (int j = 0; j <= 64; ++j) box.extend(s.point(o.u0 + (o.u1 - o.u0) * i / 16, o.v0 + (o.v1 - o.v0) * j / 64));
    const double reach = rq.tool->cutter().reach() + 1;
    std::vector<ToolPass> out;
    for (const ToolPass& pass : in) {
      std::vector<char> near(pass.size());
      for (size_t k = 0; k < pass.size(); ++k) near[k] = box.exteriorDistance(pass[k].tip) < reach;
      ToolPass cur;
      for (size_t k = 0; k < pass.size(); ++k) {
        const bool keep = near[k] || (k > 0 && near[k - 1]) || (k + 1 < pass.size() && near[k + 1]);
        if (keep) {
          cur.push_back(pass[k]);
        } else if (!cur.empty()) {
          out.push_back(std::move(cur));
          cur.clear();
        }
      }
      if (!cur.empty()) out.push_back(std::move(cur));
    }
    return out;
  };
  // The join as one pass from the root's last pose to the channel's first.
  const Program program = program_of(result);
  std::vector<DrumFinishMove> join_moves;
  if (result.join.clear && !program.root.empty() && !program.channel.empty()) {
    join_moves.push_back(program.root.back());
    join_moves.insert(join_moves.end(), program.join.begin(), program.join.end());
    join_moves.push_back(program.channel.front());
  }
  const std::vector<ToolPass> root = passes_of_moves(program.root).passes;
  const std::vector<ToolPass> channel = passes_of_moves(program.channel).passes;
  const std::vector<ToolPass> link = passes_of_moves(join_moves).passes;
  const double pitch = result.pitch_rad;
  // Blade k - 1's join runs through channel k - 1, beside blade k's pressure
  // flank; blade k + 1's starts on its root, beside the floor.
  const std::vector<ToolPass> root_passes =
      join(join(join(join(root, link), channel), turned(channel, -pitch)), turned(link, -pitch));
  const std::vector<ToolPass> floor_passes = join(
      join(join(join(join(join(channel, root), link), turned(root, pitch)), turned(link, pitch)), turned(channel, -pitch)),
      turned(channel, pitch));
  if (regions.blade) {
    const Surface& bs = *regions.blade;
    sim.root = simulate_undercut(bs, *rq.tool, near_window(root_passes, bs, regions.root), regions.root, progress);
    sim.strip = region_stats(sim.root, regions.strip);
    sim.fillet = region_stats(sim.root, regions.fillet);
  }
  if (regions.hub) {
    sim.floor = simulate_undercut(*regions.hub, *rq.tool, near_window(floor_passes, *regions.hub, regions.floor),
                                  regions.floor, progress);
    sim.channel_floor = region_stats(sim.floor, regions.channel_floor);
    sim.channel_middle = region_stats(sim.floor, regions.channel_middle);
  }
  sim.seconds = seconds_since(t0);
  return sim;
}

std::string hub_finish_apt(const HubFinishResult& result, const HubFinishRequest& rq) {
  std::ostringstream os;
  char buf[240];
  os << "$$ bliskrun hub and blade-root finish\n";
  os << "$$ TOOL " << (rq.tool ? rq.tool->description() : std::string("?")) << "\n";
  std::snprintf(buf, sizeof buf, "$$ SCALLOP %.6f CHORD_TOL %.6f ROOT_ROWS %d CHANNEL_ROWS %d POSES %d REFUSALS %zu\n",
                rq.scallop_mm, rq.steps.chord_tol_mm, result.root.rows, result.channel.rows,
                result.root.poses + result.channel.poses, result.refusals.size());
  os << buf;
  os << "MULTAX\n";
  const Program p = program_of(result);
  auto rows = [](int row) { return "$$ ROW " + std::to_string(row) + "\n"; };
  if (!p.root.empty()) {
    os << "$$ OPERATION root\n";
    write_apt_moves(os, p.root, rows);
  }
  if (!p.join.empty()) {
    if (result.join.clear) os << "$$ JOIN root to channel (" << result.join_route << ")\n";
    write_apt_moves(os, p.join, rows, "JOIN REFUSED");
  }
  if (!p.channel.empty()) {
    os << "$$ OPERATION channel\n";
    write_apt_moves(os, p.channel, rows);
  }
  os << "FINI\n";
  return os.str();
}

}  // namespace bliskrun
