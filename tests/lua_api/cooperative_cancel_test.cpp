// Long core work stops cooperatively: planning, simulation and posting each
// pass cancellation points all along, and a cancellation requested part-way
// (as the time limit's watchdog requests it) ends the run with an error at
// the recipe line of the call. The request comes from the runner's test
// hook (RunOptions::test_cancel_at): at the N-th cancellation point after
// the call on line 7 began, an amount of work rather than a clock, so the
// stop lands in that call whatever the machine's speed. A call that reached
// fewer points would run to its end and the recipe would succeed: the test
// fails then.
#include <gtest/gtest.h>

#include <sstream>

#include "lua_api/runner.h"
#include "test_support.h"

namespace bliskrun::test {
namespace {

constexpr const char* kPlanSetup =
    "local finish = require(\"blisk_finish\")\n"
    "local blisk_world = require(\"blisk_world\")\n"
    "local blisk = bliskrun.blisk{}\n"
    "local wheel = bliskrun.drum_wheel{max_diameter = 8, barrel_radius = 50, head_length = 4,\n"
    "                                  shank = {diameter = 6, length = 96}}\n"
    "local world = blisk_world.around_blade(blisk, 1)\n";  // lines 1-6

// 10 000 moves swinging C by 30 deg each: every one split many times.
constexpr const char* kPostSetup =
    "local m = bliskrun.machine.load(\"dmg_like_ac_trunnion\")\n"
    "local path = {{kind = \"rapid\", tip = {40, 0, 30}, axis = {0, -0.5, 0.866}}}\n"
    "for i = 1, 10000 do\n"
    "  local a = math.rad(30 * (i % 2))\n"
    "  path[#path + 1] = {kind = \"feed\", tip = {40, 0, 5}, axis = {0.5 * math.sin(a), -0.5 * math.cos(a), 0.866}, feed = 500}\n"
    "end\n";  // lines 1-6

// Runs `recipe` with the cancellation at `points` points into the call on
// `line`, with no time limit: only the test's request can stop it.
void expect_stop_at_line(const std::string& recipe, const std::string& line, long points) {
  TempDir dir;
  lua_api::RunOptions o;
  o.recipe_path = dir.write("recipe.lua", recipe);
  o.out_dir = dir.path() + "/out";
  o.quiet = true;
  o.time_limit_s = 0;
  o.memory_limit_mb = 2048;
  o.test_cancel_at = "recipe.lua:" + line + ":" + std::to_string(points);
  std::ostringstream err;
  const int exit_code = lua_api::run_recipe(o, err);
  const std::string out = err.str();
  EXPECT_EQ(exit_code, 1) << out;
  // The core's own Cancelled, raised at its cancellation point and turned
  // into a Lua error; the recipe frame of the call in the traceback.
  EXPECT_NE(out.find("cancelled: test cancellation after " + std::to_string(points) +
                     " cancellation points of the call at recipe.lua:" + line),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("recipe.lua:" + line + ":"), std::string::npos) << out;
  // The call did not run to its end.
  EXPECT_EQ(out.find("the call ran to its end"), std::string::npos) << out;
}

// The counts: each call passes at least twice as many cancellation points
// when it runs to its end (measured: planning ~5100, the simulation ~560,
// one program's posting ~40, two at once ~170).
TEST(CooperativeCancel, PlanningStopsAtItsLine) {
  expect_stop_at_line(std::string(kPlanSetup) +
                            "finish.plan(blisk, 1, \"pressure\", wheel, world, {c_range = 30, residual = 0.05})\n"
                            "error(\"the call ran to its end\")\n",
                        "7", 1000);
}

TEST(CooperativeCancel, SimulationStopsAtItsLine) {
  expect_stop_at_line(std::string(kPlanSetup) +
                            "local plan = finish.plan(blisk, 1, \"suction\", wheel, world, {c_range = 30, residual = 0.1})\n"
                            "plan:simulate{samples_u = 100, samples_v = 600}\n"
                            "error(\"the call ran to its end\")\n",
                        "8", 200);
}

TEST(CooperativeCancel, PostingStopsAtItsLine) {
  expect_stop_at_line(
      std::string(kPostSetup) +
          "bliskrun.post.write{machine = m, post = \"fanuc\", path = path, file = \"x.nc\", tool = {number = 1, length = 80}}\n"
          "error(\"the call ran to its end\")\n",
      "7", 20);
}

// The same programs posted at once: each worker (its machine motion, its
// post in its own Lua state) stops too.
TEST(CooperativeCancel, PostingAtOnceStopsAtItsLine) {
  expect_stop_at_line(
      std::string(kPostSetup) +
          "bliskrun.post.write_all{{machine = m, post = \"fanuc\", path = path, file = \"x.nc\", tool = {number = 1, length = 80}}, "
          "{machine = m, post = \"fanuc\", path = path, file = \"y.nc\", tool = {number = 1, length = 80}}}\n"
          "error(\"the call ran to its end\")\n",
      "7", 60);
}

}  // namespace
}  // namespace bliskrun::test
