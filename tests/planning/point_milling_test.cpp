// Point milling (issue 40): the scallop measurement against the closed form
// on a cylinder and a sphere; the planner's rows on a twisted, cambered face
// checked by brute force (every sample of the face under the swept balls of
// every emitted pose, every chord of the exact centre path); the tilt
// clearing a ledge beside the face, every pose checked against the ledge by
// an independent distance test (the tool's radius along its axis against
// the box), and a ledge no axis clears refused, not emitted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

#include "core/common/error.h"
#include "core/geometry/mesh.h"
#include "core/planning/point_milling.h"
#include "core/planning/repair_paths.h"

namespace bliskrun {
namespace {

// A cambered, twisted face: span z = H u, chord c = C (v - 1/2), camber
// y0 = A sin(pi v), the section turned by T u about Z. pu x pv points to +y
// (the camber's convex side) at u = 0.
class PointTwistedFace : public Surface {
 public:
  PointTwistedFace(double H, double C, double A, double T) : H_(H), C_(C), A_(A), T_(T) {}
  SurfaceDerivs eval(double u, double v) const override {
    const double th = T_ * u, c = std::cos(th), s = std::sin(th);
    const double ch = C_ * (v - 0.5), y0 = A_ * std::sin(kPi * v);
    const double y0v = A_ * kPi * std::cos(kPi * v), y0vv = -A_ * kPi * kPi * std::sin(kPi * v);
    SurfaceDerivs d;
    d.p = Vec3(ch * c - y0 * s, ch * s + y0 * c, H_ * u);
    d.pu = Vec3(-T_ * d.p.y(), T_ * d.p.x(), H_);
    d.pv = Vec3(C_ * c - y0v * s, C_ * s + y0v * c, 0);
    d.puu = Vec3(-T_ * T_ * d.p.x(), -T_ * T_ * d.p.y(), 0);
    d.puv = Vec3(-T_ * d.pv.y(), T_ * d.pv.x(), 0);
    d.pvv = Vec3(-y0vv * s, y0vv * c, 0);
    return d;
  }

