#pragma once
// The hub finish's steps (core/planning/hub_finish.h), shared between the
// files of core/planning/hub_finish/: each file one idea —
//   shapes.cpp        the hub sector, arcs, offsets, the ball's radius and taper
//   closed_root.cpp   each blade closed around its section, its root and mid-line
//   world.cpp         what is proved against: the world, the guards, the flute
//   poses.cpp         a row's contacts tilted clear into passes (checks and tilt)
//   root_rows.cpp     the root strip's rows: the fillet row and rows at constant height
//   channel_rows.cpp  the channel floor's rows across the channel
//   connections.cpp   steps between rows, links between passes, leads
//   join.cpp          the link from the root's last pose to the channel's first
//   program.cpp       the moves and the APT program
//   simulation.cpp    the simulation of the plan over the root strip and the floor
// Not a public interface: only these files and hub_finish.cpp include it.
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/common/timing.h"
#include "core/common/error.h"
#include "core/geometry/closed_curve.h"
#include "core/geometry/root_find.h"
#include "core/planning/ball_cutter.h"
#include "core/planning/hub_finish.h"

namespace bliskrun::hub_detail {

// Sweep step of the cutting segments' gouge check (as the repair paths'):
// the independent simulation, at 0.05 mm, measures what is left.
constexpr double kCutSweepMm = 0.15;
constexpr double kSweepTurnRad = 0.5 * kPi / 180;
// The floor's initial axes point at the channel's middle this high above
// the hub (two thirds of the built-in blade): they follow the blades' twist.
constexpr double kTargetHeightMm = 20.0;

// ---- shapes (shapes.cpp) ----

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

// The unit normal pu x pv (flipped or not); throws where it is singular.
Vec3 unit_normal(const SurfaceDerivs& d, bool flip);
inline double angle_of(const Vec3& p) { return std::atan2(p.y(), p.x()); }
inline double wrap_near(double a, double ref) { return a - 2 * kPi * std::round((a - ref) / (2 * kPi)); }

// The hub offset by d out of the material (radial_offset d; d < 0: into
// it), whichever way the meridian runs.
SurfaceOfRevolution hub_offset_out(const SurfaceOfRevolution& hub, double d);

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
Poly3 fit_poly3(const std::vector<double>& z, const std::vector<double>& y, const std::vector<double>& w);

// The ball's radius and the taper: ball_radius, taper_rad (core/planning/ball_cutter.h).

// ---- closed blades (closed_root.cpp) ----

// One blade closed around its section, with its root on the hub.
struct ClosedRoot {
  std::shared_ptr<const BSplineSurface> surface;
  double le_v = 0, te_v = 0;
  double edge_kink_deg = 0;  // close_blade's: the closed surface is the blade near its edges when ~0
  std::vector<double> v, u;  // the root (height 0) at v samples
  std::vector<Vec3> points;
  double theta_min = 0, theta_max = 0, theta_centroid = 0;
  Poly3 mid;                 // the mid-line between the two sides, theta(z)
  Poly3 mid_top;             // the same at the channel axes' target height
  double z_min = 0, z_max = 0;
};

// Blade `faces` closed around its section, its root (height 0) and its
// mid-line there and at top_level.
ClosedRoot close_root(const BladeFaces& faces, const SurfaceOfRevolution& hub, int sections, double ref_angle,
                      double top_level);
// Signed distance of q from a closed blade surface (> 0 outside), by its
// nearest point: Newton from the nearest of the given samples (u raised by
// `lift_u`, towards the ball's height), else from a coarse grid. -1 when no
// foot is found (near the medial axis, inside): callers take that as "does
// not fit", which is safe.
double blade_signed_distance(const Surface& s, const std::vector<double>& su, const std::vector<double>& sv,
                             const std::vector<Vec3>& sp, double lift_u, const Vec3& q);

// ---- what is proved against (world.cpp) ----

struct Guards {
  std::unique_ptr<GougeGuard> blade, next, hub;
  double margin = 0;
};

// The guards over blade k, blade k+1 and the hub sector, built on the
// workers, with the world of hub_finish_world when the request has none.
void make_guards(const HubFinishRequest& rq, const ClosedRoot& blade, const ClosedRoot& next, const Surface& sector,
                 bool sector_flip, Guards& guards, CollisionWorld& own_world);
// The flute above the ball and 2 r of cone as a conical body, and the world
// of both closed blades it is proved against; null where the tool has no
// flute above that (a short ball end).
std::unique_ptr<ToolBody> flute_body_of(const Tool& tool, double flute_from, const ClosedRoot& blade,
                                        const ClosedRoot& next, CollisionWorld& flute_world);

// ---- poses: the checks and the interference loop (poses.cpp) ----

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
  std::string gouge(const ToolPose& p) const;
  ToolPose flute_pose(const ToolPose& p) const { return ToolPose{p.tip + flute_from_mm * p.axis, p.axis}; }
  // The flute's margin over its clearance at a pose, resolved up to 1 mm.
  double flute_margin(const ToolPose& p) const;
  // Whether the cutting motion a -> b cuts the design or brings the flute
  // to the blades. The ball's centre runs on the chord of its path, whose
  // deviation the steps measured: the ball alone cannot dip deeper. What
  // the axis turn moves is the cone beside the ball: the bottom is swept
  // through the guards where the axis turns more than kSweepTurnRad, and the
  // flute proved against the blades unless its margins at both ends exceed
  // how far any of its points moves (|d tip| + turn * reach).
  bool motion_dips(const ToolPose& a, double margin_a, const ToolPose& b, double margin_b) const;

