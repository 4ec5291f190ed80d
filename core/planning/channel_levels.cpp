#include "core/planning/channel_levels.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "core/common/error.h"
#include "core/common/parallel.h"
#include "core/geometry/projection.h"
#include "core/geometry/root_find.h"

namespace bliskrun {

// Names of this unit live in their own namespace: the unity build puts it
// beside channel_roughing.cpp, whose private names it must not meet.
namespace channel_levels_detail {

Vec3 turned_about_z(const Vec3& p, double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  return Vec3(c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z());
}

// Where a point stands to a face: the foot, the face's unit normal (into
// the channel) and span direction (unit pu, towards the tip) there, and the
// distance signed by the side of the face (> 0 in the channel). With the
// foot on the face's boundary (its tip or hub row, a chord end) it is the
// distance to that edge, still signed by the side.
struct FaceFoot {
  double distance = 0;
  double u = 0, v = 0;
  Vec3 point = Vec3::Zero(), normal = Vec3::UnitX(), span = Vec3::UnitZ();
  // The blade's point nearest (blade_distance): the foot, or a point of the
  // rest of the blade where that is nearer.
  Vec3 nearest = Vec3::Zero();
};

// A level's cross-section at one station: the angles of the two contacts
// (the ball r + stock from each face), the slot's angle halfway, and the
// contact axes.
struct Section {
  double u = 0;          // hub meridian parameter of the station
  double theta[2] = {0, 0};
  double middle = 0;
  FaceFoot foot[2];
  Vec3 axis[2] = {Vec3::UnitZ(), Vec3::UnitZ()};
  Vec3 middle_axis = Vec3::UnitZ();
  Eigen::Vector2d crossing[2];  // (u, v) of each face where it crosses the level's circle (seeds)
};

class Geometry {
 public:
  explicit Geometry(const ChannelLevelsRequest& rq)
      : rq_(rq), r_(rq.cutter->ball_radius_mm()), hub_stock_(rq.hub_stock_mm < 0 ? rq.stock_mm : rq.hub_stock_mm),
        contact_(r_ + rq.stock_mm) {
    faces_[0] = &rq.left;
    faces_[1] = &rq.right;
    // The cone's half angle above the ball (0 for a cylindrical flute).
    const FlankCutter& c = *rq.cutter;
    const double s1 = std::min(2 * r_, 0.5 * c.flute_top_mm()), s2 = c.flute_top_mm();
    beta_ = s2 > s1 ? std::max(0.0, std::atan((c.radius_at(s2 - 1e-6) - c.radius_at(s1)) / (s2 - 1e-6 - s1))) : 0.0;
    tilt_ = beta_ + deg_to_rad(rq.tilt_deg);
    // The hub normal's sense: towards the faces' tips (their u = 1 rows).
    const double v_mid = faces_[0]->v_at(0.5);
    const Vec3 a = faces_[0]->face->point(0, v_mid), b = faces_[0]->face->point(1, v_mid);
    const ProjectionOptions po;
    const SurfaceProjection pr = project_to_surface(*rq.hub, a, po);
    if (!pr.ok) throw Error("channel levels: the left face's hub end does not project onto the hub (" + pr.failure + ")");
    const SurfaceDerivs d = rq.hub->eval(pr.u, pr.v);
    sign_ = d.pu.cross(d.pv).dot(b - a) >= 0 ? 1 : -1;
    // Which way round Z the channel runs from the left face to the right.
    const double th0 = std::atan2(a.y(), a.x());
    const Vec3 ar = faces_[1]->face->point(0, faces_[1]->v_at(0.5));
    dir_ = wrap_angle(std::atan2(ar.y(), ar.x()) - th0) >= 0 ? 1 : -1;
    // T(u) tabulated once (a root of the top's radial offset along the
    // normal each), read by linear interpolation: every section asks it.
    top_.resize(kTopSamples + 1);
    for (int j = 0; j <= kTopSamples; ++j) top_[static_cast<size_t>(j)] = solve_top_height(static_cast<double>(j) / kTopSamples);
    // Coarse samples of each face, (r, z) per (u, v), to seed the crossings.
    for (int i = 0; i < 2; ++i) {
      for (int a_ = 0; a_ <= kSeedU; ++a_)
        for (int b_ = 0; b_ <= kSeedV; ++b_) {
          const double fu = static_cast<double>(a_) / kSeedU;
          const double fv = faces_[i]->v_at(static_cast<double>(b_) / kSeedV);
          const Vec3 p = faces_[i]->face->point(fu, fv);
          seeds_[i].push_back({Eigen::Vector2d(fu, fv), Vec2(std::hypot(p.x(), p.y()), p.z())});
        }
    }
  }

  double ball_radius() const { return r_; }
  double hub_stock() const { return hub_stock_; }

  // The hub's meridian point at angle 0 and its unit normal towards the tips.
  void meridian(double u, Vec3& p, Vec3& n) const {
    const SurfaceDerivs d = rq_.hub->eval(u, 0);
    p = d.p;
    n = sign_ * d.pu.cross(d.pv).normalized();
  }
  // T(u): how far along n(u) the top lies over the hub.
  double top_height(double u) const {
    const double x = std::clamp(u, 0.0, 1.0) * kTopSamples;
    const size_t j = std::min(static_cast<size_t>(x), static_cast<size_t>(kTopSamples - 1));
    const double f = x - static_cast<double>(j);
    return top_[j] + (top_[j + 1] - top_[j]) * f;
  }
  double solve_top_height(double u) const {
    Vec3 p, n;
    meridian(u, p, n);
    const auto f = [&](double t) { return rq_.top->radial_offset(p + t * n); };
    double a = 0, fa = f(0);
    for (double b = 2; b <= 1000; b += 2) {
      const double fb = f(b);
      if ((fa > 0) != (fb > 0)) return illinois_root(f, a, b, fa, fb, 1e-9);
      a = b;
      fa = fb;
    }
    throw Error("channel levels: the top does not cross the hub's normal at u = " + std::to_string(u) +
                " within 1000 mm");
  }
  // D_l(u): the ball centre's height over the hub along n.
  double centre_height(int level, int levels, double u) const {
    const double t = top_height(u);
    return t + r_ - level * (t - hub_stock_) / levels;
  }
  Vec3 centre(double u, double height, double theta) const {
    Vec3 p, n;
    meridian(u, p, n);
    return turned_about_z(p + height * n, theta);
  }

