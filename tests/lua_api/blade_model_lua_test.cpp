// Lua bindings of the blade model (bliskrun.loft_sections and the part
// readers): errors land on the recipe line naming the option, the section or
// the data file:line. (The documented examples run in docs_examples_test.)
#include <gtest/gtest.h>

#include "test_support.h"

namespace bliskrun::test {
namespace {

class LuaBladeModelErrors : public ::testing::TestWithParam<RecipeErrorCase> {};

TEST_P(LuaBladeModelErrors, NameTheProblemAtTheRecipeLine) {
  TempDir dir;
  dir.write("bad37.dat", " Table IV NASA Rotor 37 Blade Geometry\n Z and R are in inches\n");
  dir.write("rotor37hub-shroud.dat", " Table V\n");
  dir.write("bad67.dat", "header\n   JM   NS   NB  JLE  JTE\n  110   14   22   16\n");
  EXPECT_TRUE(fails_at_line_2(dir, GetParam()));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, LuaBladeModelErrors,
    ::testing::Values(
        RecipeErrorCase{"loft_no_sections", "bliskrun.loft_sections{}", "missing required option 'sections'"},
        RecipeErrorCase{"loft_unknown_key", "bliskrun.loft_sections{sections = {}, colls = 5}", "unknown option 'colls'"},
        RecipeErrorCase{"loft_rotation", "bliskrun.loft_sections{sections = {}, rotation = 2}", "option 'rotation'"},
        RecipeErrorCase{"loft_one_section", "bliskrun.loft_sections{sections = {{}}}", "at least 2 section loops"},
        RecipeErrorCase{"loft_nan_point", "bliskrun.loft_sections{sections = {{{0, 0, 0}, {1, 0 / 0, 0}}}}",
                        "option 'sections': section 1, point 2: expected {x, y, z} of finite numbers"},
        RecipeErrorCase{"loft_not_a_list", "bliskrun.loft_sections{sections = {5}}",
                        "option 'sections': entry 1 is not a list of points"},
        RecipeErrorCase{"loft_bad_point", "bliskrun.loft_sections{sections = {{{0, 0, 0}, {1, 'x', 0}}, {}}}",
                        "section 1, point 2: expected {x, y, z}"},
        RecipeErrorCase{"loft_short_loop",
                        "bliskrun.loft_sections{sections = {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}}}}",
                        "section 1: a closed section loop needs at least 8 distinct points, got 3"},
        RecipeErrorCase{"loft_margin", "bliskrun.loft_sections{sections = {}, edge_margin = 0.6}", "option 'edge_margin'"},
        RecipeErrorCase{"r37_missing", "bliskrun.read_rotor37('nowhere')", "cannot find 'nowhere'"},
        RecipeErrorCase{"r37_not_a_folder_of_it", "bliskrun.read_rotor37('.')", "no rotor37geometry.dat in '.'"},
        RecipeErrorCase{"r37_data_line", "bliskrun.read_rotor37('bad37.dat')", "bad37.dat:2: unknown header"},
        RecipeErrorCase{"r67_data_line", "bliskrun.read_rotor67('bad67.dat')", "bad67.dat:3: expected 5 values"},
        RecipeErrorCase{"hecc_folder", "bliskrun.read_hecc('.')", "is not in a HECC impeller folder"},
        RecipeErrorCase{"hecc_blade", "bliskrun.read_hecc('.', {blade = 'middle'})", "option 'blade'"},
        RecipeErrorCase{"hecc_set", "bliskrun.read_hecc('.', {set = 'hot'})", "option 'set'"}),
    error_case_name);

}  // namespace
}  // namespace bliskrun::test
