// Lua bindings of tools and collision: errors land on the recipe line with
// the parameter's name. (The documented examples run in docs_examples_test.)
#include <gtest/gtest.h>

#include "test_support.h"

namespace bliskrun::test {
namespace {

struct ErrorCase {
  const char* name;
  const char* call;
  const char* expected;
};

class LuaToolsCollisionErrors : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(LuaToolsCollisionErrors, NameTheParameterAtTheRecipeLine) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, std::string("-- line 1\n") + GetParam().call + "\n");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("recipe.lua:2:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(GetParam().expected), std::string::npos) << r.output;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, LuaToolsCollisionErrors,
    ::testing::Values(
        ErrorCase{"barrel_below_half_diameter", "bliskrun.drum_wheel{max_diameter=8, barrel_radius=3, head_length=4}",
                  "barrel_radius: R_c = 3 mm is below D_t/2 = 4 mm"},
        ErrorCase{"corner_above_radius", "bliskrun.flat_end_mill{radius=5, corner_radius=6, flute_length=20}",
                  "corner_radius: r = 6 mm exceeds the tool radius R = 5 mm"},
        ErrorCase{"negative_size", "bliskrun.contact_wheel{radius=50, width=-2}", "option 'width'"},
        ErrorCase{"unknown_key", "bliskrun.ball_end_mill{radius=3, flute_lenght=15}",
                  "unknown option 'flute_lenght'"},
        ErrorCase{"unknown_shank_key",
                  "bliskrun.drum_wheel{max_diameter=8, barrel_radius=50, head_length=4, shank={diam=6}}",
                  "bliskrun.drum_wheel.shank: unknown option 'diam'"},
        ErrorCase{"bad_part", "bliskrun.ball_end_mill{radius=3, flute_length=15}:signed_distance({0,0,0}, 'arbor')",
                  "part: expected \"cutter\", \"shank\" or \"holder\""},
        ErrorCase{"mesh_index",
                  "bliskrun.collision_world{surfaces={{name='a', mesh={vertices={{0,0,0},{1,0,0},{0,1,0}}, "
                  "triangles={{1,2,4}}}}}}",
                  "triangles[1]: vertex index 4 outside 1..3"},
        ErrorCase{"mesh_or_surface", "bliskrun.collision_world{surfaces={{name='a'}}}",
                  "give exactly one of 'mesh' and 'surface'"},
        ErrorCase{"clearance_key",
                  "local w = bliskrun.collision_world{surfaces={{name='a', mesh={vertices={{0,0,0},{1,0,0},{0,1,0}}, "
                  "triangles={{1,2,3}}}}}}; "
                  "w:check(bliskrun.ball_end_mill{radius=3, flute_length=15}, {tip={0,0,5}, axis={0,0,1}}, "
                  "{clearance={shnak=1}})",
                  "unknown option 'shnak'"}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace bliskrun::test
