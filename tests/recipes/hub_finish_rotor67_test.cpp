// Rotor 67's root strip by the hub finish (issue 38: the strip above the
// hub, on the edge finish's own faces), as bench/rotor67_hub_strip.lua plans
// it, to 4.5 mm (19 rows, ~30 s CPU in Release; the bench goes to 9.11 mm).
// Each root row is a closed loop planned on its own; one row's last pose and
// the next row's first differed by 29-39 deg of axis, and the move between
// them swept the shank into its clearance of blade k+1: 10 of the seams had
// neither a step nor a link proved (32 to 9.11 mm). Those rows are now
// planned again entered from the row before (HubFinishPart::entered_rows).
// And no contact is refused (4 were): 3 at the trailing edge where the hub
// profile, through dense rounded data, turned the rows' "up the span" into
// the hub (SurfaceOfRevolution::offset_direction), 1 where the chord
// between two solved centres dipped 1.07 um and split the row.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "test_support.h"

namespace bliskrun::test {
namespace {

TEST(HubFinishRotor67Recipe, RootRowsEnteredFromTheRowBeforeLeaveNoSeamUnlinked) {
  const std::string data = shared_data_dir();
  if (data.empty()) GTEST_SKIP() << "../shared/data not present: Rotor 67 root strip skipped";
  TempDir dir;
  const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/bench/rotor67_hub_strip.lua", "--data",
                                       data, "--out", dir.path() + "/out", "--quiet", "--set", "top=4.5", "--set",
                                       "simulate=false"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::smatch m;
  const std::regex line(R"(root strip to 4\.50 mm: (\d+) rows, \d+ passes, (\d+) poses .*, (\d+) refused contacts, )"
                        R"((\d+) refused links, )"
                        R"((\d+) rows entered from the row before)");
  ASSERT_TRUE(std::regex_search(r.output, m, line)) << r.output;
  EXPECT_EQ(std::stoi(m[1]), 19);
  EXPECT_GT(std::stoi(m[2]), 9000);
  EXPECT_EQ(std::stoi(m[3]), 0) << r.output;  // 4 before
  EXPECT_EQ(std::stoi(m[4]), 0) << r.output;  // 10 before
  EXPECT_GE(std::stoi(m[5]), 10);
}

}  // namespace
}  // namespace bliskrun::test