 private:
  double H_, C_, A_, T_;
};

Tool point_tool() {
  // r 1.5 ball, 2.5 deg taper, 30 mm flute, shank d 8 x 30, holder d 32 x 40.
  return Tool::tapered_ball_end_mill({1.5, 2.5 * kPi / 180, 30, {8, 30}, {32, 40}});
}

// Two rows of ball centres on a cylinder of radius R (axis Z) at angles
// +-phi, offset r out of (convex) or into (concave) it; the scallop
// measured on the cylinder between them.
double cylinder_scallop(double R, double r, double phi, bool convex) {
  const double rc = convex ? R + r : R - r;
  std::vector<Vec3> a, b, pts, nrm;
  for (int i = 0; i <= 40; ++i) {
    const double z = -2 + 4.0 * i / 40;
    a.emplace_back(rc * std::cos(-phi), rc * std::sin(-phi), z);
    b.emplace_back(rc * std::cos(phi), rc * std::sin(phi), z);
  }
  for (int i = 0; i <= 200; ++i) {
    const double t = -phi + 2 * phi * i / 200;
    const Vec3 radial(std::cos(t), std::sin(t), 0);
    pts.push_back(R * radial);
    nrm.push_back(convex ? radial : Vec3(-radial));
  }
  return measured_scallop_mm(a, b, 1.5 * r / 1.5, pts, nrm);
}

TEST(PointMillingScallop, CylinderMatchesClosedForm) {
  const double r = 1.5, h = 0.005;
  for (double R : {20.0, 5.0}) {
    for (bool convex : {true, false}) {
      const double k = convex ? 1 / R : -1 / R;
      const double step = ball_step_over(h, r, k);  // along the surface
      const double phi = 0.5 * step / R;
      const double measured = cylinder_scallop(R, r, phi, convex);
      // The rows' balls are swept every 0.05 mm and the samples are 200
      // across: both err by far less than 0.1 um here.
      EXPECT_NEAR(measured, h, 1e-4) << "R " << R << (convex ? " convex" : " concave");
    }
  }
  // And on a plane the step is 2 sqrt(2 r h - h^2).
  EXPECT_NEAR(ball_step_over(h, r, 0), 2 * std::sqrt(2 * r * h - h * h), 1e-9);
}

TEST(PointMillingScallop, SphereMatchesClosedForm) {
  // Rows along two meridians of a sphere of radius R, at longitudes +-phi:
  // at the equator they are R 2 phi apart along the surface, and the sphere's
  // normal curvature across them is 1/R, as the closed form assumes.
  const double R = 12, r = 1.5, h = 0.004;
  const double step = ball_step_over(h, r, 1 / R);
  const double phi = 0.5 * step / R, rc = R + r;
  std::vector<Vec3> a, b, pts, nrm;
  for (int i = 0; i <= 200; ++i) {
    const double lat = -0.3 + 0.6 * i / 200;
    a.emplace_back(rc * std::cos(lat) * std::cos(-phi), rc * std::cos(lat) * std::sin(-phi), rc * std::sin(lat));
    b.emplace_back(rc * std::cos(lat) * std::cos(phi), rc * std::cos(lat) * std::sin(phi), rc * std::sin(lat));
  }
  for (int i = 0; i <= 100; ++i) {  // across the gap at the equator
    const double t = -phi + 2 * phi * i / 100;
    const Vec3 n(std::cos(t), std::sin(t), 0);
    pts.push_back(R * n);
    nrm.push_back(n);
  }
  EXPECT_NEAR(measured_scallop_mm(a, b, r, pts, nrm), h, 1e-4);
  // Away from the equator the meridians close in: less is left there.
  std::vector<Vec3> p2, n2;
  for (int i = 0; i <= 100; ++i) {
    const double t = -phi + 2 * phi * i / 100, lat = 0.25;
    const Vec3 n(std::cos(lat) * std::cos(t), std::cos(lat) * std::sin(t), std::sin(lat));
    p2.push_back(R * n);
    n2.push_back(n);
  }
  EXPECT_LT(measured_scallop_mm(a, b, r, p2, n2), h);
}

PointMillRequest twisted_request(const std::shared_ptr<const Surface>& face, const Tool& tool) {
  PointMillRequest rq;
  rq.face = {"twisted face", face, false};
  rq.tool = &tool;
  rq.scallop_mm = 0.01;
  rq.steps.chord_tol_mm = 0.005;
  // Above the chord tolerance: a chord inside a convex row cuts that deep.
  rq.allowed_overcut_mm = 0.01;
  rq.threads = 2;
  return rq;
}

TEST(PointMilling, TwistedFaceScallopAndChordBoundEveryRow) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "plans ~1000 poses with gouge proofs: several seconds in Release, minutes sanitized";
#endif
  const auto face = std::make_shared<const PointTwistedFace>(15, 25, 3, 0.3);
  const Tool tool = point_tool();
  const PointMillRequest rq = twisted_request(face, tool);
  const PointMillResult res = plan_point_milling(rq);
  ASSERT_TRUE(res.complete()) << res.refusals.size() << " refusals, " << res.refused_connections
                              << " refused connections; first: "
                              << (res.refusals.empty() ? std::string() : res.refusals.front().reason);
  const double r = res.ball_radius_mm;
  EXPECT_NEAR(r, 1.5, 1e-6);
  // The hub-side boundary: the first row's contacts r above u = 0.
  EXPECT_NEAR(res.first_row_u, 1.5 / 15.0, 1e-3);
  EXPECT_LE(res.scallop_max_mm, rq.scallop_mm);
  // Not needlessly tight: the rows leave at least half the allowed scallop.
  EXPECT_GT(res.scallop_max_mm, 0.5 * rq.scallop_mm);

