// Mass properties (issue 39 item 2: the payload a robot program states):
// the divergence-theorem integration over a closed triangulated surface
// against the closed forms of a box and a cylinder, anywhere and turned; the
// loft of section loops the blade is integrated as; the parallel-axis
// combination and the principal axes.
#include "core/geometry/mass_properties.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"

namespace bliskrun {
namespace {

Frame placed(const Vec3& at, double angle_deg, const Vec3& axis) {
  Frame f = Frame::Identity();
  f.linear() = Eigen::AngleAxisd(deg_to_rad(angle_deg), axis.normalized()).toRotationMatrix();
  f.translation() = at;
  return f;
}

// A box as 12 outward triangles, corners at ±size/2, then placed.
void append_box(const Vec3& size, const Frame& where, std::vector<Vec3>& v, std::vector<std::array<int, 3>>& t) {
  v.clear();
  for (int i = 0; i < 8; ++i)
    v.push_back(where * Vec3((i & 1 ? 0.5 : -0.5) * size.x(), (i & 2 ? 0.5 : -0.5) * size.y(),
                             (i & 4 ? 0.5 : -0.5) * size.z()));
  t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
       {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
}

void expect_same(const MassProperties& a, const MassProperties& b, double rel) {
  EXPECT_NEAR(a.mass_kg, b.mass_kg, rel * b.mass_kg);
  EXPECT_LT((a.cog_mm - b.cog_mm).norm(), rel * 100);
  EXPECT_LT((a.inertia_kg_mm2 - b.inertia_kg_mm2).norm(), rel * b.inertia_kg_mm2.norm())
      << a.inertia_kg_mm2 << "\n--\n" << b.inertia_kg_mm2;
}

TEST(MassProperties, ABoxIsItsClosedFormAnywhereAndTurned) {
  // 120 x 80 x 40 mm of steel (7.85 g/cm³): 3.0144 kg; Ixx = m (80² + 40²) / 12.
  const Vec3 size(120, 80, 40);
  const double density = 7.85e-6;
  for (const Frame& where : {Frame(Frame::Identity()), placed(Vec3(300, -150, 900), 37, Vec3(1, 2, 3))}) {
    std::vector<Vec3> v;
    std::vector<std::array<int, 3>> t;
    append_box(size, where, v, t);
    const MassProperties m = solid_mass_properties(v, t, density);
    EXPECT_NEAR(m.volume_mm3, 384000, 1e-6);
    EXPECT_NEAR(m.mass_kg, 3.0144, 1e-9);
    const MassProperties closed = box_mass_properties(3.0144, size, where);
    expect_same(m, closed, 1e-10);
    if (where.translation().isZero()) {
      EXPECT_NEAR(m.inertia_kg_mm2(0, 0), 3.0144 * (80 * 80 + 40 * 40) / 12.0, 1e-8);
      EXPECT_NEAR(m.inertia_kg_mm2(1, 1), 3.0144 * (120 * 120 + 40 * 40) / 12.0, 1e-8);
      EXPECT_NEAR(m.inertia_kg_mm2(2, 2), 3.0144 * (120 * 120 + 80 * 80) / 12.0, 1e-8);
      EXPECT_NEAR(m.inertia_kg_mm2(0, 1), 0, 1e-8);
    }
    // Inward normals: the same solid.
    for (auto& tri : t) std::swap(tri[1], tri[2]);
    expect_same(solid_mass_properties(v, t, density), closed, 1e-10);
  }
}

TEST(MassProperties, ALoftedCylinderConvergesToItsClosedForm) {
  // A cylinder r = 30, L = 200 about a tilted axis, as 5 section loops of n
  // points: the n-gon prism's area is n/2 r² sin(2π/n) of π r², and the
  // integration is exact for the prism, so the error is the polygon's.
  const double r = 30, length = 200, density = 4.43e-6;
  const Frame where = placed(Vec3(50, 20, -400), 25, Vec3(0, 1, 1));
  for (int n : {64, 512}) {
    std::vector<std::vector<Vec3>> loops;
    for (int k = 0; k <= 4; ++k) {
      std::vector<Vec3> loop;
      for (int i = 0; i < n; ++i) {
        const double a = 2 * kPi * i / n;
        loop.push_back(where * Vec3(r * std::cos(a), r * std::sin(a), -length / 2 + length * k / 4));
      }
      loops.push_back(loop);
    }
    std::vector<Vec3> v;
    std::vector<std::array<int, 3>> t;
    closed_loft_mesh(loops, v, t);
    const MassProperties m = solid_mass_properties(v, t, density);
    const double polygon = n / (2 * kPi) * std::sin(2 * kPi / n);  // area ratio
    EXPECT_NEAR(m.volume_mm3, polygon * kPi * r * r * length, 1e-6 * m.volume_mm3);
    const MassProperties closed = cylinder_mass_properties(density * kPi * r * r * length, r, length, where);
    const double err = 1 - polygon;  // the polygon's share of the mass and, to first order, of the inertia
    expect_same(m, closed, 2.5 * err);
    EXPECT_LT((m.cog_mm - where.translation()).norm(), 1e-9);
    // The axial moment m r²/2 of the polygon: (1 + cos(2π/n) * ...) within the same order.
    const PrincipalInertia p = principal_inertia(m.inertia_kg_mm2);
    EXPECT_NEAR(std::abs(p.axes.col(2).dot(where.linear().col(2))) + std::abs(p.axes.col(0).dot(where.linear().col(2))) +
                    std::abs(p.axes.col(1).dot(where.linear().col(2))),
                1, 1e-6);  // one principal axis is the cylinder's
  }
}

TEST(MassProperties, CombinedIsTheParallelAxisTheorem) {
  // Two 1 kg point-like cubes 200 mm apart along x: about their middle
  // Iyy = Izz = 2 · 1 · 100² (+ their own), Ixx their own only.
  const MassProperties a = box_mass_properties(1, Vec3(10, 10, 10), placed(Vec3(-100, 0, 0), 0, Vec3(0, 0, 1)));
  const MassProperties b = box_mass_properties(1, Vec3(10, 10, 10), placed(Vec3(100, 0, 0), 0, Vec3(0, 0, 1)));
  const MassProperties c = combined(a, b);
  const double own = 1 * (100 + 100) / 12.0;
  EXPECT_NEAR(c.mass_kg, 2, 1e-12);
  EXPECT_LT(c.cog_mm.norm(), 1e-12);
  EXPECT_NEAR(c.inertia_kg_mm2(0, 0), 2 * own, 1e-9);
  EXPECT_NEAR(c.inertia_kg_mm2(1, 1), 2 * own + 2 * 100 * 100, 1e-9);
  EXPECT_NEAR(c.inertia_kg_mm2(2, 2), 2 * own + 2 * 100 * 100, 1e-9);
  // Moving a body and combining commute.
  const Frame f = placed(Vec3(10, 20, 30), 40, Vec3(3, -1, 2));
  expect_same(transformed(c, f), combined(transformed(a, f), transformed(b, f)), 1e-12);
}

TEST(MassProperties, PrincipalAxesDiagonaliseAndStayNearTheFrame) {
  const Mat3 d = Vec3(3, 5, 7).asDiagonal();
  const PrincipalInertia same = principal_inertia(d);
  EXPECT_TRUE(same.axes.isApprox(Mat3::Identity()));
  EXPECT_TRUE(same.moments_kg_mm2.isApprox(Vec3(3, 5, 7)));
  const Mat3 r = placed(Vec3::Zero(), 20, Vec3(1, 1, 0)).linear();
  const PrincipalInertia p = principal_inertia(r * d * r.transpose());
  EXPECT_NEAR(p.axes.determinant(), 1, 1e-12);
  EXPECT_TRUE((p.axes * p.moments_kg_mm2.asDiagonal() * p.axes.transpose()).isApprox(r * d * r.transpose(), 1e-12));
  EXPECT_TRUE(p.axes.isApprox(r, 1e-9));  // turned 20°: each axis still nearest its own
}

TEST(MassProperties, AnOpenSurfaceIsRefusedNamingAnEdge) {
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> t;
  append_box(Vec3(1, 2, 3), Frame::Identity(), v, t);
  t.pop_back();
  try {
    solid_mass_properties(v, t, 1e-6);
    FAIL() << "an open box was integrated";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
  }
  append_box(Vec3(1, 2, 3), Frame::Identity(), v, t);
  std::swap(t[0][1], t[0][2]);  // one triangle turned against its neighbours
  EXPECT_THROW(solid_mass_properties(v, t, 1e-6), Error);
}

}  // namespace
}  // namespace bliskrun
