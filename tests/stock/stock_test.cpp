// The stock model (core/stock): blank volumes against Pappus, removed
// volumes against closed forms (a slot through a cylinder by a flat and by a
// ball end mill, a helix of overlapping plunges), air cutting, engagement,
// the material above a surface point, and the state after a 5-axis sequence
// against a brute-force count along every ray with the tools' own signed
// distance (core/tools), not the stock's ray intersection.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/common/error.h"
#include "core/stock/blank_profile.h"
#include "core/stock/revolved_solid.h"
#include "core/stock/stock.h"
#include "core/tools/pose.h"
#include "core/tools/tool.h"
#include "test_support.h"

namespace bliskrun {
namespace {

// A cylinder of radius r from z0 to z1.
BlankProfile cylinder_blank(double r, double z0, double z1) {
  return BlankProfile({{0, z0}, {r, z0}, {r, z1}, {0, z1}});
}

Move feed(const Vec3& tip, const Vec3& axis = Vec3::UnitZ()) {
  Move m;
  m.kind = Move::Kind::Feed;
  m.pose = {tip, axis};
  m.motion = "cut";
  return m;
}

Move rapid_to(const Vec3& tip, const Vec3& axis = Vec3::UnitZ()) {
  Move m = feed(tip, axis);
  m.kind = Move::Kind::Rapid;
  m.motion = "traverse";
  return m;
}

// ∫ 2·sqrt(R² - y²) dy from -w to w: the chord length of a cylinder of
// radius R integrated across a slot of half width w.
double chord_integral(double R, double w) {
  return w * std::sqrt(R * R - w * w) + R * R * std::asin(w / R) - (-w * std::sqrt(R * R - w * w) - R * R * std::asin(w / R));
}

TEST(BlankProfile, VolumeIsPappusAndBadProfilesAreRefused) {
  EXPECT_NEAR(cylinder_blank(20, 0, 10).volume(), kPi * 400 * 10, 1e-9);
  // A ring with a bore, given clockwise: r 5..20, height 10.
  const BlankProfile ring({{5, 0}, {5, 10}, {20, 10}, {20, 0}});
  EXPECT_NEAR(ring.volume(), kPi * (400 - 25) * 10, 1e-9);
  // A cone of base radius 10 and height 30.
  EXPECT_NEAR(BlankProfile({{0, 0}, {10, 0}, {0, 30}}).volume(), kPi * 100 * 30 / 3, 1e-9);
  EXPECT_THROW(BlankProfile({{0, 0}, {1, 0}}), ParameterError);
  EXPECT_THROW(BlankProfile({{0, 0}, {-1, 0}, {0, 1}}), ParameterError);
  EXPECT_THROW(BlankProfile({{0, 0}, {1, 0}, {2, 0}}), ParameterError);                  // no area
  EXPECT_THROW(BlankProfile({{0, 0}, {2, 2}, {2, 0}, {0, 2}}), ParameterError);          // a bow tie
  EXPECT_THROW(BlankProfile({{0, 0}, {std::nan(""), 0}, {0, 1}}), ParameterError);
  EXPECT_THROW(Stock(cylinder_blank(20, 0, 10), {0.001}), ParameterError);
  EXPECT_THROW(Stock(cylinder_blank(20, 0, 10), {5}), ParameterError);  // more than a quarter of the height
}

TEST(Stock, BlankVolumeOnTheGrids) {
  // A ring with a chamfered rim, 0.5 mm rays: each grid's midpoint rule
  // within 0.2 % of Pappus, their mean within 0.1 %.
  const BlankProfile blank({{8, 0}, {40, 0}, {40, 12}, {36, 16}, {8, 16}});
  const Stock s(blank, {0.5});
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.volume_of_grid(k) / blank.volume(), 1, 2e-3) << "grid " << k;
  EXPECT_NEAR(s.volume() / blank.volume(), 1, 1e-3);
  EXPECT_EQ(s.blank_volume(), s.volume());
  EXPECT_EQ(s.blank_exact_volume(), blank.volume());
}

TEST(RevolvedSolid, RaySpansAgainstTheToolsSignedDistance) {
  // Rays in every direction through every tool kind: the closed-form span's
  // ends lie on the tool's surface and its middle inside (the bull-nose and
  // barrel tori within their tangent polygon's tolerance).
  const std::vector<Tool> tools{
      Tool::ball_end_mill({4, 20, {8, 30}, {}}), Tool::flat_end_mill({5, 1.5, 20, {10, 30}, {}}),
      Tool::flat_end_mill({5, 0, 20, {}, {}}), Tool::tapered_ball_end_mill({1.5, deg_to_rad(4), 25, {8, 30}, {}}),
      Tool::drum_wheel({8, 50, 4, {6, 96}, {}}), Tool::conical_drum_wheel({6, 9, 30, 5, {5, 40}, {}})};
  const double tol = 0.002;
  for (const Tool& t : tools) {
    const RevolvedSolid solid(t.cutter(), tol);
    int hits = 0;
    for (int k = 0; k < 400; ++k) {
      // Deterministic directions and offsets over the sphere.
      const double a = 2.399963 * k, zc = 1 - (2.0 * k + 1) / 400;
      const Vec3 dir(std::sqrt(1 - zc * zc) * std::cos(a), std::sqrt(1 - zc * zc) * std::sin(a), zc);
      const Vec3 off = dir.unitOrthogonal() * (0.03 * (k % 200)) * t.cutter().max_radius() / 4 +
                       dir.cross(dir.unitOrthogonal()) * 0.01 * (k % 7) +
                       Vec3(0, 0, 0.5 * (t.cutter().z_min() + t.cutter().z_max()));
      const Vec3 origin = off - 100 * dir;
      double lo, hi;
      if (!solid.intersect(FrameRay::make(origin, dir, Vec3::Zero(), Vec3::UnitZ()), lo, hi)) {
        // A miss: no point of the ray inside the tool.
        for (double s = 0; s <= 200; s += 0.05) ASSERT_GT(t.cutter().signed_distance(Vec3(origin + s * dir)), -1e-3);
        continue;
      }
      ++hits;
      EXPECT_NEAR(t.cutter().signed_distance(Vec3(origin + lo * dir)), 0, tol + 1e-9) << t.description() << " ray " << k;
      EXPECT_NEAR(t.cutter().signed_distance(Vec3(origin + hi * dir)), 0, tol + 1e-9) << t.description() << " ray " << k;
      EXPECT_LE(t.cutter().signed_distance(Vec3(origin + 0.5 * (lo + hi) * dir)), tol);
    }
    EXPECT_GT(hits, 100) << t.description();
  }
}

TEST(RevolvedSolid, AxialSweepIsTheUnionOfTheShiftedSolids) {
  const Tool ball = Tool::ball_end_mill({4, 20, {8, 30}, {}});
  const RevolvedSolid solid(ball.cutter(), 0.002);
  for (double shift : {7.0, -7.0}) {
    const RevolvedSolid swept = solid.swept_along_axis(shift);
    EXPECT_NEAR(swept.z_min(), std::min(0.0, shift), 1e-12);
    EXPECT_NEAR(swept.z_max(), 20 + std::max(0.0, shift), 1e-12);
    // On rays across the axis at many heights, against the union of the
    // tool shifted by 0.01 mm steps.
    for (double z = -8; z <= 28; z += 0.37) {
      for (double y : {0.0, 1.3, 3.9}) {
        const Vec3 origin(-50, y, z), dir = Vec3::UnitX();
        double lo = 0, hi = 0;
        const bool hit = swept.intersect(FrameRay::make(origin, dir, Vec3::Zero(), Vec3::UnitZ()), lo, hi);
        double half = -1;  // the union's half chord at this height
        for (int q = 0; q <= 700; ++q) {
          const double s = shift * q / 700;
          const double r = ball.cutter().radius_at(z - s);
          if (r > std::abs(y)) half = std::max(half, std::sqrt(r * r - y * y));
        }
        if (half < 0) {
          EXPECT_FALSE(hit && hi - lo > 1e-6) << "z " << z << " y " << y;
          continue;
        }
        ASSERT_TRUE(hit) << "z " << z << " y " << y;
        EXPECT_NEAR(hi - lo, 2 * half, 2e-3) << "z " << z << " y " << y;
      }
    }
  }
}

TEST(Stock, SlotByAFlatEndMillThroughACylinder) {
  // Flat end R 4, tip 3 mm below the top of a cylinder r 30, straight
  // across it and out both sides: removed = 3 · ∫ 2 sqrt(30² - y²) dy over
  // |y| <= 4.
  const double R = 4, depth = 3;
  const Tool flat = Tool::flat_end_mill({R, 0, 20, {}, {}});
  for (double h : {0.5, 0.25}) {
    Stock s(cylinder_blank(30, 0, 20), {h});
    const Toolpath moves{rapid_to({-40, 0, 20 - depth}), feed({40, 0, 20 - depth})};
    const CutResult r = s.cut(moves, flat, {});
    const double expected = depth * chord_integral(30, R);
    EXPECT_NEAR(r.removed_mm3 / expected, 1, 2e-3) << "resolution " << h;
    EXPECT_NEAR((s.blank_volume() - s.volume()) / r.removed_mm3, 1, 1e-12);
    // Engagement: the slot's full width and depth; the cross-section 2 R x
    // depth. Extents are read on the rays: exact along them, across within
    // the chord of the tool's circle half a spacing off its centre.
    EXPECT_NEAR(r.moves[1].axial_mm, depth, 1e-4);
    EXPECT_LE(r.moves[1].radial_mm, 2 * R + 1e-6);
    EXPECT_GE(r.moves[1].radial_mm, 2 * std::sqrt(R * R - h * h / 4) - 1e-6);
    EXPECT_NEAR(r.moves[1].rate_max_mm2, 2 * R * depth, 0.03 * 2 * R * depth);
    // Air: in 6 mm (10 - R), the tool cutting from x = -34; out from where
    // its front leaves the last material at the slot's sides (x 29.7 at
    // |y| = R; 28.4 where the last rays at |y| = R - h/2 see it) to 40.
    EXPECT_GE(r.moves[1].air_mm, (10 - R) + (40 - 29.8) - h);
    EXPECT_LE(r.moves[1].air_mm, (10 - R) + (40 - 28.3) + h);
    EXPECT_NEAR(r.cut_mm, 80, 1e-12);
    EXPECT_EQ(r.rapid_removed_mm3, 0);
    // The same slot again removes nothing: all air.
    const CutResult again = s.cut(moves, flat, {});
    EXPECT_LT(again.removed_mm3, 1e-6);
    EXPECT_NEAR(again.air_cut_mm, 80, 1e-9);
  }
}

TEST(Stock, SlotByABallEndMillThroughACylinder) {
  // Ball R 4, 3 mm deep: the slot's section is a circular segment of height
  // 3; removed = ∫ h(y)·2 sqrt(30² - y²) dy with h(y) the segment's height
  // at y (Simpson, 20 000 intervals: the integrand is smooth).
  const double R = 4, depth = 3, zc = 20 - depth + R;
  const double w = std::sqrt(R * R - (R - depth) * (R - depth));
  const int n = 20000;
  double expected = 0;
  for (int i = 0; i <= n; ++i) {
    const double y = -w + 2 * w * i / n;
    const double f = (20 - (zc - std::sqrt(std::max(0.0, R * R - y * y)))) * 2 * std::sqrt(900 - y * y);
    expected += f * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
  }
  expected *= 2 * w / n / 3;
  const Tool ball = Tool::ball_end_mill({R, 20, {}, {}});
  const Toolpath moves{rapid_to({-40, 0, 20 - depth}), feed({40, 0, 20 - depth})};
  CutOptions o;
  o.step_mm = 0.1;  // scallops between samples 0.1²/(8·4) = 0.3 µm
  // The section (17.2 mm²) is only ~70 cells of 0.5 mm: the grids' count
  // of a round section is within 2.5 % there, 0.5 % at 0.25 mm (measured
  // +1.9 % and +0.35 %; +0.17 % at 0.125 mm).
  double error_coarse = 0;
  for (double h : {0.5, 0.25}) {
    Stock s(cylinder_blank(30, 0, 20), {h});
    const CutResult r = s.cut(moves, ball, o);
    const double error = std::abs(r.removed_mm3 / expected - 1);
    EXPECT_LT(error, h == 0.5 ? 0.025 : 0.005) << "resolution " << h;
    if (h == 0.5) {
      error_coarse = error;
    } else {
      EXPECT_LT(error, error_coarse / 2);
    }
    // Extents on the rays, each within half a spacing of the ball's centre
    // across it: the depth within the ball's rise h/√2 off its bottom, the
    // width within the section's on the rays nearest the top face (h/2
    // below it, h/2 off the centre along the feed).
    const double below = R - depth + h / 2;
    EXPECT_LE(r.moves[1].axial_mm, depth + 1e-6);
    EXPECT_GE(r.moves[1].axial_mm, depth - (R - std::sqrt(R * R - h * h / 2)) - 1e-6);
    EXPECT_LE(r.moves[1].radial_mm, 2 * w + 1e-6);
    EXPECT_GE(r.moves[1].radial_mm, 2 * std::sqrt(R * R - below * below - h * h / 4) - 1e-6);
  }
  // At the default step (the resolution) the sampling's scallops, 2 µm
  // high, cost less than 0.1 % of the volume.
  Stock fine(cylinder_blank(30, 0, 20), {0.25}), coarse(cylinder_blank(30, 0, 20), {0.25});
  const double by_fine_steps = fine.cut(moves, ball, o).removed_mm3;
  const double by_default_steps = coarse.cut(moves, ball, {}).removed_mm3;
  EXPECT_LT(by_default_steps, by_fine_steps);
  EXPECT_NEAR(by_default_steps / by_fine_steps, 1, 1e-3);
}

TEST(Stock, HelixOfOverlappingPlunges) {
  // A flat end R 3 plunges at 12 points of a helix (radius 15, 20° apart,
  // each 0.5 mm deeper): neighbouring holes overlap in a lens of area
  // 2R² acos(c/2R) - (c/2) sqrt(4R² - c²), c the chord between centres,
  // as deep as the shallower hole; no three overlap. Between plunges the
  // tool retracts up its axis and moves over the blank (air).
  const double R = 3, rho = 15, top = 20;
  const Tool flat = Tool::flat_end_mill({R, 0.0, 25, {}, {}});
  Stock s(cylinder_blank(30, 0, top), {0.25});
  Toolpath moves;
  double expected = 0, air_expected = 0, path = 0;
  const double c = 2 * rho * std::sin(deg_to_rad(10));
  const double lens = 2 * R * R * std::acos(c / (2 * R)) - 0.5 * c * std::sqrt(4 * R * R - c * c);
  Vec3 last(rho, 0, top + 2);
  moves.push_back(rapid_to(last));
  for (int k = 0; k < 12; ++k) {
    const double a = deg_to_rad(20.0 * k), depth = 4 + 0.5 * k;
    const Vec3 above(rho * std::cos(a), rho * std::sin(a), top + 2), bottom(above.x(), above.y(), top - depth);
    if (k > 0) {
      moves.push_back(feed(above));  // over the blank: air
      air_expected += (above - last).norm();
      path += (above - last).norm();
    }
    moves.push_back(feed(bottom));  // 2 mm of air, then the plunge
    moves.push_back(feed(above));   // the retract, up the hole: air
    air_expected += 2 + depth + 2;
    path += 2 * (depth + 2);
    last = above;
    expected += kPi * R * R * depth - (k > 0 ? lens * (depth - 0.5) : 0);
  }
  const CutResult r = s.cut(moves, flat, {});
  EXPECT_NEAR(r.removed_mm3 / expected, 1, 2e-3);
  EXPECT_NEAR(r.cut_mm, path, 1e-9);
  // Air within a step (0.25 mm) of the 2 mm over the top on each plunge.
  EXPECT_NEAR(r.air_cut_mm, air_expected, 12 * 0.25);
  EXPECT_EQ(r.body_contact_moves, 0);
  // A plunge's engagement: its depth of cut per sample step is the step
  // (0.25 mm), the first hole's section π R² removed per mm.
  EXPECT_NEAR(r.moves[1].rate_max_mm2, kPi * R * R, 0.01 * kPi * R * R);
  EXPECT_NEAR(r.moves[1].axial_mm, 0.25, 1e-3);
}

TEST(Stock, MovesAboveTheBlankCutAir) {
  Stock s(cylinder_blank(30, 0, 20), {0.5});
  const Tool ball = Tool::ball_end_mill({4, 20, {8, 30}, {}});
  // A 5-axis move, the axis turning 30°, the ball's lowest point 0.1 mm
  // above the top at both ends (the tip rises by R (1 - cos 30°) as the
  // ball's centre rises over it) and higher between: all air.
  const Vec3 tilted(std::sin(deg_to_rad(30)), 0, std::cos(deg_to_rad(30)));
  const double rise = 4 * (1 - tilted.z());
  const CutResult r = s.cut({feed({-20, -5, 20.1}), feed({25, 10, 20.1 + rise}, tilted)}, ball, {});
  const double length = Vec3(45, 15, rise).norm();
  EXPECT_EQ(r.removed_mm3, 0);
  EXPECT_NEAR(r.air_cut_mm, length, 1e-9);
  EXPECT_NEAR(r.cut_mm, length, 1e-9);
  EXPECT_EQ(s.volume(), s.blank_volume());
  // 0.2 mm lower it cuts near both ends (the ball's lowest point rises
  // between them), and that much less of the move is air.
  const CutResult low = s.cut({feed({-20, -5, 19.9}), feed({25, 10, 19.9 + rise}, tilted)}, ball, {});
  EXPECT_GT(low.removed_mm3, 0.1);
  EXPECT_LT(low.air_cut_mm, length - 1);
}

TEST(Stock, RapidsAndShanksInTheStockAreReported) {
  Stock s(cylinder_blank(30, 0, 20), {0.5});
  // Flute 5 mm, shank as wide: a slot 8 mm deep runs 3 mm of shank through
  // the stock above the flutes; then a rapid through the blank (a crash).
  const Tool flat = Tool::flat_end_mill({4, 0.5, 5, {8, 40}, {}});
  const CutResult r = s.cut({rapid_to({-40, 0, 12}), feed({0, 0, 12}), rapid_to({0, 20, 12})}, flat, {});
  EXPECT_GT(r.moves[1].body_mm3, 1.0);
  EXPECT_EQ(r.body_contact_moves, 2);
  EXPECT_EQ(r.rapid_cut_moves, 1);
  EXPECT_GT(r.rapid_removed_mm3, 100);
  CutOptions quiet;
  quiet.check_body = false;
  EXPECT_EQ(Stock(cylinder_blank(30, 0, 20), {0.5}).cut({rapid_to({-40, 0, 12}), feed({0, 0, 12})}, flat, quiet).body_contact_moves, 0);
}

TEST(Stock, MaterialAboveASurfacePoint) {
  // A blank whose top is a 45° cone, z = 35 - r: at a point s below it along
  // its normal, the material above is s, at any azimuth.
  const BlankProfile blank({{0, 0}, {30, 0}, {30, 5}, {0, 35}});
  const Stock st(blank, {0.5});
  for (double az : {0.0, 0.5, 1.1, 2.9}) {
    const Vec3 radial(std::cos(az), std::sin(az), 0);
    const Vec3 normal = (radial + Vec3::UnitZ()).normalized();
    const Vec3 on_top = 15 * radial + Vec3(0, 0, 20);
    for (double s : {0.3, 1.0, 2.5}) {
      EXPECT_NEAR(st.material_above(on_top - s * normal, normal), s, 0.01) << "azimuth " << az << " s " << s;
    }
    // Above the surface: negative, the gap to the material.
    EXPECT_NEAR(st.material_above(on_top + 0.4 * normal, normal), -0.4, 0.01);
  }
  EXPECT_TRUE(std::isnan(st.material_above({100, 0, 0}, Vec3::UnitZ())));
  // The flat top, inside the cylinder part: 2.5 below the top face at r < 5.
  const BlankProfile flat_top({{0, 0}, {30, 0}, {30, 20}, {0, 20}});
  EXPECT_NEAR(Stock(flat_top, {0.5}).material_above({1, 2, 17.5}, Vec3::UnitZ()), 2.5, 1e-5);
}

TEST(Stock, ThreadsChangeNoFigure) {
  // The grids are cut side by side: one thread or three, every figure and
  // the state are the same, bit for bit.
  const Tool bull = Tool::flat_end_mill({3, 1, 10, {6, 20}, {}});
  Toolpath moves{rapid_to({-35, -5, 18})};
  for (int k = 0; k < 40; ++k) {
    const double a = 0.15 * k;
    moves.push_back(feed({-30 + 1.5 * k, 8 * std::sin(a), 17 - 0.1 * k},
                         Vec3(0.3 * std::sin(a), 0.2, 1).normalized()));
  }
  std::vector<CutResult> results;
  std::vector<double> volumes;
  for (int threads : {1, 3}) {
    Stock s(cylinder_blank(30, 0, 20), {0.5});
    CutOptions o;
    o.threads = threads;
    results.push_back(s.cut(moves, bull, o));
    volumes.push_back(s.volume());
  }
  EXPECT_GT(results[0].samples, 64);  // enough placements for the threads to be used
  EXPECT_EQ(volumes[0], volumes[1]);
  ASSERT_EQ(results[0].moves.size(), results[1].moves.size());
  for (size_t m = 0; m < moves.size(); ++m) {
    EXPECT_EQ(results[0].moves[m].removed_mm3, results[1].moves[m].removed_mm3) << "move " << m;
    EXPECT_EQ(results[0].moves[m].air_mm, results[1].moves[m].air_mm) << "move " << m;
    EXPECT_EQ(results[0].moves[m].radial_mm, results[1].moves[m].radial_mm) << "move " << m;
  }
}

TEST(Stock, BadMovesAndGridsAreRefused) {
  Stock s(cylinder_blank(30, 0, 20), {0.5});
  const Tool ball = Tool::ball_end_mill({4, 20, {}, {}});
  EXPECT_THROW(s.cut({feed({0, 0, 30}), feed({0, 0, std::nan("")})}, ball, {}), ParameterError);
  EXPECT_THROW(s.cut({feed({0, 0, 30}), feed({0, 0, 30}, -Vec3::UnitZ())}, ball, {}), ParameterError);
  EXPECT_THROW(s.cut({feed({0, 0, 30}), feed({1e7, 0, 30})}, ball, {}), ParameterError);  // 2·10^7 samples
  CutOptions o;
  o.threads = 0;
  EXPECT_THROW(s.cut({feed({0, 0, 30})}, ball, o), ParameterError);
  EXPECT_EQ(s.volume(), s.blank_volume());
  // 10^11 rays.
  EXPECT_THROW(Stock(cylinder_blank(1e4, 0, 1e3), {0.05}), ParameterError);
}

// Even-odd point-in-polygon, the blank's meridian without BlankProfile.
bool in_polygon(const std::vector<Vec2>& poly, const Vec2& q) {
  bool in = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2 &a = poly[i], &b = poly[j];
    if ((a.y() > q.y()) != (b.y() > q.y()) && q.x() < a.x() + (q.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y())) {
      in = !in;
    }
  }
  return in;
}

