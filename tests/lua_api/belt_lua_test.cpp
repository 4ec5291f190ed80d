// bliskrun.belt_paths{...}: bad options land on the recipe line and say what
// was expected.
#include <gtest/gtest.h>

#include "test_support.h"

namespace bliskrun::test {
namespace {

class LuaBeltErrors : public ::testing::TestWithParam<RecipeErrorCase> {};

TEST_P(LuaBeltErrors, NameTheProblemAtTheRecipeLine) {
  TempDir dir;
  EXPECT_TRUE(fails_at_line_2(dir, GetParam()));
}

// A 20 mm wide flat face, 60 mm long: the first line of every case.
#define FACE "bliskrun.point_grid{rows = 2, cols = 2, points = {{0,0,0},{0,60,0},{20,0,0},{20,60,0}}}:surface()"

INSTANTIATE_TEST_SUITE_P(
    Cases, LuaBeltErrors,
    ::testing::Values(
        RecipeErrorCase{"unknown_key", "bliskrun.belt_paths{face = " FACE ", wheel = bliskrun.contact_wheel{radius = 20, width = 10}, scalop = 1}",
                        "unknown option 'scalop'"},
        RecipeErrorCase{"missing_wheel", "bliskrun.belt_paths{face = " FACE "}", "option 'wheel'"},
        RecipeErrorCase{"not_a_wheel",
                        "bliskrun.belt_paths{face = " FACE ", wheel = bliskrun.ball_end_mill{radius = 3, flute_length = 9}}",
                        "expected a contact wheel"},
        RecipeErrorCase{"scallop_range",
                        "bliskrun.belt_paths{face = " FACE ", wheel = bliskrun.contact_wheel{radius = 20, width = 10}, scallop = -1}",
                        "option 'scallop'"},
        RecipeErrorCase{"along_choice",
                        "bliskrun.belt_paths{face = " FACE ", wheel = bliskrun.contact_wheel{radius = 20, width = 10}, along = 'w'}",
                        "option 'along'"},
        RecipeErrorCase{"wheel_wider_than_face",
                        "bliskrun.belt_paths{face = " FACE ", wheel = bliskrun.contact_wheel{radius = 20, width = 80}}",
                        "not longer than the wheel width"}),
    error_case_name);

}  // namespace
}  // namespace bliskrun::test
