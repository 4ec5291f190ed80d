#include "core/io/hecc_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/common/error.h"
#include "test_support.h"

namespace bliskrun {
namespace {

std::string loop_text(const std::string& header, char sep, int rows) {
  std::string s = header + "\r\n";
  for (int i = 0; i < rows; ++i)
    s += std::to_string(0.1 * i) + sep + std::to_string(0.5 * i) + sep + "2.0\r\n";
  return s;
}

void expect_hecc_error(const std::string& text, const std::string& where, const std::string& what) {
  try {
    parse_hecc_section(text, "s.txt", false);
    ADD_FAILURE() << "no error; expected " << where << " " << what;
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(HeccReader, ConvertsInchesAndRThetaBothLayouts) {
  for (bool comma : {false, true}) {
    const std::string text = comma ? loop_text("X,R*THETA,R", ',', 10) : loop_text("   X   R*THETA   R", ' ', 10);
    const std::vector<Vec3> loop = parse_hecc_section(text, "s", false);
    ASSERT_EQ(loop.size(), 10u);
    EXPECT_NEAR(loop[3].z(), 0.3 * 25.4, 1e-9);
    EXPECT_NEAR(std::hypot(loop[3].x(), loop[3].y()), 50.8, 1e-9);
    EXPECT_NEAR(std::atan2(loop[3].y(), loop[3].x()), 1.5 / 2.0, 1e-12);  // θ = (R·θ)/R
    const std::vector<Vec3> mirrored = parse_hecc_section(text, "s", true);
    EXPECT_NEAR(std::atan2(mirrored[3].y(), mirrored[3].x()), -0.75, 1e-12);
  }
  const std::vector<Vec2> path = parse_hecc_flowpath("x\tr\r\n-5.0\t1.0\r\n0.0\t2.0", "hub.txt");
  ASSERT_EQ(path.size(), 2u);
  EXPECT_DOUBLE_EQ(path[0].x(), -127.0);
  EXPECT_DOUBLE_EQ(path[1].y(), 50.8);
}

TEST(HeccReader, MalformedInputNamesFileLine) {
  expect_hecc_error(loop_text("X R THETA", ' ', 10), "s.txt:1:", "unknown header");
  expect_hecc_error(loop_text("1.0 2.0", ' ', 10), "s.txt:1:", "unknown header");
  EXPECT_EQ(parse_hecc_section(loop_text("0.5 1.0 2.0", ' ', 10), "s", false).size(), 11u);  // header-less file
  expect_hecc_error(loop_text("X R*THETA R", ' ', 3), "s.txt:", "short block: expected at least 8 rows");
  std::string bad = loop_text("X R*THETA R", ' ', 10);
  bad.replace(bad.find("2.0", bad.find('\n')), 3, "two");
  expect_hecc_error(bad, "s.txt:2:", "expected a finite number");
  expect_hecc_error(loop_text("X R*THETA R", ' ', 10) + "1.0 2.0\r\n", "s.txt:12:", "expected 3 numbers");
  try {
    parse_hecc_flowpath("x r\n1.0\n", "hub.txt");
    ADD_FAILURE();
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("hub.txt:2: expected 2 numbers"), std::string::npos) << e.what();
  }
}

double theta_deg(const Vec3& p) { return std::atan2(p.y(), p.x()) * 180 / kPi; }

TEST(HeccReader, RealFilesMatchProvenanceFigures) {
  const std::string data = test::shared_data_dir();
  if (data.empty()) GTEST_SKIP() << "../shared/data not present: HECC checks skipped";
  const std::string dir = data + "/nasa_hecc_impeller";
  const BladeSections main = read_hecc_impeller(dir, HeccSet::design_intent, HeccBlade::main);
  EXPECT_EQ(main.blade_count, 15);
  ASSERT_EQ(main.sections.size(), 11u);
  EXPECT_EQ(main.sections[0].size(), 201u);
  // PROVENANCE.md counts 200 rows for section 07: it is the file without a header line, 201 rows of data.
  EXPECT_EQ(main.sections[6].size(), 201u);
  auto range = [](const std::vector<Vec3>& loop, auto f) {
    double lo = 1e300, hi = -1e300;
    for (const Vec3& p : loop) lo = std::min(lo, f(p)), hi = std::max(hi, f(p));
    return std::make_pair(lo, hi);
  };
  auto z = [](const Vec3& p) { return p.z(); };
  auto r = [](const Vec3& p) { return std::hypot(p.x(), p.y()); };
  // Section 01: X -0.005 ... 5.266 in, R 1.594 ... 8.494 in; section 11: X ... 4.640, R 4.251 ... 8.500.
  EXPECT_NEAR(range(main.sections[0], z).first, -0.005 * 25.4, 0.013);
  EXPECT_NEAR(range(main.sections[0], z).second, 5.266 * 25.4, 0.013);
  EXPECT_NEAR(range(main.sections[0], r).first, 1.594 * 25.4, 0.013);
  EXPECT_NEAR(range(main.sections[0], r).second, 8.494 * 25.4, 0.013);
  EXPECT_NEAR(range(main.sections[10], z).second, 4.640 * 25.4, 0.013);
  EXPECT_NEAR(range(main.sections[10], r).first, 4.251 * 25.4, 0.013);
  EXPECT_NEAR(range(main.sections[10], r).second, 8.500 * 25.4, 0.013);
  // First row of main section 01 as written: 5.2658401 8.3691072 8.4915237 (θ mirrored).
  EXPECT_NEAR(main.sections[0][0].z(), 5.2658401 * 25.4, 1e-9);
  EXPECT_NEAR(std::atan2(main.sections[0][0].y(), main.sections[0][0].x()), -8.3691072 / 8.4915237, 1e-12);
  EXPECT_EQ(main.hub_meridian.size(), 350u);
  EXPECT_EQ(main.casing_meridian.size(), 310u);

  // One θ convention for both sets: θ falls from the LE (min z) to the TE (max r) by about 54°.
  auto wrap = [&](const BladeSections& b) {
    const auto& s = b.sections[0];
    const auto le = std::min_element(s.begin(), s.end(), [](const Vec3& a, const Vec3& c) { return a.z() < c.z(); });
    const auto te = std::max_element(s.begin(), s.end(), [&](const Vec3& a, const Vec3& c) { return r(a) < r(c); });
    double d = theta_deg(*te) - theta_deg(*le);
    return std::remainder(d, 360.0);
  };
  EXPECT_NEAR(wrap(main), -53.7, 1.5);
  const BladeSections cold = read_hecc_impeller(dir, HeccSet::as_manufactured, HeccBlade::main);
  ASSERT_EQ(cold.sections.size(), 14u);
  EXPECT_EQ(cold.sections[0].size(), 400u);
  EXPECT_NEAR(wrap(cold), -53.7, 1.5);
  // Cold exit radius about 8.475 ... 8.481 in.
  EXPECT_NEAR(range(cold.sections[6], r).second, 8.478 * 25.4, 0.1);
  const BladeSections splitter = read_hecc_impeller(dir, HeccSet::design_intent, HeccBlade::splitter);
  EXPECT_EQ(splitter.sections.size(), 11u);
  EXPECT_LT(wrap(splitter), -21.0);
  EXPECT_GT(wrap(splitter), -25.5);
}

}  // namespace
}  // namespace bliskrun
