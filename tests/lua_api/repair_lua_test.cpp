// bliskrun.rebuild_sections{...}, damaged_blade, measure, rebuild_damaged: bad options, sections and points land on
// the recipe line and say what was expected. (What it rebuilds is measured in
// tests/repair/section_loft_test.cpp; docs/lua_api.md runs an example.)
#include <gtest/gtest.h>

#include "test_support.h"

namespace bliskrun::test {
namespace {

class LuaRepairErrors : public ::testing::TestWithParam<RecipeErrorCase> {};

TEST_P(LuaRepairErrors, NameTheProblemAtTheRecipeLine) {
  TempDir dir;
  EXPECT_TRUE(fails_at_line_2(dir, GetParam()));
}

// Two elliptic sections of 120 points, the second (at z = 10) without the
// points of x < -10 mm: its leading edge is missing.
#define DAMAGED                                                                                          \
  "(function() local s = {} for k = 0, 1 do local p = {} for i = 0, 119 do local t = 2 * math.pi * i / 120 " \
  "local x, y = 15 * math.cos(t), 4 * math.sin(t) if k == 0 or x > -10 then p[#p + 1] = {x, y} end end "    \
  "s[#s + 1] = {points = p, z = 10 * k} end return s end)()"

INSTANTIATE_TEST_SUITE_P(
    Cases, LuaRepairErrors,
    ::testing::Values(
        RecipeErrorCase{"unknown_key", "bliskrun.rebuild_sections{sections = {}, smoothing = 0.1, smoothng = 1}",
                        "unknown option 'smoothng'"},
        RecipeErrorCase{"missing_smoothing", "bliskrun.rebuild_sections{sections = {}}", "option 'smoothing'"},
        RecipeErrorCase{"negative_smoothing", "bliskrun.rebuild_sections{sections = {}, smoothing = -1}",
                        "option 'smoothing'"},
        RecipeErrorCase{"section_unknown_key",
                        "bliskrun.rebuild_sections{sections = {{points = {}, height = 3}}, smoothing = 0.1}",
                        "unknown option 'height'"},
        RecipeErrorCase{"section_not_a_table", "bliskrun.rebuild_sections{sections = {5}, smoothing = 0.1}",
                        "sections[1]: expected {points = {...}, z = h}"},
        RecipeErrorCase{"flat_point_without_z",
                        "bliskrun.rebuild_sections{sections = {{points = {{1, 2, 3}, {1, 2}}}}, smoothing = 0.1}",
                        "sections[1].points[2]: expected {x, y, z}"},
        RecipeErrorCase{"too_few_sections",
                        "bliskrun.rebuild_sections{sections = {{points = {{1, 2}}, z = 0}}, smoothing = 0.1}",
                        "at least 2 sections"},
        RecipeErrorCase{"damaged_section", "bliskrun.rebuild_sections{sections = " DAMAGED ", smoothing = 0.1}",
                        "section 2 has a gap"},
        RecipeErrorCase{"damaged_blade_unknown_key", "bliskrun.damaged_blade{twst = 1}", "unknown option 'twst'"},
        RecipeErrorCase{"damaged_blade_twist", "bliskrun.damaged_blade{twist = 30}", "option 'twist'"},
        RecipeErrorCase{"damaged_blade_bad_loop", "bliskrun.damaged_blade{loops = {{{0, 0, 0}, {1, 2}}}}",
                        "bliskrun.damaged_blade: option 'loops': loop 1, point 2: expected {x, y, z} of finite numbers"},
        RecipeErrorCase{"damaged_blade_edge_span",
                        "bliskrun.damaged_blade{edge_depth = 1, edge_from = 0.6, edge_to = 0.5}",
                        "edge_to: expected a span above edge_from"},
        RecipeErrorCase{"measure_noise", "bliskrun.damaged_blade{}:measure{noise = 1}", "option 'noise'"},
        RecipeErrorCase{"rebuild_damaged_missing", "bliskrun.rebuild_damaged{blade = 1}", "option 'measurement'"}),
    error_case_name);

}  // namespace
}  // namespace bliskrun::test
