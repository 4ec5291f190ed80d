// bliskrun.simulate: a ball held a known height over a sample of the
// impeller's hub (a surface of revolution) leaves exactly that height there,
// pushed below it reports the overcut with its pass, pose and point; bad
// passes are errors naming the pass.
#include <gtest/gtest.h>

#include "test_support.h"

namespace bliskrun::test {
namespace {

TEST(SimulateLua, ABallOverTheHubLeavesItsHeightAndAGougeIsLocated) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir,
      "local hub = bliskrun.impeller{}:hub()\n"
      "local ball = bliskrun.ball_end_mill{radius = 3, flute_length = 10}\n"
      "-- samples: u in {0.4, 0.5, 0.6}, v in {0, 0.005, 0.01}; the middle one is (0.5, 0.005)\n"
      "local d = hub:eval(0.5, 0.005)\n"
      "local p, n = d.point, d.normal\n"
      "local radial = math.sqrt(p.x ^ 2 + p.y ^ 2)\n"
      "local flip = n.x * p.x / radial + n.y * p.y / radial + n.z < 0\n"
      "local s = flip and -1 or 1\n"
      "local function over(h) return {tip = {p.x + s * h * n.x, p.y + s * h * n.y, p.z + s * h * n.z},\n"
      "                              axis = {s * n.x, s * n.y, s * n.z}} end\n"
      "local function run(h)\n"
      "  return bliskrun.simulate{surface = hub, passes = {{tool = ball, poses = {over(h)}}}, samples_u = 3,\n"
      "                           samples_v = 3, u = {0.4, 0.6}, v = {0, 0.01}, flip_normal = flip,\n"
      "                           search_above = 1, search_below = 0.5}\n"
      "end\n"
      "local a = run(0.2)\n"
      "assert(math.abs(a.residual_min - 0.2) < 1e-4, a.residual_min)\n"
      "assert(a.overcut == 0 and a.overcut_pass == nil and a.samples == 9 and a.poses == 1)\n"
      "local b = run(-0.05)\n"
      "assert(math.abs(b.overcut + 0.05) < 1e-4, b.overcut)\n"
      "assert(b.overcut_pass == 1 and b.overcut_pose == 1)\n"
      "assert(math.abs(b.overcut_u - 0.5) < 1e-12 and math.abs(b.overcut_v - 0.005) < 1e-12)\n"
      "assert(math.abs(b.overcut_point.x - p.x) < 1e-9 and math.abs(b.overcut_point.z - p.z) < 1e-9)\n"
      "-- the most material left, and where: the middle sample alone kept holds the ball's height\n"
      "local middle = {false, false, false, false, true, false, false, false, false}\n"
      "local function run_kept(h, keep, v)\n"
      "  return bliskrun.simulate{surface = hub, passes = {{tool = ball, poses = {over(h)}}}, samples_u = 3,\n"
      "                           samples_v = 3, u = {0.4, 0.6}, v = v or {0, 0.01}, flip_normal = flip, keep = keep}\n"
      "end\n"
      "local k = run_kept(0.2, middle)\n"
      "assert(math.abs(k.residual_max - 0.2) < 1e-4 and k.residual_max_u == 0.5, k.residual_max)\n"
      "assert(math.abs(k.residual_max_v - 0.005) < 1e-12 and math.abs(k.residual_max_point.y - p.y) < 1e-9)\n"
      "assert(a.residual_max >= a.residual_min and a.residual_max_point ~= nil)\n"
      "-- the gouge's sample dropped: the deepest kept sample's motion is not known (it read pass 0)\n"
      "local others = {}\n"
      "for i = 1, 9 do others[i] = not middle[i] end\n"
      "local c = run_kept(-0.05, others, {0.0049, 0.0051})  -- its neighbours along v gouged too\n"
      "assert(c.overcut < 0 and c.overcut > b.overcut and c.overcut_pass == nil and c.overcut_pose == nil, tostring(c.overcut_pass))\n"
      "-- two groups: each is swept alone, the whole is the lower of the two\n"
      "local g = bliskrun.simulate{surface = hub, passes = {{tool = ball, poses = {over(0.3)}, group = 'high'},\n"
      "                                                    {tool = ball, poses = {over(-0.02)}, group = 'low'}},\n"
      "                            samples_u = 3, samples_v = 3, u = {0.4, 0.6}, v = {0, 0.01}, flip_normal = flip}\n"
      "assert(#g.groups == 2 and g.groups[1].name == 'high' and g.groups[2].name == 'low')\n"
      "assert(math.abs(g.groups[1].residual_min - 0.3) < 1e-4 and g.groups[1].overcut == 0)\n"
      "assert(math.abs(g.overcut + 0.02) < 1e-4 and g.overcut_pass == 2 and g.overcut_pose == 1)\n"
      "assert(g.poses == 2 and g.groups[2].overcut_pass == 2)\n"
      "local ok, err = pcall(bliskrun.simulate, {surface = hub, passes = {{tool = ball, poses = {over(0)}, group = 'a'},\n"
      "                                                                 {tool = ball, poses = {over(0)}}}})\n"
      "assert(not ok and err:find('every pass or none has a group'), err)\n"
      "ok, err = pcall(bliskrun.simulate, {surface = hub, passes = {{tool = ball, poses = {over(0)}}, {poses = {}}}})\n"
      "assert(not ok and err:find(\"passes%[2%].tool: expected a bliskrun.Tool\"), err)\n"
      "ok, err = pcall(bliskrun.simulate, {surface = hub, passes = {}, v = {0.5, 0.2}})\n"
      "assert(not ok and err:find(\"option 'v': expected {lo, hi}\"), err)\n");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

}  // namespace
}  // namespace bliskrun::test
