// The demo recipe of the README, run through the executable as a user runs it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "test_support.h"

namespace bliskrun::test {
namespace {

namespace fs = std::filesystem;

TEST(BliskWheelDesignRecipe, WritesTables1And2AndTheCurvaturePictures) {
  TempDir dir;
  const std::string recipe = std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blisk_wheel_design.lua";
  const RecipeResult r = run_bliskrun({recipe, "--out", dir.path(), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Table 1"), std::string::npos);
  EXPECT_NE(r.output.find("Table 2"), std::string::npos);

  std::ifstream in(dir.path() + "/blisk_wheel_design.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  // The built-in blisk is built to the paper's scale: d_min ~10.5 mm, blade
  // height 30 mm, k1 max ~0.0435 and k_e max ~0.0195 within C +-30 deg.
  EXPECT_NEAR(j["part"]["narrowest_passage_mm"].get<double>(), 10.5, 0.05);
  EXPECT_NEAR(j["part"]["blade_height_mm"].get<double>(), 30.0, 1e-9);
  // Over the machined flank (trimmed between hub and casing): 0.0425 / 0.0192.
  EXPECT_NEAR(j["table1"]["k1_max"].get<double>(), 0.0435, 0.003);
  EXPECT_NEAR(j["table1"]["ke_max"].get<double>(), 0.0195, 0.002);
  EXPECT_LT(j["table1"]["ke_max"].get<double>(), j["table1"]["k1_max"].get<double>());
  // The whole grid reaches below the hub, where the blade keeps curving: its
  // extremes are at least the machined flank's, and each extreme is placed
  // on the machined flank (span and chord fractions in [0, 1]).
  for (const char* key : {"k1_max", "k2_max", "ke_max"}) {
    EXPECT_GE(j["table1_whole_grid"][key].get<double>(), j["table1"][key].get<double>()) << key;
    const std::string side = j["table1"][std::string(key) + "_flank"];
    const auto& at = j["flanks"][side][key];
    EXPECT_GE(at["u"].get<double>(), 0.0);
    EXPECT_LE(at["u"].get<double>(), 1.0);
    EXPECT_GE(at["v"].get<double>(), 0.0);
    EXPECT_LE(at["v"].get<double>(), 1.0);
  }
  EXPECT_LT(j["table1"]["k1_max"].get<double>(), j["table1_whole_grid"]["k1_max"].get<double>());
  // Table 2: the traditional rule gives R_c 20, the extended one 50; D_t 8.
  EXPECT_EQ(j["table2"]["traditional"]["barrel_radius"].get<double>(), 20.0);
  EXPECT_EQ(j["table2"]["extended"]["barrel_radius"].get<double>(), 50.0);
  EXPECT_EQ(j["table2"]["extended"]["max_diameter"].get<double>(), 8.0);
  for (const char* side : {"pressure", "suction"}) {
    const fs::path png = fs::path(dir.path()) / ("gaussian_curvature_" + std::string(side) + ".png");
    ASSERT_TRUE(fs::exists(png)) << png;
    EXPECT_GT(fs::file_size(png), 2000u);
  }
  // The run's page and the ParaView collection (issue 19).
  EXPECT_TRUE(fs::exists(fs::path(dir.path()) / "report.html"));
  EXPECT_TRUE(fs::exists(fs::path(dir.path()) / "blisk_wheel_design.pvd"));
}

TEST(BliskWheelDesignRecipe, SameInputsGiveIdenticalBytes) {
  TempDir a, b;
  const std::string recipe = std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blisk_wheel_design.lua";
  const std::vector<std::string> small = {"--quiet", "--set", "rows=30", "--set", "cols=120"};
  std::vector<std::string> args_a = {recipe, "--out", a.path()}, args_b = {recipe, "--out", b.path()};
  args_a.insert(args_a.end(), small.begin(), small.end());
  args_b.insert(args_b.end(), small.begin(), small.end());
  ASSERT_EQ(run_bliskrun(args_a).exit_code, 0);
  ASSERT_EQ(run_bliskrun(args_b).exit_code, 0);
  for (const char* f : {"blisk_wheel_design.json", "gaussian_curvature_pressure.png", "gaussian_curvature_suction.png", "report.html"}) {
    std::ifstream fa(a.path() + "/" + f, std::ios::binary), fb(b.path() + "/" + f, std::ios::binary);
    const std::string sa((std::istreambuf_iterator<char>(fa)), {}), sb((std::istreambuf_iterator<char>(fb)), {});
    EXPECT_FALSE(sa.empty());
    EXPECT_EQ(sa, sb) << f;
  }
}

}  // namespace
}  // namespace bliskrun::test
