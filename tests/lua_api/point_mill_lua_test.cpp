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
