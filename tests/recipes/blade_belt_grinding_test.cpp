// scripts/recipes/blade_belt_grinding.lua on the built-in blade: three
// stations on both flanks, each within its measured chord error and scallop,
// the number of paths following the step-over formula station to station.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "core/planning/belt_paths.h"
#include "test_support.h"

namespace bliskrun::test {
namespace {

TEST(BladeBeltGrindingRecipe, ThreeStationsOnBothFlanksWithinTheirMeasuredTolerances) {
  TempDir dir;
  const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blade_belt_grinding.lua",
                                       "--out", dir.path(), "--quiet", "--verify"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // --verify: every robot program's read-back, and its wheel check.
  EXPECT_NE(r.output.find("read-back verification: 12 program(s)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" 0 configuration flips; wheel and belt clear of the blade over "), std::string::npos);
  EXPECT_TRUE(has_run_report(dir.path(), "blade_belt_grinding.pvd"));
  // The report's pictures: the paths on each flank (one polyline per coarse
  // path, 23 + 23) and the measured scallop and chord charts (6 + 6).
  {
    std::ifstream page(dir.path() + "/report.html");
    const std::string html((std::istreambuf_iterator<char>(page)), std::istreambuf_iterator<char>());
    EXPECT_NE(html.find("Measured scallop per path"), std::string::npos);
    EXPECT_NE(html.find("Paths on the pressure flank, coarse station"), std::string::npos);
    size_t lines = 0;
    for (size_t at = html.find("<polyline"); at != std::string::npos; at = html.find("<polyline", at + 1)) ++lines;
    EXPECT_EQ(lines, 23u + 23u + 6u + 6u);
  }
  std::ifstream in(dir.path() + "/blade_belt_grinding.json");
  ASSERT_TRUE(in.good());
  const nlohmann::json j = nlohmann::json::parse(in);
  ASSERT_EQ(j["stations"].size(), 3u);
  for (const char* side : {"pressure", "suction"}) {
    // The flank is nearly flat across the paths (span-wise): paths are about
    // one flat step-over 2√(2rh) apart, so (paths - 1) · L spans the same
    // blade height at every station.
    std::vector<double> spans;
    for (const auto& st : j["stations"]) {
      const auto& f = st["flanks"][side];
      EXPECT_LE(f["chord_max"].get<double>(), st["chord_tol"].get<double>() * (1 + 1e-9)) << side;
      EXPECT_LE(f["scallop_max"].get<double>(), st["scallop"].get<double>() * (1 + 1e-9)) << side;
      EXPECT_GT(f["scallop_max"].get<double>(), 0.9 * st["scallop"].get<double>()) << side;  // not wasteful
      const double step = belt_step_over(st["scallop"].get<double>(), st["wheel"]["radius"].get<double>(), 0);
      spans.push_back((f["paths"].get<int>() - 1) * step);
      EXPECT_EQ(f["path"].size(), f["paths"].get<size_t>());
      // Every path trimmed by half the wheel width at both ends.
      const auto& first = f["path"][0];
      EXPECT_GT(first["length"].get<double>(), 10.0);
    }
    for (double s : spans) EXPECT_NEAR(s, spans[1], 2.5) << side;  // ~31 mm of blade height
  }
  // The scan of the blade as clamped, registered to the model: a clamping
  // error that moves blade points by more than 1 mm is corrected to a few
  // micrometres (5 um scan noise, 3 % stray points, partial coverage).
  EXPECT_GT(j["scan"]["blade_error_uncorrected_mm"].get<double>(), 0.5);
  EXPECT_LT(j["scan"]["blade_error_corrected_um"].get<double>(), 5.0);
  EXPECT_TRUE(j["scan"]["converged"].get<bool>());
  // One program per station, flank and robot, each read back and replayed
  // through its arm within 2 um before it was written; no configuration
  // change along a program; grinding moves within the joints' speeds.
  ASSERT_EQ(j["programs"].size(), 12u);
  // One main program per robot calls the station programs; every file within 500 kB.
  EXPECT_TRUE(std::filesystem::exists(dir.path() + "/kuka_main.src"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() + "/abb_main.mod"));
  for (const auto& p : j["programs"]) {
    ASSERT_TRUE(p.contains("file")) << p.dump();
    EXPECT_TRUE(std::filesystem::exists(dir.path() + "/" + p["file"].get<std::string>()));
    EXPECT_LE(p["largest_bytes"].get<double>(), 500000.0);
    EXPECT_LT(p["max_position_mm"].get<double>(), 0.002);
    EXPECT_EQ(p["branch_changes"].get<int>(), 0);
    EXPECT_LT(p["joint_speed_ratio"].get<double>(), 1.0);
    EXPECT_TRUE(p["refusals"].empty());
    // The setup sheet beside it, its cycle time by the estimate's closed
    // form: the contact travel of every path at 20 mm/s plus one ramp
    // (v/a, 1 m/s^2) per path when no joint slows a step; the travel is
    // the flank's path lengths for that station.
    {
      std::ifstream sheet_in(dir.path() + "/" + p["setup_sheet"].get<std::string>().substr(
                                                   0, p["setup_sheet"].get<std::string>().size() - 5) + ".json");
      ASSERT_TRUE(sheet_in.good()) << p["setup_sheet"];
      const nlohmann::json c = nlohmann::json::parse(sheet_in)["cycle_time"];
      double travel = 0;
      for (const auto& st : j["stations"])
        if (st["name"] == p["station"])
          for (const auto& path : st["flanks"][p["flank"].get<std::string>()]["path"]) travel += path["length"].get<double>();
      EXPECT_NEAR(c["grinding_mm"].get<double>(), travel, 1e-3 * travel) << p["file"];
      ASSERT_EQ(c["joint_limited_steps"].get<int>(), 0) << p["file"];
      EXPECT_NEAR(c["grinding_s"].get<double>(),
                  c["grinding_mm"].get<double>() / 20 + c["paths"].get<double>() * 20.0 / 1000, 1e-9) << p["file"];
      EXPECT_NEAR(c["total_s"].get<double>(),
                  c["grinding_s"].get<double>() + c["link_s"].get<double>() + c["home_s"].get<double>(), 1e-9);
      EXPECT_GT(c["link_s"].get<double>(), 0);
      EXPECT_DOUBLE_EQ(p["cycle_time_s"].get<double>(), c["total_s"].get<double>());
    }
    // The wheel and belt checked against the whole blade on every move and
    // between moves. The rubber gives where the face is concave along the
    // path — the pressure flank, (w/2)^2 k / 2 = 0.1-0.3 mm at the wheels'
    // ends — and next to nothing on the convex suction flank.
    EXPECT_GT(p["wheel_poses_checked"].get<double>(), p["moves"].get<double>());
    if (p["flank"] == "pressure") {
      EXPECT_GT(p["wheel_conformity_mm"].get<double>(), 0.1) << p["file"];
    } else {
      EXPECT_LT(p["wheel_conformity_mm"].get<double>(), 0.05) << p["file"];
    }
  }
}

}  // namespace
}  // namespace bliskrun::test
