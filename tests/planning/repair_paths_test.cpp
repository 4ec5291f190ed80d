// Repair toolpaths (core/planning/repair_paths.h) against closed forms and
// brute force: the scallop between zigzag passes on a flat and on a
// cylinder, the chord error of a pass, the spiral's pitch, the arcs'
// tangency, refusal where the ball would gouge the surface next to the
// region, and the tilt where the holder would hit a wall.
#include "core/planning/repair_paths.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "core/common/error.h"
#include "core/geometry/mesh.h"

namespace bliskrun {
namespace {

// A cylinder of radius rho about Z: u around it (angle a u), v along it
// (length len v); pu x pv points out of the axis (convex to the tool).
class PathsCylinder : public Surface {
 public:
  PathsCylinder(double rho, double angle, double len) : rho_(rho), a_(angle), len_(len) {}
  SurfaceDerivs eval(double u, double v) const override {
    const double t = a_ * u, c = std::cos(t), s = std::sin(t);
    SurfaceDerivs d;
    d.p = Vec3(rho_ * c, rho_ * s, len_ * v);
    d.pu = Vec3(-rho_ * a_ * s, rho_ * a_ * c, 0);
    d.pv = Vec3(0, 0, len_);
    d.puu = Vec3(-rho_ * a_ * a_ * c, -rho_ * a_ * a_ * s, 0);
    return d;
  }

 private:
  double rho_, a_, len_;
};

// A plane patch: u along x (width w), v along y (length len), normal +z.
class PathsPlane : public Surface {
 public:
  PathsPlane(double w, double len) : w_(w), len_(len) {}
  SurfaceDerivs eval(double u, double v) const override {
    SurfaceDerivs d;
    d.p = Vec3(w_ * u, len_ * v, 0);
    d.pu = Vec3(w_, 0, 0);
    d.pv = Vec3(0, len_, 0);
    return d;
  }

 private:
  double w_, len_;
};

// A cylinder closed in v, once around per unit v: u along the axis
// (height h), pu x pv out of the material (the spiral's surface).
class Tube : public Surface {
 public:
  Tube(double rho, double h) : rho_(rho), h_(h) {}
  SurfaceDerivs eval(double u, double v) const override {
    const double t = -2 * kPi * v, c = std::cos(t), s = std::sin(t), w = -2 * kPi;
    SurfaceDerivs d;
    d.p = Vec3(rho_ * c, rho_ * s, h_ * u);
    d.pu = Vec3(0, 0, h_);
    d.pv = Vec3(-rho_ * w * s, rho_ * w * c, 0);
    d.pvv = Vec3(-rho_ * w * w * c, -rho_ * w * w * s, 0);
    return d;
  }

 private:
  double rho_, h_;
};

// A plate (z = 0 for x < 0) running into a concave round of radius rf
// (z = rf - sqrt(rf^2 - x^2) for 0 <= x <= x_max): u along x over
// [x0, x_max], v along y over [0, len]. Normal up, out of the material.
class PlateWithRound : public Surface {
 public:
  PlateWithRound(double x0, double x_max, double rf, double len) : x0_(x0), x1_(x_max), rf_(rf), len_(len) {}
  double z(double x) const { return x < 0 ? 0 : rf_ - std::sqrt(rf_ * rf_ - x * x); }
  SurfaceDerivs eval(double u, double v) const override {
    const double w = x1_ - x0_, x = x0_ + w * u;
    double dz = 0, ddz = 0;
    if (x >= 0) {
      const double q = std::sqrt(rf_ * rf_ - x * x);
      dz = x / q;
      ddz = rf_ * rf_ / (q * q * q);
    }
    SurfaceDerivs d;
    d.p = Vec3(x, len_ * v, z(x));
    d.pu = Vec3(w, 0, w * dz);
    d.pv = Vec3(0, len_, 0);
    d.puu = Vec3(0, 0, w * w * ddz);
    // pu x pv = (-w dz len, 0, w len): up.
    return d;
  }

