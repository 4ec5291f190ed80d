// Tools: profiles against closed forms, signed distance against brute force
// on the sampled surface, parameter errors, cut width (blisk paper Fig. 6)
// and the circumscribed FCL polytope.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/common/error.h"
#include "core/tools/tool.h"
#include "core/tools/tool_fcl.h"

namespace bliskrun {
namespace {

// Blisk paper Table 3, wheel 2 (the extended design): D_t 8, R_c 50, L_c 4, d 6, h 96.
Tool paper_wheel_of_barrel(double barrel_radius = 50) {
  DrumWheelSpec s;
  s.max_diameter_mm = 8;
  s.barrel_radius_mm = barrel_radius;
  s.head_length_mm = 4;
  s.shank = {6, 96};
  return Tool::drum_wheel(s);
}

std::vector<Tool> every_tool() {
  std::vector<Tool> tools{paper_wheel_of_barrel()};
  tools.push_back(Tool::conical_drum_wheel({6, 9, 30, 5, {5, 40}, {}}));
  tools.push_back(Tool::flat_end_mill({5, 1.5, 20, {10, 30}, {30, 40}}));
  tools.push_back(Tool::ball_end_mill({3, 15, {6, 30}, {}}));
  tools.push_back(Tool::tapered_ball_end_mill({1.5, deg_to_rad(4), 25, {8, 30}, {}}));
  tools.push_back(Tool::contact_wheel({50, 20, {}, {}}));
  return tools;
}

// Points on a profile element by its own parametrisation (independent of the
// closest-point code under test).
std::vector<Vec2> sample_element(const ProfileElement& e, double spacing) {
  std::vector<Vec2> out;
  if (e.kind == ProfileElement::Kind::Segment) {
    const int n = std::max(1, static_cast<int>(std::ceil((e.end - e.start).norm() / spacing)));
    for (int i = 0; i <= n; ++i) out.push_back(e.start + (e.end - e.start) * (double(i) / n));
    return out;
  }
  const double a0 = std::atan2(e.start.y() - e.centre.y(), e.start.x() - e.centre.x());
  const double a1 = std::atan2(e.end.y() - e.centre.y(), e.end.x() - e.centre.x());
  const int n = std::max(1, static_cast<int>(std::ceil(e.radius * (a1 - a0) / spacing)));
  for (int i = 0; i <= n; ++i) {
    const double a = a0 + (a1 - a0) * i / n;
    out.push_back(e.centre + e.radius * Vec2(std::cos(a), std::sin(a)));
  }
  return out;
}

std::vector<Vec2> sample_profile(const Profile& p, double spacing) {
  std::vector<Vec2> out;
  for (const ProfileElement& e : p.elements()) {
    for (const Vec2& q : sample_element(e, spacing)) out.push_back(q);
  }
  return out;
}

// Crossing-number test against the closed polygon chain + axis.
bool inside_polygon(const std::vector<Vec2>& poly, const Vec2& q) {
  bool in = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[j];
    if ((a.y() > q.y()) != (b.y() > q.y()) &&
        q.x() < (b.x() - a.x()) * (q.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      in = !in;
    }
  }
  return in;
}

TEST(DrumWheel, ProfileIsTheBarrelArcCentredAtHalfHeight) {
  for (double rc : {20.0, 50.0}) {  // Table 3 wheels 1 and 2
    const Tool t = paper_wheel_of_barrel(rc);
    for (int i = 0; i <= 400; ++i) {
      const double z = 4.0 * i / 400;
      const double expected = 4.0 - rc + std::sqrt(rc * rc - (z - 2.0) * (z - 2.0));
      EXPECT_NEAR(t.cutter().radius_at(z), expected, 1e-12) << "R_c " << rc << " z " << z;
    }
    EXPECT_DOUBLE_EQ(t.cutter().max_radius(), 4.0);
    EXPECT_DOUBLE_EQ(t.flank_contact_height(), 2.0);
    // Whole tool: the shank above the head, nothing beyond it.
    EXPECT_DOUBLE_EQ(t.radius_at(50), 3.0);
    EXPECT_DOUBLE_EQ(t.radius_at(100.5), 0.0);
    EXPECT_DOUBLE_EQ(t.radius_at(-0.1), 0.0);
  }
}

TEST(Tools, ProfilesMatchClosedForms) {
  const Tool ball = Tool::ball_end_mill({3, 15, {6, 30}, {}});
  const Tool bull = Tool::flat_end_mill({5, 1.5, 20, {10, 30}, {}});
  const Tool taper = Tool::tapered_ball_end_mill({1.5, deg_to_rad(4), 25, {8, 30}, {}});
  for (int i = 0; i <= 300; ++i) {
    const double z = 15.0 * i / 300;
    const double ball_r = z < 3 ? std::sqrt(9 - (3 - z) * (3 - z)) : 3;
    EXPECT_NEAR(ball.radius_at(z), ball_r, 1e-12);
    const double bull_r = z < 1.5 ? 3.5 + std::sqrt(2.25 - (1.5 - z) * (1.5 - z)) : 5;
    EXPECT_NEAR(bull.radius_at(z), bull_r, 1e-12);
    // Tapered: ball below the tangent circle, then the cone of half angle 4 deg.
    const double b = deg_to_rad(4), zt = 1.5 * (1 - std::sin(b));
    const double taper_r = z < zt ? std::sqrt(2.25 - (1.5 - z) * (1.5 - z)) : 1.5 * std::cos(b) + (z - zt) * std::tan(b);
    EXPECT_NEAR(taper.radius_at(z), taper_r, 1e-12);
  }
  const Tool wheel = Tool::contact_wheel({50, 20, {}, {}});
  EXPECT_DOUBLE_EQ(wheel.radius_at(-9.9), 50);
  EXPECT_DOUBLE_EQ(wheel.radius_at(10.1), 0);
  // Ball end: distance to the sphere below the centre, exactly.
  EXPECT_NEAR(ball.signed_distance(Vec3(1, 2, -4), ToolPartId::Cutter), Vec3(1, 2, -7).norm() - 3, 1e-12);
  EXPECT_NEAR(ball.signed_distance(Vec3(0.5, 0, 2.5), ToolPartId::Cutter), Vec3(0.5, 0, -0.5).norm() - 3, 1e-12);
}

TEST(ConicalDrumWheel, BarrelArcRunsFromBottomToTopDiameter) {
  const Tool t = Tool::conical_drum_wheel({6, 9, 30, 5, {5, 40}, {}});
  EXPECT_NEAR(t.cutter().radius_at(0), 3, 1e-12);
  EXPECT_NEAR(t.cutter().radius_at(5), 4.5, 1e-12);
  // Every side point lies on one circle of radius R_c, bulging outwards.
  const ProfileElement& arc = t.cutter().elements()[1];
  ASSERT_EQ(arc.kind, ProfileElement::Kind::Arc);
  for (int i = 0; i <= 50; ++i) {
    const double z = 5.0 * i / 50;
    EXPECT_NEAR((Vec2(t.cutter().radius_at(z), z) - arc.centre).norm(), 30, 1e-9);
    EXPECT_GE(t.cutter().radius_at(z), 3 + 1.5 * z / 5 - 1e-12);  // outside the chord
  }
  EXPECT_NEAR(t.cutter().meridian_curvature(2.5), 1.0 / 30, 1e-15);
}

TEST(Profile, RejectsChainsThatAreNotConvexProfiles) {
  using E = ProfileElement;
  auto name_of = [](std::vector<ProfileElement> e) -> std::string {
    try {
      Profile p(std::move(e));
    } catch (const ParameterError& err) {
      return err.name() + ": " + err.what();
    }
    return "<no error>";
  };
  // Off the axis at the start.
  EXPECT_NE(name_of({E::segment({1, 0}, {2, 0}), E::segment({2, 0}, {2, 1}), E::segment({2, 1}, {0, 1})})
                .find("must start on the axis"),
            std::string::npos);
  // A notch (clockwise turn).
  EXPECT_NE(name_of({E::segment({0, 0}, {2, 0}), E::segment({2, 0}, {1, 1}), E::segment({1, 1}, {2, 2}),
                     E::segment({2, 2}, {0, 2})})
                .find("convex"),
            std::string::npos);
  // Running downwards.
  EXPECT_NE(name_of({E::segment({0, 1}, {2, 0}), E::segment({2, 0}, {0, 2})}).find("downwards"), std::string::npos);
  // Gap between elements.
  EXPECT_NE(name_of({E::segment({0, 0}, {2, 0}), E::segment({2, 0.1}, {0, 1})}).find("does not start where"),
            std::string::npos);
}

TEST(Tools, SignedDistanceMatchesBruteForceOnSampledSurface) {
  std::mt19937 rng(7);
  for (const Tool& tool : every_tool()) {
    const Profile& p = tool.cutter();
    // Sample the revolved surface: meridian spacing h, 720 meridians.
    const double h = 0.01;
    const std::vector<Vec2> meridian = sample_profile(p, h);
    const int meridians = 720;
    std::vector<Vec3> surface;
    for (int j = 0; j < meridians; ++j) {
      const double a = 2 * kPi * j / meridians;
      for (const Vec2& q : meridian) surface.emplace_back(q.x() * std::cos(a), q.x() * std::sin(a), q.y());
    }
    // Largest gap between samples: half the meridian spacing and half the
    // arc between meridians at the largest radius.
    const double gap = std::hypot(h / 2, kPi * p.max_radius() / meridians);
    std::uniform_real_distribution<double> ur(0, 1.4 * p.max_radius());
    std::uniform_real_distribution<double> uz(p.z_min() - 2, p.z_max() + 2);
    std::uniform_real_distribution<double> ua(0, 2 * kPi);
    int inside = 0;
    for (int k = 0; k < 40; ++k) {
      const double r = ur(rng), z = uz(rng), a = ua(rng);
      const Vec3 q(r * std::cos(a), r * std::sin(a), z);
      double brute = 1e300;
      for (const Vec3& s : surface) brute = std::min(brute, (s - q).squaredNorm());
      brute = std::sqrt(brute);
      const double sd = tool.signed_distance(q, ToolPartId::Cutter);
      EXPECT_LE(std::abs(sd), brute + 1e-9) << tool.description();
      EXPECT_GE(std::abs(sd), brute - gap) << tool.description();
      if (std::abs(sd) > 2 * gap) {
        const bool in = inside_polygon(meridian, Vec2(r, z));
        EXPECT_EQ(sd < 0, in) << tool.description() << " at r " << r << " z " << z;
        inside += in;
      }
    }
    EXPECT_GT(inside, 0) << "no interior sample for " << tool.description();
  }
}

// The distance-only signed distance (wedge tests instead of angles) is the
// distance to the closest point, for every tool, near and far, on and off
// the axis, at the arcs' centres and a micrometre around every vertex; and
// negative exactly where the point is inside the solid (r < R(z)) — the
// sign is taken from the nearest element's side, R(z) asked only at vertices.
TEST(Profile, SignedDistanceIsTheDistanceToTheClosestPoint) {
  std::mt19937 rng(11);
  for (const Tool& tool : every_tool()) {
    const Profile& p = tool.cutter();
    std::uniform_real_distribution<double> ur(0, 1.4 * p.max_radius());
    std::uniform_real_distribution<double> uz(p.z_min() - 2, p.z_max() + 2);
    std::vector<Vec2> points;
    for (int k = 0; k < 4000; ++k) points.emplace_back(ur(rng), uz(rng));
    for (const ProfileElement& e : p.elements()) {
      if (e.kind == ProfileElement::Kind::Arc) points.push_back(e.centre);
      // A grid round every vertex, inside and out: where the bounding
      // cylinder's distance (the fast path) stops being the solid's.
      for (int i = -20; i <= 20; ++i)
        for (int j = -20; j <= 20; ++j) {
          const Vec2 q = e.start + Vec2(0.05 * i, 0.05 * j);
          if (q.x() >= 0) points.push_back(q);
        }
      for (double dr : {-1e-3, 0.0, 1e-3})
        for (double dz : {-1e-3, 0.0, 1e-3})
          if (e.start.x() + dr >= 0) points.push_back(e.start + Vec2(dr, dz));
    }
    int inside_count = 0;
    for (const Vec2& q : points) {
      const double expected = (p.closest_point(q).point - q).norm();
      const double sd = p.signed_distance(q);
      EXPECT_NEAR(std::abs(sd), expected, 1e-12 * std::max(1.0, expected))
          << tool.description() << " at r " << q.x() << " z " << q.y();
      if (expected < 1e-12) continue;  // on the profile: either sign
      const bool inside = q.y() > p.z_min() && q.y() < p.z_max() && q.x() < p.radius_at(q.y());
      EXPECT_EQ(sd < 0, inside) << tool.description() << " at r " << q.x() << " z " << q.y();
      inside_count += inside ? 1 : 0;
    }
    EXPECT_GT(inside_count, 100) << tool.description();
  }
}

TEST(Tools, InvalidParametersNameTheParameter) {
  auto name_of = [](auto&& make) -> std::string {
    try {
      make();
    } catch (const ParameterError& e) {
      return e.name();
    }
    return "<no error>";
  };
  EXPECT_EQ(name_of([] { Tool::drum_wheel({8, 3.9, 4, {6, 96}, {}}); }), "barrel_radius");  // R_c < D_t/2
  EXPECT_EQ(name_of([] { Tool::drum_wheel({-8, 50, 4, {6, 96}, {}}); }), "max_diameter");
  EXPECT_EQ(name_of([] { Tool::drum_wheel({8, 50, 0, {6, 96}, {}}); }), "head_length");
  EXPECT_EQ(name_of([] { Tool::drum_wheel({8, 50, 4, {-6, 96}, {}}); }), "shank.diameter");
  EXPECT_EQ(name_of([] { Tool::drum_wheel({8, 50, 4, {0, 96}, {}}); }), "shank.diameter");
  EXPECT_EQ(name_of([] { Tool::drum_wheel({8, 50, 4, {6, -1}, {}}); }), "shank.length");
  EXPECT_EQ(name_of([] { Tool::drum_wheel({8, 4.5, 9.5, {6, 96}, {}}); }), "barrel_radius");  // R_c <= L_c/2
  EXPECT_EQ(name_of([] { Tool::flat_end_mill({5, 5.5, 20, {}, {}}); }), "corner_radius");     // r > R
  EXPECT_EQ(name_of([] { Tool::flat_end_mill({5, 1, 0.5, {}, {}}); }), "flute_length");
  EXPECT_EQ(name_of([] { Tool::ball_end_mill({3, 2, {}, {}}); }), "flute_length");
  EXPECT_EQ(name_of([] { Tool::tapered_ball_end_mill({1.5, deg_to_rad(90), 25, {}, {}}); }), "half_angle");
  EXPECT_EQ(name_of([] { Tool::contact_wheel({50, -1, {}, {}}); }), "width");
  EXPECT_EQ(name_of([] { Tool::conical_drum_wheel({6, 9, 1, 5, {}, {}}); }), "barrel_radius");
  EXPECT_EQ(name_of([] { paper_wheel_of_barrel().cut_width(2, 0.0, -0.01); }), "residual_height");
  EXPECT_EQ(name_of([] { paper_wheel_of_barrel().cut_width(2, 0.03, 0.01); }), "normal_curvature");  // 1/0.03 < R_c: gouge
  // The message says why, with the numbers.
  try {
    Tool::drum_wheel({8, 3.9, 4, {6, 96}, {}});
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("below D_t/2 = 4"), std::string::npos) << e.what();
  }
}

// Blisk paper Fig. 6: the width between the two points where the wheel's
// profile meets the residual surface, against the circle-circle closed form.
TEST(DrumWheel, CutWidthMatchesCircleIntersection) {
  for (double rc : {20.0, 50.0}) {
    const Tool t = paper_wheel_of_barrel(rc);
    for (double h : {0.002, 0.014}) {
      // Flat surface: chord of the barrel circle at depth h.
      EXPECT_NEAR(t.cut_width(2, 0, h).width_mm, 2 * std::sqrt(2 * rc * h - h * h), 1e-9);
      for (double k : {-0.0435, -0.0195, 0.0089, 0.0195}) {
        // Barrel circle s^2 + (t - R_c)^2 = R_c^2; residual circle
        // s^2 + (t - c2)^2 = r2^2 with c2 = 1/k, r2 = |1/k| - h sign(k).
        // Their difference is linear in t.
        const double c2 = 1 / k, r2 = std::abs(1 / k) - (k > 0 ? h : -h);
        const double t_common = (c2 * c2 - r2 * r2) / (2 * (c2 - rc));
        const double s = std::sqrt(rc * rc - (t_common - rc) * (t_common - rc));
        if (s > 2) {
          // The barrel stays below the residual height over the whole 4 mm
          // head: the end faces meet it, and the width is the head length.
          EXPECT_NEAR(t.cut_width(2, k, h).width_mm, 4, 1e-9) << "R_c " << rc << " k " << k;
          continue;
        }
        const CutWidth w = t.cut_width(2, k, h);
        EXPECT_NEAR(w.width_mm, 2 * s, 1e-9) << "R_c " << rc << " k " << k << " h " << h;
        EXPECT_NEAR(w.a.y(), t_common, 1e-9);
        EXPECT_NEAR(w.b.y(), t_common, 1e-9);
      }
    }
  }
  // The paper's numbers: a 14 µm residual on a flat flank gives a 2.37 mm
  // row with R_c = 50 and 1.50 mm with R_c = 20 (the extended design's gain).
  EXPECT_NEAR(paper_wheel_of_barrel(50).cut_width(2, 0, 0.014).width_mm, 2.366, 1e-3);
  EXPECT_NEAR(paper_wheel_of_barrel(20).cut_width(2, 0, 0.014).width_mm, 1.497, 1e-3);
  // A residual the barrel does not reach within the 4 mm head: the end faces
  // bound the strip.
  EXPECT_NEAR(paper_wheel_of_barrel(50).cut_width(2, 0, 0.05).width_mm, 4, 1e-12);
  // A flat side against a flat surface never rises: no finite width.
  EXPECT_THROW(Tool::flat_end_mill({5, 1, 20, {}, {}}).cut_width(10, 0, 0.01), ParameterError);
}

TEST(DrumWheel, EffectiveRadiusFollowsEuler) {
  const Tool t = paper_wheel_of_barrel(50);
  EXPECT_NEAR(t.effective_radius(2, 0), 50, 1e-12);           // along the axis: R_c
  EXPECT_NEAR(t.effective_radius(2, kPi / 2), 4, 1e-12);      // round the axis: D_t/2
  EXPECT_NEAR(t.effective_radius(2, kPi / 4), 1 / (0.5 / 50 + 0.5 / 4), 1e-12);
  const Tool mill = Tool::flat_end_mill({5, 1.5, 20, {}, {}});
  EXPECT_TRUE(std::isinf(mill.effective_radius(10, 0)));      // straight side
  EXPECT_NEAR(mill.effective_radius(10, kPi / 2), 5, 1e-12);
}

TEST(Profile, PointWithNormalOnArcsAndCorners) {
  const Tool ball = Tool::ball_end_mill({3, 15, {}, {}});
  for (double a : {-kPi / 2, -1.0, -0.3, 0.0}) {
    const ProfilePoint p = ball.cutter().point_with_normal(Vec2(std::cos(a), std::sin(a)));
    EXPECT_NEAR((p.point - (Vec2(0, 3) + 3 * Vec2(std::cos(a), std::sin(a)))).norm(), 0, 1e-12);
  }
  // The drum wheel's bottom corner carries every normal between the bottom
  // face's and the arc's first one.
  const Tool wheel = paper_wheel_of_barrel(50);
  const double r_end = 4 - 50 + std::sqrt(2500 - 4);
  const ProfilePoint corner = wheel.cutter().point_with_normal(Vec2(std::cos(-0.5), std::sin(-0.5)));
  EXPECT_NEAR((corner.point - Vec2(r_end, 0)).norm(), 0, 1e-12);
  const ProfilePoint bottom = wheel.cutter().point_with_normal(Vec2(0, -1));
  EXPECT_NEAR(bottom.point.norm(), 0, 1e-12);  // flat face: its first point, on the axis
}

// The FCL body contains the tool and stays within its stated overestimate.
TEST(ToolFcl, CircumscribedPolytopeContainsTheSolid) {
  for (const Tool& tool : every_tool()) {
    for (double tol : {0.01, 0.05}) {
      const RevolvedPolytope poly = circumscribed_polytope(tool.cutter(), tol);
      EXPECT_LE(poly.overestimate_mm, 2.01 * tol);
      // Outward face planes: every vertex on the inner side (convex, oriented).
      std::vector<std::pair<Vec3, double>> planes;
      for (const auto& f : poly.faces) {
        const Vec3 n = (poly.vertices[f[1]] - poly.vertices[f[0]]).cross(poly.vertices[f[2]] - poly.vertices[f[0]]);
        ASSERT_GT(n.norm(), 0);
        planes.emplace_back(n.normalized(), n.normalized().dot(poly.vertices[f[0]]));
      }
      for (const Vec3& v : poly.vertices) {
        for (const auto& [n, d] : planes) ASSERT_LE(n.dot(v) - d, 1e-9);
        const double sd = tool.signed_distance(v, ToolPartId::Cutter);
        EXPECT_GE(sd, -1e-9);
        EXPECT_LE(sd, poly.overestimate_mm + 1e-9);
      }
      // Surface points of the true solid lie inside every face plane.
      for (const Vec2& q : sample_profile(tool.cutter(), 0.1)) {
        for (int j = 0; j < 31; ++j) {
          const double a = 2 * kPi * j / 31;
          const Vec3 p(q.x() * std::cos(a), q.x() * std::sin(a), q.y());
          for (const auto& [n, d] : planes) ASSERT_LE(n.dot(p) - d, 1e-9) << tool.description();
        }
      }
    }
  }
}

TEST(Profile, SplitAtAHeightGivesTheSolidBelowAndAbove) {
  // Through the tapered ball's arc, its cone, and a ball end's flute.
  for (const auto& [tool, z] : {std::pair<Tool, double>{Tool::tapered_ball_end_mill({1.5, deg_to_rad(4), 25, {8, 30}, {}}), 1.0},
                                {Tool::tapered_ball_end_mill({1.5, deg_to_rad(4), 25, {8, 30}, {}}), 6.0},
                                {Tool::ball_end_mill({3, 15, {6, 30}, {}}), 9.0}}) {
    const Profile& whole = tool.cutter();
    const auto [below, above] = whole.split_at(z);
    EXPECT_EQ(below.z_min(), whole.z_min());
    EXPECT_NEAR(below.z_max(), z, 1e-12);
    EXPECT_NEAR(above.z_min(), z, 1e-12);
    EXPECT_EQ(above.z_max(), whole.z_max());
    for (int i = 1; i < 200; ++i) {
      const double h = whole.z_min() + (whole.z_max() - whole.z_min()) * i / 200;
      if (std::abs(h - z) < 1e-9) continue;  // on the cut
      const Profile& piece = h < z ? below : above;
      EXPECT_NEAR(piece.radius_at(h), whole.radius_at(h), 1e-9) << h;
      // A point just inside the whole solid is inside the piece of its height.
      const Vec2 inside(0.9 * whole.radius_at(h), h);
      EXPECT_LT(piece.signed_distance(inside), 0) << h;
      EXPECT_GT((h < z ? above : below).signed_distance(inside), 0) << h;
    }
  }
  EXPECT_THROW(Tool::ball_end_mill({3, 15, {}, {}}).cutter().split_at(0), ParameterError);
}

TEST(ToolFcl, ALongCutterIsTwoPiecesWhoseBottomReachesLess) {
  // The impeller's tapered ball end (r 3, 2 deg, 90 mm flute): cut at two
  // of its largest radii; the bottom's reach is that height's corner.
  const Tool long_cutter = Tool::tapered_ball_end_mill({3, deg_to_rad(2), 90, {16, 60}, {}});
  const std::vector<FclToolPart> parts = fcl_parts(long_cutter, 0.01);
  ASSERT_EQ(parts.front().id, ToolPartId::Cutter);
  ASSERT_EQ(parts.front().pieces.size(), 2u);
  const double rmax = long_cutter.cutter().max_radius(), cut = 2 * rmax;
  EXPECT_NEAR(parts.front().pieces[0].reach_mm, std::hypot(cut, long_cutter.cutter().radius_at(cut)), 0.03);
  EXPECT_GT(parts.front().pieces[1].reach_mm, 90);
  EXPECT_EQ(parts.front().reach_mm, parts.front().pieces[1].reach_mm);
  // The shank, and a short cutter, stay whole.
  EXPECT_EQ(parts[1].pieces.size(), 1u);
  EXPECT_EQ(fcl_parts(paper_wheel_of_barrel(), 0.01).front().pieces.size(), 1u);
}

}  // namespace
}  // namespace bliskrun
