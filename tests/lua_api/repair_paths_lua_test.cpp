// bliskrun.repair_paths{...} and bliskrun.close_blade{...}: bad options land
// on the recipe line and say what was expected.
#include <gtest/gtest.h>

#include "test_support.h"

namespace bliskrun::test {
namespace {

class LuaRepairPathErrors : public ::testing::TestWithParam<RecipeErrorCase> {};

TEST_P(LuaRepairPathErrors, NameTheProblemAtTheRecipeLine) {
  TempDir dir;
  EXPECT_TRUE(fails_at_line_2(dir, GetParam()));
}

// A 20 x 60 mm flat face, a ball-end mill and a world with one far plate,
// on the line of every case.
#define SETUP                                                                                                   \
  "local face = bliskrun.point_grid{rows = 2, cols = 2, points = {{0,0,0},{0,60,0},{20,0,0},{20,60,0}}}:surface(); " \
  "local ball = bliskrun.ball_end_mill{radius = 3, flute_length = 12}; "                                        \
  "local world = bliskrun.collision_world{surfaces = {{name = 'far', mesh = {vertices = "                       \
  "{{500,0,0},{501,0,0},{501,1,0}}, triangles = {{1,2,3}}}}}}; "

INSTANTIATE_TEST_SUITE_P(
    Cases, LuaRepairPathErrors,
    ::testing::Values(
        RecipeErrorCase{"unknown_key", SETUP "bliskrun.repair_paths{design = face, tool = ball, world = world, scalop = 0.01}",
                        "unknown option 'scalop'"},
        RecipeErrorCase{"missing_world", SETUP "bliskrun.repair_paths{design = face, tool = ball}", "option 'world'"},
        RecipeErrorCase{"pattern_choice",
                        SETUP "bliskrun.repair_paths{design = face, tool = ball, world = world, pattern = 'spiral2'}",
                        "option 'pattern'"},
        RecipeErrorCase{"scallop_type",
                        SETUP "bliskrun.repair_paths{design = face, tool = ball, world = world, scallop = 'fine'}",
                        "option 'scallop'"},
        RecipeErrorCase{"window", SETUP "bliskrun.repair_paths{design = face, tool = ball, world = world, u = {0.5, 0.2}}",
                        "option 'u': expected {lo, hi} with 0 <= lo < hi <= 1"},
        RecipeErrorCase{"zigzag_across_the_seam",
                        SETUP "bliskrun.repair_paths{design = face, tool = ball, world = world, v = {0.9, 0.1}}",
                        "the region crosses the surface's seam (v from 0.9 round through 0 to 0.1)"},
        RecipeErrorCase{"not_a_ball",
                        SETUP "bliskrun.repair_paths{design = face, world = world, tool = "
                              "bliskrun.flat_end_mill{radius = 3, corner_radius = 0.5, flute_length = 12}}",
                        "expected a ball-end mill"},
        RecipeErrorCase{"deposit_below_stock",
                        SETUP "bliskrun.repair_paths{design = face, tool = ball, world = world, deposit = 0.1, stock = 0.2}",
                        "deposit: expected at least the stock"},
        RecipeErrorCase{"close_blade_unknown", SETUP "bliskrun.close_blade{pressure = face, suction = face, sectons = 3}",
                        "unknown option 'sectons'"},
        RecipeErrorCase{"close_blade_sections", SETUP "bliskrun.close_blade{pressure = face, suction = face, sections = 1}",
                        "option 'sections'"}),
    error_case_name);

// A small finishing plan over a flat face through Lua: moves in the posts'
// shape, the zigzag's passes joined by bridges, nothing refused.
TEST(LuaRepairPaths, PlansAZigzagWithBridgesOverAFace) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, std::string(SETUP) + R"(
local plan = bliskrun.repair_paths{design = face, tool = ball, world = world, u = {0.2, 0.3}, v = {0.4, 0.5},
                                   deposit = 1, layer = 0.5, stock = 0.2, scallop = 0.01}
assert(#plan.layers == 3 and plan.layers[3].finishing and math.abs(plan.layers[1].offset - 0.7) < 1e-12, #plan.layers)
assert(plan.refused_connections == 0 and #plan.refusals == 0)
assert(plan.bridges > 0 and plan.links == 2, plan.links)   -- the links join the layers
local kinds = {}
for _, m in ipairs(plan.moves) do kinds[m.motion] = (kinds[m.motion] or 0) + 1 end
assert(kinds["lead-out"] and kinds.bridge and kinds["lead-in"] and kinds.cut and kinds.retract)
assert(plan.moves[plan.first_finishing_move].layer == 3 and plan.moves[plan.first_finishing_move - 1].layer == 2)
)");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

}  // namespace
}  // namespace bliskrun::test