// The tool's cutter contains p at pose (independent of the stock's ray
// intersection: core/tools' exact signed distance).
bool in_cutter(const Tool& tool, const ToolPose& pose, const Vec3& p) {
  const Vec3 d = p - pose.tip;
  const double z = d.dot(pose.axis);
  const double r = (d - z * pose.axis).norm();
  return tool.cutter().signed_distance(Vec2(r, z)) <= 0;
}

TEST(Stock, StateAfterAFiveAxisSequenceAgainstBruteForce) {
  // A ring blank with a chamfer; a ball end and a bull-nose mill, tilted
  // axes turning within moves. Every ray of the three grids is sampled at
  // 0.02 mm: a sample is material if it is in the blank and in no sampled
  // tool position (the model's own samples: ceil(speed / step) per move).
  const std::vector<Vec2> meridian{{3, 0}, {12, 0}, {12, 7}, {10, 9}, {3, 9}};
  const BlankProfile blank(meridian);
  const double h = 0.5;
  Stock stock(blank, {h});
  const Tool ball = Tool::ball_end_mill({2.5, 12, {}, {}});
  const Tool bull = Tool::flat_end_mill({3, 1, 10, {}, {}});
  const auto axis = [](double tilt_deg, double az_deg) {
    const double t = deg_to_rad(tilt_deg), a = deg_to_rad(az_deg);
    return Vec3(std::sin(t) * std::cos(a), std::sin(t) * std::sin(a), std::cos(t));
  };
  struct Pass {
    const Tool* tool;
    Toolpath moves;
  };
  std::vector<Pass> passes{
      {&ball, {rapid_to({-14, -3, 7}, axis(20, 0)), feed({-6, -4, 6.5}, axis(20, 0)), feed({4, 2, 6}, axis(35, 60)),
               feed({9, 8, 7.5}, axis(10, 120))}},
      {&bull, {rapid_to({14, -9, 8}, axis(15, 200)), feed({6, -6, 7}, axis(25, 180)), feed({-3, -10, 7.5}, axis(5, 90)),
               feed(Vec3(-3, -10, 7.5) - 3.5 * axis(5, 90), axis(5, 90))}}};
  CutOptions o;
  o.step_mm = 0.3;
  std::vector<std::vector<ToolPose>> positions(passes.size());
  for (size_t p = 0; p < passes.size(); ++p) {
    stock.cut(passes[p].moves, *passes[p].tool, o);
    const auto& mv = passes[p].moves;
    positions[p].push_back(mv[0].pose);
    for (size_t m = 1; m < mv.size(); ++m) {
      const PoseMotion motion(mv[m - 1].pose, mv[m].pose);
      const int n = static_cast<int>(std::ceil(motion.max_point_speed(passes[p].tool->cutter().reach()) / o.step_mm));
      for (int k = 1; k <= n; ++k) positions[p].push_back(motion.pose_at(static_cast<double>(k) / n));
    }
  }
  // The last move is a plunge along the axis, which the model sweeps
  // exactly; the brute force's positions 0.3 mm apart cover the same (the
  // bull-nose's side is a cylinder longer than the step, and the corner is
  // only the last position's).
  const double dt = 0.02;
  double worst = 0, total_model = 0, total_brute = 0;
  for (int k = 0; k < 3; ++k) {
    const DexelGrid& g = stock.grid(k);
    const Vec3 dir = g.direction();
    for (int j = 0; j < g.nv; ++j) {
      for (int i = 0; i < g.nu; ++i) {
        const Vec3 origin = g.origin(i, j);
        // The positions whose bounding capsule (the cutter's widest radius
        // about its axis segment) the ray crosses, with the stretch of the
        // ray it can hold.
        struct Near {
          const Tool* tool;
          const ToolPose* pose;
          double t0, t1;
        };
        std::vector<Near> near;
        for (size_t q = 0; q < passes.size(); ++q) {
          const Profile& cutter = passes[q].tool->cutter();
          const double radius = cutter.max_radius(), length = cutter.z_max();
          for (const ToolPose& pose : positions[q]) {
            const auto across = [&](const Vec3& v) { return Vec3(v - v.dot(dir) * dir); };
            const Vec3 p0 = across(pose.tip - origin), p1 = across(pose.axis);
            const double s = p1.squaredNorm() > 1e-12 ? std::clamp(-p0.dot(p1) / p1.squaredNorm(), 0.0, length) : 0.0;
            if ((p0 + s * p1).norm() > radius) continue;
            const double ta = (pose.tip - origin).dot(dir), tb = ta + length * pose.axis.dot(dir);
            near.push_back({passes[q].tool, &pose, std::min(ta, tb) - radius, std::max(ta, tb) + radius});
          }
        }
        int inside = 0;
        // The blank spans z 0..9 and r up to 12 (the grids' rays run from
        // coordinate -12.5 or -0.5).
        const double t_first = k == 2 ? -0.5 : -12.5, t_last = k == 2 ? 9.5 : 12.5;
        for (double t = t_first + dt / 2; t < t_last; t += dt) {
          const Vec3 p = origin + t * dir;
          bool material = in_polygon(meridian, Vec2(std::hypot(p.x(), p.y()), p.z()));
          for (const Near& n : near) {
            if (!material) break;
            if (t >= n.t0 && t <= n.t1 && in_cutter(*n.tool, *n.pose, p)) material = false;
          }
          inside += material;
        }
        const double brute = inside * dt, model = g.ray(i, j).length();
        worst = std::max(worst, std::abs(brute - model));
        total_model += model;
        total_brute += brute;
      }
    }
  }
  // Each ray within a few samples (a span's ends are each within dt/2, up to
  // four spans; the bull-nose's torus within its 2 µm tangent polygon).
  EXPECT_LT(worst, 4 * dt + 0.005);
  EXPECT_NEAR(total_model / total_brute, 1, 2e-3);
  // The stock's volume is the mean of the three grids' ray sums.
  EXPECT_NEAR(stock.volume(), total_model * h * h / 3, 1e-6 * stock.volume());
  EXPECT_LT(stock.volume(), stock.blank_volume() - 50);
}