  // Each contact tilted until clear (its own settings), the motion from the
  // previous accepted pose too; refusals and dipping motions split the row.
  // `start_previous`: the pose the row is entered from (the previous row's
  // last), which the first contact's motion must clear as well; null: none.
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
                int& gouge_splits, Progress& progress, const ToolPose* start_previous = nullptr) const;
};

// ---- root rows (root_rows.cpp) ----

// The row of contacts at one level of the root, as the ball centre's closed
// path (interpolated through row_samples points) and the v and u of each.
struct RootRow {
  double level = 0;  // height above the hub; -1 for the fillet row
  std::vector<double> v, u;  // v unwrapped from v_start, increasing
  std::vector<double> cum;   // the centre path's chord-length knots
  ClosedCurve path;
  std::vector<double> height;  // contact height above the hub per sample
};

// Where v runs past 1 (the rows start mid-flank): v mod 1.
inline double wrap01(double v) { return v - std::floor(v); }

// Blade k's root rows' geometry: contact heights above the hub, the ball's
// centre on the blade's offset, and the u of a row at each v.
struct RootGeometry {
  const HubFinishRequest& rq;
  const SurfaceOfRevolution& hub;
  const ClosedRoot& blade;
  const Surface& bs;  // blade.surface
  double r = 0;       // the ball's radius
  double v_start = 0;  // where every row starts: the middle of one flank (away from the edges)
  int ns = 0;          // samples per row (rq.row_samples)
  double du_per_mm = 0;
  double fillet_top = 1e300;  // the fillet row's highest contact, once known

  RootGeometry(const HubFinishRequest& rq, const ClosedRoot& blade, double r);
  // Height of a contact above the hub; the fillet's condition: the centre
  // r from the hub.
  double height(double u, double v) const;
  Vec3 centre_of(double u, double v) const;
  double fillet_gap(double u, double v) const;
  // u of the root at v (seed for the row solves).
  double root_u(double v) const;
  // u of the row at v: the fillet row's, or a constant-height row's (the
  // fillet row's where that is higher).
  double solve_u(bool fillet, double level, double v, double guess) const;
  RootRow make_row(bool fillet, double level) const;
};