  FaceFoot foot(int i, const Vec3& x, Eigen::Vector2d& seed) const {
    ProjectionOptions po;
    po.seed = seed;
    const SurfaceProjection pr = project_to_surface(*faces_[i]->face, x, po);
    if (!pr.ok) throw Error(std::string("channel levels: a point does not project onto the ") + side_name(i) + " face (" +
                            pr.failure + ")");
    seed = Eigen::Vector2d(pr.u, pr.v);
    const SurfaceDerivs d = faces_[i]->face->eval(pr.u, pr.v);
    FaceFoot f;
    f.u = pr.u;
    f.v = pr.v;
    f.point = pr.point;
    f.normal = d.pu.cross(d.pv).normalized();
    f.span = d.pu.normalized();
    // On the face's boundary (its tip or hub row, its chord ends) the
    // distance is to that edge: the offset along the normal would be short.
    const double along = (x - pr.point).dot(f.normal);
    f.distance = pr.on_boundary ? (along >= 0 ? 1 : -1) * pr.distance : along;
    return f;
  }

  // Where face i meets the circle of the level point (u, height): its (u,
  // v), by Newton on the point's radius and z from the nearest coarse
  // sample; over the face's tip (or under its hub row) the edge's point at
  // the circle's z; beyond the face's chord part (`edge` set) the point of
  // its end at the circle's radius. nullopt when Newton fails.
  std::optional<Eigen::Vector2d> crossing(int i, double u, double height, const Eigen::Vector2d* seed,
                                          bool* edge = nullptr) const {
    const Vec3 c = centre(u, height, 0);
    const double rc = std::hypot(c.x(), c.y()), zc = c.z();
    Eigen::Vector2d x;
    if (seed) {
      x = *seed;
    } else {
      double best = std::numeric_limits<double>::infinity();
      for (const auto& s : seeds_[i]) {
        const double e = (s.second - Vec2(rc, zc)).squaredNorm();
        if (e < best) {
          best = e;
          x = s.first;
        }
      }
    }
    const ChannelFace& f = *faces_[i];
    const double vlo = std::min(f.v_inlet, f.v_outlet), vhi = std::max(f.v_inlet, f.v_outlet);
    bool u_fixed = false, v_fixed = false;
    x[1] = std::clamp(x[1], vlo, vhi);
    for (int it = 0; it < 60; ++it) {
      const SurfaceDerivs d = f.face->eval(x[0], x[1]);
      const double r = std::hypot(d.p.x(), d.p.y());
      const Vec2 e(r - rc, d.p.z() - zc);
      const double ru = (d.p.x() * d.pu.x() + d.p.y() * d.pu.y()) / r, rv = (d.p.x() * d.pv.x() + d.p.y() * d.pv.y()) / r;
      Eigen::Vector2d step;
      if (u_fixed && v_fixed) break;
      if (v_fixed) {  // along the chord end: its point at the circle's radius
        if (std::abs(ru) < 1e-12) return std::nullopt;
        step = Eigen::Vector2d(e.x() / ru, 0);
      } else if (u_fixed) {  // along the tip (or hub) row: its point at the circle's z
        if (std::abs(d.pv.z()) < 1e-12) return std::nullopt;
        step = Eigen::Vector2d(0, e.y() / d.pv.z());
      } else {
        Eigen::Matrix2d j;
        j << ru, rv, d.pu.z(), d.pv.z();
        if (std::abs(j.determinant()) < 1e-14) return std::nullopt;
        step = j.inverse() * Eigen::Vector2d(e.x(), e.y());
      }
      x -= step;
      if (x[0] < 0 || x[0] > 1) {
        x[0] = std::clamp(x[0], 0.0, 1.0);
        u_fixed = true;
      }
      if (x[1] < vlo || x[1] > vhi) {
        x[1] = std::clamp(x[1], vlo, vhi);
        v_fixed = true;
      }
      if (step.norm() < 1e-12) break;
    }
    if (edge) *edge = v_fixed;
    return x;
  }

  // The distance from x to the blade of face i: to the face (signed, > 0
  // in the channel) and, near its chord ends, to the rest of the blade
  // (its rounds, its other flank; unsigned). seeds[0] the face's, seeds[k]
  // the k-th other surface's (updated).
  double blade_distance(int i, const Vec3& x, std::vector<Eigen::Vector2d>& seeds, FaceFoot* at = nullptr) const {
    const ChannelFace& f = *faces_[i];
    if (seeds.size() < f.blade.size() + 1) seeds.resize(f.blade.size() + 1, Eigen::Vector2d(0.5, 0.5));
    FaceFoot ff = foot(i, x, seeds[0]);
    ff.nearest = ff.point;
    if (at) *at = ff;
    double d = ff.distance;
    if (f.blade.empty()) return d;
    // How far the foot lies from the chord part's nearer end, mm: the rest
    // of the blade is no nearer than that less the distance to the face.
    const double vlo = std::min(f.v_inlet, f.v_outlet), vhi = std::max(f.v_inlet, f.v_outlet);
    const double to_end = std::min(ff.v - vlo, vhi - ff.v) * f.face->eval(ff.u, ff.v).pv.norm();
    if (to_end > std::abs(d) + contact_ + 2) return d;
    for (size_t k = 0; k < f.blade.size(); ++k) {
      ProjectionOptions po;
      po.seed = seeds[k + 1];
      SurfaceProjection pr = project_to_surface(*f.blade[k], x, po);
      if (!pr.ok) pr = project_to_surface(*f.blade[k], x);
      if (!pr.ok) throw Error(std::string("channel levels: a point does not project onto the ") + side_name(i) +
                              " blade's other surfaces (" + pr.failure + ")");
      seeds[k + 1] = Eigen::Vector2d(pr.u, pr.v);
      if (pr.distance < d) {
        d = pr.distance;
        if (at) at->nearest = pr.point;
      }
    }
    return d;
  }