  // Brute force: the face sampled on a 0.1 mm grid between the first and the
  // last row, each sample under every emitted pose's ball swept along its
  // pass (hashed by 2 mm cells).
  std::unordered_map<long long, std::vector<Vec3>> cells;
  auto key = [](const Vec3& p) {
    const long long x = static_cast<long long>(std::floor(p.x() / 2)) + 1000,
                    y = static_cast<long long>(std::floor(p.y() / 2)) + 1000,
                    z = static_cast<long long>(std::floor(p.z() / 2)) + 1000;
    return (x * 4096 + y) * 4096 + z;
  };
  int passes_checked = 0;
  for (const PointMillPass& pass : res.passes) {
    for (size_t i = 0; i < pass.poses.size(); ++i) {
      const PointMillPose& pp = pass.poses[i];
      const Vec3 c = pp.pose.tip + r * pp.pose.axis;
      ASSERT_LT((c - pp.centre).norm(), 1e-6) << "the ball's centre is not where the contact puts it";
      if (i == 0) continue;
      const Vec3 c0 = pass.poses[i - 1].pose.tip + r * pass.poses[i - 1].pose.axis;
      const int n = std::max(1, static_cast<int>(std::ceil((c - c0).norm() / 0.02)));
      for (int k = 0; k <= n; ++k) {
        const Vec3 q = c0 + (c - c0) * (static_cast<double>(k) / n);
        cells[key(q)].push_back(q);
      }
      // Chord: the exact centre path between the stations against the
      // straight segment the centre moves on.
      const PointMillPose& pa = pass.poses[i - 1];
      double dev = 0;
      for (int k = 1; k < 40; ++k) {
        const double v = pa.v + (pp.v - pa.v) * k / 40.0;
        const SurfaceDerivs d = face->eval(pp.u, v);
        const Vec3 q = d.p + r * d.pu.cross(d.pv).normalized();
        const Vec3 seg = c - c0;
        const double t = std::clamp((q - c0).dot(seg) / seg.squaredNorm(), 0.0, 1.0);
        dev = std::max(dev, (q - (c0 + t * seg)).norm());
      }
      EXPECT_LE(dev, res.chord_tol_mm + 1e-5) << "row " << pass.row << " station " << i;
    }
    ++passes_checked;
  }
  EXPECT_EQ(passes_checked, static_cast<int>(res.rows.size()));
  double worst = 0;
  const double u_last = res.passes.back().level;
  for (int i = 0; i <= 120; ++i) {
    const double u = res.first_row_u + (u_last - res.first_row_u) * i / 120.0;
    for (int j = 0; j <= 250; ++j) {
      const SurfaceDerivs d = face->eval(u, 0.01 + 0.98 * j / 250.0);  // ends: the ball rounds off there
      const Vec3 n = d.pu.cross(d.pv).normalized();
      double low = std::numeric_limits<double>::infinity();
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const auto it = cells.find(key(d.p + Vec3(2.0 * dx, 2.0 * dy, 2.0 * dz)));
            if (it == cells.end()) continue;
            for (const Vec3& c : it->second) {
              const Vec3 e = c - d.p;
              const double along = e.dot(n), perp2 = e.squaredNorm() - along * along;
              if (perp2 < r * r) low = std::min(low, along - std::sqrt(r * r - perp2));
            }
          }
      worst = std::max(worst, low);
      ASSERT_GT(low, -rq.allowed_overcut_mm) << "overcut at u " << u << " v " << j;
    }
  }
  // The measured scallop (with the chord's sag between stations: the
  // centre's path may stand off its curve by chord_tol).
  EXPECT_LE(res.chord_tol_mm, rq.steps.chord_tol_mm);
  EXPECT_LE(worst, rq.scallop_mm + res.chord_tol_mm + 1e-4);
  EXPECT_LE(res.max_turn_rad_per_mm, rq.max_turn_rad_per_mm + 1e-9);
}

