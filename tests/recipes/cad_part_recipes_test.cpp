// Recipes on a real part read from CAD (issue 36 item 5): the NASA/GE E3
// turbine rotor blade from its IGES file, belt ground on its suction flank
// by the KUKA cell (the pressure flank's concave leading-edge region is
// narrower than the stations' wheels: the recipe refuses those paths, as
// its report says).
#include <gtest/gtest.h>

#include <filesystem>

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

}  // namespace
}  // namespace bliskrun::test
