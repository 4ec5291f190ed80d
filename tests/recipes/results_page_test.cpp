// scripts/tools/results.lua, which writes bench/RESULTS.md from the recipes'
// JSON reports (bench/results.sh runs it): run through the executable on a
// hand-made runs folder, so every figure below is known.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "test_support.h"

namespace bliskrun::test {
namespace {

std::string read_page(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct ResultsPage : ::testing::Test {
  TempDir dir;
  std::string page;

  void generate(const std::string& index) {
    dir.write("index.json", index);
    const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/tools/results.lua", "--data",
                                         dir.path(), "--out", dir.path() + "/page", "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    page = read_page(dir.path() + "/page/RESULTS.md");
  }
};

const char* kIndex = R"({"date": "2026-11-27 15:00 UTC", "commit": "abc1234", "nproc": 2, "cpu": "Test CPU",
  "mem_total_kb": 25165824, "load": "1.00 2.00 3.00", "threads": 2, "runs": [
  {"recipe": "blisk_post.lua", "settings": "", "out": "post", "exit_code": 0, "wall_s": 4.5, "user_s": 3.25,
   "sys_s": 0.25, "max_rss_kb": 102400},
  {"recipe": "blisk_wheel_design.lua", "settings": "", "out": "wheel", "exit_code": 0, "wall_s": 1, "user_s": 1,
   "sys_s": 0, "max_rss_kb": 1024},
  {"recipe": "blade_edges.lua", "settings": "", "out": "edges", "exit_code": 1, "wall_s": 2, "user_s": 1,
   "sys_s": 0, "max_rss_kb": 1024},
  {"recipe": "blisk_job.lua", "settings": "blades=2", "out": "job", "exit_code": 1, "wall_s": 2, "user_s": 1,
   "sys_s": 0, "max_rss_kb": 1024}]})";

// blisk_post.json as the recipe writes it (two programs), with an escaped
// string and exponents, which the script's JSON reader must take.
const char* kPost = R"({"blade": 1, "planned_moves": 1649, "side": "suction \"flank\" \u00b5",
  "programs": [{"blocks": 1673, "inserted": 24, "positioning": 27, "max_position_mm": 2.5e-3, "file": "a.nc"},
               {"blocks": 1649, "inserted": 0, "positioning": 13, "max_position_mm": 8.3E-4, "file": "b.h"}],
  "rows": 14})";

TEST_F(ResultsPage, FiguresComeFromTheReportsInTheirUnits) {
  dir.write("post/blisk_post.json", kPost);
  generate(kIndex);
  EXPECT_NE(page.find("- Date: 2026-11-27 15:00 UTC; commit `abc1234`"), std::string::npos) << page;
  EXPECT_NE(page.find("- Machine: 2 cores (Test CPU), 24.0 GiB memory; load average 1.00 2.00 3.00"),
            std::string::npos) << page;
  // Runs: wall, CPU = user + sys, peak memory in MB.
  EXPECT_NE(page.find("| `blisk_post.lua` | defaults | 0 | 4.5 | 3.5 | 100 |"), std::string::npos) << page;
  EXPECT_NE(page.find("| Fanuc: blocks (inserted, positioning) | 1673 (24, 27) |"), std::string::npos) << page;
  EXPECT_NE(page.find("| Fanuc: tip within (µm) of the plan, read back | 2.50 |"), std::string::npos) << page;
  EXPECT_NE(page.find("| Heidenhain: tip within (µm) of the plan, read back | 0.83 |"), std::string::npos) << page;
}

TEST_F(ResultsPage, AMissingKeyIsListedAndAFailedRunSaysSo) {
  dir.write("post/blisk_post.json", kPost);
  // The wheel-design report without table2: its rows show a dash, and the keys are listed.
  dir.write("wheel/blisk_wheel_design.json",
            R"({"part": {"narrowest_passage_mm": 10.5}, "table1": {"k1_max": 0.0425, "k1_max_flank": "pressure",
                "k2_max": 0.0384, "k2_max_flank": "suction", "ke_max": 0.0192, "ke_max_flank": "pressure"}})");
  generate(kIndex);
  EXPECT_NE(page.find("| narrowest passage d_min (mm) | 10.5 |"), std::string::npos) << page;
  EXPECT_NE(page.find("| k1 max (1/mm), flank | 0.0425, pressure |"), std::string::npos) << page;
  EXPECT_NE(page.find("| traditional wheel: R_c / D_t (mm) | — |"), std::string::npos) << page;
  const auto missing = page.find("## Declared figures not found");
  ASSERT_NE(missing, std::string::npos) << page;
  EXPECT_NE(page.find("- `blisk_wheel_design.lua: table2.traditional.barrel_radius`", missing), std::string::npos)
      << page;
  // blade_edges.lua wrote no report (exit 1): said, not hidden.
  EXPECT_NE(page.find("No report (`blade_edges.json`): the run failed"), std::string::npos) << page;
}

TEST_F(ResultsPage, EarlierFiguresAreCarriedUntilTheSameRunReplacesThem) {
  dir.write("post/blisk_post.json", kPost);
  generate(kIndex);
  const auto earlier = page.find("## Measured earlier, not re-run by this script");
  ASSERT_NE(earlier, std::string::npos) << page;
  // A 2-blade job does not replace the 22-blade figures; nothing replaces the real-data runs here.
  EXPECT_NE(page.find("- `blisk_job.lua` `blades=22`", earlier), std::string::npos) << page;
  EXPECT_NE(page.find("- `rotor67_finish.lua` `--data`", earlier), std::string::npos) << page;
  EXPECT_NE(page.find("- `bench` (", earlier), std::string::npos) << page;
  // With bench.json present, the benchmark table replaces the carried bench figures.
  dir.write("bench.json", R"({"benchmarks": [{"name": "BM_Interpolate/100", "real_time": 3.6, "cpu_time": 3.5,
                                              "time_unit": "ms"}]})");
  generate(kIndex);
  EXPECT_NE(page.find("| `BM_Interpolate/100` | 3.6 ms | 3.5 ms |"), std::string::npos) << page;
  EXPECT_EQ(page.find("- `bench` ("), std::string::npos) << page;
}

}  // namespace
}  // namespace bliskrun::test
