// The tilt-until-clear loop on the built-in blisk: a drum wheel on the
// pressure flank of blade 1, checked against the neighbouring blades and the
// hub, with the paper's C-axis limit.
#include <gtest/gtest.h>

#include "test_support.h"

namespace bliskrun::test {
namespace {

TEST(BliskInterference, TiltLoopClearsTheNeighbouringBladesOrRefuses) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, R"(
local blisk_world = require("blisk_world")
local blisk = bliskrun.blisk{grid_rows = 40, grid_cols = 120}
local world = blisk_world.around_blade(blisk, 1, {chord_tol = 0.02})
assert(#world:names() == 13)  -- 4 neighbouring flanks and their 4 edge rounds, hub, own flanks and rounds for the shank
local wheel = bliskrun.drum_wheel{max_diameter = 8, barrel_radius = 50, head_length = 4,
                                  shank = {diameter = 6, length = 96}}
-- Contacts on blade 1's pressure flank: five at mid-span, four at u = 0.06,
-- which is below the hub (the flank reaches past it as a CAD grid does), so
-- the wheel sits in the hub there. The wheel axis at lambda = 0 lies in the
-- tangent plane across the feed, towards the tip.
local flank = blisk:flank(1, "pressure")
local contacts = {}
for j = 1, 9 do
  local e = flank:eval(j <= 5 and 0.5 or 0.06, 0.1 * j)
  local t = e.pv
  -- Y = Z x X must point to the tip (+pu): choose the travel direction so.
  local n = e.normal
  local y = {n[2]*t[3] - n[3]*t[2], n[3]*t[1] - n[1]*t[3], n[1]*t[2] - n[2]*t[1]}
  if y[1]*e.pu[1] + y[2]*e.pu[2] + y[3]*e.pu[3] < 0 then t = {-t[1], -t[2], -t[3]} end
  contacts[#contacts + 1] = {point = e.point, tangent = t, normal = n}
end
local c = {cutter = 0.2, shank = 0.5}
local run = world:tilt(wheel, contacts, {clearance = c, lead_step = 0.5, lead_max = 60,
  -- Blade 1 stands at theta = 0: its radial direction +X is the C reference.
  axis_limit = {name = "C", rotary_axis = {0, 0, 1}, reference = {1, 0, 0}, min = -30, max = 30}})
assert(#run.poses + #run.refusals == 9, "every contact is either emitted or refused")
assert(#run.poses == 5, "the mid-span contacts clear, got " .. #run.poses)
for _, f in ipairs(run.refusals) do assert(f.index >= 6, "refused a mid-span contact " .. f.index) end
for _, p in ipairs(run.poses) do
  -- Independent check of every emitted pose.
  local chk = world:check(wheel, {tip = p.tip, axis = p.axis}, {clearance = c})
  assert(chk.clear, "emitted pose " .. p.index .. " is not clear")
end
for _, f in ipairs(run.refusals) do assert(#f.reason > 0) end
-- A contact below the hub cannot be cleared within the C limit: the reason
-- says what was tried and what stopped it.
assert(run.refusals[1].reason:find("no axis clears"), run.refusals[1].reason)
)");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// The blade's own edge rounds are check surfaces for the shank and holder
// (blisk_world.around_blade's own block): a shank lying along the span in
// front of blade 1's leading edge, 20 um into its round near the tip, is
// refused against the round (without the own rounds its nearest surface
// was its own pressure flank, 0.33 mm off, and the test failed);
// 0.2 mm off the round it is clear; and the cutter resting in the round is
// not refused (it touches its own blade by design).
TEST(BliskInterference, TheShankIsCheckedAgainstTheBladesOwnEdgeRounds) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, R"lua(
local blisk_world = require("blisk_world")
local blisk = bliskrun.blisk{grid_rows = 40, grid_cols = 120}
local world = blisk_world.around_blade(blisk, 1, {chord_tol = 0.02})
local tool = bliskrun.flat_end_mill{radius = 3, corner_radius = 0.5, flute_length = 9,
                                    shank = {diameter = 6, length = 50}, holder = {diameter = 12, length = 40}}
-- The front of the round (u 0.5) at 0.85 of its span, its normal out of the
-- blade; the tool's axis up the span, the shank's axis 3 mm - depth in
-- front of the round, its lower end 1 mm below the point.
local e = blisk_world.edge_round(blisk, 1, "leading").surface:eval(0.5, 0.85)
local n, a = e.normal, e.pv
local la = math.sqrt(a[1]^2 + a[2]^2 + a[3]^2)
a = {a[1] / la, a[2] / la, a[3] / la}
local function shank_at(depth)
  local off, back = 3 - depth, 10
  return {tip = {e.point[1] + off * n[1] - back * a[1], e.point[2] + off * n[2] - back * a[2],
                 e.point[3] + off * n[3] - back * a[3]}, axis = a}
end
local function part(check, name)
  for _, p in ipairs(check.parts) do if p.part == name then return p end end
end
local into = world:check(tool, shank_at(0.02))
local shank = part(into, "shank")
assert(not into.clear and shank.object == "blade 1 leading edge (own)" and shank.distance < 0.05,
       string.format("shank: %s at %.4f mm", tostring(shank.object), shank.distance))
local off = world:check(tool, shank_at(-0.2))
assert(off.clear, "0.2 mm off the round: " .. tostring(off.worst))
local cutter = world:check(tool, {tip = {e.point[1] - 0.01 * n[1], e.point[2] - 0.01 * n[2], e.point[3] - 0.01 * n[3]},
                                  axis = n})
assert(cutter.clear, "the cutter in its own round: " .. tostring(cutter.worst))
)lua");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

}  // namespace
}  // namespace bliskrun::test

namespace bliskrun::test {
namespace {

TEST(BliskInterference, MachineTravelLimitsTheTiltLoop) {
  // The blisk paper's machine (C table within +-30 deg, B head): a wheel
  // axis across the feed at azimuth 90 deg is out of its reach, so the loop
  // refuses the contact and says the machine is why.
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, R"(
local paper = bliskrun.machine.define{
  name = "blisk paper machine",
  linear = {X = {-500, 500}, Y = {-500, 500}, Z = {-500, 500}},
  rotary = {{name = "C", carrier = "part", direction = {0, 0, 1}, travel = {-30, 30}},
            {name = "B", carrier = "tool", direction = {0, 1, 0}, pivot = {0, 0, 200}, travel = {-90, 90}}},
}
local wheel = bliskrun.drum_wheel{max_diameter = 8, barrel_radius = 50, head_length = 4,
                                  shank = {diameter = 6, length = 96}}
local world = bliskrun.collision_world{surfaces = {
  {name = "far plate", mesh = {vertices = {{-50, 500, -5}, {50, 500, -5}, {50, 500, 5}},
                               triangles = {{1, 2, 3}}}}}}
local contact = {point = {0, 0, 0}, tangent = {1, 0, 0}, normal = {0, 0, 1}}
local free = world:tilt(wheel, {contact}, {})
assert(#free.poses == 1, "without a machine the pose is clear")
local run = world:tilt(wheel, {contact}, {machine = paper, lead_max = 45})
assert(#run.poses == 0 and #run.refusals == 1)
assert(run.refusals[1].reason:find("machine 'blisk paper machine'"), run.refusals[1].reason)
local ok, msg = pcall(function() return world:tilt(wheel, {contact}, {machine = 5}) end)
assert(not ok and msg:find("expected a bliskrun.machine"), msg)
)");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

}  // namespace
}  // namespace bliskrun::test