TEST(PointMilling, RowsAcrossTheFlowRunHubToShroudWithinTheScallop) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "a plan with gouge proofs: a second in Release, a minute sanitized";
#endif
  const auto face = std::make_shared<const PointTwistedFace>(15, 25, 3, 0.3);
  const Tool tool = point_tool();
  PointMillRequest rq = twisted_request(face, tool);
  rq.rows = PointMillRows::AcrossFlow;
  rq.scallop_mm = 0.03;
  rq.v0 = 0.3, rq.v1 = 0.5;
  const PointMillResult res = plan_point_milling(rq);
  ASSERT_TRUE(res.complete());
  EXPECT_LE(res.scallop_max_mm, rq.scallop_mm);
  EXPECT_GT(res.scallop_max_mm, 0.5 * rq.scallop_mm);
  // Each pass at constant v, its contacts from the hub-side boundary to the
  // shroud (or back, zigzag), the axis up the span.
  for (const PointMillPass& pass : res.passes) {
    for (const PointMillPose& pp : pass.poses) {
      EXPECT_NEAR(pp.v, pass.level, 1e-12);
      EXPECT_GE(pp.u, res.first_row_u - 1e-12);
      EXPECT_GT(pp.pose.axis.z(), 0.5);
    }
  }
  EXPECT_NEAR(res.passes.front().level, 0.3, 1e-12);
  EXPECT_NEAR(res.passes.back().level, 0.5, 1e-12);
}

// A plane face x = C (v - 1/2), y = Y, z = H u; pu x pv = +y, out of the material.
class PointStripPlane : public Surface {
 public:
  PointStripPlane(double H, double C, double Y = 0) : H_(H), C_(C), Y_(Y) {}
  SurfaceDerivs eval(double u, double v) const override {
    SurfaceDerivs d;
    d.p = Vec3(C_ * (v - 0.5), Y_, H_ * u);
    d.pu = Vec3(0, 0, H_);
    d.pv = Vec3(C_, 0, 0);
    d.puu = d.puv = d.pvv = Vec3::Zero();
    return d;
  }

 private:
  double H_, C_, Y_;
};

// Brute force: the largest and the mean distance from the face's samples at
// (u, v) to the balls of every emitted pass, the centres sub-sampled every
// 0.01 mm.
struct PointStripBruteForce {
  double worst = -std::numeric_limits<double>::infinity(), mean = 0;
};
PointStripBruteForce point_strip_brute_force(const Surface& face, const PointMillResult& res, const std::vector<Vec2>& uv) {
  const double r = res.ball_radius_mm;
  PointStripBruteForce out;
  for (const Vec2& q : uv) {
    const Vec3 p = face.eval(q.x(), q.y()).p;
    double best = std::numeric_limits<double>::infinity();
    for (const PointMillPass& pass : res.passes)
      for (size_t k = 0; k < pass.poses.size(); ++k) {
        const Vec3 a = k ? pass.poses[k - 1].centre : pass.poses[k].centre, b = pass.poses[k].centre;
        const int n = 1 + static_cast<int>((b - a).norm() / 0.01);
        for (int m = 0; m <= n; ++m) best = std::min(best, (p - (a + (b - a) * m / n)).norm() - r);
      }
    out.worst = std::max(out.worst, best);
    out.mean += best / static_cast<double>(uv.size());
  }
  return out;
}

// The root strip the rows stop above (issue 40): its height is hub_stop's,
// and the material the ball leaves in it is what a brute force finds (every
// emitted pass, the centre sub-sampled every 0.01 mm between poses, against
// every strip sample) and, on a plane, the closed form: a point d below the
// first row's contact is sqrt(d^2 + r^2) - r from the ball.
TEST(PointMilling, RootStripHeightIsTheHubStopAndItsMaterialIsMeasured) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "a plan with gouge proofs: a second in Release, a minute sanitized";
#endif
  const double H = 15, C = 10;
  const auto face = std::make_shared<const PointStripPlane>(H, C);
  const Tool tool = point_tool();
  PointMillRequest rq = twisted_request(face, tool);
  rq.scallop_mm = 0.05;
  const double r = 1.5, stop = 3 * r;
  rq.hub_stop_mm = stop;
  rq.u1 = (stop + 3) / H;
  const PointMillResult res = plan_point_milling(rq);
  ASSERT_TRUE(res.complete());
  const int su = 6, sv = 21;
  const PointMillStrip st = measure_root_strip(rq, res, su, sv);
  EXPECT_NEAR(st.u1, stop / H, 1e-12);
  EXPECT_NEAR(st.height_mm, stop, 1e-9);
  EXPECT_NEAR(st.height_min_mm, stop, 1e-9);
  EXPECT_EQ(st.samples, su * sv);
  // Closed form: the largest at the window's edge, a full stop below the row.
  EXPECT_NEAR(st.material_max_mm, std::sqrt(stop * stop + r * r) - r, 1e-3);
  EXPECT_NEAR(st.max_u, 0, 1e-12);
  // Brute force over the same samples.
  std::vector<Vec2> uv;
  for (int i = 0; i < su; ++i)
    for (int j = 0; j < sv; ++j) uv.emplace_back(st.u1 * i / su, static_cast<double>(j) / (sv - 1));
  const PointStripBruteForce brute = point_strip_brute_force(*face, res, uv);
  EXPECT_NEAR(st.material_max_mm, brute.worst, 1e-4);
  EXPECT_NEAR(st.material_mean_mm, brute.mean, 1e-4);
  // Far beyond any finishing tolerance: the strip is not finished by these rows.
  EXPECT_GT(st.material_max_mm, 1.0);
}

