#include "core/io/rotor37_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/common/error.h"
#include "test_support.h"

namespace bliskrun {
namespace {

std::string surface(int n, int points = kRotor37PointsPerSurface) {
  std::string s = " SURFACE NUMBER     " + std::to_string(n) + " FROM THE HUB.\n";
  s += "    J      Z           R         THETA 1     THETA 2\n";
  for (int j = 1; j <= points; ++j) {
    const double t = (j - 1) / 99.0;
    const double half = (j == 1 || j == 100) ? 0.0 : 0.01;
    s += std::to_string(j) + " " + std::to_string(4.0 * t) + " 20.0 " + std::to_string(0.05 * t + half) + " " +
         std::to_string(0.05 * t - half) + "\n";
  }
  return s;
}

std::string geometry(int surfaces = kRotor37Surfaces) {
  std::string s = " Table IV NASA Rotor 37 Blade Geometry\n Z and R are in centimeters\n\n";
  for (int k = 1; k <= surfaces; ++k) s += surface(k);
  return s;
}

const char* kHubShroud =
    "Table V \n NASA Rotor 37 Hub and Shroud Coordinates (centimeters)\n\n"
    " Zhub\n 3 points\n -1.0 0.0 1.0\n Rhub\n 3 points\n 17.5 17.6 17.7\n"
    " Zshroud\n 2 points\n -1.0 1.0\n Rshroud\n 2 points\n 25.0 24.0\n";

void expect_rotor37_error(const std::string& geo, const std::string& hs, const std::string& where, const std::string& what) {
  try {
    parse_rotor37(geo, "g.dat", hs, "hs.dat");
    ADD_FAILURE() << "no error; expected " << where << " " << what;
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(Rotor37Reader, ConvertsCentimetresAndRadiansToThePartFrame) {
  const BladeSections b = parse_rotor37(geometry(), "g.dat", kHubShroud, "hs.dat");
  EXPECT_EQ(b.blade_count, 36);
  ASSERT_EQ(b.sections.size(), 13u);
  ASSERT_EQ(b.sections[0].size(), 198u);
  // J = 2 on THETA1: Z = 4/99 cm, R = 20 cm, θ = 0.05/99 + 0.01 rad (to the 6 decimals written).
  const Vec3 p = b.sections[0][1];
  EXPECT_NEAR(p.z(), 40.0 / 99, 1e-5);
  EXPECT_NEAR(std::hypot(p.x(), p.y()), 200.0, 1e-9);
  EXPECT_NEAR(std::atan2(p.y(), p.x()), 0.05 / 99 + 0.01, 1e-6);
  // Last loop point is J = 2 on THETA2.
  EXPECT_NEAR(std::atan2(b.sections[0].back().y(), b.sections[0].back().x()), 0.05 / 99 - 0.01, 1e-6);
  ASSERT_EQ(b.hub_meridian.size(), 3u);
  EXPECT_DOUBLE_EQ(b.hub_meridian[2].x(), 10.0);
  EXPECT_DOUBLE_EQ(b.hub_meridian[2].y(), 177.0);
  ASSERT_EQ(b.casing_meridian.size(), 2u);
  EXPECT_DOUBLE_EQ(b.casing_meridian[1].y(), 240.0);
}

TEST(Rotor37Reader, UnknownHeaderNamesLine) {
  expect_rotor37_error(" Table IV NASA Rotor 38\n", kHubShroud, "g.dat:1:", "unknown header");
  std::string g = geometry();
  g.replace(g.find("THETA 2"), 7, "PHI   2");
  expect_rotor37_error(g, kHubShroud, "g.dat:5:", "unknown header");
}

TEST(Rotor37Reader, ShortBlockNamesLine) {
  std::string g = " Table IV NASA Rotor 37 Blade Geometry\n Z and R are in centimeters\n\n" + surface(1, 50) + surface(2);
  // Line 4 title, 5 header, 6..55 data; line 56 is the next title.
  expect_rotor37_error(g, kHubShroud, "g.dat:56:", "short block: expected 100 points");
}

TEST(Rotor37Reader, WrongCountsNameLine) {
  expect_rotor37_error(geometry(12), kHubShroud, "g.dat:", "expected 13 surfaces, got 12");
  std::string hs = kHubShroud;
  hs.replace(hs.find("17.5 17.6 17.7"), 14, "17.5 17.6");
  expect_rotor37_error(geometry(), hs, "hs.dat:", "short block: expected 3 values of Rhub");
  std::string wrong = kHubShroud;
  wrong.replace(wrong.find(" 25.0 24.0"), 10, " 25.0 24.0 23.0");
  expect_rotor37_error(geometry(), wrong, "hs.dat:", "wrong count: expected 2 values of Rshroud");
}

TEST(Rotor37Reader, NonNumericFieldNamesLine) {
  std::string g = geometry();
  g.replace(g.find("20.0"), 4, "2O.0");
  expect_rotor37_error(g, kHubShroud, "g.dat:6:", "expected a finite number");
  std::string missing = geometry();
  const size_t at = missing.find("\n2 ");
  missing.replace(missing.find(' ', at + 3), 1, "\n");  // splits row J = 2 into two lines
  expect_rotor37_error(missing, kHubShroud, "g.dat:7:", "expected 5 numbers");
}

TEST(Rotor37Reader, RealFileMatchesProvenanceFigures) {
  const std::string data = test::shared_data_dir();
  if (data.empty()) GTEST_SKIP() << "../shared/data not present: Rotor 37 checks skipped";
  const std::string dir = data + "/nasa_rotor37/agard_table/";
  const BladeSections b = read_rotor37(dir + "rotor37geometry.dat", dir + "rotor37hub-shroud.dat");
  ASSERT_EQ(b.sections.size(), 13u);
  for (const auto& s : b.sections) ASSERT_EQ(s.size(), 198u);
  auto range = [](const std::vector<Vec3>& loop, auto f) {
    double lo = 1e300, hi = -1e300;
    for (const Vec3& p : loop) lo = std::min(lo, f(p)), hi = std::max(hi, f(p));
    return std::make_pair(lo, hi);
  };
  auto z = [](const Vec3& p) { return p.z(); };
  auto r = [](const Vec3& p) { return std::hypot(p.x(), p.y()); };
  auto th = [](const Vec3& p) { return std::atan2(p.y(), p.x()); };
  // Section 1: Z 0.028 ... 4.305 cm, R 17.790 ... 18.734 cm, θ up to 0.0775 rad (PROVENANCE.md);
  // the file's smallest θ (THETA2, near the TE) is -0.1179506, not the -0.1165 PROVENANCE.md quotes.
  EXPECT_NEAR(range(b.sections[0], z).first, 0.28, 0.01);
  EXPECT_NEAR(range(b.sections[0], z).second, 43.05, 0.01);
  EXPECT_NEAR(range(b.sections[0], r).first, 177.90, 0.01);
  EXPECT_NEAR(range(b.sections[0], r).second, 187.34, 0.01);
  EXPECT_NEAR(range(b.sections[0], th).first, -0.1179506, 1e-7);
  EXPECT_NEAR(range(b.sections[0], th).second, 0.0775, 1e-4);
  // Section 13: Z 0.638 ... 3.415 cm, R 24.468 ... 25.232 cm.
  EXPECT_NEAR(range(b.sections[12], z).first, 6.38, 0.01);
  EXPECT_NEAR(range(b.sections[12], z).second, 34.15, 0.01);
  EXPECT_NEAR(range(b.sections[12], r).first, 244.68, 0.01);
  EXPECT_NEAR(range(b.sections[12], r).second, 252.32, 0.01);
  // First point: J = 1 of surface 1 as written in the file (cm -> mm).
  EXPECT_NEAR(b.sections[0][0].z(), 0.28, 0.01);
  // Max tangential thickness R(θ1 - θ2): 6.3 mm at the hub, 3.9 mm at the tip.
  auto thickness = [&](const std::vector<Vec3>& loop) {
    double t = 0;
    for (int j = 1; j < 99; ++j) t = std::max(t, r(loop[j]) * (th(loop[j]) - th(loop[197 - j + 1])));
    return t;
  };
  EXPECT_NEAR(thickness(b.sections[0]), 6.3, 0.05);
  EXPECT_NEAR(thickness(b.sections[12]), 3.9, 0.05);
  ASSERT_EQ(b.hub_meridian.size(), 31u);
  ASSERT_EQ(b.casing_meridian.size(), 32u);
  EXPECT_NEAR(b.hub_meridian.front().x(), -228.6, 0.001);
  EXPECT_NEAR(b.hub_meridian.back().x(), 152.4, 0.001);
  EXPECT_NEAR(b.casing_meridian.back().y(), 237.363, 0.001);
}

}  // namespace
}  // namespace bliskrun