  // The contact axis at ball centre c: the face's span direction, in the
  // plane square to the direction from the blade's nearest point to c,
  // turned away from the blade by the cone's half angle and the tilt.
  Vec3 contact_axis(const FaceFoot& f, const Vec3& c) const {
    Vec3 n = c - f.nearest;
    n = n.norm() > 1e-9 ? n.normalized() : f.normal;
    Vec3 span = f.span - f.span.dot(n) * n;
    span = span.norm() > 1e-9 ? span.normalized() : f.span;
    return (std::cos(tilt_) * span + std::sin(tilt_) * n).normalized();
  }

  // The section of a level (height along n) at station u; nullopt where
  // neither contact's foot lies inside its face's chord part. A contact
  // beyond its face's chord keeps r + stock off the face's end and the rest
  // of that blade; where the face ends short of the circle (the ball never
  // comes r + stock near that blade there: the channel's mouth), that side
  // reaches to the angle of the face's end. Throws
  // Error where both faces cross the circle and the ball and its stock do
  // not fit between them.
  std::optional<Section> section(double u, double height, const Section* near) const {
    Section s;
    s.u = u;
    double phi[2];
    bool edge[2] = {false, false};
    for (int i = 0; i < 2; ++i) {
      const std::optional<Eigen::Vector2d> x = crossing(i, u, height, near ? &near->crossing[i] : nullptr, &edge[i]);
      if (!x) return std::nullopt;
      s.crossing[i] = *x;
      const Vec3 p = faces_[i]->face->point((*x)[0], (*x)[1]);
      phi[i] = std::atan2(p.y(), p.x());
    }
    phi[1] = phi[0] + wrap_angle(phi[1] - phi[0]);
    if ((phi[1] - phi[0]) * dir_ <= 0) return std::nullopt;  // the faces cross: no channel here
    const double mid = 0.5 * (phi[0] + phi[1]);
    const double r_circle = std::hypot(centre(u, height, 0).x(), centre(u, height, 0).y());
    bool inside[2] = {false, false};
    for (int i = 0; i < 2; ++i) {
      // From behind face i (or at its end, within r + stock of it) to the
      // middle: the ball's distance to that blade less r + stock changes
      // sign once.
      const double into = i == 0 ? dir_ : -dir_;  // from face i into the channel, in angle
      std::vector<Eigen::Vector2d> seeds{s.crossing[i]};
      const auto h = [&](double th) { return blade_distance(i, centre(u, height, th), seeds) - contact_; };
      double a = phi[i], ha = h(a);
      for (int k = 0; k < 3 && ha >= 0; ++k) ha = h(a -= into * contact_ / r_circle);
      if (ha >= 0) {
        // The face ends short of this circle (the channel's mouth, where the
        // other face still runs on): that side is open, its paths reach no
        // further than the face's end's angle, r + stock or more off it.
        s.theta[i] = phi[i];
        seeds.assign(1, s.crossing[i]);
        blade_distance(i, centre(u, height, phi[i]), seeds, &s.foot[i]);
        s.axis[i] = contact_axis(s.foot[i], centre(u, height, phi[i]));
        continue;
      }
      const double hb = h(mid);
      if (hb <= 0) {
        if (edge[0] || edge[1]) return std::nullopt;
        throw Error("channel levels at u = " + std::to_string(u) + ", " + std::to_string(height) +
                    " mm over the hub: a ball of radius " + std::to_string(r_) + " mm with " +
                    std::to_string(rq_.stock_mm) + " mm stock does not fit between the faces");
      }
      s.theta[i] = illinois_root(h, a, mid, ha, hb, 1e-11);
      seeds.assign(1, s.crossing[i]);
      blade_distance(i, centre(u, height, s.theta[i]), seeds, &s.foot[i]);
      const ChannelFace& f = *faces_[i];
      const double w = (s.foot[i].v - f.v_inlet) / (f.v_outlet - f.v_inlet);
      inside[i] = w > 1e-7 && w < 1 - 1e-7;
      s.axis[i] = contact_axis(s.foot[i], centre(u, height, s.theta[i]));
    }
    // A station of the level: one contact at least on its face (beyond
    // both chords the circle is outside the channel).
    if (!inside[0] && !inside[1]) return std::nullopt;
    if ((s.theta[1] - s.theta[0]) * dir_ <= 0) {
      if (edge[0] || edge[1]) return std::nullopt;
      throw Error("channel levels at u = " + std::to_string(u) + ", " + std::to_string(height) +
                  " mm over the hub: the ball with its stock does not fit between the faces (the contacts cross)");
    }
    s.middle = 0.5 * (s.theta[0] + s.theta[1]);
    s.middle_axis = (s.axis[0] + s.axis[1]).normalized();
    return s;
  }

