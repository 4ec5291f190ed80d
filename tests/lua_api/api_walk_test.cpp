// Every function and method reachable from `bliskrun` at run time, called
// with hostile arguments (tests/lua_api/api_fuzz/api_walk.lua) through the
// executable: the run must end normally (each call returned or raised a Lua
// error), within its time limit, and must have reached the whole table.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "test_support.h"

namespace bliskrun::test {
namespace {

TEST(ApiWalk, EveryFunctionAndMethodSurvivesHostileArguments) {
  TempDir dir;
  const std::string recipe = std::string(BLISKRUN_SOURCE_DIR) + "/tests/lua_api/api_fuzz/api_walk.lua";
  const RecipeResult r = run_bliskrun(
      {recipe, "--quiet", "--out", dir.path() + "/out", "--time-limit", "120", "--memory-limit", "2048"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(dir.path() + "/out/api_walk.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  // The walk found the bindings it must (a floor, so new ones only add).
  EXPECT_GE(summary["functions"].get<int>(), 30) << summary.dump();
  EXPECT_GE(summary["calls"].get<int>(), 4000) << summary.dump();
  const auto types = summary["types"].get<std::vector<std::string>>();
  for (const char* t : {"bliskrun.Blisk", "bliskrun.Surface", "bliskrun.Curve", "bliskrun.Mesh",
                        "bliskrun.PointGrid", "bliskrun.CurvatureMap", "bliskrun.Tool", "bliskrun.CollisionWorld",
                        "bliskrun.Machine", "bliskrun.PostedProgram"})
    EXPECT_NE(std::find(types.begin(), types.end(), t), types.end()) << t << " not reached: " << summary.dump();
}

}  // namespace
}  // namespace bliskrun::test
