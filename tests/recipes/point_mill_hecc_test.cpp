// Point milling (issue 40) of a real face: a chord-wise window of the NASA
// HECC impeller's main-blade minus face (the lofted face, the one flank
// milling misses by 0.23 mm) planned with its own world (the blades either
// side and the hub, 0.05 mm meshes; the hub for the cutter too, exactly)
// through the executable; every emitted
// move then checked in an independent collision check against a finer
// tessellation (0.01 mm) of the same surfaces, and the plan's moves
// simulated on the lofted face. Skipped without ../shared/data.
#include <gtest/gtest.h>

#include <string>

#include "test_support.h"

namespace bliskrun::test {
namespace {

// Both tests' start: blade 1's main minus face of the HECC design, the r 2
// tapered ball, and which way the face's normal points out of the material.
const char* const kHeccMainMinusFace = R"LUA(
local iw = require("impeller_world")
local part = require("hecc_impeller_part").load{set = "design"}
local cutter = bliskrun.tapered_ball_end_mill{tip_radius = 2, half_angle = 2, flute_length = 90,
                                              shank = {diameter = 12, length = 60},
                                              holder = {diameter = 40, length = 60}}
local face, back = iw.design_face(part, 1, "minus", "main"), iw.design_face(part, 1, "plus", "main")
local e, q = face:eval(0.5, 0.5), back:point(0.5, 0.5)
local flip = e.normal[1] * (e.point[1] - q[1]) + e.normal[2] * (e.point[2] - q[2]) + e.normal[3] * (e.point[3] - q[3]) < 0
)LUA";

TEST(PointMillHeccRecipe, EveryPoseOfAMainFaceWindowIsClearOfAFinerTessellation) {
  if (shared_data_dir().empty()) GTEST_SKIP() << "../shared/data not present: HECC point-milling recipe skipped";
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "HECC point milling skipped under the sanitizers (runs in the Release suite)";
#endif
  TempDir dir;
  const std::string recipe = dir.write("recipe.lua", std::string(kHeccMainMinusFace) + R"(
local plan = bliskrun.point_mill{face = {surface = face, flip = flip}, tool = cutter,
                                 world = iw.face_world(part, iw.meshes(part, 0.05), "main", "minus", {hub_cutter = true}),
                                 v = {0.45, 0.55}, scallop = 0.05, chord_tol = 0.02, allowed_overcut = 0.02,
                                 clearance = 0.5, holder_clearance = 0.5}
local r = plan:report()
assert(r.complete, "refused: " .. tostring(r.refusals[1] and r.refusals[1].reason or r.refused[1]))
assert(r.scallop_measured <= 0.05 and r.max_deviation <= 0.02, "scallop or chord beyond the asked")
-- Independent: a world of the same surfaces tessellated five times finer.
local fine = iw.face_world(part, iw.meshes(part, 0.01), "main", "minus", {hub_cutter = true})
local checked = 0
for _, m in ipairs(plan:moves()) do
  local c = fine:check(cutter, {tip = m.tip, axis = m.axis}, {clearance = {cutter = 0, shank = 0.5, holder = 0.5}})
  assert(c.clear, string.format("move %d (%s) not clear of the finer tessellation", checked + 1, m.motion))
  checked = checked + 1
end
local sim = plan:simulate{samples = {40, 20}}
assert(sim.overcut > -0.02 and sim.left_max < 0.05, string.format("left %.4f overcut %.4f", sim.left_max, sim.overcut))
print(string.format("POINTMILL rows %d poses %d moves %d scallop %.4f left %.4f overcut %.4f", r.rows, r.poses,
                    checked, r.scallop_measured, sim.left_max, sim.overcut))
)");
  const RecipeResult r = run_bliskrun({recipe, "--data", shared_data_dir(), "--out", dir.path() + "/out", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("POINTMILL rows"), std::string::npos) << r.output;
}

// The same window carried down to the fillet line (issue 40): the first
// row's ball touches the hub. Independently of the planner: every move of
// the tool clear of a 5x finer tessellation of the blades either side (the
// hub for the cutter less the planner's allowance), the ball's centre at
// every move and halfway along every motion at least r less the allowed
// overcut from the exact hub (hub:project), and the root strip — fillet
// line to 6 mm above the face's edge — within the scallop and the chord's
// sag, where the stopped rows of main left it unfinished.
TEST(PointMillHeccRecipe, RowsCarriedDownToTheFilletClearTheHubAndFinishTheStrip) {
  if (shared_data_dir().empty()) GTEST_SKIP() << "../shared/data not present: HECC point-milling recipe skipped";
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "HECC point milling skipped under the sanitizers (runs in the Release suite)";
#endif
  TempDir dir;
  const std::string recipe = dir.write("recipe.lua", std::string(kHeccMainMinusFace) + R"LUA(
local allowance, overcut = 0.3, 0.02
local plan = bliskrun.point_mill{face = {surface = face, flip = flip}, tool = cutter, hub = part:hub(), hub_stop = 6,
                                 world = iw.face_world(part, iw.meshes(part, 0.05), "main", "minus", {hub_cutter = allowance}),
                                 v = {0.45, 0.55}, u = {0, 0.3}, scallop = 0.05, chord_tol = 0.02,
                                 allowed_overcut = overcut, clearance = 0.5, holder_clearance = 0.5}
local r = plan:report()
assert(r.complete, "refused: " .. tostring(r.refusals[1] and r.refusals[1].reason or r.refused[1]))
assert(r.follows_fillet and r.scallop_measured <= 0.05)
local fine = iw.face_world(part, iw.meshes(part, 0.01), "main", "minus", {hub_cutter = allowance})
local hub = part:hub()
local function hub_gap(c)
  local f = hub:project(c)
  return math.sqrt((c[1] - f.point[1]) ^ 2 + (c[2] - f.point[2]) ^ 2 + (c[3] - f.point[3]) ^ 2) - 2
end
local lowest, prev = math.huge, nil
for i, m in ipairs(plan:moves()) do
  local c = fine:check(cutter, {tip = m.tip, axis = m.axis}, {clearance = {cutter = 0, shank = 0.5, holder = 0.5}})
  assert(c.clear, string.format("move %d (%s) not clear of the finer tessellation", i, m.motion))
  local centre = {m.tip[1] + 2 * m.axis[1], m.tip[2] + 2 * m.axis[2], m.tip[3] + 2 * m.axis[3]}
  local g = hub_gap(centre)
  if prev then
    g = math.min(g, hub_gap({0.5 * (centre[1] + prev[1]), 0.5 * (centre[2] + prev[2]), 0.5 * (centre[3] + prev[3])}))
  end
  assert(g >= -overcut, string.format("move %d: the ball %.4f mm into the hub", i, -g))
  lowest, prev = math.min(lowest, g), centre
end
assert(lowest < 0.01, string.format("the first row's ball should touch the hub (%.4f mm off)", lowest))
local strip = plan:root_strip{samples = {6, 20}}
assert(strip.from_fillet and strip.left_max <= 0.05 + 0.02, string.format("strip left %.4f", strip.left_max))
print(string.format("POINTFILLET lowest %.4f strip %.2f mm high left %.4f corner %.3f", lowest, strip.height,
                    strip.left_max, strip.corner_left_max))
)LUA");
  const RecipeResult r = run_bliskrun({recipe, "--data", shared_data_dir(), "--out", dir.path() + "/out", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("POINTFILLET lowest"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace bliskrun::test
