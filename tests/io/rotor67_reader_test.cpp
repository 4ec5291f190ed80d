#include "core/io/rotor67_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <fstream>

#include "core/common/error.h"
#include "core/geometry/differential.h"
#include "core/geometry/interpolation.h"
#include "core/parts/rotor67_flanks.h"
#include "test_support.h"

namespace bliskrun {
namespace {

// A two-surface, 6-point file in the export's layout (values in feet).
std::string tiny(const std::string& radius_line = "  1.0 1.0 1.0 1.0 1.0 1.0") {
  std::string s = "free text header\n   JM   NS   NB  JLE  JTE\n    6    2   22    2    5\n";
  for (int k = 1; k <= 2; ++k) {
    s += " Surface number  " + std::to_string(k) + " from hub\n";
    s += " Axial Distance\n  1.000000\n  -0.1 0.0 0.1 0.2 0.3 0.4\n";
    s += " Radius*Theta Distance\n  1.000000\n  0.0 0.0 0.05 0.1 0.12 0.12\n";
    s += " Delta (Radius*Theta) = Tangential thickness\n  1.000000\n  0 0 0.02 0.02 0 0\n";
    s += " Radius\n  1.000000\n" + radius_line + "\n";
  }
  return s;
}

TEST(Rotor67Reader, ConvertsFeetToMillimetresWithZOnTheAxis) {
  const StreamSurfaceRotor r = parse_rotor67(tiny(), "tiny.dat");
  EXPECT_EQ(r.blade_count, 22);
  EXPECT_EQ(r.leading_edge, 1);
  EXPECT_EQ(r.trailing_edge, 4);
  ASSERT_EQ(r.surfaces.size(), 2u);
  EXPECT_DOUBLE_EQ(r.surfaces[0].x_mm[2], 0.1 * 304.8);
  EXPECT_DOUBLE_EQ(r.surfaces[0].r_mm[2], 304.8);
  EXPECT_DOUBLE_EQ(r.surfaces[0].theta_upper_rad[2], 0.05);          // R·θ / R
  EXPECT_DOUBLE_EQ(r.surfaces[0].theta_lower_rad[2], 0.05 - 0.02);   // upper − thickness
  EXPECT_DOUBLE_EQ(r.hub_meridian[3].x(), 0.2 * 304.8);
}

TEST(Rotor67Reader, MalformedInputNamesFileLine) {
  struct Case {
    std::string text, expected;
  } cases[] = {
      {"no header here\n", "tiny.dat:2: unexpected end of file"},
      {tiny("  1.0 1.0 x 1.0 1.0 1.0"), "tiny.dat:16: expected numbers (Radius), got 'x'"},
      {tiny("  1.0 1.0 1.0 1.0 1.0"), "tiny.dat:17: expected 6 values of 'Radius', got 5 before this line"},
      {tiny("  1.0 1.0 0.0 1.0 1.0 1.0"), "radius must be > 0"},
  };
  for (const auto& c : cases) {
    try {
      parse_rotor67(c.text, "tiny.dat");
      ADD_FAILURE() << "no error for: " << c.expected;
    } catch (const DataError& e) {
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos) << e.what();
    }
  }
}

TEST(Rotor67Reader, RealFileMatchesProvenanceFigures) {
  const std::string data = test::shared_data_dir();
  if (data.empty()) GTEST_SKIP() << "../shared/data not present: Rotor 67 checks skipped";
  const StreamSurfaceRotor r = read_rotor67(data + "/nasa_rotor67/rotor67geometry.dat");
  EXPECT_EQ(r.blade_count, 22);
  ASSERT_EQ(r.surfaces.size(), 14u);
  // PROVENANCE.md: hub LE at (x, R) = (-0.00075, 0.09561) m, casing LE R 0.25549 m.
  EXPECT_NEAR(r.surfaces[0].x_mm[r.leading_edge], -0.75, 0.01);
  EXPECT_NEAR(r.surfaces[0].r_mm[r.leading_edge], 95.61, 0.01);
  EXPECT_NEAR(r.surfaces[13].r_mm[r.leading_edge], 255.49, 0.01);
  // Flanks: pu x pv points out of the material, away from the other side.
  const RotorFlanks f = rotor_flank_grids(r);
  const BSplineSurface p = interpolate_grid(f.pressure), s = interpolate_grid(f.suction);
  for (double u : {0.2, 0.5, 0.8}) {
    const Vec3 pp = p.point(u, 0.5), ps = s.point(u, 0.5);
    EXPECT_GT(curvature(p.eval(u, 0.5)).normal.dot(pp - ps), 0) << u;
    EXPECT_GT(curvature(s.eval(u, 0.5)).normal.dot(ps - pp), 0) << u;
    // Thickness between the flanks at mid-chord: a few mm (PROVENANCE: 8.2 mm
    // max at the hub, 5.8 mm near the tip, tangential).
    EXPECT_GT((pp - ps).norm(), 2.0);
    EXPECT_LT((pp - ps).norm(), 9.0);
  }
}

TEST(Rotor67Recipe, WheelDesignOnTheRealBlade) {
  const std::string data = test::shared_data_dir();
  if (data.empty()) GTEST_SKIP() << "../shared/data not present: Rotor 67 recipe skipped";
  test::TempDir dir;
  const test::RecipeResult r = test::run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/rotor67_wheel_design.lua",
                                                   "--data", data, "--out", dir.path(), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(test::has_run_report(dir.path(), "rotor67_wheel_design.pvd"));
  std::ifstream in(dir.path() + "/rotor67_wheel_design.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  // Passage at the hub: pitch 2 pi 96 mm / 22 = 27 mm less the blade's
  // thickness and stagger.
  EXPECT_GT(j["part"]["narrowest_passage_mm"].get<double>(), 15.0);
  EXPECT_LT(j["part"]["narrowest_passage_mm"].get<double>(), 25.0);
  EXPECT_LE(j["table1"]["ke_max"].get<double>(), j["table1"]["k1_max"].get<double>() + 1e-12);
  EXPECT_GE(j["table2"]["extended"]["barrel_radius"].get<double>(), j["table2"]["traditional"]["barrel_radius"].get<double>());
  EXPECT_TRUE(std::filesystem::exists(dir.path() + "/rotor67_gaussian_curvature_pressure.png"));
}

}  // namespace
}  // namespace bliskrun