// The job's stock verdict (scripts/lib/job/stock.lua, issue 41): a job's
// moves cut a small blank through Job:cut_stock as a planned job's would —
// operation 1 a slot 2 mm deep with the flutes (clean), operation 2 a rapid
// diagonally through the blank, operation 3 a plunge 8 mm deep with 5 mm of
// flute and a step sideways there (the shank in the stock). The rapid is turned into a feed at its
// operation's rate from 1 mm before the stock on (the part before it a
// rapid in air, posted apart: the cycle time drops); the shank FAILs the verdict, naming
// operation 3 and its move count; operation 1 alone PASSes with its stock
// requirements measured 0. A rapid left in the stock (the figures of a
// stock:cut, as the job would have them) FAILs it, naming the operation.
const char* kStockVerdictRecipe = R"LUA(
local Job = require("job.model").Job
local stock_report = require("job.stock")
local run_report = require("run_report")
local flat = bliskrun.flat_end_mill{radius = 4, corner_radius = 0.5, flute_length = 5, shank = {diameter = 8, length = 40}}
local up = {0, 0, 1}
local profile = {{0, 0}, {20, 0}, {20, 10}, {0, 10}}
local function mv(op, kind, x, y, z) return {operation = op, tool = 1, kind = kind, tip = {x, y, z}, axis = up} end
local function verdict(moves, ops)
  local j = setmetatable({blank = {profile = profile, resolution = 1}, operations = ops,
                          tools = {{number = 1, tool = flat}}}, Job)
  local r = {planned = {moves = moves}}
  r.planned.stock = j:cut_stock(r.planned)
  return run_report.verdict(stock_report.requirements(r, {})), r.planned.stock
