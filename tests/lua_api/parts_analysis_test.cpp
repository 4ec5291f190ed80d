// Lua bindings of io, parts and analysis: results agree with core, errors land
// on the recipe line naming the parameter or the data file:line. (The
// documented examples run in docs_examples_test.)
#include <gtest/gtest.h>

#include <filesystem>

#include "core/analysis/curvature_stats.h"
#include "core/geometry/interpolation.h"
#include "core/parts/builtin_blisk.h"
#include "test_support.h"

namespace bliskrun::test {
namespace {

class LuaPartsAnalysisErrors : public ::testing::TestWithParam<RecipeErrorCase> {};

TEST_P(LuaPartsAnalysisErrors, NameTheProblemAtTheRecipeLine) {
  TempDir dir;
  dir.write("bad_grid.txt", "# grid 2 2\n0 0 0\n1 0 0\n0 1 0\n");
  dir.write("nan_grid.txt", "# grid 2 2\n0 0 0\n1 0 0\n0 nan 0\n1 1 0\n");
  dir.write("repeated_grid.txt", "# grid 2 2\n0 0 0\n0 0 0\n0 1 0\n1 1 0\n");
  std::filesystem::create_directories(dir.path() + "/folder.txt");
  EXPECT_TRUE(fails_at_line_2(dir, GetParam()));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, LuaPartsAnalysisErrors,
    ::testing::Values(
        RecipeErrorCase{"unknown_blisk_key", "bliskrun.blisk{blade_cont = 20}", "unknown option 'blade_cont'"},
        RecipeErrorCase{"blisk_range", "bliskrun.blisk{grid_rows = 2}", "option 'grid_rows'"},
        RecipeErrorCase{"blisk_core_check", "bliskrun.blisk{casing_radius_inlet = 50}",
                  "casing_radius_inlet: expected a radius above hub_radius_inlet (60)"},
        RecipeErrorCase{"blade_index", "bliskrun.blisk{}:flank_grid(23, 'pressure')",
                  "argument 'blade': 23 is outside 1..22"},
        RecipeErrorCase{"side", "bliskrun.blisk{}:flank(1, 'concave')",
                  "argument 'side': expected \"pressure\" or \"suction\""},
        RecipeErrorCase{"grid_count", "bliskrun.read_point_grid('bad_grid.txt')",
                  "bad_grid.txt:4: expected 2 x 2 = 4 points, got 3"},
        RecipeErrorCase{"grid_nan", "bliskrun.read_point_grid('nan_grid.txt')", "nan_grid.txt:4:"},
        RecipeErrorCase{"grid_degenerate", "bliskrun.read_point_grid('repeated_grid.txt')", "repeated_grid.txt:3:"},
        RecipeErrorCase{"grid_unreadable", "bliskrun.read_point_grid('folder.txt')", "folder.txt"},
        RecipeErrorCase{"grid_order", "bliskrun.read_point_grid('bad_grid.txt', {order = 'diagonal'})",
                  "option 'order'"},
        RecipeErrorCase{"grid_outside", "bliskrun.read_point_grid('/etc/passwd')", "/etc/passwd"},
        RecipeErrorCase{"stats_samples", "bliskrun.curvature_stats(bliskrun.blisk{}:flank(1, 'pressure'), {samples_u = 1})",
                  "option 'samples_u'"},
        RecipeErrorCase{"wheel_missing", "bliskrun.design_drum_wheel{k1_max = 0.04, d_min = 10}",
                  "missing required option 'ke_max'"},
        RecipeErrorCase{"wheel_core", "bliskrun.design_drum_wheel{k1_max = 0.04, ke_max = 0.05, d_min = 10}",
                  "ke_max: k_e is a normal curvature and cannot exceed k1 max"}),
    error_case_name);

// The recipe's numbers are core's numbers: passage, Table-1 statistics with
// positions, Table 2, and the grid round trip through a file. (Angles pass
// through degrees at the Lua boundary, so the recipe's blisk differs from
// core's default by rounding: compare to 1e-9 relative.)
TEST(LuaPartsAnalysis, RecipeAgreesWithCore) {
  const BuiltinBlisk blisk;
  const CurvatureStats st =
      curvature_stats(interpolate_grid(blisk.flank_grid(0, FlankSide::kPressure)));
  char expected[512];
  std::snprintf(expected, sizeof expected,
                "local want = {passage = %.17g, k1 = %.17g, k1u = %.17g, k1v = %.17g, "
                "ke = %.17g, ke_angle = %.17g, k2 = %.17g, neg = %.17g}\n",
                blisk.narrowest_passage_mm(), st.k1_max.value, st.k1_max.u, st.k1_max.v,
                st.ke_max.value, rad_to_deg(st.ke_max.angle_rad), st.k2_max.value,
                st.negative_K_fraction);
  const std::string recipe = std::string(expected) + R"(
local function near(a, b) return math.abs(a - b) <= 1e-9 * math.max(1, math.abs(b)) end
local blisk = bliskrun.blisk{}
assert(near(blisk:narrowest_passage(), want.passage))
local grid = blisk:flank_grid(1, "pressure")
bliskrun.write_point_grid(grid, "p.txt")
local back = bliskrun.read_point_grid("p.txt")
for _, ij in ipairs({{1, 1}, {37, 411}, {100, 500}}) do
  local a, b = grid:point(ij[1], ij[2]), back:point(ij[1], ij[2])
  assert(a.x == b.x and a.y == b.y and a.z == b.z)
end
local st = bliskrun.curvature_stats(back:surface())
assert(near(st.k1_max.value, want.k1) and st.k1_max.u == want.k1u and st.k1_max.v == want.k1v)
assert(near(st.ke_max.value, want.ke) and near(st.ke_max.angle, want.ke_angle))
assert(near(st.k2_max.value, want.k2) and st.negative_K_fraction == want.neg)
assert(st.c_range == 30 and st.samples_u == 100 and st.samples_v == 500)
local wide = bliskrun.curvature_stats(back:surface(), {c_range = 90, samples_u = 20, samples_v = 50})
assert(wide.ke_max.value == wide.k1_max.value)
local path = st.map:write_svg("k.svg")
assert(bliskrun.read_text("k.svg"):find("</svg>"))
local w = bliskrun.design_drum_wheel{k1_max = 0.0435, ke_max = 0.0195, d_min = 10.5}
assert(w.traditional.barrel_radius == 20 and w.traditional.max_diameter == 8)
assert(w.extended.barrel_radius == 50 and w.extended.max_diameter == 8)
assert(math.abs(w.traditional.radius_limit - 23.0) < 0.05)
)";
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, recipe);
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

}  // namespace
}  // namespace bliskrun::test
