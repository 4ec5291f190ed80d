// The time limit stops long core work cooperatively: planning, simulation
// and posting each reach a cancellation point long before the watchdog's
// last resort (limit + 2 s). Each recipe sets the limit inside one long core
// call; the run must end with the limit error at that call's line and
// without "stopped by the watchdog". Release only: under the sanitizers the
// set-up before the call may itself outlast the limit.
#include <gtest/gtest.h>

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

void expect_cooperative_stop(const std::string& recipe, const std::string& line, const std::string& limit) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "timing of the set-up under the sanitizers";
#endif
  TempDir dir;
  const std::string path = dir.write("recipe.lua", recipe);
  const RecipeResult r = run_bliskrun({path, "--quiet", "--out", dir.path() + "/out", "--time-limit", limit});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("recipe.lua:" + line + ": "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("time limit of " + limit + " s exceeded (--time-limit)"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("stopped by the watchdog"), std::string::npos) << r.output;
}

TEST(CooperativeCancel, PlanningStopsAtItsLine) {
  // The set-up takes ~0.3 s, the full pressure flank at a 4 um residual ~3 s.
  expect_cooperative_stop(std::string(kPlanSetup) +
                              "finish.plan(blisk, 1, \"pressure\", wheel, world, {c_range = 30, residual = 0.004})\n",
                          "7", "1");
}

TEST(CooperativeCancel, SimulationStopsAtItsLine) {
  // A small plan (a few rows, seconds even on a loaded machine), then a
  // simulation far too fine to finish (24 M samples: minutes).
  expect_cooperative_stop(std::string(kPlanSetup) +
                              "local plan = finish.plan(blisk, 1, \"suction\", wheel, world, {c_range = 30, residual = 0.1})\n"
                              "plan:simulate{samples_u = 2000, samples_v = 12000}\n",
                          "8", "15");
}

TEST(CooperativeCancel, PostingStopsAtItsLine) {
  // 100 000 moves swinging C by 30 deg each: every one split many times.
  expect_cooperative_stop(
      "local m = bliskrun.machine.load(\"dmg_like_ac_trunnion\")\n"
      "local path = {{kind = \"rapid\", tip = {40, 0, 30}, axis = {0, -0.5, 0.866}}}\n"
      "for i = 1, 100000 do\n"
      "  local a = math.rad(30 * (i % 2))\n"
      "  path[#path + 1] = {kind = \"feed\", tip = {40, 0, 5}, axis = {0.5 * math.sin(a), -0.5 * math.cos(a), 0.866}, feed = 500}\n"
      "end\n"
      "bliskrun.post.write{machine = m, post = \"fanuc\", path = path, file = \"x.nc\", tool = {number = 1, length = 80}}\n",
      "7", "3");
}

// The same programs posted at once: each worker (its machine motion, its
// post in its own Lua state) stops at the limit too.
TEST(CooperativeCancel, PostingAtOnceStopsAtItsLine) {
  expect_cooperative_stop(
      "local m = bliskrun.machine.load(\"dmg_like_ac_trunnion\")\n"
      "local path = {{kind = \"rapid\", tip = {40, 0, 30}, axis = {0, -0.5, 0.866}}}\n"
      "for i = 1, 100000 do\n"
      "  local a = math.rad(30 * (i % 2))\n"
      "  path[#path + 1] = {kind = \"feed\", tip = {40, 0, 5}, axis = {0.5 * math.sin(a), -0.5 * math.cos(a), 0.866}, feed = 500}\n"
      "end\n"
      "bliskrun.post.write_all{{machine = m, post = \"fanuc\", path = path, file = \"x.nc\", tool = {number = 1, length = 80}},\n"
      "                        {machine = m, post = \"fanuc\", path = path, file = \"y.nc\", tool = {number = 1, length = 80}}}\n",
      "7", "3");
}

}  // namespace
}  // namespace bliskrun::test