// The fillet row and the rows above it up to rq.root_top_mm (sets the
// fillet's and the rows' figures in res and geo.fillet_top).
std::vector<RootRow> plan_root_rows(RootGeometry& geo, HubFinishResult& res);
// The contacts of a root row, stepped by chord height along its centres'
// path; sets its deviation.
std::vector<Planner::Contact> root_contacts(const RootGeometry& geo, const RootRow& row, const TiltSettings& base,
                                            double& dev);

// ---- channel rows (channel_rows.cpp) ----

// One row across the channel floor at ball-centre height z.
struct FloorRow {
  double z = 0, radius = 0, theta0 = 0, theta1 = 0, cell0 = 0, cell1 = 0;
  Vec3 normal_zr = Vec3::Zero();  // the hub normal in the meridian plane (n_z, n_r)
};

// The channel floor's geometry: the ball's centre on the hub offset by r,
// between where it touches blade k and blade k+1.
struct FloorGeometry {
  const HubFinishRequest& rq;
  const ClosedRoot& blade;
  const ClosedRoot& next;
  double r = 0, pitch = 0;
  double lift_u = 0;  // blade_signed_distance's seed lift
  std::unique_ptr<SurfaceOfRevolution> off;
  double zo0 = 0, zo1 = 0;  // the offset's z range

  FloorGeometry(const HubFinishRequest& rq, const ClosedRoot& blade, const ClosedRoot& next, double r, double pitch,
                double lift_u);
  // Signed distance of a point from a closed blade (its nearest point,
  // seeded from the nearest root sample).
  double signed_distance(const ClosedRoot& b, const Vec3& q) const;
  // The floor row at centre height z: between where the ball touches blade
  // k and blade k+1 (or the cell's mid-lines).
  FloorRow row_at(double z) const;
  // How far the ball whose centre runs straight from ca to cb cuts below
  // blade k, blade k+1 and the hub, measured at 9 points of the segment.
  double ball_dip(const Vec3& ca, const Vec3& cb) const;
};

// The floor rows from inlet to outlet (sets the channel's figures in res).
std::vector<FloorRow> plan_floor_rows(const FloorGeometry& geo, double z_in, double z_out, HubFinishResult& res);
// The contacts of floor row j (reversed on odd rows), the axis aimed at the
// channel's middle; sets its deviation.
std::vector<Planner::Contact> floor_contacts(const FloorGeometry& geo, const FloorRow& fr, size_t j,
                                             const TiltSettings& base, double& dev);

// ---- rows into passes (poses.cpp) ----

// Every row's contacts (root rows first, then floor rows) into passes on
// the workers, gathered into res.root and res.channel; `floor` null without
// the channel. Returns the rows' seconds.
double plan_passes(const Planner& planner, const TiltSettings& base, const RootGeometry& root,
                   const std::vector<RootRow>& root_rows, const FloorGeometry* floor,
                   const std::vector<FloorRow>& floor_rows, HubFinishResult& res, Progress& progress);

// ---- connections (connections.cpp) ----

// The steps, links and leads of a part's passes; `floor` null without the
// channel.
void connect_part(const HubFinishRequest& rq, const LinkChecks& checks, const LinkOptions& lo,
                  const FloorGeometry* floor, HubFinishPart& part, Progress& own);

// ---- the join (join.cpp) ----

// HubFinishResult::join: plan_link from the root's last pose to the
// channel's first by each route in turn (see hub_finish.h), the first that
// proves kept.
void plan_join(HubFinishResult& res, const LinkChecks& checks, const LinkOptions& lo, double ball_r,
               const CollisionWorld& flute_world);

// ---- program (program.cpp) ----

// The whole program in three pieces: the root, the join (its rapids, or a
// Stop), the channel.
struct Program {
  Toolpath root, join, channel;
};
Program program_of(const HubFinishResult& r);

}  // namespace bliskrun::hub_detail
