// Recipes on a real part read from CAD (issue 36 item 5): the NASA/GE E3
// turbine rotor blade from its IGES file, belt ground on its suction flank
// by the KUKA cell. The pressure flank is refused, as the report says: the
// file's surface is wavy along the chord (at 20, 50, 80 % span its chordwise
// curvature alternates between convex stretches and concave ones of 6-10 mm
// radius over the whole chord), tighter than the wheels (r 25, 20, 15 mm).
// The file's own sections are so, evaluated apart from OCCT (de Boor on the
// IGES records): the section at R = 13.571 in changes curvature sign 18
// times along the inner 80 % of its concave side, radii down to 5 mm.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "core/cad/cad.h"
#include "core/geometry/interpolation.h"
#include "core/parts/builtin_blisk.h"
#include "test_support.h"

namespace bliskrun::test {
namespace {

TEST(CadPartRecipes, E3BladeBeltGrindingFromIges) {
  if (shared_data_dir().empty() || !std::filesystem::exists(shared_data_dir() + "/e3_hpt_stage1/hpt_stator1.igs"))
    GTEST_SKIP() << "../shared/data/e3_hpt_stage1 not present: E3 belt grinding recipe skipped";
  TempDir dir;
  const std::string out = dir.path() + "/out";
  const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blade_belt_grinding.lua",
                                       "--data", shared_data_dir(), "--out", out, "--set", "part=e3", "--set",
                                       "sides=suction", "--set", "robots=kuka", "--set", "feed=10"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* station : {"coarse", "fine", "polish"})
    EXPECT_TRUE(std::filesystem::exists(out + "/kuka_" + station + "_suction.src")) << station;
  EXPECT_NE(r.output.find("read back within"), std::string::npos) << r.output;
}

// Your own part from STEP (issue 36 item 5, "a recipe reads a STEP file of
// a real part"): the E3 blade, hub and casing as a CAD system would export
// them to STEP (written here by OCCT from the IGES geometry, in mm), ground
// with --set part=cad. The same blade as from the IGES file (the surface
// round trip: 3.5e-11 mm): the same paths on the suction flank, within
// their tolerances, points and measured chord and scallop within 1 %.
TEST(CadPartRecipes, YourOwnBladeFromStepGrindsAsFromIges) {
  const std::string e3 = shared_data_dir().empty() ? "" : shared_data_dir() + "/e3_hpt_stage1";
  if (e3.empty() || !std::filesystem::exists(e3 + "/hpt_stator1.igs"))
    GTEST_SKIP() << "../shared/data/e3_hpt_stage1 not present: STEP recipe skipped";
  TempDir dir;
  const CadModel blade = read_cad(e3 + "/hpt_stator1.igs");
  ASSERT_EQ(blade.faces.size(), 1u);
  write_step(dir.path() + "/blade.step", {blade.faces[0].surface.get()});
  write_step(dir.path() + "/hub.step", {}, {read_cad(e3 + "/hub.igs").curves.at(0).curve.get()});
  write_step(dir.path() + "/casing.step", {}, {read_cad(e3 + "/case.igs").curves.at(0).curve.get()});
  // Your files are read from the data folder you name (--data), as a shop's would be.
  {
    // The round trip itself: the STEP's surface and hub against the IGES's.
    const CadModel back = read_cad(dir.path() + "/blade.step");
    double worst = 0;
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; j <= 40; ++j)
        worst = std::max(worst, (back.faces.at(0).surface->point(i / 20.0, j / 40.0) -
                                 blade.faces[0].surface->point(i / 20.0, j / 40.0)).norm());
    EXPECT_LT(worst, 1e-7) << "STEP round trip of the blade surface, mm";

  }
  auto run = [&](const std::string& out, std::vector<std::string> extra, const std::string& data) {
    std::vector<std::string> args = {std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blade_belt_grinding.lua",
                                      "--data", data, "--out", out, "--quiet", "--set", "sides=suction",
                                      "--set", "robots=kuka", "--set", "feed=10"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_bliskrun(args);
  };
  const RecipeResult step = run(dir.path() + "/step", {"--set", "part=cad", "--set", "cad=blade.step", "--set",
                                                       "cad_hub=hub.step", "--set", "cad_casing=casing.step"},
                                dir.path());
  ASSERT_EQ(step.exit_code, 0) << step.output;
  const RecipeResult iges = run(dir.path() + "/iges", {"--set", "part=e3"}, shared_data_dir());
  ASSERT_EQ(iges.exit_code, 0) << iges.output;
  auto report = [](const std::string& file) {
    std::ifstream in(file);
    return nlohmann::json::parse(in);
  };
  const nlohmann::json a = report(dir.path() + "/step/blade_belt_grinding.json");
  const nlohmann::json b = report(dir.path() + "/iges/blade_belt_grinding.json");
  ASSERT_EQ(a["stations"].size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    const auto& fa = a["stations"][k]["flanks"]["suction"];
    const auto& fb = b["stations"][k]["flanks"]["suction"];
    // The same paths; the points along them within 1 %: the chord guarantee
    // halves a step whose measured chord is over the tolerance, and the
    // measurement near it moves with the last bits of the evaluation (the
    // surfaces agree to 1e-10 mm, the NURBS are stored differently).
    EXPECT_EQ(fa["paths"], fb["paths"]) << k;
    EXPECT_NEAR(fa["points"].get<double>(), fb["points"].get<double>(), 0.01 * fb["points"].get<double>()) << k;
    const double chord_tol = a["stations"][k]["chord_tol"].get<double>();
    const double scallop = a["stations"][k]["scallop"].get<double>();
    EXPECT_LE(fa["chord_max"].get<double>(), chord_tol * (1 + 1e-9)) << k;
    EXPECT_LE(fa["scallop_max"].get<double>(), scallop * (1 + 1e-9)) << k;
    EXPECT_NEAR(fa["chord_max"].get<double>(), fb["chord_max"].get<double>(), 0.01 * chord_tol) << k;
    EXPECT_NEAR(fa["scallop_max"].get<double>(), fb["scallop_max"].get<double>(), 0.01 * scallop) << k;
  }
  EXPECT_TRUE(std::filesystem::exists(dir.path() + "/step/kuka_polish_suction.src"));
  // A file of several faces without cad_face is refused, naming them.
  write_step(dir.path() + "/two.step", {blade.faces[0].surface.get(), blade.faces[0].surface.get()});
  const RecipeResult two = run(dir.path() + "/two", {"--set", "part=cad", "--set", "cad=two.step"}, dir.path());
  EXPECT_EQ(two.exit_code, 1);
  EXPECT_NE(two.output.find("expected one face, the closed airfoil; the file has 2"), std::string::npos) << two.output;
}

// Your own blisk from STEP (issue 36): the built-in blisk's blade 1 (both
// flanks, each the kernel's B-spline through its 100 x 500 grid) and its hub
// and casing meridians written to one STEP file, finished with the drum
// wheel by blisk_drum_finish --set part=cad --set blade_count=22. The same
// blisk: the same wheel (the same narrowest passage and curvature), and
// both flanks planned and simulated as on the built-in blisk, verified.
TEST(CadPartRecipes, BliskDrumFinishFromStepAsOnTheBuiltinBlisk) {
  TempDir dir;
  const BuiltinBlisk blisk;
  const NurbsSurface pressure(interpolate_grid(blisk.flank_grid(0, FlankSide::kPressure)));
  const NurbsSurface suction(interpolate_grid(blisk.flank_grid(0, FlankSide::kSuction)));
  auto line = [](const std::vector<Vec2>& zr) {
    return NurbsCurve(1, {0, 0, 1, 1}, {Vec3(zr.front().y(), 0, zr.front().x()), Vec3(zr.back().y(), 0, zr.back().x())},
                      {1, 1});
  };
  const NurbsCurve hub = line(blisk.hub_meridian()), casing = line(blisk.casing_meridian());
  write_step(dir.path() + "/blisk_blade1.step", {&suction, &pressure}, {&casing, &hub});
  auto run = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = {std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blisk_drum_finish.lua",
                                      "--data", dir.path(), "--out", out, "--quiet", "--threads", "2",
                                      "--set", "samples_u=80", "--set", "samples_v=400"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_bliskrun(args);
  };
  const RecipeResult cad = run(dir.path() + "/cad", {"--set", "part=cad", "--set", "cad=blisk_blade1.step",
                                                     "--set", "blade_count=22"});
  ASSERT_EQ(cad.exit_code, 0) << cad.output;
  auto report = [](const std::string& file) {
    std::ifstream in(file);
    return nlohmann::json::parse(in);
  };
  // Against the built-in blisk's own run (BliskDrumFinishRecipe, same
  // settings: not run again here, the suite's time is counted): the same
  // passage and wheel, rows and widths in the ranges that test holds the
  // built-in blisk to, verified.
  const nlohmann::json a = report(dir.path() + "/cad/blisk_drum_finish.json");
  EXPECT_TRUE(a["verified"].get<bool>());
  EXPECT_EQ(a["part"]["kind"], "blisk from CAD");
  EXPECT_EQ(a["part"]["blades"], 22);
  EXPECT_NEAR(a["part"]["narrowest_passage_mm"].get<double>(), blisk.narrowest_passage_mm(), 1e-4);
  EXPECT_EQ(a["wheel"]["rule"], "extended");
  const double residual = a["settings"]["residual_mm"], chord_tol = a["settings"]["chord_tol_mm"];
  for (const char* side : {"pressure", "suction"}) {
    SCOPED_TRACE(side);
    const nlohmann::json& f = a["flanks"][side];
    EXPECT_EQ(f["refusals"].get<int>(), 0);
    EXPECT_EQ(f["refused_links"].get<int>(), 0);
    EXPECT_EQ(f["row_count"].get<int>(), 13 + (side == std::string("suction") ? 1 : 0) + f["inserted_rows"].get<int>());
    EXPECT_EQ(f["uncovered_gaps"].get<int>(), 0);
    EXPECT_GT(f["width_min"].get<double>(), 2.0);
    EXPECT_LT(f["width_max"].get<double>(), 2.8);
    EXPECT_LE(f["max_deviation"].get<double>(), chord_tol * (1 + 1e-9));
    const nlohmann::json& sim = f["simulation"];
    EXPECT_GT(sim["undercut_max_mm"].get<double>(), 0.8 * residual);
    EXPECT_LT(sim["undercut_max_mm"].get<double>(), 1.05 * residual);
    EXPECT_GE(sim["overcut_mm"].get<double>(), -chord_tol);
    EXPECT_EQ(sim["untouched"].get<int>(), 0);
  }
  // Without a blade count the run is refused before anything is planned.
  const RecipeResult no_count = run(dir.path() + "/none", {"--set", "part=cad", "--set", "cad=blisk_blade1.step"});
  EXPECT_EQ(no_count.exit_code, 1);
  EXPECT_NE(no_count.output.find("--set part=cad needs --set blade_count=N"), std::string::npos) << no_count.output;
}

// Tip repair of the E3 rotor blade from its IGES file (issue 36 item 5):
// the repair chain takes the CAD blade (its closed airfoil cut into 25
// sections for the design loft, bliskrun.damaged_blade's loops), measures
// the broken blade, rebuilds it and checks the rebuild between its sections.
// At the default 10 um that check refuses it (18 um at the rebuilt tip above
// the break, also without the simulated twist and bend: the E3 sections
// change faster along the span than the rebuilt loft through 24 measured
// plane sections follows), so no region is made and the run fails on its
// verdict; with rebuild_tolerance = 25 um the damaged region is the tip
// above 80 % span. Paths are left out here (--set paths=false: 46918 poses,
// 14 s CPU); they are planned when the recipe is run as a user runs it.
TEST(CadPartRecipes, E3BladeTipRepairFromIges) {
  if (shared_data_dir().empty() || !std::filesystem::exists(shared_data_dir() + "/e3_hpt_stage1/hpt_stator1.igs"))
    GTEST_SKIP() << "../shared/data/e3_hpt_stage1 not present: E3 repair recipe skipped";
  TempDir dir;
  auto run = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = {std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blade_repair.lua", "--data",
                                      shared_data_dir(), "--out", out, "--quiet", "--set", "part=e3",
                                      "--set", "paths=false"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_bliskrun(args);
  };
  const RecipeResult strict = run(dir.path() + "/strict", {});
  EXPECT_EQ(strict.exit_code, 1) << strict.output;
  EXPECT_NE(strict.output.find("rebuilt blade between sections"), std::string::npos) << strict.output;
  const RecipeResult loose = run(dir.path() + "/loose", {"--set", "rebuild_tolerance=0.025"});
  ASSERT_EQ(loose.exit_code, 0) << loose.output;
  std::ifstream in(dir.path() + "/loose/blade_repair.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_TRUE(j["rebuild"]["trusted"].get<bool>());
  EXPECT_GT(j["rebuild"]["between_sections_max_um"].get<double>(), 10.0);
  EXPECT_LE(j["rebuild"]["between_sections_max_um"].get<double>(), 25.0);
  // The tip above 80 % of the blade's height is the region, nothing else.
  const double height = j["blade"]["height_mm"].get<double>();
  EXPECT_GT(height, 40.0);  // 1.7 in between the hub and tip sections
  EXPECT_LT(height, 45.0);
  EXPECT_GT(j["region"]["tip_volume_mm3"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(j["region"]["volume_mm3"].get<double>(), j["region"]["tip_volume_mm3"].get<double>());
  EXPECT_EQ(j["region"]["edge_volume_mm3"].get<double>(), 0.0);
}

}  // namespace
}  // namespace bliskrun::test
