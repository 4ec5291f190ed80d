// bliskrun.simulate: a ball held a known height over a sample of the
// impeller's hub (a surface of revolution) leaves exactly that height there,
// pushed below it reports the overcut with its pass, pose and point; bad
// passes are errors naming the pass.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/common/raster.h"
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

std::string simulate_lua_slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// What an SVG map draws between its plot and the colour bar's caption: the
// plot's frame, the axes, the colour bar and its labels.
std::string simulate_lua_bar(const std::string& svg) {
  const size_t at = svg.find(">µm</text>");
  if (at == std::string::npos) return {};
  const size_t from = svg.rfind("</g>", at);
  return svg.substr(from, at - from);
}

// Maps read at a glance (issue 37): a map's values are drawn in µm on the
// scale given (two maps of different material left, one scale: the same
// colour bar, labelled in µm with 3 digits); a mosaic names its tiles,
// names its axes without 0..1 ticks, and its gaps are "not part of this
// map", apart from the "never reached" samples.
TEST(SimulateLua, MapsShareAFixedScaleInMicronsAndAMosaicLabelsItsTiles) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir,
      "local hub = bliskrun.impeller{}:hub()\n"
      "local ball = bliskrun.ball_end_mill{radius = 3, flute_length = 10}\n"
      "local d = hub:eval(0.5, 0.005)\n"
      "local p, n = d.point, d.normal\n"
      "local radial = math.sqrt(p.x ^ 2 + p.y ^ 2)\n"
      "local flip = n.x * p.x / radial + n.y * p.y / radial + n.z < 0\n"
      "local s = flip and -1 or 1\n"
      "local function over(h) return {tip = {p.x + s * h * n.x, p.y + s * h * n.y, p.z + s * h * n.z},\n"
      "                              axis = {s * n.x, s * n.y, s * n.z}} end\n"
      "local function run(h, v)\n"
      "  return bliskrun.simulate{surface = hub, passes = {{tool = ball, poses = {over(h)}}}, samples_u = 3,\n"
      "                           samples_v = 3, u = {0.4, 0.6}, v = v, flip_normal = flip,\n"
      "                           search_above = 1, search_below = 0.5}\n"
      "end\n"
      "-- a: 5 um left under the ball; b: a window the ball never comes near\n"
      "local a, b = run(0.005, {0, 0.01}), run(0.005, {0.3, 0.31})\n"
      "assert(b.untouched == 9 and a.residual_min < 0.01, tostring(a.residual_min))\n"
      "a.map:write_svg('a.svg', {scale_um = 30})\n"
      "b.map:write_svg('b.svg', {scale_um = 30})\n"
      "a.map:write_svg('a_auto.svg')\n"
      "local m = bliskrun.map_mosaic{rows = {{{map = a.map, label = 'pressure flank'}, {map = b.map, label = 'leading edge', transpose = true}}},\n"
      "                              u_label = 'up: span, hub to tip', v_label = 'across: chord'}\n"
      "m:write_svg('mosaic.svg', {scale_um = 30})\n"
      "m:write_png('mosaic.png', {scale_um = 30})\n"
      "local ok, err = pcall(bliskrun.map_mosaic, {rows = {{{map = a.map, label = {}}}}})\n"
      "assert(not ok and err:find('rows%[1%]%[1%]%.label: expected text'), err)\n"
      "ok, err = pcall(a.map.write_png, a.map, 'x.png', {scale = 0.03})\n"
      "assert(not ok and err:find('scale_um'), err)\n");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string out = dir.path() + "/out/";
  const std::string a = simulate_lua_slurp(out + "a.svg"), b = simulate_lua_slurp(out + "b.svg");
  const std::string bar = simulate_lua_bar(a);
  ASSERT_FALSE(bar.empty()) << a;
  EXPECT_EQ(bar, simulate_lua_bar(b));
  for (const char* label : {">-30.0</text>", ">-15.0</text>", ">0</text>", ">15.0</text>", ">30.0</text>"})
    EXPECT_NE(bar.find(label), std::string::npos) << label << bar;
  EXPECT_NE(b.find(">never reached</text>"), std::string::npos);
  EXPECT_EQ(a.find("e-0"), std::string::npos);
  // Without scale_um: the largest |value| (a few µm) rounded up to 1, 2, 3 or 5 x 10^k.
  const std::string automatic = simulate_lua_slurp(out + "a_auto.svg");
  EXPECT_EQ(automatic.find(">30.0</text>"), std::string::npos);
  EXPECT_EQ(automatic.find("e-0"), std::string::npos);
  const std::string mosaic = simulate_lua_slurp(out + "mosaic.svg");
  EXPECT_NE(mosaic.find("\">pressure flank</text>"), std::string::npos);
  EXPECT_NE(mosaic.find("\">leading edge</text>"), std::string::npos);
  EXPECT_NE(mosaic.find(">up: span, hub to tip</text>"), std::string::npos);
  EXPECT_NE(mosaic.find(">across: chord</text>"), std::string::npos);
  EXPECT_EQ(mosaic.find(">0.25</text>"), std::string::npos);  // no 0..1 ticks across a mosaic
  EXPECT_NE(mosaic.find(">not part of this map</text>"), std::string::npos);  // the gaps
  EXPECT_NE(mosaic.find(">never reached</text>"), std::string::npos);        // b's samples
  const RgbImage png = decode_png(simulate_lua_slurp(out + "mosaic.png"), "mosaic.png");
  EXPECT_GT(png.width, 800);
}

}  // namespace
}  // namespace bliskrun::test
