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

TEST(PointMillHeccRecipe, EveryPoseOfAMainFaceWindowIsClearOfAFinerTessellation) {
  if (shared_data_dir().empty()) GTEST_SKIP() << "../shared/data not present: HECC point-milling recipe skipped";
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "HECC point milling skipped under the sanitizers (runs in the Release suite)";
#endif
  TempDir dir;
  const std::string recipe = dir.write("recipe.lua", R"(
local iw = require("impeller_world")
local part = require("hecc_impeller_part").load{set = "design"}
local cutter = bliskrun.tapered_ball_end_mill{tip_radius = 2, half_angle = 2, flute_length = 90,
                                              shank = {diameter = 12, length = 60},
                                              holder = {diameter = 40, length = 60}}
local face, back = iw.design_face(part, 1, "minus", "main"), iw.design_face(part, 1, "plus", "main")
local e, q = face:eval(0.5, 0.5), back:point(0.5, 0.5)
local flip = e.normal[1] * (e.point[1] - q[1]) + e.normal[2] * (e.point[2] - q[2]) + e.normal[3] * (e.point[3] - q[3]) < 0
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

}  // namespace
}  // namespace bliskrun::test
