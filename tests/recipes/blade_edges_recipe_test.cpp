// scripts/recipes/blade_edges.lua on a band of the built-in blade's leading
// edge (small samples): the recipe passes its own verification, and the
// report shows no gouge beyond e1 itself (within the window and beyond it
// as far as the rows reach) on the edge or the flanks, rows of both
// methods, and the moves the gouge guard turned into links.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "test_support.h"

namespace bliskrun::test {
namespace {

TEST(BladeEdgesRecipe, LeadingEdgeBandPassesWithoutGouge) {
  TempDir dir;
  const std::string out = dir.path() + "/out";
  const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blade_edges.lua", "--out",
                                       out, "--quiet", "--set", "part=builtin", "--set", "edges=leading", "--set",
                                       "v0=0.45", "--set", "v1=0.55", "--set", "samples_u=80", "--set", "samples_v=60"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has_run_report(out, "blade_edges.pvd"));
  std::ifstream in(out + "/blade_edges.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  const auto& e = j["edges"]["leading"];
  EXPECT_TRUE(e["verified"].get<bool>());
  EXPECT_GE(e["row_count"].get<int>(), 2);
  EXPECT_GE(e["side_rows"].get<int>(), 2);
  EXPECT_GT(e["poses"].get<int>(), 50);
  const double e1 = -0.001;
  EXPECT_GE(e["simulation"]["overcut_mm"].get<double>(), e1);
  EXPECT_GE(e["simulation"]["flank_overcut_mm"].get<double>(), e1);
  EXPECT_GE(e["gouge_breaks"].get<int>(), 0);
  // Beside blade 22 poses are tilted onto the corner and partial rows fill
  // what their narrower strips leave: nothing refused, the band held.
  EXPECT_EQ(e["refusals"].get<int>(), 0);
  EXPECT_EQ(e["refused_links"].get<int>(), 0);
  EXPECT_GT(e["infill_rows"].get<int>(), 0);
  EXPECT_TRUE(e["within_band"].get<bool>()) << e["simulation"]["undercut_max_mm"].get<double>();
}

// --set method=side (issue 38): the side-edge method plans the same band
// through every step. Its own report holds the tolerance band (overcut >= e1
// on the edge and the flanks, material left <= e2), every contact is on the
// corner (none on the bottom), and the rows are the ones the default run's
// side-edge comparison predicts on the same settings: the same strips and the
// same stopping rule, so the same row count (measured: 4 rows, 17 partial,
// 25 passes (one short lift; 26 without) against the default's 4, 17 and 25;
// left 15.4 um, overcut 0.80 / 0.32 um edge / flanks).
TEST(BladeEdgesRecipe, SideMethodHoldsTheBandWithTheComparisonsRows) {
  TempDir dir;
  auto run = [&](const std::string& method) {
    const std::string out = dir.path() + "/" + method;
    const RecipeResult r =
        run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blade_edges.lua", "--out", out, "--quiet",
                      "--set", "part=builtin", "--set", "edges=leading", "--set", "v0=0.45", "--set", "v1=0.55", "--set",
                      "samples_u=80", "--set", "samples_v=60", "--set", "method=" + method});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    std::ifstream in(out + "/blade_edges.json");
    return nlohmann::json::parse(in)["edges"]["leading"];
  };
  const nlohmann::json side = run("side");
  const nlohmann::json bottom = run("bottom");
  EXPECT_EQ(side["method"].get<std::string>(), "side");
  EXPECT_TRUE(side["verified"].get<bool>());
  EXPECT_EQ(side["refusals"].get<int>(), 0);
  EXPECT_EQ(side["refused_links"].get<int>(), 0);
  const double e1 = side["e1"].get<double>();
  const double e2 = side["e2"].get<double>();
  EXPECT_GE(side["simulation"]["overcut_mm"].get<double>(), e1);
  EXPECT_GE(side["simulation"]["flank_overcut_mm"].get<double>(), e1);
  EXPECT_EQ(side["simulation"]["untouched"].get<int>(), 0);
  EXPECT_LE(side["simulation"]["undercut_max_mm"].get<double>(), e2);
  EXPECT_TRUE(side["within_band"].get<bool>());
  // Side-edge positioning only: no contact on the bottom, which the default
  // method uses wherever it can.
  EXPECT_EQ(side["bottom_contacts"].get<int>(), 0);
  EXPECT_GT(side["corner_contacts"].get<int>(), 0);
  EXPECT_GT(bottom["bottom_contacts"].get<int>(), 0);
  // The same stopping rule: the default run's side-edge comparison rows.
  EXPECT_EQ(side["row_count"].get<int>(), bottom["side_rows"].get<int>());
  EXPECT_GE(side["row_count"].get<int>(), 2);
  const int passes = side["passes"].get<int>();
  const int bottom_passes = bottom["passes"].get<int>();
  EXPECT_GE(passes, side["row_count"].get<int>());
  EXPECT_LE(passes, 2 * bottom_passes);  // plausibly near the default's, not a pass per pose
  EXPECT_GE(2 * passes, bottom_passes);
  EXPECT_GT(side["poses"].get<int>(), 50);
}