// The plane face at y = 30 (PointStripPlane) standing square on a flat hub:
// the annulus z = 0, 10 < rho < 60, as a surface of revolution about Z (its
// normal +z, into the channel).
std::shared_ptr<const SurfaceOfRevolution> point_flat_hub() {
  std::vector<Vec2> m;
  for (int i = 0; i <= 10; ++i) m.emplace_back(0.0, 10.0 + 5.0 * i);
  return std::make_shared<const SurfaceOfRevolution>(m);
}

// Issue 40, the root strip finished: with the hub, the rows are carried down
// to the fillet line (the first row's ball touches face and hub: contact r
// above a square corner), so the band up to the hub stop (3 r) is milled
// within the scallop; the same request stopping at the hub stop (main's
// behaviour) leaves r (sqrt(5) - 1) at the fillet line (closed form: that
// point is r off and 2 r below the first row's centre). Below the fillet
// line the corner keeps the ball's fillet: (sqrt(2) - 1) r at the hub.
TEST(PointMilling, RowsCarriedDownToTheFilletFinishTheRootStrip) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "two plans with gouge proofs: a second in Release, a minute sanitized";
#endif
  const double H = 15, C = 10, r = 1.5, stop = 3 * r;
  const auto face = std::make_shared<const PointStripPlane>(H, C, 30);
  const Tool tool = point_tool();
  PointMillRequest rq = twisted_request(face, tool);
  rq.scallop_mm = 0.02;
  rq.hub_stop_mm = stop;
  rq.u1 = (stop + 3) / H;
  rq.hub = point_flat_hub();
  const int su = 6, sv = 11;

  rq.follow_fillet = false;
  const PointMillResult stopped = plan_point_milling(rq);
  ASSERT_TRUE(stopped.complete());
  EXPECT_FALSE(stopped.follows_fillet);
  const PointMillStrip before = measure_root_strip(rq, stopped, su, sv);
  EXPECT_TRUE(before.from_fillet);
  EXPECT_NEAR(before.u0, r / H, 1e-9);  // the fillet line: contact r above the square corner
  EXPECT_NEAR(before.u1, stop / H, 1e-12);
  EXPECT_NEAR(before.height_mm, stop - r, 1e-6);
  EXPECT_NEAR(before.material_max_mm, r * (std::sqrt(5.0) - 1), 1e-3);
  EXPECT_GT(before.material_max_mm, 0.05);  // beyond any face tolerance: main's FAIL

  rq.follow_fillet = true;
  const PointMillResult res = plan_point_milling(rq);
  ASSERT_TRUE(res.complete()) << (res.refusals.empty() ? "" : res.refusals.front().reason);
  EXPECT_TRUE(res.follows_fillet);
  EXPECT_NEAR(res.fillet_u_min, r / H, 1e-9);
  EXPECT_NEAR(res.fillet_u_max, r / H, 1e-9);
  EXPECT_LE(res.scallop_max_mm, rq.scallop_mm);
  // Every pose: the ball on the face, no deeper into the hub than allowed
  // (its centre's height less r is its depth below z = 0), its axis up.
  double lowest = std::numeric_limits<double>::infinity();
  for (const PointMillPass& pass : res.passes)
    for (const PointMillPose& pp : pass.poses) {
      const Vec3 c = pp.pose.tip + r * pp.pose.axis;
      EXPECT_NEAR(c.y(), 30 + r, 1e-6);
      EXPECT_GE(c.z() - r, -rq.allowed_overcut_mm);
      EXPECT_GE(pp.u, r / H - 1e-9);
      EXPECT_GT(pp.pose.axis.z(), 0.5);
      lowest = std::min(lowest, c.z());
    }
  EXPECT_NEAR(lowest, r, 1e-6);  // the first row touches the hub
  const PointMillStrip after = measure_root_strip(rq, res, su, sv);
  EXPECT_NEAR(after.u0, r / H, 1e-9);
  ASSERT_EQ(after.lower_u.size(), static_cast<size_t>(sv));
  for (double u : after.lower_u) EXPECT_NEAR(u, r / H, 1e-9);  // the fillet line at every column
  EXPECT_NEAR(after.height_mm, before.height_mm, 1e-9);  // the same band
  EXPECT_EQ(after.samples, su * sv);
  // Brute force over the same samples.
  std::vector<Vec2> band, corner;
  for (int i = 0; i < su; ++i)
    for (int j = 0; j < sv; ++j) {
      const double v = static_cast<double>(j) / (sv - 1);
      band.emplace_back(r / H + (stop - r) / H * i / su, v);
      corner.emplace_back(r / H * i / su, v);
    }
  EXPECT_NEAR(after.material_max_mm, point_strip_brute_force(*face, res, band).worst, 1e-4);
  // Within the scallop (and the chord's sag), far inside 0.05 mm.
  EXPECT_LE(after.material_max_mm, rq.scallop_mm + res.chord_tol_mm + 1e-4);
  // The corner: the fillet row's ball leaves (sqrt(2) - 1) r at the hub.
  EXPECT_NEAR(after.corner_max_mm, (std::sqrt(2.0) - 1) * r, 1e-3);
  EXPECT_NEAR(after.corner_u, 0, 1e-12);
  EXPECT_NEAR(after.corner_max_mm, point_strip_brute_force(*face, res, corner).worst, 1e-4);
}