  // The pose of path k of n towards `side` (k = 0: the slot) at a section,
  // its axis blended `blend` of the way from the middle's to the contact's.
  ToolPose pose(const Section& s, double height, int side, int k, int n, double blend) const {
    const double f = n > 0 ? static_cast<double>(k) / n : 0.0;
    const Vec3 c = centre(s.u, height, s.middle + (s.theta[side] - s.middle) * f);
    const Vec3 axis = (s.middle_axis + (s.axis[side] - s.middle_axis) * blend).normalized();
    return {c - r_ * axis, axis};
  }

  // The hub's point nearest x and its unit normal towards the tips.
  void hub_under(const Vec3& x, double u_seed, Vec3& p, Vec3& n) const {
    ProjectionOptions po;
    double v = std::atan2(x.y(), x.x()) / (2 * kPi);
    po.seed = Eigen::Vector2d(u_seed, v - std::floor(v));
    const SurfaceProjection pr = project_to_surface(*rq_.hub, x, po);
    if (!pr.ok) throw Error("channel levels: a point does not project onto the hub (" + pr.failure + ")");
    const SurfaceDerivs d = rq_.hub->eval(pr.u, pr.v);
    p = d.p;
    n = sign_ * d.pu.cross(d.pv).normalized();
  }

  bool inside_chord(int i, double v) const {
    const ChannelFace& f = *faces_[i];
    const double w = (v - f.v_inlet) / (f.v_outlet - f.v_inlet);
    return w > 1e-7 && w < 1 - 1e-7;
  }
  static const char* side_name(int i) { return i == 0 ? "left" : "right"; }

