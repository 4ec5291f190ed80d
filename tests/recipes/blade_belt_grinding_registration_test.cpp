// scripts/recipes/blade_belt_grinding.lua's scan registration (issue 39
// item 5): a scan read from a file with --set scan=FILE and a clamping error
// of 5 deg / 5 mm registered; a scan of one flank refused — the verdict
// fails, the run exits non-zero after writing the report, and no program is
// posted.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/parts/builtin_blisk.h"
#include "test_support.h"

namespace bliskrun::test {
namespace {

nlohmann::json report_of(const std::string& dir) {
  std::ifstream in(dir + "/blade_belt_grinding.json");
  return nlohmann::json::parse(in);
}

size_t programs_in(const std::string& dir) {
  size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) n += e.path().extension() == ".src";
  return n;
}

TEST(BladeBeltGrindingRegistration, AScanFileWithFiveDegreesAndFiveMillimetresIsRegisteredAndPosted) {
  // Both flanks of the built-in blade 1 (the recipe's blade), the span
  // between 10 % and 85 % (inside the hub and casing trim), turned 5 deg
  // about (1, 2, 3) through the rotor axis and shifted 5 mm, to 1e-4 mm.
  TempDir dir;
  const std::string out = dir.path() + "/out";
  std::filesystem::create_directories(out);
  const BuiltinBlisk blisk;
  Eigen::Isometry3d clamp = Eigen::Isometry3d::Identity();
  clamp.linear() = Eigen::AngleAxisd(deg_to_rad(5), Vec3(1, 2, 3).normalized()).toRotationMatrix();
  clamp.translation() = Vec3(3, 4, 0);
  {
    std::ofstream xyz(out + "/scan.xyz");
    xyz.precision(10);
    for (FlankSide side : {FlankSide::kPressure, FlankSide::kSuction}) {
      const auto s = blisk.flank_surface(0, side);
      for (int i = 0; i <= 80; ++i)
        for (int j = 0; j <= 80; ++j) {
          const Vec3 p = clamp * s->eval(0.1 + 0.75 * i / 80, j / 80.0).p;
          xyz << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
        }
    }
  }
  const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blade_belt_grinding.lua",
                                       "--out", out, "--quiet", "--set", "robots=kuka", "--set", "sides=pressure",
                                       "--set", "scan=scan.xyz", "--set", "scan_noise=0.002"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = report_of(out);
  const auto& scan = j["scan"];
  EXPECT_EQ(scan["points"].get<int>(), 2 * 81 * 81);
  EXPECT_TRUE(scan["trusted"].get<bool>()) << scan.dump();
  // The measured clamping error is the one put in (a file carries no truth
  // for the recipe to compare with: the test does).
  EXPECT_NEAR(scan["measured"]["angle_deg"].get<double>(), 5, 1e-3);
  EXPECT_NEAR(scan["measured"]["offset_mm"].get<double>(), 5, 5e-3);
  EXPECT_FALSE(scan.contains("blade_error_corrected_um"));
  EXPECT_EQ(programs_in(out), 3u + 1u);  // one per station, and the robot's main program calling them
  EXPECT_TRUE(std::filesystem::exists(out + "/kuka_main.src"));
  EXPECT_TRUE(j["verdict"]["pass"].get<bool>());
}

TEST(BladeBeltGrindingRegistration, AOneFlankScanFailsTheVerdictAndNothingIsPosted) {
  TempDir dir;
  const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blade_belt_grinding.lua",
                                       "--out", dir.path(), "--quiet", "--set", "robots=kuka", "--set", "sides=pressure",
                                       "--set", "scan_flanks=pressure"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("verdict FAIL: scan registration"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("scan both flanks"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir.path() + "/report.html"));
  const nlohmann::json j = report_of(dir.path());
  EXPECT_FALSE(j["scan"]["trusted"].get<bool>());
  EXPECT_FALSE(j["verdict"]["pass"].get<bool>());
  bool condition_failed = false;
  for (const auto& q : j["verdict"]["requirements"])
    condition_failed = condition_failed || (q["name"] == "scan registration: condition of the normal matrix" && !q["pass"].get<bool>());
  EXPECT_TRUE(condition_failed);
  // The stop, not just the flag: the three station programs were planned
  // and none was posted, nor the main program that would call them; the
  // verdict's failed line says what to scan.
  EXPECT_EQ(programs_in(dir.path()), 0u);
  EXPECT_FALSE(std::filesystem::exists(dir.path() + "/kuka_main.src"));
  ASSERT_EQ(j["programs"].size(), 3u);
  for (const auto& p : j["programs"]) {
    EXPECT_FALSE(p.contains("file")) << p.dump();
    EXPECT_EQ(p.value("not_posted", ""), "the scan registration is not trusted") << p.dump();
  }
  bool says_what_to_scan = false;
  for (const auto& q : j["verdict"]["requirements"])
    if (!q["pass"].get<bool>() && q.contains("note"))
      says_what_to_scan = says_what_to_scan || q["note"].get<std::string>().find("scan both flanks") != std::string::npos;
  EXPECT_TRUE(says_what_to_scan);
}

TEST(BladeBeltGrindingRegistration, AScanOfSomethingElseFailsTheVerdictWithTheReportWritten) {
  // A plane 200 mm from the blade: nothing within reach of the model. The
  // fit's error becomes the verdict's, not an aborted run.
  TempDir dir;
  const std::string out = dir.path() + "/out";
  std::filesystem::create_directories(out);
  {
    std::ofstream xyz(out + "/scan.xyz");
    for (int i = 0; i < 40; ++i)
      for (int j = 0; j < 40; ++j) xyz << 300 + i << ' ' << j << " 0\n";
  }
  const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blade_belt_grinding.lua",
                                       "--out", out, "--quiet", "--set", "robots=kuka", "--set", "sides=pressure",
                                       "--set", "scan=scan.xyz"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("verdict FAIL: scan registration: converged"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("scan the whole blade"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(out + "/report.html"));
  EXPECT_EQ(programs_in(out), 0u);
  EXPECT_FALSE(report_of(out)["scan"]["trusted"].get<bool>());
}

TEST(BladeBeltGrindingRegistration, Rotor67IsRegisteredToItsNoise) {
  // Issue 39 found 10.8 um left on Rotor 67 with a fit rms of 32 um against
  // 5 um noise: stray points 0.5-0.7 mm off the blade were inside the
  // point-to-point reach (3 x the median pair distance, which follows the
  // model's 0.2-0.5 mm sample spacing there) and pulled. The point-to-plane
  // gate drops them: the rms is the noise and the blade within ~1 um.
  const std::string data = shared_data_dir();
  if (data.empty()) GTEST_SKIP() << "no real part data (../shared/data)";
  TempDir dir;
  const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blade_belt_grinding.lua",
                                       "--out", dir.path(), "--quiet", "--data", data, "--set", "part=rotor67",
                                       "--set", "robots=kuka", "--set", "sides=pressure"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = report_of(dir.path());
  const auto& scan = j["scan"];
  EXPECT_NEAR(scan["rms_um"].get<double>(), 5.0, 0.2);
  EXPECT_LT(scan["blade_error_corrected_um"].get<double>(), 2.0);
  EXPECT_GT(scan["outliers"].get<int>(), 0.029 * scan["points"].get<int>());  // the 3 % stray points, all of them
  EXPECT_TRUE(scan["trusted"].get<bool>());
}

}  // namespace
}  // namespace bliskrun::test