// Distance from q to the box [lo, hi].
double box_distance(const Vec3& q, const Vec3& lo, const Vec3& hi) {
  const Vec3 d = (lo - q).cwiseMax(q - hi).cwiseMax(Vec3::Zero());
  return d.norm();
}

TriangleMesh box_between(const Vec3& lo, const Vec3& hi) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  const int f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                        {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& t : f) m.triangles.emplace_back(t[0], t[1], t[2]);
  return m;
}

// The smallest gap between the tool at any emitted pose and the box: the
// box's surface sampled every 0.25 mm, each sample's signed distance from
// the tool by its exact profile (the tool is a solid of revolution: the
// sample's height up the axis and its distance from it), not FCL's.
double min_gap_to_box(const PointMillResult& res, const Tool& tool, const Vec3& lo, const Vec3& hi) {
  std::vector<Vec3> pts;
  const double h = 0.25;
  const Vec3 ext = hi - lo;
  const int nx = static_cast<int>(std::ceil(ext.x() / h)), ny = static_cast<int>(std::ceil(ext.y() / h)),
            nz = static_cast<int>(std::ceil(ext.z() / h));
  for (int i = 0; i <= nx; ++i)
    for (int j = 0; j <= ny; ++j)
      for (int k = 0; k <= nz; ++k)
        if (i == 0 || i == nx || j == 0 || j == ny || k == 0 || k == nz)
          pts.emplace_back(lo.x() + ext.x() * i / nx, lo.y() + ext.y() * j / ny, lo.z() + ext.z() * k / nz);
  double gap = std::numeric_limits<double>::infinity();
  for (const PointMillPass& pass : res.passes)
    for (const PointMillPose& pp : pass.poses)
      for (const Vec3& q : pts) {
        const Vec3 d = q - pp.pose.tip;
        const double z = d.dot(pp.pose.axis);
        const double rho = (d - z * pp.pose.axis).norm();
        gap = std::min(gap, tool.signed_distance(Vec3(rho, 0, z)));
      }
  return gap;
}