end
local slot = {mv(1, "rapid", -30, 0, 15), mv(1, "rapid", -30, 0, 8), mv(1, "feed", 30, 0, 8), mv(1, "rapid", 30, 0, 15)}
local clean, st = verdict(slot, {{kind = "rough_channels", feed = 900}})
assert(st.operations[1].removed_mm3 > 100, "the slot cuts")
assert(clean.overall == "PASS" and #clean.requirements == 2, run_report.failures(clean))
for _, q in ipairs(clean.requirements) do assert(q.measured == 0 and q.at_most == 0, q.name) end
local all = table.move(slot, 1, #slot, 1, {})
for _, m in ipairs({mv(2, "rapid", 30, 10, 15), mv(2, "rapid", -30, 10, 6), mv(2, "rapid", -30, -10, 15),
                    mv(3, "rapid", 0, -10, 15), mv(3, "feed", 0, -10, 2), mv(3, "feed", 10, -10, 2),
                    mv(3, "feed", 10, -10, 15)}) do
  all[#all + 1] = m
end
local ops = {{kind = "rough_channels", feed = 900}, {kind = "drum_finish", feed = 500}, {kind = "hub_finish", feed = 700}}
local bad, st2 = verdict(all, ops)
assert(all[6].kind == "feed" and all[6].feed == 500 and all[5].kind == "rapid" and all[7].kind == "rapid",
       "the rapid through the stock, and only it, turned into a feed")
assert(st2.rapids_fed == 1 and st2.operations[2].rapid_cut_moves == 0 and st2.operations[2].removed_mm3 > 50)
-- Fed from where it meets the stock on: its flat bottom reaches the
-- blank's top (z = 10; the slot at y = 0 is 6 mm away) at t = 5/9 of its
-- way from (30, 10, 15) to (-30, 10, 6), so it is a rapid up to 1 mm of tip
-- path before that (the entry bisected to 0.01 mm) and a feed on.
local d = math.sqrt(60 ^ 2 + 9 ^ 2)
local t = 5 / 9 - 1 / d
local split = all[6].rapid_to
assert(split and math.abs(split.tip[3] - (15 - 9 * t)) < 0.01 and math.abs(split.tip[1] - (30 - 60 * t)) < 0.05
       and split.tip[2] == 10 and split.axis[3] == 1, "split at the stock")
assert(math.abs(st2.fed[1].rapid_mm - t * d) < 0.02 and math.abs(st2.fed[1].length_mm - d) < 1e-9)
-- Independently: from the stock operation 1 left, the rapid part cuts
-- nothing, cutter, shank or holder; 0.1 mm past the feed's 1 mm it would.
local after_slot = bliskrun.stock{profile = profile, resolution = 1}
after_slot:cut(slot, flat)
local function cut_to(tt)
  local to = {kind = "rapid", tip = {30 - 60 * tt, 10, 15 - 9 * tt}, axis = up}
  return after_slot:copy():cut({mv(2, "rapid", 30, 10, 15), to}, flat)
end
local air = after_slot:copy():cut({mv(2, "rapid", 30, 10, 15), {kind = "rapid", tip = split.tip, axis = split.axis}}, flat)
assert(air.removed_mm3 == 0 and air.rapid_cut_moves == 0 and air.body_contact_moves == 0, "the rapid part is in air")
assert(cut_to(t + 1.1 / d).removed_mm3 > 0, "the feed starts within 1.1 mm of the stock")
-- Posted (j:program_path): the part in air a rapid of its own before the
-- feed; the posted cycle time's cutting drops by that part at the feed
-- rate (32.7 mm at 500 mm/min: 3.9 s), the positioning grows by less.
-- The way in and out of the program are the job's (proved against its
-- part), not under test here.
for _, m in ipairs(all) do if m.kind == "feed" then m.feed = m.feed or ops[m.operation].feed end end
local j = setmetatable({operations = ops, name = "split rapid", planned = {moves = all},
                        tools = {{number = 1, tool = flat, length = 80, spindle_rpm = 10000}},
                        clearance_surface = {contains = function() return false end}, prove_motion = function() end}, Job)
require("job")
local path = j:program_path({machine = "dmg_like_ac_trunnion", post = "fanuc", file = "split.nc"}, 1)
assert(#path == #all + 1 and path[6].kind == "rapid" and path[6].tip == split.tip and path[7] == all[6], "posted split")
local split_cycle = j:post{machine = "dmg_like_ac_trunnion", post = "fanuc", file = "split.nc",
                          machine_check = false}.cycle_time
all[6].rapid_to = nil
local whole_cycle = j:post{machine = "dmg_like_ac_trunnion", post = "fanuc", file = "whole.nc",
                          machine_check = false}.cycle_time
local saved = 60 * st2.fed[1].rapid_mm / 500
assert(math.abs(whole_cycle.cut_s - split_cycle.cut_s - saved) < 0.05 * saved
       and split_cycle.rapid_s > whole_cycle.rapid_s and split_cycle.total_s < whole_cycle.total_s - 0.5 * saved,
       string.format("cycle: split %.2f s (cut %.2f), whole %.2f s (cut %.2f)", split_cycle.total_s, split_cycle.cut_s,
                     whole_cycle.total_s, whole_cycle.cut_s))
local function has(text, what) return text:find(what, 1, true) ~= nil end
local why = run_report.failures(bad)
assert(bad.overall == "FAIL" and has(why, "operation 3 (hub finish): shank or holder in the stock (moves) ")
       and not has(why, "operation 1 (") and not has(why, "operation 2 (") and not has(why, "rapids through"), why)
-- A rapid in the stock as stock:cut reports it, in the job's figures.
local raw = bliskrun.stock{profile = profile, resolution = 1}:cut({mv(2, "rapid", 30, 10, 15), mv(2, "rapid", -30, 10, 6)}, flat)
local e = {operation = 2, kind = "drum_finish", rapid_cut_moves = raw.rapid_cut_moves,
           rapid_removed_mm3 = raw.rapid_removed_mm3, body_contact_moves = raw.body_contact_moves,
           body_contact_max_mm3 = raw.body_contact_max_mm3}
local crash = run_report.verdict(stock_report.requirements({planned = {stock = {operations = {e}}}}, {}))
why = run_report.failures(crash)
assert(crash.overall == "FAIL" and has(why, "operation 2 (drum finish): rapids through the stock (moves) 1 count")
       and not has(why, "shank"), why)
)LUA";

TEST(Stock, JobVerdictFailsOnARapidOrAShankInTheStock) {
  test::TempDir dir;
  const test::RecipeResult r = test::run_recipe_text(dir, kStockVerdictRecipe);
  EXPECT_EQ(r.exit_code, 0) << r.output;  // the recipe asserts the verdicts (the sandbox has no io)
}

}  // namespace
}  // namespace bliskrun