// The paper's tool (R 5, r 1) does not fit beside the built-in blade's
// neighbour: contacts are refused and samples never reached. The run
// FAILS (non-zero exit after the report is written), the verdict names
// both, and the material left is said to be a lower bound, not the
// simulation's cap printed as a measure (issue 38: "up to 100.0 um", exit 0).
TEST(BladeEdgesRecipe, RefusedContactsFailTheRun) {
  TempDir dir;
  const std::string out = dir.path() + "/out";
  const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blade_edges.lua", "--out",
                                       out, "--quiet", "--set", "part=builtin", "--set", "edges=leading", "--set",
                                       "R=5", "--set", "r=1", "--set", "v0=0.45", "--set", "v1=0.47", "--set",
                                       "samples_u=40", "--set", "samples_v=20"});
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("verdict FAIL"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("refused contacts and links"), std::string::npos) << r.output;
  std::ifstream in(out + "/blade_edges.json");
  ASSERT_TRUE(in.good());  // the report is written before the run fails
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_FALSE(j["verdict"]["pass"].get<bool>());
  const auto& e = j["edges"]["leading"];
  EXPECT_GT(e["refusals"].get<int>(), 0);
  if (e["simulation"]["untouched"].get<int>() > 0) {
    EXPECT_TRUE(e["simulation"]["undercut_capped"].get<bool>());
    EXPECT_NE(e["simulation"]["undercut_text"].get<std::string>().find("never reached"), std::string::npos);
    // The verdict states the material left as a bound with the count, not
    // the capped figure as a measure.
    bool found = false;
    for (const auto& q : j["verdict"]["requirements"]) {
      if (q["name"].get<std::string>().find("material left") == std::string::npos) continue;
      found = true;
      EXPECT_FALSE(q["pass"].get<bool>());
      ASSERT_TRUE(q["measured"].is_string()) << q.dump();
      EXPECT_EQ(q["measured"].get<std::string>().rfind(">= ", 0), 0u) << q.dump();
      EXPECT_NE(q["note"].get<std::string>().find(std::to_string(e["simulation"]["untouched"].get<int>()) +
                                                  " samples never reached"),
                std::string::npos)
          << q.dump();
    }
    EXPECT_TRUE(found);
    EXPECT_NE(r.output.find("a lower bound"), std::string::npos) << r.output;
  }
}

#if !defined(BLISKRUN_SANITIZED)
// The same recipe on NASA Rotor 67's trailing edge near the hub (v
// 0.145-0.155, small samples), one run asserting what two runs (this band
// and one at mid-span, 0.43-0.46, ~65 s each) asserted apart: the edge
// region built from flanks lofted to the data's edge points, every pose and
// link proved, no gouge, the band held. Before the region followed the
// data (a circle fitted between flank ends a chord margin from the edge)
// the whole edge refused ~2700 contacts and ~2200 links and the simulation
// found 0.1 mm overcut. Near the hub the axes on the round's side lean 0.4
// towards the blisk's axis and the holder, 120 mm up the tool, sits at its
// clearance of the hub: one link, into a 2-pose partial row from across
// the round, swept the holder inside that clearance on every route, and
// was emitted as a stop; a route radially out, tried for it, cut 0.1 mm
// into a flank beyond the guards (found only by this recipe's simulation).
// Now every traverse is proved against the own blade with the cutter too,
// and the link is proved with the rows either side rearranged. (Measured:
// 212 poses, left 13.2 um, overcut 0.74 / 0.38 um edge / flanks.)
TEST(BladeEdgesRecipe, Rotor67TrailingEdgeNearTheHubIsProvedAndLinksEveryPass) {
  const std::string data = shared_data_dir();
  if (data.empty()) GTEST_SKIP() << "../shared/data not present: Rotor 67 edge recipe skipped";
  TempDir dir;
  const std::string out = dir.path() + "/out";
  const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blade_edges.lua", "--data",
                                       data, "--out", out, "--quiet", "--set", "edges=trailing", "--set", "v0=0.145",
                                       "--set", "v1=0.155", "--set", "samples_u=80", "--set", "samples_v=60"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(out + "/blade_edges.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["part"].get<std::string>(), "NASA Rotor 67 blade 1");
  const auto& e = j["edges"]["trailing"];
  EXPECT_TRUE(e["verified"].get<bool>());  // the flank cut by the radial route: -100 um
  EXPECT_LT(e["region"]["circle_misfit_mm"].get<double>(), 0.002);  // the flanks meet
  EXPECT_LT(e["region"]["fit_deviation_mm"].get<double>(), 0.002);
  EXPECT_EQ(e["refusals"].get<int>(), 0);
  EXPECT_EQ(e["refused_links"].get<int>(), 0);    // 1 before
  EXPECT_GE(e["rearranged_rows"].get<int>(), 1);  // the link's rows cut the other way or order
  EXPECT_GT(e["poses"].get<int>(), 150);
  const double e1 = -0.001;
  EXPECT_GE(e["simulation"]["overcut_mm"].get<double>(), e1);
  EXPECT_GE(e["simulation"]["flank_overcut_mm"].get<double>(), e1);
  EXPECT_EQ(e["simulation"]["untouched"].get<int>(), 0);
  EXPECT_LE(e["simulation"]["undercut_max_mm"].get<double>(), 0.02 + 1e-3);
  EXPECT_TRUE(e["within_band"].get<bool>());
}
#endif

}  // namespace
}  // namespace bliskrun::test
