// Lua bindings of tools and collision: errors land on the recipe line with
// the parameter's name. (The documented examples run in docs_examples_test.)
#include <gtest/gtest.h>

#include "test_support.h"

namespace bliskrun::test {
namespace {

class LuaToolsCollisionErrors : public ::testing::TestWithParam<RecipeErrorCase> {};

TEST_P(LuaToolsCollisionErrors, NameTheParameterAtTheRecipeLine) {
  TempDir dir;
  EXPECT_TRUE(fails_at_line_2(dir, GetParam()));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, LuaToolsCollisionErrors,
    ::testing::Values(
        RecipeErrorCase{"barrel_below_half_diameter", "bliskrun.drum_wheel{max_diameter=8, barrel_radius=3, head_length=4}",
                  "barrel_radius: R_c = 3 mm is below D_t/2 = 4 mm"},
        RecipeErrorCase{"corner_above_radius", "bliskrun.flat_end_mill{radius=5, corner_radius=6, flute_length=20}",
                  "corner_radius: r = 6 mm exceeds the tool radius R = 5 mm"},
        RecipeErrorCase{"negative_size", "bliskrun.contact_wheel{radius=50, width=-2}", "option 'width'"},
        RecipeErrorCase{"unknown_key", "bliskrun.ball_end_mill{radius=3, flute_lenght=15}",
                  "unknown option 'flute_lenght'"},
        RecipeErrorCase{"unknown_shank_key",
                  "bliskrun.drum_wheel{max_diameter=8, barrel_radius=50, head_length=4, shank={diam=6}}",
                  "bliskrun.drum_wheel.shank: unknown option 'diam'"},
        RecipeErrorCase{"bad_part", "bliskrun.ball_end_mill{radius=3, flute_length=15}:signed_distance({0,0,0}, 'arbor')",
                  "part: expected \"cutter\", \"shank\" or \"holder\""},
        RecipeErrorCase{"mesh_index",
                  "bliskrun.collision_world{surfaces={{name='a', mesh={vertices={{0,0,0},{1,0,0},{0,1,0}}, "
                  "triangles={{1,2,4}}}}}}",
                  "triangles[1]: vertex index 4 outside 1..3"},
        RecipeErrorCase{"mesh_or_surface", "bliskrun.collision_world{surfaces={{name='a'}}}",
                  "give exactly one of 'mesh' and 'surface'"},
        RecipeErrorCase{"clearance_key",
                  "local w = bliskrun.collision_world{surfaces={{name='a', mesh={vertices={{0,0,0},{1,0,0},{0,1,0}}, "
                  "triangles={{1,2,3}}}}}}; "
                  "w:check(bliskrun.ball_end_mill{radius=3, flute_length=15}, {tip={0,0,5}, axis={0,0,1}}, "
                  "{clearance={shnak=1}})",
                  "unknown option 'shnak'"}),
    error_case_name);

}  // namespace
}  // namespace bliskrun::test
