// bliskrun.impeller{...}: the recipe's impeller is core's, the camber data
// round-trips through a file, and errors land on the recipe line.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/parts/impeller.h"
#include "test_support.h"

namespace bliskrun::test {
namespace {

class LuaImpellerErrors : public ::testing::TestWithParam<RecipeErrorCase> {};

TEST_P(LuaImpellerErrors, NameTheProblemAtTheRecipeLine) {
  TempDir dir;
  dir.write("thin.dat", "blades 5\nmain shroud 4\n20 0 10 1\n21 1 10 1\n22 2 10 1\n23 3 10 1\n"
                        "main hub 4\n8 -2 0 1\n9 -1 0 1\n10 0 0 -1\n11 1 0 1\n");
  dir.write("unpaired.dat", "blades 5\nmain shroud 4\n20 0 10 1\n21 1 10 1\n22 2 10 1\n23 3 10 1\n"
                            "main hub 5\n8 -2 0 1\n9 -1 0 1\n10 0 0 1\n11 1 0 1\n12 2 0 1\n");
  EXPECT_TRUE(fails_at_line_2(dir, GetParam()));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, LuaImpellerErrors,
    ::testing::Values(
        RecipeErrorCase{"unknown_key", "bliskrun.impeller{blade = 17}", "unknown option 'blade'"},
        RecipeErrorCase{"range", "bliskrun.impeller{blades = 1}", "option 'blades'"},
        RecipeErrorCase{"core_check", "bliskrun.impeller{shroud_inlet_radius = 40}",
                        "shroud_inlet_radius: expected a radius between hub_inlet_radius and outlet_radius"},
        RecipeErrorCase{"camber_and_builtin", "bliskrun.impeller{camber = 'thin.dat', blades = 9}",
                        "option 'blades' is for the built-in impeller"},
        RecipeErrorCase{"camber_file", "bliskrun.impeller{camber = 'thin.dat'}",
                        "thin.dat:10: main hub: expected a half thickness h > 0"},
        RecipeErrorCase{"camber_unpaired", "bliskrun.impeller{camber = 'unpaired.dat'}",
                        "unpaired.dat:7: expected as many points in 'main hub' as in 'main shroud' (4: point i "
                        "of each lies on one ruling), got 5"},
        RecipeErrorCase{"blade_index", "bliskrun.impeller{}:face(18, 'plus')",
                        "argument 'blade': 18 is outside 1..17"},
        RecipeErrorCase{"side", "bliskrun.impeller{}:face(1, 'pressure')",
                        "argument 'side': expected \"plus\" or \"minus\""},
        RecipeErrorCase{"flank_missing_radius",
                        "bliskrun.flank_mill{face = bliskrun.impeller{}:face(1, 'plus'), tool = bliskrun.ball_end_mill{radius = 3, flute_length = 90}}",
                        "missing required option 'ball_radius'"},
        RecipeErrorCase{"flank_wrong_radius",
                        "bliskrun.flank_mill{face = bliskrun.impeller{}:face(1, 'plus'), tool = bliskrun.ball_end_mill{radius = 3, flute_length = 90}, ball_radius = 2}",
                        "ball_radius: the tool (ball-end mill"},
        RecipeErrorCase{"flank_overcut_weight_below_one",
                        "bliskrun.flank_mill{face = bliskrun.impeller{}:face(1, 'plus'), tool = bliskrun.ball_end_mill{radius = 3, flute_length = 90}, ball_radius = 3, overcut_weight = 0.5}",
                        "option 'overcut_weight': 0.5 is out of range [1"},
        RecipeErrorCase{"flank_hub_not_revolution",
                        "local i = bliskrun.impeller{} bliskrun.flank_mill{face = i:face(1, 'plus'), hub = i:face(2, 'plus'), tool = bliskrun.ball_end_mill{radius = 3, flute_length = 90}, ball_radius = 3}",
                        "option 'hub': expected a surface of revolution"},
        RecipeErrorCase{"no_splitter", "bliskrun.impeller{splitters = false}:face(1, 'plus', 'splitter')",
                        "this impeller has no splitter blades"}),
    error_case_name);

TEST(LuaImpeller, RecipeAgreesWithCoreAndCamberDataRoundTrips) {
  const Impeller imp(builtin_impeller_definition());
  const Vec3 p = imp.face(BladeKind::kSplitter, 4, CamberSide::kMinus)->point(0.25, 0.75);
  char expected[256];
  std::snprintf(expected, sizeof expected, "local want = {%.17g, %.17g, %.17g, %.17g}\n", p.x(), p.y(),
                p.z(), imp.outer_radius_mm());
  const std::string recipe = std::string(expected) + R"(
-- angles pass through degrees at the boundary: compare to 1e-9 relative
local function near(a, b) return math.abs(a - b) <= 1e-9 * math.max(1, math.abs(b)) end
local imp = bliskrun.impeller{}
assert(imp:blade_count() == 17 and imp:has_splitter())
assert(near(imp:outer_radius(), want[4]))
local q = imp:face(5, "minus", "splitter"):point(0.25, 0.75)
assert(near(q.x, want[1]) and near(q.y, want[2]) and near(q.z, want[3]))
local path = imp:write_camber("impeller.dat")
local back = bliskrun.impeller{camber = path}
local r = back:face(5, "minus", "splitter"):point(0.25, 0.75)
assert(r.x == q.x and r.y == q.y and r.z == q.z, "camber data round trip")
assert(tostring(back):find("impeller.dat"))
assert(#imp:hub_meridian() > 10)
local h = imp:hub():point(0.5, 0.0)
assert(h.z >= 0)
)";
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, recipe);
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

}  // namespace
}  // namespace bliskrun::test