 private:
  double x0_, x1_, rf_, len_;
};

TriangleMesh quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  TriangleMesh m;
  m.vertices = {a, b, c, d};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

// A world with nothing near the part (a triangle far away).
CollisionWorld far_world() {
  CollisionWorld w;
  w.add("far", quad(Vec3(1000, 1000, 1000), Vec3(1001, 1000, 1000), Vec3(1001, 1001, 1000), Vec3(1000, 1001, 1000)));
  return w;
}

Tool ball_mill(double r, double shank_len = 30, double holder_d = 20) {
  BallEndMillSpec s;
  s.radius_mm = r;
  s.flute_length_mm = 4 * r;
  s.shank = {2 * r, shank_len};
  s.holder = {holder_d, 40};
  return Tool::ball_end_mill(s);
}

RepairPathRequest finishing_only(std::shared_ptr<const Surface> s, const Tool& tool, const CollisionWorld& world) {
  RepairPathRequest rq;
  rq.design = std::move(s);
  rq.tool = &tool;
  rq.world = &world;
  rq.deposit_mm = 0;
  rq.stock_mm = 0;
  return rq;
}

// Scallop left between balls of radius r touching a circle of radius rho
// (rho = inf: a line) at contacts an arc s apart: the cusp on the bisector.
double scallop_closed_form(double s, double r, double rho) {
  if (std::isinf(rho)) return r - std::sqrt(r * r - 0.25 * s * s);
  const double half = 0.5 * s / rho, big = rho + r;
  const double d = big * std::cos(half) - std::sqrt(r * r - std::pow(big * std::sin(half), 2));
  return d - rho;
}

// Brute force: the largest, over points of the surface between two
// neighbouring contacts, of the distance to the nearer ball.
double scallop_brute(const Surface& s, double ua, double ub, double v, double r) {
  auto centre = [&](double u) {
    const SurfaceDerivs d = s.eval(u, v);
    return Vec3(d.p + r * d.pu.cross(d.pv).normalized());
  };
  const Vec3 ca = centre(ua), cb = centre(ub);
  double worst = 0;
  for (int i = 0; i <= 4000; ++i) {
    const Vec3 q = s.point(ua + (ub - ua) * i / 4000.0, v);
    worst = std::max(worst, std::min((q - ca).norm(), (q - cb).norm()) - r);
  }
  return worst;
}

TEST(RepairPaths, ZigzagScallopOnAFlatAndACylinderMatchesTheClosedFormAndBruteForce) {
  const Tool tool = ball_mill(3);
  const CollisionWorld world = far_world();
  const double h = 0.005;
  for (const double rho : {std::numeric_limits<double>::infinity(), 20.0}) {
    std::shared_ptr<const Surface> s;
    double width_mm;
    if (std::isinf(rho)) {
      s = std::make_shared<PathsPlane>(6.0, 10.0);
      width_mm = 6;
    } else {
      s = std::make_shared<PathsCylinder>(rho, 0.3, 10.0);  // 6 mm around
      width_mm = rho * 0.3;
    }
    RepairPathRequest rq = finishing_only(s, tool, world);
    rq.scallop_mm = h;
    const RepairPathResult r = plan_repair_paths(rq);
    ASSERT_EQ(r.layers.size(), 1u);
    ASSERT_GE(r.passes.size(), 5u);
    EXPECT_TRUE(r.refusals.empty());
    // Closed form (the flat: h = r - sqrt(r^2 - (s/2)^2)).
    const double s_expected = std::isinf(rho) ? 2 * std::sqrt(2 * 3 * h - h * h) : ball_step_over(h, 3, 1 / rho);
    EXPECT_NEAR(r.layers[0].step_over_max_mm, s_expected, 1e-9);
    EXPECT_NEAR(scallop_closed_form(s_expected, 3, rho), h, 1e-9);
    const int full = static_cast<int>(std::ceil(width_mm / s_expected - 1e-9));
    EXPECT_EQ(static_cast<int>(r.passes.size()), full + 1);
    // Between every two neighbouring passes, measured: the full steps leave
    // h, the last (shorter) one less.
    for (size_t k = 0; k + 1 < r.passes.size(); ++k) {
      const double ua = r.passes[k].u, ub = r.passes[k + 1].u;
      const double arc = std::isinf(rho) ? 6 * (ub - ua) : rho * 0.3 * (ub - ua);
      const double brute = scallop_brute(*s, ua, ub, 0.5, 3);
      // (the brute force samples the cusp 1.5e-4 mm apart: within 1e-5 mm)
      EXPECT_NEAR(brute, scallop_closed_form(arc, 3, rho), 1e-5) << "pass " << k;
      EXPECT_LE(brute, h + 1e-9);
      if (k + 2 < r.passes.size()) EXPECT_NEAR(brute, h, 1e-5) << "pass " << k;
    }
    // The convex cylinder needs the passes closer than the flat.
    if (!std::isinf(rho)) EXPECT_LT(s_expected, 2 * std::sqrt(2 * 3 * h - h * h));
  }
}

TEST(RepairPaths, ChordErrorOfEveryPassWithinToleranceByBruteForce) {
  // A pass around a tight cylinder (radius 2 mm): the ball's contacts step
  // by the chord tolerance along it.
  const Tool tool = ball_mill(1);
  const CollisionWorld world = far_world();
  auto s = std::make_shared<Tube>(2.0, 4.0);
  RepairPathRequest rq = finishing_only(s, tool, world);
  rq.u0 = 0.4;
  rq.u1 = 0.5;
  rq.v0 = 0.1;
  rq.v1 = 0.6;
  rq.steps.chord_tol_mm = 0.002;
  rq.guard_spacing_mm = 0.03;
  const RepairPathResult r = plan_repair_paths(rq);
  ASSERT_FALSE(r.passes.empty());
  double worst = 0;
  int segments = 0;
  for (const RepairPass& p : r.passes) {
    for (size_t i = 0; i + 1 < p.poses.size(); ++i) {
      const RepairPose &a = p.poses[i], &b = p.poses[i + 1];
      const Vec3 ab = b.contact - a.contact;
      for (int k = 1; k < 200; ++k) {
        const Vec3 q = s->point(p.u, a.v + (b.v - a.v) * k / 200.0);
        const double t = std::clamp((q - a.contact).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        worst = std::max(worst, (q - a.contact - t * ab).norm());
      }
      ++segments;
    }
  }
  EXPECT_GT(segments, 50);
  EXPECT_LE(worst, 0.002 * (1 + 1e-6));
  // On this convex pass the chord's sag is a gouge of the ball: segments
  // whose swept ball the guard finds below the surface were halved.
  EXPECT_GT(r.gouge_splits, 0);
  EXPECT_LE(worst, r.max_deviation_mm * (1 + 1e-6));
}

TEST(RepairPaths, SpiralPitchIsTheStepOverAndNeedsNoLinks) {
  const Tool tool = ball_mill(2);
  const CollisionWorld world = far_world();
  const double height = 5;
  auto s = std::make_shared<Tube>(4.0, height);
  RepairPathRequest rq = finishing_only(s, tool, world);
  rq.pattern = RepairPattern::Spiral;
  rq.u0 = 0.2;
  rq.u1 = 0.6;
  rq.scallop_mm = 0.01;
  rq.steps.chord_tol_mm = 0.005;
  const RepairPathResult r = plan_repair_paths(rq);
  ASSERT_EQ(r.passes.size(), 1u);  // one spiral, no pass-to-pass link
  EXPECT_EQ(r.links + r.bridges, 0);
  ASSERT_EQ(r.connections.size(), 2u);  // lead-in and lead-out only
  // Along the axis the tube is straight: the closed form of a flat.
  const double step = 2 * std::sqrt(2 * 2 * 0.01 - 0.01 * 0.01);
  EXPECT_NEAR(r.layers[0].step_over_max_mm, step, 1e-9);
  const double du = step / height;
  const int turns = r.layers[0].turns;
  EXPECT_EQ(turns, static_cast<int>(std::ceil(0.4 / du - 1e-9)) + 2);
  // Every contact sits on the slanted line of its turn: u = u0 + (t - 1) du
  // over the full turns, u0 on the first (flat) turn, u1 on the last; the
  // height gained per turn (the pitch) is the step-over.
  const std::vector<RepairPose>& poses = r.passes[0].poses;
  int checked = 0;
  for (const RepairPose& p : poses) {
    const double z = p.contact.z();
    if (p.t > turns - 2 && p.t < turns - 1) continue;  // the last, shorter slanted turn
    const double expected = p.t <= 1 ? 0.2 * height
                            : p.t >= turns - 1 ? 0.6 * height
                                               : 0.2 * height + (p.t - 1) * step;
    EXPECT_NEAR(z, expected, 1e-9) << "t = " << p.t;
    if (p.t > 1 && p.t < turns - 3) {
      // The same angle one turn later is one pitch higher.
      EXPECT_NEAR(s->point(rq.u0 + p.t * du, p.v).z() - z, step, 1e-9);
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
  // Continuous around: no step between consecutive contacts longer than
  // the longest allowed step.
  for (size_t i = 0; i + 1 < poses.size(); ++i)
    EXPECT_LE((poses[i + 1].contact - poses[i].contact).norm(), rq.steps.max_step_mm + 1e-9);
}

TEST(RepairPaths, AWindowAcrossTheSeamIsTheSpiralsAndRefusedByTheZigzag) {
  // Issue 43: a region crossing the loft's seam (v from 0.9 round through 0
  // to 0.1) was refused whatever the pattern. The spiral goes all the way
  // round and ignores v: the same plan as over v = [0, 1]. The zigzag runs
  // its passes along v over the window: refused, saying so.
  const Tool tool = ball_mill(2);
  const CollisionWorld world = far_world();
  auto s = std::make_shared<Tube>(4.0, 5);
  RepairPathRequest rq = finishing_only(s, tool, world);
  rq.pattern = RepairPattern::Spiral;
  rq.u0 = 0.2;
  rq.u1 = 0.4;
  rq.scallop_mm = 0.01;
  const RepairPathResult whole = plan_repair_paths(rq);
  rq.v0 = 0.9;
  rq.v1 = 0.1;
  const RepairPathResult across = plan_repair_paths(rq);
  ASSERT_EQ(across.passes.size(), whole.passes.size());
  ASSERT_EQ(across.passes[0].poses.size(), whole.passes[0].poses.size());
  for (size_t i = 0; i < whole.passes[0].poses.size(); ++i)
    EXPECT_EQ((across.passes[0].poses[i].contact - whole.passes[0].poses[i].contact).norm(), 0.0);
  rq.pattern = RepairPattern::Zigzag;
  try {
    plan_repair_paths(rq);
    FAIL() << "a zigzag across the seam was planned";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("crosses the surface's seam"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("spiral"), std::string::npos) << e.what();
  }
}

TEST(RepairPaths, EachZigzagLayerStartsOnTheSideWhereTheLayerBeforeEnded) {
  // Roughing layers and the finish over a patch of a flat: a layer whose
  // pass count is odd ends on the far side (v1); the next layer must start
  // there, or the link between them crosses the whole region (round a
  // blade's edge: through the blade).
  const Tool tool = ball_mill(3);
  const CollisionWorld world = far_world();
  auto s = std::make_shared<PathsPlane>(20.0, 60.0);
  RepairPathRequest rq = finishing_only(s, tool, world);
  rq.u0 = 0.4;
  rq.u1 = 0.5;
  rq.v0 = 0.45;
  rq.v1 = 0.55;
  rq.deposit_mm = 1.0;
  rq.layer_mm = 0.4;
  rq.stock_mm = 0.2;
  const RepairPathResult r = plan_repair_paths(rq);
  ASSERT_GE(r.layers.size(), 3u);
  int odd_layers = 0;
  for (size_t L = 0; L + 1 < r.layers.size(); ++L) {
    const RepairLayer& a = r.layers[L];
    const RepairLayer& b = r.layers[L + 1];
    odd_layers += a.passes % 2;
    const RepairPose& end = r.passes[a.first_pass + a.passes - 1].poses.back();
    const RepairPose& start = r.passes[b.first_pass].poses.front();
    EXPECT_NEAR(end.v, start.v, 1e-9) << "layer " << L << " ends at v = " << end.v << ", the next starts at v = "
                                      << start.v;
    EXPECT_NEAR(end.u, start.u, 1e-9);
  }
  EXPECT_GT(odd_layers, 0) << "no layer with an odd pass count: the test would pass with any start";
  EXPECT_EQ(r.refused_connections, 0);
}

TEST(RepairPaths, ArcLeadOutsAreTangentToThePassAndBridgesJoinThem) {
  const Tool tool = ball_mill(3);
  const CollisionWorld world = far_world();
  auto s = std::make_shared<PathsCylinder>(20.0, 0.3, 10.0);
  RepairPathRequest rq = finishing_only(s, tool, world);
  rq.v0 = 0.2;
  rq.v1 = 0.8;
  rq.arc_radius_mm = 1.5;
  const RepairPathResult r = plan_repair_paths(rq);
  ASSERT_GE(r.passes.size(), 3u);
  EXPECT_EQ(r.bridges, static_cast<int>(r.passes.size()) - 1);
  EXPECT_EQ(r.refused_connections, 0);
  for (size_t c = 1; c + 1 < r.connections.size(); ++c) {
    const RepairConnection& con = r.connections[c];
    ASSERT_EQ(con.kind, RepairConnection::Kind::Bridge);
    const RepairPose& e = r.passes[con.from_pass].poses.back();
    const RepairPose& st = r.passes[con.to_pass].poses.front();
    // The pass runs along its tangent into its end.
    const RepairPose& before = r.passes[con.from_pass].poses[r.passes[con.from_pass].poses.size() - 2];
    EXPECT_GT((e.contact - before.contact).normalized().dot(e.tangent), 0.999);
    // The lead-out: on the circle of radius 1.5 centred 1.5 along the normal
    // from the end pose, in the plane of tangent and normal; that circle's
    // tangent at the end pose is the pass's tangent.
    const Vec3 centre = e.pose.tip + 1.5 * e.normal;
    const Vec3 side = e.tangent.cross(e.normal);
    EXPECT_NEAR(e.tangent.dot(e.normal), 0, 1e-12);
    int arcs = 0;
    for (size_t i = 0; i < con.poses.size(); ++i) {
      if (con.motion[i] != "lead-out") continue;
      EXPECT_NEAR((con.poses[i].tip - centre).norm(), 1.5, 1e-9);
      EXPECT_NEAR((con.poses[i].tip - e.pose.tip).dot(side), 0, 1e-9);
      EXPECT_NEAR((con.poses[i].axis - e.pose.axis).norm(), 0, 1e-12);  // the end pose's axis
      ++arcs;
    }
    EXPECT_EQ(arcs, rq.arc_segments);
    // The first arc move leaves along the tangent (half the arc step off it).
    const Vec3 first = (con.poses[0].tip - e.pose.tip).normalized();
    EXPECT_NEAR(std::acos(std::clamp(first.dot(e.tangent), -1.0, 1.0)), 0.5 * (kPi / 2) / rq.arc_segments, 1e-9);
    // The lead-in mirrors it into the next pass.
    const Vec3 last = (st.pose.tip - con.poses.back().tip).normalized();
    EXPECT_NEAR(std::acos(std::clamp(last.dot(st.tangent), -1.0, 1.0)), 0.5 * (kPi / 2) / rq.arc_segments, 1e-9);
    // Zigzag: the next pass runs back.
    EXPECT_LT(e.tangent.dot(st.tangent), -0.99);
  }
}

TEST(RepairPaths, ContactsWhereTheBallWouldGougeTheRoundNextToTheRegionAreRefused) {
  // Ball radius 3 over a plate running into a concave round of radius 2:
  // the ball cannot sit in the round, and near it touches its wall.
  const Tool tool = ball_mill(3);
  const CollisionWorld world = far_world();
  const double rf = 2, x0 = -6, x1 = 1.6;
  auto s = std::make_shared<PlateWithRound>(x0, x1, rf, 6.0);
  RepairPathRequest rq = finishing_only(s, tool, world);
  rq.scallop_mm = 0.01;
  rq.guard_spacing_mm = 0.05;
  rq.max_lift_mm = 0;  // refuse, never lift (the lift has its own test)
  const RepairPathResult r = plan_repair_paths(rq);
  // Brute force: the ball centre at contact + R n against the profile.
  auto penetration = [&](double u) {
    const SurfaceDerivs d = s->eval(u, 0.5);
    const Vec3 n = d.pu.cross(d.pv).normalized();
    const Vec3 c = d.p + 3 * n;
    double least = 1e300;
    for (int i = 0; i <= 20000; ++i) {
      const double x = x0 + (x1 - x0) * i / 20000.0;
      least = std::min(least, std::hypot(x - c.x(), s->z(x) - c.z()) - 3);
    }
    return least;
  };
  int accepted = 0, refused = 0;
  for (const RepairPass& p : r.passes) {
    const double pen = penetration(p.u);
    EXPECT_GE(pen, -rq.steps.chord_tol_mm - 1e-4) << "accepted pass at u = " << p.u;
    accepted += static_cast<int>(p.poses.size());
  }
  for (const RepairRefusal& f : r.refusals) {
    EXPECT_NE(f.reason.find("into the design"), std::string::npos) << f.reason;
    EXPECT_LT(penetration(f.u), -0.5 * rq.steps.chord_tol_mm) << "refused at u = " << f.u;
    ++refused;
  }
  EXPECT_GT(accepted, 0);
  EXPECT_GT(refused, 0);
  EXPECT_EQ(r.gouge_refusals, refused);
}

TEST(RepairPaths, ABallBesideATroughNarrowerThanItIsLiftedByWhatBruteForceNeedsAndRefusedBeyondMaxLift) {
  // The plate and round of the test above: approaching the round (radius 2)
  // the ball (radius 3) touching the plate cuts the round's wall, more the
  // nearer it gets. With max_lift the planner lifts such a contact off the
  // plate until the ball cuts no deeper than allowed, and refuses it where
  // that takes more than max_lift.
  const Tool tool = ball_mill(3);
  const CollisionWorld world = far_world();
  const double R = 3, rf = 2, x0 = -6, x1 = 1.6;
  auto s = std::make_shared<PlateWithRound>(x0, x1, rf, 6.0);
  RepairPathRequest rq = finishing_only(s, tool, world);
  rq.scallop_mm = 0.001;  // passes 0.15 mm apart: several in the band that lifts
  rq.guard_spacing_mm = 0.05;
  rq.max_lift_mm = 0.3;
  const RepairPathResult r = plan_repair_paths(rq);
  // Brute force over the profile: penetration of a ball centred at c.
  auto penetration = [&](const Vec3& c) {
    double least = 1e300;
    for (int i = 0; i <= 40000; ++i) {
      const double x = x0 + (x1 - x0) * i / 40000.0;
      least = std::min(least, std::hypot(x - c.x(), s->z(x) - c.z()) - R);
    }
    return least;
  };
  // What the planner allows a pose: the chord tolerance less what the
  // guard's samples can miss (spacing^2 / 8R).
  const double allowed = rq.steps.chord_tol_mm - r.guard_spacing_mm * r.guard_spacing_mm / (8 * R);
  // The lift along the normal (up, on the plate) a contact at u needs: by
  // bisection on the brute-force penetration.
  auto needed_lift = [&](double u) {
    const Vec3 c0 = s->point(u, 0.5) + R * Vec3::UnitZ();
    if (penetration(c0) >= -allowed) return 0.0;
    double lo = 0, hi = 1;
    for (int k = 0; k < 40; ++k) {
      const double mid = 0.5 * (lo + hi);
      (penetration(c0 + mid * Vec3::UnitZ()) >= -allowed ? hi : lo) = mid;
    }
    return hi;
  };
  int lifted_passes = 0, plain_passes = 0;
  double largest = 0;
  for (const RepairPass& p : r.passes) {
    if (s->point(p.u, 0.5).x() >= 0) continue;  // on the round itself the normal is not up
    const double need = needed_lift(p.u);
    for (const RepairPose& q : p.poses) {
      EXPECT_LE(q.lift_mm, rq.max_lift_mm);
      EXPECT_NEAR(q.lift_mm, need, 1e-3 * 0.5) << "u = " << p.u;
      // The pose as emitted, not as planned: its ball centre is clear.
      EXPECT_GE(penetration(q.pose.tip + R * q.pose.axis), -rq.steps.chord_tol_mm) << "u = " << p.u;
      largest = std::max(largest, q.lift_mm);
    }
    (need > 0 ? lifted_passes : plain_passes) += 1;
  }
  EXPECT_GE(lifted_passes, 3);
  EXPECT_GT(plain_passes, 10);
  EXPECT_GT(r.lifted, 0);
  EXPECT_DOUBLE_EQ(r.max_lift_mm, largest);
  // Refused only where the lift needed passes max_lift.
  ASSERT_GT(r.refusals.size(), 0u);
  for (const RepairRefusal& f : r.refusals) {
    EXPECT_NE(f.reason.find("it still cuts"), std::string::npos) << f.reason;
    if (s->point(f.u, 0.5).x() < 0) EXPECT_GT(needed_lift(f.u), rq.max_lift_mm - 1e-3 * 0.5) << "u = " << f.u;
  }
}

TEST(RepairPaths, TheAxisTiltsAwayWhereTheHolderWouldHitAWall) {
  // A 4 mm wide flat strip; a wall at x = 14 up to z = 100. Holder radius
  // 12.5 from 42 mm above the tip: upright at x = 4 it reaches x = 16.5.
  const Tool tool = ball_mill(3, 30, 25);
  CollisionWorld world;
  world.add("wall", quad(Vec3(14, -50, -5), Vec3(14, 50, -5), Vec3(14, 50, 100), Vec3(14, -50, 100)));
  auto s = std::make_shared<PathsPlane>(4.0, 10.0);
  RepairPathRequest rq = finishing_only(s, tool, world);
  rq.scallop_mm = 0.05;
  rq.tilt.clearances.shank_mm = rq.tilt.clearances.holder_mm = 0.5;
  const RepairPathResult r = plan_repair_paths(rq);
  // Brute force: the holder's largest x, over both end circles.
  auto holder_max_x = [&](const ToolPose& p) {
    const Vec3 a = p.axis.normalized();
    const double across = 12.5 * std::sqrt(std::max(0.0, 1 - a.x() * a.x()));
    return std::max((p.tip + 42 * a).x(), (p.tip + 82 * a).x()) + across;
  };
  int tilted = 0, upright = 0;
  for (const RepairPass& p : r.passes)
    for (const RepairPose& q : p.poses) {
      EXPECT_LE(holder_max_x(q.pose), 14 - 0.5 + 2e-3) << "x = " << q.contact.x();
      // The lead axis (10° towards the feed, no tilt) at this contact.
      ContactFrame f{q.contact, q.tangent, q.normal};
      const ToolPose lead = place_tool(tool, f, axis_from_lead_tilt(f, rq.tilt.lead0_rad, rq.tilt.tilt0_rad));
      if (holder_max_x(lead) > 14 - 0.5 + 0.01) {
        EXPECT_TRUE(q.tilted) << "x = " << q.contact.x();
      }
      tilted += q.tilted;
      upright += !q.tilted;
    }
  EXPECT_GT(tilted, 0);
  EXPECT_GT(upright, 0);
  EXPECT_TRUE(r.refusals.empty());
}

}  // namespace
}  // namespace bliskrun
