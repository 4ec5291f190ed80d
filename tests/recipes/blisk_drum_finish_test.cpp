// The drum-finishing recipes of issue 4, run through the executable as a
// user runs them, with smaller simulation grids to keep the suite quick.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/analysis/heat_map.h"
#include "core/common/raster.h"
#include "test_support.h"

namespace bliskrun::test {
namespace {

namespace fs = std::filesystem;

std::string recipe_path(const char* name) { return std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/" + name; }

std::string slurp_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

size_t count_of(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

std::vector<std::string> finish_args(const std::string& out, const char* threads) {
  return {recipe_path("blisk_drum_finish.lua"), "--out", out, "--quiet", "--threads", threads,
          "--set", "samples_u=80", "--set", "samples_v=400"};
}

TEST(BliskDrumFinishRecipe, PlansBothFlanksClearAndTheSimulationFindsTheResidualAndNoGouge) {
  TempDir dir;
  const RecipeResult r = run_bliskrun(finish_args(dir.path(), "2"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has_run_report(dir.path(), "blisk_drum_finish.pvd"));
  const nlohmann::json j = nlohmann::json::parse(slurp_file(fs::path(dir.path()) / "blisk_drum_finish.json"));
  EXPECT_TRUE(j["verified"].get<bool>());
  EXPECT_EQ(j["wheel"]["rule"], "extended");
  // The concave pressure flank: the shank (d 6 x 96) lies along the blade
  // near the hub, so the tilt loop leans the axis there; the convex suction
  // flank needs no lead.
  EXPECT_GT(j["flanks"]["pressure"]["tilted_poses"].get<int>(), 0);
  EXPECT_EQ(j["flanks"]["suction"]["tilted_poses"].get<int>(), 0);
  const double residual = j["settings"]["residual_mm"], chord_tol = j["settings"]["chord_tol_mm"];
  for (const char* side : {"pressure", "suction"}) {
    SCOPED_TRACE(side);
    const nlohmann::json& f = j["flanks"][side];
    EXPECT_EQ(f["refusals"].get<int>(), 0);
    EXPECT_EQ(f["refused_links"].get<int>(), 0);
    // Wheel 2 (R_c 50) on a 30 mm blade at 14 um: about 2.3 mm rows, more
    // where the lead raised to clear the shank from the blade itself moved
    // the contact along the barrel (rows inserted; none left uncovered).
    EXPECT_GE(f["row_count"].get<int>(), 11);
    EXPECT_LE(f["row_count"].get<int>(), 25);
    EXPECT_EQ(f["row_count"].get<int>(), 13 + (side == std::string("suction") ? 1 : 0) + f["inserted_rows"].get<int>());
    EXPECT_EQ(f["uncovered_gaps"].get<int>(), 0);
    EXPECT_GT(f["width_min"].get<double>(), 2.0);
    EXPECT_LT(f["width_max"].get<double>(), 2.8);
    // Every segment's measured chord deviation is within the tolerance.
    EXPECT_LE(f["max_deviation"].get<double>(), chord_tol * (1 + 1e-9));
    for (const auto& row : f["rows"]) EXPECT_LE(row["max_deviation"].get<double>(), chord_tol * (1 + 1e-9));
    // The first row is raised off the hub; the strip is reported.
    EXPECT_GT(f["first_row_u"].get<double>(), 0.0);
    EXPECT_GT(f["hub_strip"].get<double>(), 1.0);
    EXPECT_LT(f["hub_strip"].get<double>(), 5.0);
    // The simulation: material left up to the residual height (rows spaced
    // for it; a little over from the sampled curvature and the chords), no
    // gouge beyond the chord tolerance, every sample reached.
    const nlohmann::json& sim = f["simulation"];
    EXPECT_GT(sim["undercut_max_mm"].get<double>(), 0.8 * residual);
    EXPECT_LT(sim["undercut_max_mm"].get<double>(), 1.05 * residual);
    EXPECT_GT(sim["undercut_mean_mm"].get<double>(), 0.0);
    EXPECT_LT(sim["undercut_mean_mm"].get<double>(), sim["undercut_max_mm"].get<double>());
    EXPECT_GE(sim["overcut_mm"].get<double>(), -chord_tol);
    EXPECT_EQ(sim["untouched"].get<int>(), 0);
    // 80 rows of samples over the machined window, continued at the same
    // spacing through the hub strip (overcut only there).
    EXPECT_GT(sim["first_machined_row"].get<int>(), 0);
    EXPECT_EQ(sim["samples"].get<int>(), (80 + sim["first_machined_row"].get<int>()) * 400);
    // APT: one GOTO per pose, two per link between rows, the lead-in and
    // the lead-out (every move of the program simulated).
    const std::string apt = slurp_file(fs::path(dir.path()) / f["apt"].get<std::string>());
    const size_t rows = f["rows"].size();
    EXPECT_EQ(count_of(apt, "GOTO/"), f["poses"].get<size_t>() + 2 * (rows - 1) + 2);
    EXPECT_EQ(count_of(apt, "RAPID"), 2 * (rows - 1) + 2);
    EXPECT_EQ(f["links"]["retract"], "normal");
    EXPECT_GT(f["links"]["offset_min"].get<double>(), 0.0);
    EXPECT_GE(f["links"]["deepest_cut"].get<double>(), -chord_tol);
    EXPECT_EQ(count_of(apt, "$$ ROW "), rows);
    EXPECT_EQ(count_of(apt, "STOP"), 0u);
    // The JSON carries the same toolpath: feeds at the poses, two rapids per
    // link, the lead-in and lead-out; each move says which motion ends at it.
    EXPECT_EQ(f["toolpath"].size(), f["poses"].get<size_t>() + 2 * (rows - 1) + 2);
    EXPECT_EQ(f["toolpath"][0]["kind"], "rapid");
    EXPECT_EQ(f["toolpath"][0]["motion"], "start");
    EXPECT_EQ(f["toolpath"][1]["motion"], "approach");
    EXPECT_EQ(f["toolpath"].back()["motion"], "retract");
    EXPECT_EQ(f["toolpath"][0]["tip"].size(), 3u);
    // The undercut map is a PNG with the default 800 x 320 plot, coloured
    // where material is left (red end of the scale).
    const fs::path png = fs::path(dir.path()) / sim["picture"].get<std::string>();
    ASSERT_TRUE(fs::exists(png));
    EXPECT_LT(fs::file_size(png), 1000000u);
    const RgbImage im = decode_png(slurp_file(png), png.string());
    HeatMapOptions defaults;
    defaults.title = "x";
    EXPECT_EQ(im.height, heat_map_raster_layout(defaults).height);
    int reddish = 0;
    for (int y = 40; y < 360; ++y)
      for (int x = 80; x < 880; ++x) {
        const Rgb c = im.at(x, y);
        reddish += c[0] > c[2] + 20;
      }
    EXPECT_GT(reddish, 1000);
  }
}

// Issue 37: the verdict comes first in the JSON and the page, PASS per
// requirement on the default run; links retracting along the wheel's axis
// (which drags the barrel into the concave flank) allowed to dip 100 um are
// refused by the link guard, and a refusal FAILs the run: exit 1, after the
// page and the JSON say so.
TEST(BliskDrumFinishRecipe, VerdictFailsTheRunAfterThePageWhenARequirementFails) {
  TempDir pass_dir, fail_dir;
  const std::vector<std::string> small = {"--set", "samples_u=40", "--set", "samples_v=150"};
  std::vector<std::string> args = {recipe_path("blisk_drum_finish.lua"), "--out", pass_dir.path(), "--quiet",
                                   "--threads", "2"};
  args.insert(args.end(), small.begin(), small.end());
  const RecipeResult ok = run_bliskrun(args);
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  const std::string json = slurp_file(fs::path(pass_dir.path()) / "blisk_drum_finish.json");
  EXPECT_EQ(json.find("{\n  \"verdict\": {"), 0u);
  const nlohmann::json v = nlohmann::json::parse(json)["verdict"];
  EXPECT_EQ(v["overall"], "PASS");
  EXPECT_EQ(v["requirements"].size(), 10u);  // five per flank
  for (const auto& q : v["requirements"]) EXPECT_TRUE(q["pass"].get<bool>()) << q.dump();
  const std::string page = slurp_file(fs::path(pass_dir.path()) / "report.html");
  EXPECT_LT(page.find("Verdict: <strong>PASS</strong>"), page.find("<nav>"));

  args[2] = fail_dir.path();
  for (const char* extra : {"--set", "link=axis", "--set", "link_overcut=0.1"}) args.push_back(extra);
  const RecipeResult bad = run_bliskrun(args);
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_NE(bad.output.find("verdict FAIL: pressure flank: refused poses and links"), std::string::npos) << bad.output;
  const nlohmann::json fail = nlohmann::json::parse(slurp_file(fs::path(fail_dir.path()) / "blisk_drum_finish.json"));
  EXPECT_EQ(fail["verdict"]["overall"], "FAIL");
  EXPECT_NE(slurp_file(fs::path(fail_dir.path()) / "report.html").find("Verdict: <strong>FAIL</strong>"), std::string::npos);
}

// Issue 7: same recipe and inputs give the same bytes, whatever the thread
// count (the simulation splits tool positions over the workers).
TEST(BliskDrumFinishRecipe, OneAndTwoThreadsWriteIdenticalBytes) {
  TempDir one, two;
  ASSERT_EQ(run_bliskrun(finish_args(one.path(), "1")).exit_code, 0);
  ASSERT_EQ(run_bliskrun(finish_args(two.path(), "2")).exit_code, 0);
  int files = 0;
  for (const auto& e : fs::directory_iterator(one.path())) {
    const fs::path other = fs::path(two.path()) / e.path().filename();
    ASSERT_TRUE(fs::exists(other)) << other;
    EXPECT_EQ(slurp_file(e.path()), slurp_file(other)) << e.path().filename();
    ++files;
  }
  EXPECT_EQ(files, 11);  // json, 2 apt, 2 png, pvd, 2 flank vtp, 2 toolpath vtp, report.html
}

TEST(BliskDrumStudyRecipe, ExtendedWheelNeedsFewerRowsAndOnlyConstantChordExceedsTheTolerance) {
  TempDir dir;
  const RecipeResult r = run_bliskrun({recipe_path("blisk_drum_study.lua"), "--out", dir.path(), "--quiet", "--set",
                                       "samples_u=60", "--set", "samples_v=300"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has_run_report(dir.path(), "blisk_drum_study.pvd"));
  EXPECT_NE(r.output.find("Table 4"), std::string::npos);
  EXPECT_NE(r.output.find("Table 5"), std::string::npos);
  const nlohmann::json j = nlohmann::json::parse(slurp_file(fs::path(dir.path()) / "blisk_drum_study.json"));
  const nlohmann::json& g = j["groups"];
  const double tol = j["chord_tol_mm"];
  // Wheel 2 (extended rule) needs fewer rows than wheel 1 at the same residual.
  EXPECT_EQ(g["a"]["rows"], g["b"]["rows"]);
  EXPECT_EQ(g["c"]["rows"], g["d"]["rows"]);
  EXPECT_LT(g["c"]["rows"].get<int>(), g["a"]["rows"].get<int>());
  // Eq. 17 as written exceeds the chord tolerance; the variable method, measured, never does.
  EXPECT_GT(g["a"]["max_chord_error_mm"].get<double>(), tol * 1.05);
  EXPECT_GT(g["c"]["max_chord_error_mm"].get<double>(), tol * 1.05);
  EXPECT_LE(g["b"]["max_chord_error_mm"].get<double>(), tol * (1 + 1e-9));
  EXPECT_LE(g["d"]["max_chord_error_mm"].get<double>(), tol * (1 + 1e-9));
  EXPECT_EQ(g["b"]["rows_over_tolerance"].get<int>(), 0);
  EXPECT_GT(g["a"]["rows_over_tolerance"].get<int>(), 0);
  for (const char* id : {"a", "b", "c", "d"}) {
    SCOPED_TRACE(id);
    EXPECT_EQ(g[id]["refusals"].get<int>(), 0);
    EXPECT_GT(g[id]["table5"]["undercut_std_mm"].get<double>(), 0.0);
    EXPECT_TRUE(fs::exists(fs::path(dir.path()) / g[id]["picture"].get<std::string>()));
    // Fig. 13's row: one chord error per segment between its contacts.
    EXPECT_EQ(g[id]["fig13_row"]["chord_error_mm"].size() + 1, g[id]["fig13_row"]["v"].size());
  }
  // Variable chord puts more points where the curvature rises (Fig. 12).
  EXPECT_GT(g["b"]["poses"].get<int>(), g["a"]["poses"].get<int>());
  for (const char* f : {"fig12_points_per_row.svg", "fig13_chord_error.svg"}) {
    const std::string svg = slurp_file(fs::path(dir.path()) / f);
    EXPECT_NE(svg.find("<polyline"), std::string::npos) << f;
  }
}

// Issue 6 with issue 4: a real Rotor 67 flank planned with the wheel its own
// Table 2 gives, and simulated. The suction flank: the pressure flank needs
// the tilt loop on most poses (the shank along the concave blade) and takes
// about a minute, too long for the suite.
TEST(Rotor67FinishRecipe, PlansARealFlankClearAndTheSimulationFindsNoGouge) {
  if (shared_data_dir().empty()) GTEST_SKIP() << "../shared/data not present: Rotor 67 finishing recipe skipped";
#ifdef BLISKRUN_SANITIZED
  // ~9 minutes under ASan+UBSan; the planner and simulation it drives run
  // there in the built-in blisk's recipe and planning tests.
  GTEST_SKIP() << "Rotor 67 finishing recipe skipped under the sanitizers (runs in the Release suite)";
#endif
  TempDir dir;
  const RecipeResult r = run_bliskrun({recipe_path("rotor67_finish.lua"), "--data", shared_data_dir(), "--out",
                                       dir.path(), "--quiet", "--set", "samples_u=150", "--set", "samples_v=300",
                                       "--set", "side=suction"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has_run_report(dir.path(), "rotor67_finish.pvd"));
  const nlohmann::json j = nlohmann::json::parse(slurp_file(fs::path(dir.path()) / "rotor67_finish.json"));
  EXPECT_EQ(j["part"]["blades"].get<int>(), 22);
  // Table 2 of Rotor 67: the extended wheel R_c 50, D_t 18 (d_min 20.13 mm).
  EXPECT_EQ(j["wheel"]["table2"]["barrel_radius"].get<double>(), 50.0);
  EXPECT_EQ(j["wheel"]["table2"]["max_diameter"].get<double>(), 18.0);
  const nlohmann::json& f = j["flank"];
  EXPECT_TRUE(f["verified"].get<bool>());
  EXPECT_EQ(f["refusals"].get<int>(), 0);
  EXPECT_EQ(f["refused_links"].get<int>(), 0);
  // About 130 mm of span at ~2.3 mm rows.
  EXPECT_GT(f["row_count"].get<int>(), 40);
  EXPECT_LT(f["row_count"].get<int>(), 90);
  EXPECT_LE(f["max_deviation"].get<double>(), 0.002 * (1 + 1e-9));
  const nlohmann::json& sim = f["simulation"];
  // The convex flank: the chords sag into it by up to the tolerance; the
  // planner bounds what the axis turning between poses adds (issue 11), so
  // every move of the program, links included, stays within it.
  EXPECT_LT(f["axis_turn_deviation_mm"].get<double>(), 0.001);
  EXPECT_GE(sim["overcut_mm"].get<double>(), -0.002 - 1e-4);
  EXPECT_EQ(f["links"]["retract"], "normal");
  EXPECT_GT(f["links"]["lead_in"].get<double>(), 0.0);
  EXPECT_GT(f["links"]["lead_out"].get<double>(), 0.0);
  EXPECT_LT(sim["overcut_mm"].get<double>(), -0.001);
  EXPECT_GT(sim["undercut_max_mm"].get<double>(), 0.005);
  EXPECT_LT(sim["undercut_max_mm"].get<double>(), 0.018);  // residual 14 um + chord 2 um on a concave flank
  EXPECT_EQ(sim["untouched"].get<int>(), 0);
  EXPECT_TRUE(fs::exists(fs::path(dir.path()) / f["apt"].get<std::string>()));
}

}  // namespace
}  // namespace bliskrun::test
