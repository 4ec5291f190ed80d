// scripts/recipes/blisk_post.lua through the executable: both programs are
// written, proven by read-back, and reported.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "test_support.h"

namespace bliskrun::test {
namespace {

TEST(MachineRecipe, BliskPostWritesAndVerifiesBothPrograms) {
  TempDir dir;
  const std::string out = dir.path() + "/out";
  const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blisk_post.lua",
                                       "--out", out, "--set", "rows=4", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* file : {"/blade_ac_fanuc.nc", "/blade_bc_heidenhain.h", "/blisk_post.json"}) {
    std::ifstream in(out + file);
    EXPECT_TRUE(in.good()) << file;
  }
  std::ifstream json(out + "/blisk_post.json");
  std::stringstream text;
  text << json.rdbuf();
  EXPECT_NE(text.str().find("\"planned_moves\": 492"), std::string::npos) << text.str();
  std::ifstream fanuc(out + "/blade_ac_fanuc.nc");
  std::string first;
  std::getline(fanuc, first);
  EXPECT_EQ(first, "%");
}

}  // namespace
}  // namespace bliskrun::test
