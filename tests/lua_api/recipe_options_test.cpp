// What a recipe accepts (scripts/lib/recipe_options.lua, issue 37 item 5):
// `--help` lists the declared options without planning; an unknown --set
// name, a wrong type or an implausible value is refused before anything is
// planned or written, with what was expected.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "test_support.h"

namespace bliskrun::test {
namespace {

namespace fs = std::filesystem;

std::string recipe_file(const std::string& name) { return std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/" + name; }

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Files the run left in `out` (none when it stopped before writing).
int files_in(const std::string& out) {
  int n = 0;
  std::error_code ec;
  if (!fs::exists(out, ec)) return 0;
  for (const auto& e : fs::recursive_directory_iterator(out)) n += e.is_regular_file();
  return n;
}

// The --help row of `option`: the line that starts with it.
std::string help_row(const std::string& help, const std::string& option) {
  std::istringstream lines(help);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string first;
    words >> first;
    if (first == option) return line;
  }
  return "";
}

TEST(RecipeOptions, HelpListsEveryShippedRecipesOptionsWithoutPlanning) {
  int recipes = 0;
  for (const auto& e : fs::directory_iterator(std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes")) {
    if (e.path().extension() != ".lua") continue;
    ++recipes;
    TempDir dir;
    const RecipeResult r = run_bliskrun({e.path().string(), "--help", "--out", dir.path() + "/out"});
    EXPECT_EQ(r.exit_code, 0) << e.path() << ":\n" << r.output;
    EXPECT_TRUE(has(r.output, "options of ")) << e.path() << ":\n" << r.output;
    EXPECT_TRUE(has(r.output, "option") && has(r.output, "type") && has(r.output, "unit") &&
                has(r.output, "default") && has(r.output, "range"))
        << r.output;
    EXPECT_FALSE(fs::exists(dir.path() + "/out")) << e.path() << ": --help wrote to the out folder";
  }
  EXPECT_GE(recipes, 19);
}

TEST(RecipeOptions, HelpRowGivesTypeUnitDefaultRangeAndHelp) {
  TempDir dir;
  const RecipeResult r = run_bliskrun({recipe_file("blisk_drum_finish.lua"), "--help", "--out", dir.path() + "/out"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string row = help_row(r.output, "chord_tol");
  ASSERT_FALSE(row.empty()) << r.output;
  for (const char* part : {" number ", " mm ", " 0.002 ", " 1e-05..0.1 ", "chord deviation"})
    EXPECT_TRUE(has(row, part)) << "'" << part << "' missing in: " << row;
  const std::string wheel = help_row(r.output, "wheel");
  EXPECT_TRUE(has(wheel, "extended|traditional") && has(wheel, " extended ")) << wheel;
  // A value the recipe computes shows how.
  EXPECT_TRUE(has(help_row(r.output, "wheel_diameter"), "Table 2's")) << r.output;
}

TEST(RecipeOptions, UnknownNameIsRefusedWithTheKnownNames) {
  TempDir dir;
  const RecipeResult r = run_bliskrun(
      {recipe_file("blisk_drum_finish.lua"), "--quiet", "--out", dir.path() + "/out", "--set", "c_rnage=20"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "--set c_rnage=20: this recipe has no option 'c_rnage'")) << r.output;
  EXPECT_TRUE(has(r.output, "did you mean 'c_range'?")) << r.output;
  EXPECT_TRUE(has(r.output, "it accepts: all_blades, all_samples_u, all_samples_v, blade, blade_count, c_range, cad, "
                            "cad_axial_origin, cad_casing, cad_coordinates, cad_faces, cad_hub, chord_tol, link, "
                            "link_overcut, map_scale_um, part, residual, samples_u, samples_v, shank_clearance, steps, "
                            "wheel, wheel_diameter"))
      << r.output;
  EXPECT_TRUE(has(r.output, "blisk_drum_finish.lua:")) << "error not at the recipe's line: " << r.output;
  EXPECT_EQ(files_in(dir.path() + "/out"), 0);
}

TEST(RecipeOptions, MillimetreValueOfAMicrometreToleranceIsRefused) {
  TempDir dir;
  const RecipeResult r = run_bliskrun(
      {recipe_file("blisk_drum_finish.lua"), "--quiet", "--out", dir.path() + "/out", "--set", "chord_tol=2"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "--set chord_tol=2: expected 1e-05..0.1 mm")) << r.output;
  EXPECT_TRUE(has(r.output, "2 um is chord_tol=0.002")) << r.output;
  EXPECT_EQ(files_in(dir.path() + "/out"), 0);
  // The same slip in another recipe, and a plausible value passes the check
  // (the run then stops at the unknown name that follows it).
  const RecipeResult job = run_bliskrun(
      {recipe_file("impeller_job.lua"), "--quiet", "--out", dir.path() + "/out2", "--set", "chord_tol=5"});
  EXPECT_EQ(job.exit_code, 1);
  EXPECT_TRUE(has(job.output, "--set chord_tol=5: expected 1e-05..0.1 mm")) << job.output;
}

TEST(RecipeOptions, WheelWiderThanTheNarrowestPassageIsRefusedBeforePlanning) {
  TempDir dir;
  const RecipeResult r = run_bliskrun(
      {recipe_file("blisk_drum_finish.lua"), "--quiet", "--out", dir.path() + "/out", "--set", "wheel_diameter=12"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  // The built-in blisk's d_min is 10.502 mm (docs/lua_api/parts.md: ~10.5).
  EXPECT_TRUE(has(r.output, "its diameter 12.000 mm is not below the narrowest passage between the blades, "
                            "d_min = 10.5"))
      << r.output;
  EXPECT_FALSE(has(r.output, "rows")) << "planning started: " << r.output;
  EXPECT_EQ(files_in(dir.path() + "/out"), 0);
}

// The same refusal on a real part, whose d_min is measured between two of
// its blades (Rotor 67: 20.13 mm), before the wheel design writes anything.
TEST(RecipeOptions, WheelWiderThanARealPartsPassageIsRefusedBeforeAnythingIsWritten) {
  if (shared_data_dir().empty()) GTEST_SKIP() << "../shared/data not present: Rotor 67 wheel check skipped";
  TempDir dir;
  const RecipeResult r = run_bliskrun({recipe_file("rotor67_finish.lua"), "--data", shared_data_dir(), "--quiet", "--out",
                                       dir.path() + "/out", "--set", "wheel_diameter=21"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "its diameter 21.000 mm is not below the narrowest passage between the blades, "
                            "d_min = 20.1"))
      << r.output;
  EXPECT_EQ(files_in(dir.path() + "/out"), 0);
}

// The declaration itself, on a recipe of the test's.
TEST(RecipeOptions, DeclaredValuesAreTypedDefaultedAndChecked) {
  TempDir dir;
  const std::string r = dir.write("r.lua",
                                  "local opt = require('recipe_options'){\n"
                                  "  n = {type = 'integer', default = 3, range = {1, 10}, help = 'count'},\n"
                                  "  tol = {type = 'number', unit = 'mm', default = 0.01, range = {1e-4, 0.1}, help = 't'},\n"
                                  "  side = {type = 'string', default = 'a', choices = {'a', 'b'}, help = 's'},\n"
                                  "  on = {type = 'boolean', default = true, help = 'o'},\n"
                                  "  life = {type = 'number', unit = 'mm', range = {1, 1e6}, help = 'l'},\n"
                                  "}\n"
                                  "bliskrun.write_text('v.txt', string.format('%s %s %s %s %s', opt.n, opt.tol, opt.side,"
                                  " opt.on, opt.life))\n");
  auto run = [&](std::vector<std::string> sets) {
    std::vector<std::string> a = {r, "--quiet", "--out", dir.path() + "/out"};
    for (const auto& s : sets) a.insert(a.end(), {"--set", s});
    return run_bliskrun(a);
  };
  auto written = [&] {
    std::ifstream in(dir.path() + "/out/v.txt");
    return std::string((std::istreambuf_iterator<char>(in)), {});
  };
  ASSERT_EQ(run({}).exit_code, 0);
  EXPECT_EQ(written(), "3 0.01 a true nil");
  ASSERT_EQ(run({"n=7", "tol=0.002", "side=b", "on=false", "life=500"}).exit_code, 0);
  EXPECT_EQ(written(), "7 0.002 b false 500");
  const struct {
    const char* set;
    const char* expected;
  } refused[] = {{"n=0", "--set n=0: expected 1..10 (count)"},
                 {"n=2.5", "--set n=2.5: expected a whole number"},
                 {"n=x", "--set n=x: expected a whole number"},
                 {"tol=0.5", "--set tol=0.5: expected 0.0001..0.1 mm"},
                 {"side=c", "--set side=c: expected one of a|b"},
                 {"on=yes", "--set on=yes: expected true or false"},
                 {"sid=a", "no option 'sid' (did you mean 'side'?); it accepts: life, n, on, side, tol"}};
  for (const auto& c : refused) {
    const RecipeResult bad = run({c.set});
    EXPECT_EQ(bad.exit_code, 1) << c.set;
    EXPECT_TRUE(has(bad.output, "r.lua:1: ") && has(bad.output, c.expected)) << c.set << ": " << bad.output;
  }
}

TEST(RecipeOptions, HelpOfARecipeThatDeclaresNothingStopsBeforeTheCore) {
  TempDir dir;
  const std::string r = dir.write("plain.lua", "bliskrun.write_text('x.txt', tostring(args.n))\n");
  const RecipeResult help = run_bliskrun({r, "--help", "--out", dir.path() + "/out"});
  EXPECT_EQ(help.exit_code, 2) << help.output;
  EXPECT_TRUE(has(help.output, "declares no options")) << help.output;
  EXPECT_FALSE(fs::exists(dir.path() + "/out/x.txt"));
  // Without --help such a recipe still reads args as before.
  EXPECT_EQ(run_bliskrun({r, "--quiet", "--out", dir.path() + "/out", "--set", "n=1"}).exit_code, 0);
}

}  // namespace
}  // namespace bliskrun::test