TEST(PointMilling, TiltClearsALedgeBesideTheFaceAndRefusesWhatNoAxisClears) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "three plans with world checks: seconds in Release, minutes sanitized";
#endif
  // A flat face (x along the chord, z up the span, normal +y) and a ledge
  // sticking out of its plane 15 mm above its top: at the 10 deg lean the
  // flute passes through it from the top rows.
  const auto face = std::make_shared<const PointTwistedFace>(15, 20, 0, 0);
  const Tool tool = point_tool();
  PointMillRequest rq = twisted_request(face, tool);
  rq.scallop_mm = 0.05;
  rq.v0 = 0.35, rq.v1 = 0.65;
  const Vec3 lo(-15, 0, 30), hi(15, 6, 32);
  CollisionWorld world;
  PartMask no_cutter;
  no_cutter.cutter = false;
  world.add("face (shank)", tessellate(*face, 0.05), CheckSurfaceOptions{no_cutter, 0.05});
  world.add("ledge", box_between(lo, hi));
  rq.world = &world;

  PointMillRequest free_rq = rq;
  CollisionWorld free_world;
  free_world.add("face (shank)", tessellate(*face, 0.05), CheckSurfaceOptions{no_cutter, 0.05});
  free_rq.world = &free_world;
  const PointMillResult free_res = plan_point_milling(free_rq);
  ASSERT_TRUE(free_res.complete());
  EXPECT_LT(min_gap_to_box(free_res, tool, lo, hi), -0.1) << "the ledge must be in the way of the operation's axis";
  EXPECT_EQ(free_res.tilted, 0);

  const PointMillResult res = plan_point_milling(rq);
  ASSERT_TRUE(res.complete()) << (res.refusals.empty() ? "" : res.refusals.front().reason);
  EXPECT_GT(res.tilted, 0);
  EXPECT_EQ(res.poses, free_res.poses);
  // The world's clearance for the cutter is 0; the samples 0.25 mm apart
  // can miss a corner's ~0.01 mm.
  EXPECT_GE(min_gap_to_box(res, tool, lo, hi), -0.01);
  EXPECT_LE(res.scallop_max_mm, rq.scallop_mm);

  // A ledge 40 mm out: nothing within the 45 deg lean clears the top rows.
  CollisionWorld wide;
  wide.add("face (shank)", tessellate(*face, 0.05), CheckSurfaceOptions{no_cutter, 0.05});
  const Vec3 lo2(-15, 0, 22), hi2(15, 40, 24);
  wide.add("ledge", box_between(lo2, hi2));
  rq.world = &wide;
  const PointMillResult refused = plan_point_milling(rq);
  EXPECT_FALSE(refused.refusals.empty());
  EXPECT_LT(refused.poses, free_res.poses);
  if (refused.poses > 0) EXPECT_GE(min_gap_to_box(refused, tool, lo2, hi2), -0.01);
}

TEST(PointMillingParameters, ErrorsNameTheOption) {
  const auto face = std::make_shared<const PointTwistedFace>(15, 25, 3, 0.3);
  const Tool tool = point_tool();
  const Tool flat = Tool::flat_end_mill({3, 0.5, 20, {6, 30}, {}});
  auto expect_key = [&](PointMillRequest rq, const char* key) {
    try {
      plan_point_milling(rq);
      ADD_FAILURE() << "no error for " << key;
    } catch (const ParameterError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  PointMillRequest rq = twisted_request(face, tool);
  PointMillRequest bad = rq;
  bad.tool = &flat;
  expect_key(bad, "tool");
  bad = rq, bad.scallop_mm = 0;
  expect_key(bad, "scallop");
  bad = rq, bad.lean_rad = 1 * kPi / 180;
  expect_key(bad, "lean");
  bad = rq, bad.u1 = 0;
  expect_key(bad, "window");
  bad = rq, bad.hub_stop_mm = 20;
  expect_key(bad, "hub_stop");
  bad = rq, bad.face.surface = nullptr;
  expect_key(bad, "face");
}

}  // namespace
}  // namespace bliskrun
