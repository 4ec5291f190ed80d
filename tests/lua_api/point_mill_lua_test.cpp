// bliskrun.point_mill from Lua: bad options name the problem at the recipe's
// line (the options' checks are the binding's; the planner's own errors come
// through as ParameterError naming the option).
#include <gtest/gtest.h>

#include <string>

#include "test_support.h"

namespace bliskrun::test {
namespace {

class LuaPointMillErrors : public ::testing::TestWithParam<RecipeErrorCase> {};

TEST_P(LuaPointMillErrors, NameTheProblemAtTheRecipeLine) {
  TempDir dir;
  EXPECT_TRUE(fails_at_line_2(dir, GetParam()));
}

// A 20 mm wide flat face, 60 mm long, and a tapered ball end.
#define PM_FACE "bliskrun.point_grid{rows = 2, cols = 2, points = {{0,0,0},{0,60,0},{20,0,0},{20,60,0}}}:surface()"
#define PM_TOOL "bliskrun.tapered_ball_end_mill{tip_radius = 2, half_angle = 2, flute_length = 40}"

// The built-in impeller's splitter plus face, a window at its hub: rows
// stopped 6 mm above the hub edge (main's behaviour) leave the root strip
// (fillet line to the stop) millimetres thick; carried down to the fillet
// line they leave it within the scallop and the chord's sag — the strip's
// material checked in Lua against every move's ball centre (brute force,
// segments sub-sampled every 0.02 mm) at the measure's own worst point and
// between its samples.
TEST(LuaPointMill, RowsCarriedDownToTheFilletFinishTheBuiltInImpellersRootStrip) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "two point-milling plans: a second or two in Release, a minute sanitized";
#endif
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, R"LUA(
local imp = bliskrun.impeller{}
local tool = bliskrun.tapered_ball_end_mill{tip_radius = 2, half_angle = 2, flute_length = 60}
local face = imp:face(1, "plus", "splitter")
local function plan_of(follow)
  return bliskrun.point_mill{face = face, tool = tool, u = {0, 0.25}, v = {0.49, 0.51}, scallop = 0.03,
                             chord_tol = 0.01, hub = imp:hub(), follow_fillet = follow, hub_stop = 6, threads = 2,
                             allowed_overcut = 0.01, guard_spacing = 0.25}  -- coarse guards: a lighter test
end
local function brute(plan, u, v)
  local p = face:point(u, v)
  local best, prev = math.huge, nil
  for _, m in ipairs(plan:moves()) do
    local c = {m.tip[1] + 2 * m.axis[1], m.tip[2] + 2 * m.axis[2], m.tip[3] + 2 * m.axis[3]}
    local a = prev or c
    local len = math.sqrt((c[1] - a[1]) ^ 2 + (c[2] - a[2]) ^ 2 + (c[3] - a[3]) ^ 2)
    local n = math.max(1, math.ceil(len / 0.02))
    for k = 0, n do
      local t = k / n
      local q = {a[1] + t * (c[1] - a[1]), a[2] + t * (c[2] - a[2]), a[3] + t * (c[3] - a[3])}
      best = math.min(best, math.sqrt((p[1] - q[1]) ^ 2 + (p[2] - q[2]) ^ 2 + (p[3] - q[3]) ^ 2))
    end
    prev = c
  end
  return best - 2
end
local stopped, followed = plan_of(false), plan_of(true)
assert(stopped:report().complete and followed:report().complete)
assert(not stopped:report().follows_fillet and followed:report().follows_fillet)
local before, after = stopped:root_strip{samples = {6, 9}}, followed:root_strip{samples = {6, 9}}
assert(before.from_fillet and after.from_fillet and math.abs(before.u0 - after.u0) < 1e-12
       and math.abs(before.height - after.height) < 1e-9, "not the same band")
-- The measure is the brute force's at its worst point.
assert(math.abs(before.left_max - brute(stopped, before.max_u, before.max_v)) < 1e-3, "before")
assert(math.abs(after.left_max - brute(followed, after.max_u, after.max_v)) < 1e-3, "after")
-- And at points of the band between the measure's samples the brute force
-- finds no more than the scallop and the chord's sag.
for i = 0, 2 do
  for j = 0, 2 do
    local v = 0.49 + 0.02 * j / 2
    local u = after.u1 - (after.u1 - after.u0) * (i + 0.5) / 3
    if u > after.u0 + 0.01 then  -- above the fillet line at every v of the window
      local left = brute(followed, u, v)
      assert(left <= 0.03 + 0.01 + 1e-3, string.format("(%g, %g): %g mm left", u, v, left))
    end
  end
end
assert(before.left_max > 1, "stopped: the strip is millimetres thick")
assert(after.left_max <= 0.03 + 0.01 + 1e-3, "followed: within the scallop and the chord")
)LUA");
  ASSERT_EQ(r.exit_code, 0) << r.output;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, LuaPointMillErrors,
    ::testing::Values(
        RecipeErrorCase{"UnknownOption", "bliskrun.point_mill{face = " PM_FACE ", tool = " PM_TOOL ", scalop = 0.01}",
                        "unknown option 'scalop'"},
        RecipeErrorCase{"Rows", "bliskrun.point_mill{face = " PM_FACE ", tool = " PM_TOOL ", rows = \"diagonal\"}",
                        "option 'rows'"},
        RecipeErrorCase{"Window", "bliskrun.point_mill{face = " PM_FACE ", tool = " PM_TOOL ", u = {0.5, 0.2}}",
                        "option 'u'"},
        RecipeErrorCase{"NotATool", "bliskrun.point_mill{face = " PM_FACE ", tool = 3}", "option 'tool'"},
        RecipeErrorCase{"FlatEnd",
                        "bliskrun.point_mill{face = " PM_FACE ", tool = bliskrun.flat_end_mill{radius = 3, "
                        "flute_length = 20}}",
                        "ball"},
        RecipeErrorCase{"LeanInsideTaper",
                        "bliskrun.point_mill{face = " PM_FACE ", tool = bliskrun.tapered_ball_end_mill{tip_radius = 2, "
                        "half_angle = 12, flute_length = 40}, lean = 5}",
                        "lean"},
        RecipeErrorCase{"Neighbour", "bliskrun.point_mill{face = " PM_FACE ", tool = " PM_TOOL ", neighbours = {3}}",
                        "option 'neighbours' [1]"},
        RecipeErrorCase{"HubNotARevolution",
                        "bliskrun.point_mill{face = " PM_FACE ", tool = " PM_TOOL ", hub = " PM_FACE "}",
                        "option 'hub': expected a surface of revolution"}),
    error_case_name);

}  // namespace
}  // namespace bliskrun::test