 private:
  static constexpr int kSeedU = 16, kSeedV = 64, kTopSamples = 1024;
  std::vector<double> top_;
  const ChannelLevelsRequest& rq_;
  const ChannelFace* faces_[2];
  double r_, hub_stock_, contact_;
  double beta_ = 0, tilt_ = 0;
  double sign_ = 1;
  int dir_ = 1;
  std::vector<std::pair<Eigen::Vector2d, Vec2>> seeds_[2];
};

// One level laid out: its stations' sections and its paths per side.
struct Level {
  int index = 0;  // 1 = the top
  double u_in = 0, u_out = 0;
  std::vector<double> height;     // D_l at each station
  std::vector<Section> sections;  // one per station
  int paths[2] = {1, 1};          // N per side
  double u_at(double t) const { return u_in + (u_out - u_in) * t; }
};

// The u range of a level: where the section exists (one contact's foot at
// least inside its face's chord part), from a scan of the hub's meridian
// refined by bisection at both ends.
void level_range(const Geometry& g, int level, int levels, Level& out) {
  constexpr int kScan = 24;
  // A section that throws (the ball not fitting) is no station of the
  // level; the reason is kept for when the level has none.
  std::string why;
  const auto valid = [&](double u) {
    try {
      return g.section(u, g.centre_height(level, levels, u), nullptr).has_value();
    } catch (const Error& e) {
      why = e.what();
      return false;
    }
  };
  std::vector<bool> ok(kScan + 1);
  for (int j = 0; j <= kScan; ++j) ok[static_cast<size_t>(j)] = valid(static_cast<double>(j) / kScan);
  int first = -1, last = -1;
  for (int j = 0; j <= kScan; ++j)
    if (ok[static_cast<size_t>(j)]) {
      if (first < 0) first = j;
      last = j;
    }
  if (first < 0)
    throw Error("channel levels: level " + std::to_string(level) + " has no station where both faces bound it" +
                (why.empty() ? std::string() : " (" + why + ")"));
  for (int j = first; j <= last; ++j)
    if (!ok[static_cast<size_t>(j)])
      throw Error("channel levels: level " + std::to_string(level) + " is interrupted along the channel (at u = " +
                  std::to_string(static_cast<double>(j) / kScan) + ")" + (why.empty() ? std::string() : ": " + why));
  const auto refine = [&](double in, double out_) {
    for (int it = 0; it < 24 && std::abs(out_ - in) > 1e-7; ++it) {
      const double m = 0.5 * (in + out_);
      (valid(m) ? in : out_) = m;
    }
    return in;
  };
  out.u_in = first > 0 ? refine(static_cast<double>(first) / kScan, static_cast<double>(first - 1) / kScan) : 0.0;
  out.u_out = last < kScan ? refine(static_cast<double>(last) / kScan, static_cast<double>(last + 1) / kScan) : 1.0;
}

// Lays out level l at `stations` stations (sections seeded from the
// neighbour's).
Level lay_out_level(const Geometry& g, int level, int levels, int stations) {
  Level lv;
  lv.index = level;
  level_range(g, level, levels, lv);
  const Section* near = nullptr;
  for (int j = 0; j < stations; ++j) {
    const double u = lv.u_at(static_cast<double>(j) / (stations - 1));
    const double h = g.centre_height(level, levels, u);
    std::optional<Section> s = g.section(u, h, near);
    if (!s) s = g.section(u, h, nullptr);
    if (!s)
      throw Error("channel levels: level " + std::to_string(level) + " lost its section at u = " + std::to_string(u));
    lv.height.push_back(h);
    lv.sections.push_back(*s);
    near = &lv.sections.back();
  }
  return lv;
}

// A level's path of ball centres: path k of n towards `side` at every
// station (k = 0: the slot).
std::vector<Vec3> path_centres(const Geometry& g, const Level& l, int side, int k, int n) {
  std::vector<Vec3> c;
  c.reserve(l.sections.size());
  for (size_t j = 0; j < l.sections.size(); ++j) {
    const Section& s = l.sections[j];
    c.push_back(g.centre(s.u, l.height[j], s.middle + (s.theta[side] - s.middle) * (static_cast<double>(k) / n)));
  }
  return c;
}

// The point of a polyline nearest x, over its segments [first, last); false
// where that is one of the polyline's own ends (x lies beyond it, not
// beside it).
bool nearest_on(const std::vector<Vec3>& line, const Vec3& x, long first, long last, Vec3& out) {
  first = std::max(0L, first);
  last = std::min(static_cast<long>(line.size()) - 1, last);
  double best = std::numeric_limits<double>::infinity();
  bool end = true;
  for (long j = first; j < last; ++j) {
    const Vec3 a = line[static_cast<size_t>(j)], d = line[static_cast<size_t>(j + 1)] - a;
    const double t = std::clamp((x - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    const Vec3 q = a + t * d;
    const double e = (q - x).squaredNorm();
    if (e < best) {
      best = e;
      out = q;
      end = (j == 0 && t == 0) || (j + 2 == static_cast<long>(line.size()) && t == 1);
    }
  }
  return !end;
}

// The largest cusp between the contact paths of two levels on face i: for
// every station of level a, the point of level b's contact path nearest
// its ball centre (the two balls' closest pass), the face sampled between
// the two centres, offset by the stock, and the height each ball leaves
// there along the face normal. Face points over the top are not the
// part's.
double face_cusp(const Geometry& g, const ChannelLevelsRequest& rq, const Level& a, const Level& b, int i) {
  double worst = 0;
  const double r = g.ball_radius();
  const int na = a.paths[i], nb = b.paths[i];
  const std::vector<Vec3> pa = path_centres(g, a, i, na, na), pb = path_centres(g, b, i, nb, nb);
  for (size_t j = 0; j < pa.size(); ++j) {
    const Vec3& ca = pa[j];
    Vec3 cb;
    if (!nearest_on(pb, ca, 0, static_cast<long>(pb.size()), cb)) continue;  // beyond b's ends
    Eigen::Vector2d seed(a.sections[j].foot[i].u, a.sections[j].foot[i].v);
    for (int k = 1; k < 16; ++k) {
      const Vec3 x = ca + (cb - ca) * (k / 16.0);
      const FaceFoot f = g.foot(i, x, seed);
      if (f.u <= 1e-9 || f.u >= 1 - 1e-9) continue;  // over the face's tip or under its hub row
      if (!g.inside_chord(i, f.v)) continue;           // beyond its chord part: another blade surface's
      if (rq.top->radial_offset(f.point) > 0) continue;  // above the blank: not the part's
      const Vec3 q = f.point + rq.stock_mm * f.normal;
      worst = std::max(worst, std::min(height_to_ball(q, f.normal, ca, r), height_to_ball(q, f.normal, cb, r)));
    }
  }
  return worst;
}

// The hub level's cusp on the hub between paths k and k + 1 of side i: at
// every station of path k the nearest point of path k + 1, the hub under
// the line between the two ball centres offset by its stock, and the
// height each ball leaves along the hub normal.
double hub_cusp(const Geometry& g, const Level& lv, int side, int n, int samples) {
  double worst = 0;
  const double r = g.ball_radius();
  std::vector<Vec3> next = path_centres(g, lv, side, 0, n);
  for (int k = 0; k < n; ++k) {
    const std::vector<Vec3> here = next;
    next = path_centres(g, lv, side, k + 1, n);
    for (size_t j = 0; j < here.size(); ++j) {
      const Vec3& ca = here[j];
      Vec3 cb;
      if (!nearest_on(next, ca, static_cast<long>(j) - 6, static_cast<long>(j) + 6, cb)) continue;
      for (int m = 1; m < samples; ++m) {
        Vec3 p, nh;
        g.hub_under(ca + (cb - ca) * (static_cast<double>(m) / samples), lv.sections[j].u, p, nh);
        const Vec3 q = p + g.hub_stock() * nh;
        const double hh = std::min(height_to_ball(q, nh, ca, r), height_to_ball(q, nh, cb, r));
        worst = std::max(worst, hh);
      }
    }
  }
  return worst;
}

// The largest distance across the paths of one side at any station from
// the slot to the contact, perpendicular to the slot's direction there
// (paths run along the channel, the level's circles cross it obliquely).
double side_width(const Geometry& g, const Level& l, int side) {
  const std::vector<Vec3> mid = path_centres(g, l, side, 0, 1), contact = path_centres(g, l, side, 1, 1);
  double width = 0;
  for (size_t j = 0; j < mid.size(); ++j) {
    const size_t a = j > 0 ? j - 1 : j, b = j + 1 < mid.size() ? j + 1 : j;
    const Vec3 t = (mid[b] - mid[a]).normalized(), d = contact[j] - mid[j];
    width = std::max(width, (d - d.dot(t) * t).norm());
  }
  return width;
}

// Ball centre of a pose.
Vec3 ball_centre(const ToolPose& p, double r) { return p.tip + r * p.axis; }

}  // namespace channel_levels_detail

ChannelLevelsPlan plan_channel_levels(const ChannelLevelsRequest& rq, Progress& progress) {
  using namespace channel_levels_detail;
  if (!rq.left.face || !rq.right.face) throw ParameterError("faces", "expected the two blade faces of the channel");
  if (!rq.hub) throw ParameterError("hub", "expected the hub surface of revolution");
  if (!rq.top) throw ParameterError("top", "expected the blank's top, a surface of revolution (the casing)");
  if (!rq.cutter) throw ParameterError("tool", "expected a ball or tapered ball-end cutter");
  if (rq.world && !rq.body) throw ParameterError("world", "a collision world needs the tool's body");
  if (rq.stations < 2) throw ParameterError("stations", "expected at least 2 stations along the channel");
  if (rq.interior_stations < 2)
    throw ParameterError("interior_stations", "expected at least 2 stations for the paths between the contacts");
  if (!(rq.stock_mm >= 0)) throw ParameterError("stock", "expected a stock >= 0 in mm");
  if (std::isnan(rq.hub_stock_mm) || rq.hub_stock_mm > rq.stock_mm)
    throw ParameterError("hub_stock", "expected a hub stock from 0 up to the faces' stock, mm");
  if (!(rq.step_down_mm > 0)) throw ParameterError("step_down", "expected a step-down > 0 in mm");
  const double r = rq.cutter->ball_radius_mm();
  if (!(rq.step_over_mm > 0) || rq.step_over_mm > 2 * r)
    throw ParameterError("step_over", "expected a step-over > 0 and at most the ball's diameter, mm");
  if (!(rq.scallop_mm > 0) || rq.scallop_mm >= r)
    throw ParameterError("scallop", "expected a cusp height > 0 and below the ball radius, mm");
  if (!(rq.chord_tol_mm > 0)) throw ParameterError("chord_tol", "expected a chord tolerance > 0 in mm");
  if (!(rq.tilt_deg >= 0 && rq.tilt_deg < 45)) throw ParameterError("tilt", "expected 0 <= tilt < 45 degrees");
  if (rq.threads < 1) throw ParameterError("threads", "expected at least 1");

  const Geometry g(rq);
  ChannelLevelsPlan plan;
  plan.hub_stock_mm = g.hub_stock();

  // The top's height over the hub: its range over the hub's meridian.
  plan.top_height_min_mm = std::numeric_limits<double>::infinity();
  plan.top_height_max_mm = 0;
  for (int j = 0; j <= 32; ++j) {
    const double t = g.top_height(j / 32.0);
    plan.top_height_min_mm = std::min(plan.top_height_min_mm, t);
    plan.top_height_max_mm = std::max(plan.top_height_max_mm, t);
  }
  const double depth = plan.top_height_max_mm - g.hub_stock();
  if (!(depth > 0)) throw Error("channel levels: the top does not lie above the hub's stock");
  // The levels: the step-down, or closer where the balls' cusp between two
  // levels on a flat face would exceed the scallop (the measure below
  // decides: one more level while a face's cusp exceeds it).
  const double h = rq.scallop_mm;
  const double flat_step = 2 * std::sqrt(2 * r * h - h * h);
  int levels = std::max(1, static_cast<int>(std::ceil(depth / std::min(rq.step_down_mm, flat_step) - 1e-9)));
  // Paths per side: neighbouring paths at most step_over apart at every
  // station, across the paths' direction.
  const auto count_paths = [&](Level& l) {
    for (int side = 0; side < 2; ++side)
      l.paths[side] = std::max(1, static_cast<int>(std::ceil(side_width(g, l, side) / rq.step_over_mm - 1e-9)));
  };
  std::vector<Level> lv;
  const int levels_first = levels;
  for (int attempt = 0;; ++attempt) {
    lv.assign(static_cast<size_t>(levels), Level{});
    run_parallel(static_cast<size_t>(levels), rq.threads, progress, "channel levels: sections", [&](size_t k, Progress&) {
      lv[k] = lay_out_level(g, static_cast<int>(k) + 1, levels, rq.stations);
      count_paths(lv[k]);
    });
    std::vector<double> cusp(2 * static_cast<size_t>(levels), 0.0);
    parallel_for_index(2 * static_cast<size_t>(levels - 1), rq.threads, [&](size_t q) {
      const size_t k = q / 2;
      cusp[q] = face_cusp(g, rq, lv[k], lv[k + 1], static_cast<int>(q % 2));
    });
    plan.face_cusp_max_mm[0] = plan.face_cusp_max_mm[1] = 0;
    for (size_t q = 0; q < cusp.size(); ++q)
      plan.face_cusp_max_mm[q % 2] = std::max(plan.face_cusp_max_mm[q % 2], cusp[q]);
    const double worst = std::max(plan.face_cusp_max_mm[0], plan.face_cusp_max_mm[1]);
    if (worst <= h) break;
    if (attempt >= 8) throw Error("channel levels: the cusp between levels stays above the scallop");
    // A cusp grows with the square of the levels' spacing: as many more
    // levels as that asks for at once, and at least one.
    levels = std::max(levels + 1, static_cast<int>(std::ceil(levels * std::sqrt(worst / h) * 1.01)));
  }
  plan.levels = levels;
  plan.levels_added = levels - levels_first;
  plan.level_step_max_mm = depth / levels;
  {
    Level& bottom = lv.back();
    for (int side = 0; side < 2; ++side) {
      for (;; ++bottom.paths[side]) {
        const double c = hub_cusp(g, bottom, side, bottom.paths[side], 16);
        if (c <= h) {
          plan.hub_cusp_max_mm = std::max(plan.hub_cusp_max_mm, c);
          break;
        }
        if (bottom.paths[side] > 1000) throw Error("channel levels: the hub's cusp stays above the scallop");
        ++plan.paths_added;
      }
    }
  }
  for (const Level& l : lv) {
    plan.paths_left.push_back(l.paths[0]);
    plan.paths_right.push_back(l.paths[1]);
    for (int side = 0; side < 2; ++side)
      plan.step_over_max_mm = std::max(plan.step_over_max_mm, side_width(g, l, side) / l.paths[side]);
  }
  // A level's floor between paths a_e apart keeps a cusp of the ball's,
  // which the next level takes with its depth.
  const double ae = std::min(plan.step_over_max_mm, 2 * r);
  plan.axial_engagement_max_mm = plan.level_step_max_mm + r - std::sqrt(r * r - 0.25 * ae * ae);
  const double ap = std::min(plan.level_step_max_mm, r);
  plan.slot_width_mm = 2 * std::sqrt(2 * r * ap - ap * ap);
  // Contact heights over the hub: the hub level's and the top level's.
  const auto height_over_hub = [&](const Vec3& x, double u) {
    Vec3 p, n;
    g.hub_under(x, u, p, n);
    return (x - p).dot(n);
  };
  for (int i = 0; i < 2; ++i) {
    plan.corner_mm[i] = 0;
    plan.contact_top_mm[i] = std::numeric_limits<double>::infinity();
    for (const Section& s : lv.back().sections)
      plan.corner_mm[i] = std::max(plan.corner_mm[i], height_over_hub(s.foot[i].point, s.u));
    for (const Section& s : lv.front().sections)
      plan.contact_top_mm[i] = std::min(plan.contact_top_mm[i], height_over_hub(s.foot[i].point, s.u));
  }
  plan.hub_u_in = lv.back().u_in;
  plan.hub_u_out = lv.back().u_out;

  // The passes in cutting order: level by level from the top, in each the
  // slot, then the paths towards the left face, then towards the right.
  struct Spec {
    size_t level;
    ChannelPassKind kind;
    int side, k, n;
    bool forward;  // inlet -> outlet
  };
  std::vector<Spec> specs;
  for (size_t l = 0; l < lv.size(); ++l) {
    specs.push_back({l, ChannelPassKind::Notch, 0, 0, lv[l].paths[0], specs.size() % 2 == 0});
    for (int k = 1; k <= lv[l].paths[0]; ++k)
      specs.push_back({l, ChannelPassKind::WidenLeft, 0, k, lv[l].paths[0], specs.size() % 2 == 0});
    for (int k = 1; k <= lv[l].paths[1]; ++k)
      specs.push_back({l, ChannelPassKind::WidenRight, 1, k, lv[l].paths[1], specs.size() % 2 == 0});
  }

  ChannelChecks checks;
  checks.world = rq.world;
  checks.body = rq.body;
  checks.clearances = rq.clearances;
  checks.motion_tol_mm = rq.motion_tol_mm;
  checks.link = rq.link;
  const int last_level = static_cast<int>(lv.size());
  // Each pass on its own (they share nothing but read-only geometry): its
  // poses, the chord's insertions, the proofs, its pieces and refusals.
  struct PassResult {
    std::vector<ChannelPass> pieces;
    std::vector<ChannelRefusal> refusals;
    long turned = 0, inserted = 0;
    double station_step = 0;
  };
  std::vector<PassResult> results(specs.size());
  run_parallel(specs.size(), rq.threads, progress, "channel levels: passes, proved", [&](size_t p, Progress&) {
    const Spec& spec = specs[p];
    const Level& l = lv[spec.level];
    PassResult& out = results[p];
    const bool contact = spec.kind != ChannelPassKind::Notch && spec.k == spec.n;
    const bool exact = contact || l.index == last_level;  // paths that leave the stock: the chord tolerance holds
    const double blend = spec.n > 0 ? static_cast<double>(spec.k) / spec.n : 0.0;
    // The poses at the stations with those the chord tolerance needs
    // between them (halving), in cutting order.
    std::vector<std::pair<double, ToolPose>> poses;
    const int m = static_cast<int>(l.sections.size());
    const auto station_pose = [&](int j) { return g.pose(l.sections[static_cast<size_t>(j)], l.height[static_cast<size_t>(j)], spec.side, spec.k, spec.n, blend); };
    std::function<void(const Section&, double, const ToolPose&, const Section&, double, const ToolPose&, int)> fill;
    fill = [&](const Section& sa, double ta, const ToolPose& a, const Section& sb, double tb, const ToolPose& b, int depth) {
      const double tm = 0.5 * (ta + tb), um = l.u_at(tm);
      const double hm = g.centre_height(l.index, last_level, um);
      std::optional<Section> sm = g.section(um, hm, &sa);
      if (!sm) sm = g.section(um, hm, nullptr);
      if (!sm) throw Error("channel levels: level " + std::to_string(l.index) + " has no section at u = " + std::to_string(um));
      const ToolPose pm = g.pose(*sm, hm, spec.side, spec.k, spec.n, blend);
      const Vec3 chord_mid = 0.5 * (ball_centre(a, r) + ball_centre(b, r));
      if ((ball_centre(pm, r) - chord_mid).norm() <= rq.chord_tol_mm) return;
      if (depth >= 10)
        throw Error("channel levels: level " + std::to_string(l.index) + ": a path cannot be kept within " +
                    std::to_string(rq.chord_tol_mm) + " mm between stations (1024 poses)");
      fill(sa, ta, a, *sm, tm, pm, depth + 1);
      poses.emplace_back(tm, pm);
      ++out.inserted;
      fill(*sm, tm, pm, sb, tb, b, depth + 1);
    };
    // The stations this pass runs through, in cutting order.
    std::vector<int> js;
    const int count = exact ? m : std::clamp(rq.interior_stations, 2, m);
    for (int q = 0; q < count; ++q) {
      const int j = static_cast<int>(std::lround(static_cast<double>(q) * (m - 1) / (count - 1)));
      js.push_back(spec.forward ? j : m - 1 - j);
    }
    for (size_t q = 0; q < js.size(); ++q) {
      const int j = js[q];
      const double t = static_cast<double>(j) / (m - 1);
      const ToolPose pose = station_pose(j);
      if (q > 0 && exact) {
        const int jp = js[q - 1];
        const double tp = static_cast<double>(jp) / (m - 1);
        const ToolPose prev = station_pose(jp);
        fill(l.sections[static_cast<size_t>(jp)], tp, prev, l.sections[static_cast<size_t>(j)], t, pose, 0);
      }
      poses.emplace_back(t, pose);
    }
    for (size_t q = 1; q < poses.size() && contact; ++q)
      out.station_step = std::max(out.station_step, (ball_centre(poses[q].second, r) - ball_centre(poses[q - 1].second, r)).norm());
    // Proved one by one; a pose that is not clear turned about its ball
    // centre to the nearest clear blend of the middle's and the
    // contact's axes (towards and beyond the middle's first).
    ChannelPieces pieces(checks, out.pieces, out.refusals);
    pieces.begin(spec.kind, spec.k, l.index);
    // A pose proved, or turned about its ball centre to the nearest clear
    // blend of the middle's and the contact's axes (towards and beyond the
    // middle's first); its check in `pc`.
    const auto proved_pose = [&](double t, ToolPose pose, PoseCheck& pc) {
      pc = rq.world->check(*rq.body, pose, rq.clearances, 0.0);
      if (pc.clear) return pose;
      const double u = l.u_at(t);
      const double hgt = g.centre_height(l.index, last_level, u);
      const std::optional<Section> s = g.section(u, hgt, &l.sections[static_cast<size_t>(std::lround(t * (m - 1)))]);
      const Vec3 centre = ball_centre(pose, r);
      for (int j = 1; s && j <= 8; ++j) {
        const double b = blend + (j % 2 == 1 ? -1 : 1) * 0.25 * ((j + 1) / 2);
        if (b < -1 || b > 2) continue;
        const Vec3 axis = (s->middle_axis + (s->axis[spec.side] - s->middle_axis) * b).normalized();
        const ToolPose turned{centre - r * axis, axis};
        const PoseCheck tc = rq.world->check(*rq.body, turned, rq.clearances, 0.0);
        if (tc.clear) {
          pc = tc;
          ++out.turned;
          return turned;
        }
      }
      return pose;
    };
    // Where the motion between two clear poses is not (the cone sweeping
    // past a face between two axes), the pose halfway is inserted — the
    // path's own, proved and turned like the others — and each half proved
    // again, down to 1/16 of the motion; what still does not prove is left
    // to the pieces' check (a refusal: the pass splits there).
    struct Proved {
      double t;
      ToolPose pose;
      PoseCheck check;
      MotionCheck motion;  // from the pose before
    };
    std::vector<Proved> chain;
    std::function<void(Proved, Proved, int)> reach = [&](Proved a, Proved b, int depth) {
      b.motion = rq.world->check_motion(*rq.body, a.pose, b.pose, rq.clearances, rq.motion_tol_mm);
      if (b.motion.clear || depth >= 4) {
        chain.push_back(b);
        return;
      }
      Proved mid;
      mid.t = 0.5 * (a.t + b.t);
      const double um = l.u_at(mid.t), hm = g.centre_height(l.index, last_level, um);
      std::optional<Section> sm = g.section(um, hm, &l.sections[static_cast<size_t>(std::lround(mid.t * (m - 1)))]);
      if (!sm) sm = g.section(um, hm, nullptr);
      if (!sm) {
        chain.push_back(b);
        return;
      }
      mid.pose = proved_pose(mid.t, g.pose(*sm, hm, spec.side, spec.k, spec.n, blend), mid.check);
      if (!mid.check.clear) {
        chain.push_back(b);
        return;
      }
      ++out.inserted;
      reach(a, mid, depth + 1);
      reach(chain.back(), b, depth + 1);
    };
    for (auto& tp : poses) {
      if (!rq.world) {
        pieces.add(tp.second, tp.first);
        continue;
      }
      Proved p;
      p.t = tp.first;
      p.pose = proved_pose(tp.first, tp.second, p.check);
      if (!chain.empty() && chain.back().check.clear && p.check.clear) {
        const size_t from = chain.size();
        reach(chain.back(), p, 0);
        for (size_t q = from; q < chain.size(); ++q) pieces.add(chain[q].pose, chain[q].t, &chain[q].check, &chain[q].motion);
      } else {
        chain.push_back(p);
        pieces.add(p.pose, p.t, &p.check);
      }
    }
    pieces.end();
  });
  std::vector<ChannelPass> pieces;
  for (PassResult& res : results) {
    for (ChannelPass& piece : res.pieces) pieces.push_back(std::move(piece));
    for (ChannelRefusal& refusal : res.refusals) plan.refusals.push_back(std::move(refusal));
    plan.turned += res.turned;
    plan.inserted += res.inserted;
    plan.station_step_max_mm = std::max(plan.station_step_max_mm, res.station_step);
  }

  // Between pieces at the same station: a direct step at the feed — across
  // a level along its circle (a straight step across the hub level cuts a
  // chord into the hub's stock: the circle is kept within the chord
  // tolerance), or the ramp down to the next level's slot.
  const ChannelStep step = [&](const ChannelPass& from, const ChannelPass& to,
                               std::vector<std::pair<double, ToolPose>>& between) {
    if (from.t.back() != to.t.front()) return false;
    if (from.level != to.level) return true;
    const Level& l = lv[static_cast<size_t>(from.level - 1)];
    const double t = to.t.front(), u = l.u_at(t), hgt = g.centre_height(l.index, last_level, u);
    const ToolPose& a = from.poses.back();
    const ToolPose& b = to.poses.front();
    const Vec3 ca = ball_centre(a, r), cb = ball_centre(b, r);
    const double ta = std::atan2(ca.y(), ca.x());
    const double tb = ta + wrap_angle(std::atan2(cb.y(), cb.x()) - ta);
    const double rc = std::hypot(ca.x(), ca.y());
    const int n = static_cast<int>(std::ceil(std::abs(tb - ta) / std::sqrt(8 * rq.chord_tol_mm / rc) - 1e-9));
    for (int k = 1; k < n; ++k) {
      const double f = static_cast<double>(k) / n;
      const Vec3 axis = (a.axis + (b.axis - a.axis) * f).normalized();
      between.emplace_back(t, ToolPose{g.centre(u, hgt, ta + (tb - ta) * f) - r * axis, axis});
    }
    return true;
  };
  join_channel_pieces(std::move(pieces), checks, step, plan);
  return plan;
}

}  // namespace bliskrun
