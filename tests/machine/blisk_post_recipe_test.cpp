// scripts/recipes/blisk_post.lua through the executable: both programs are
// written, proven by read-back, and reported.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "test_support.h"

namespace bliskrun::test {
namespace {

// The real drum-finish plan of one flank, posted for two machines: both
// programs written and verified, and the Fanuc program never moves a rotary
// axis, or more than one linear axis, in a G0 after the first positioning
// (the controller would leave the proved path there).
TEST(MachineRecipe, BliskPostWritesTheRealPlanWithNoRotaryRapids) {
  TempDir dir;
  const std::string out = dir.path() + "/out";
  const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blisk_post.lua",
                                       "--out", out, "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has_run_report(out, "blisk_post.pvd"));
  for (const char* file : {"/blade_ac_fanuc.nc", "/blade_bc_heidenhain.h", "/blisk_post.json"}) {
    std::ifstream in(out + file);
    EXPECT_TRUE(in.good()) << file;
  }
  std::ifstream json(out + "/blisk_post.json");
  std::stringstream text;
  text << json.rdbuf();
  EXPECT_NE(text.str().find("\"positioning\": "), std::string::npos) << text.str();
  EXPECT_EQ(text.str().find("\"positioning\": 0,"), std::string::npos) << text.str();  // the links turn C
  std::ifstream fanuc(out + "/blade_ac_fanuc.nc");
  std::string line;
  std::getline(fanuc, line);
  EXPECT_EQ(line, "%");
  int rapids = 0, motion_blocks = 0;
  bool g0 = false;
  while (std::getline(fanuc, line)) {
    if (line.empty() || line[0] == '(') continue;
    if (line.find(" G0 ") != std::string::npos) g0 = true;
    if (line.find(" G1 ") != std::string::npos) g0 = false;
    const bool moves = line.find(" X") != std::string::npos || line.find(" Y") != std::string::npos ||
                       line.find(" Z") != std::string::npos || line.find(" A") != std::string::npos ||
                       line.find(" C") != std::string::npos;
    if (!moves) continue;
    ++motion_blocks;
    if (!g0) continue;
    if (++rapids == 1) continue;  // the first move, from the tool-change position
    int linear = 0;
    for (const char* w : {" X", " Y", " Z"}) linear += line.find(w) != std::string::npos;
    EXPECT_EQ(line.find(" A"), std::string::npos) << line;
    EXPECT_EQ(line.find(" C"), std::string::npos) << line;
    EXPECT_LE(linear, 1) << line;
  }
  EXPECT_GT(motion_blocks, 1000);
}

}  // namespace
}  // namespace bliskrun::test
