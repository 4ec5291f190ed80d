// The recipe runner: exit codes, errors at the recipe's file:line, the
// sandbox, allowed folders, limits, --set.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_support.h"

namespace bliskrun::test {
namespace {

namespace fs = std::filesystem;

TEST(Runner, OkRecipeExitsZero) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, "local x = 2 * um\nassert(x == 0.002)\n");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(Runner, RuntimeErrorNamesRecipeLine) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, "local a = 1\n\nerror('boom')\n");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("recipe.lua:3: boom"), std::string::npos) << r.output;
}

TEST(Runner, SyntaxErrorNamesRecipeLine) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, "local a = 1\nlocal = 2\n");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("recipe.lua:2:"), std::string::npos) << r.output;
}

TEST(Runner, CoreErrorReachesRecipeAsLuaErrorAtItsLine) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(
      dir, "local ok, msg = pcall(function() return bliskrun.interpolate_curve({{0,0,0},{0,0,0}}) end)\n"
           "assert(not ok)\nassert(msg:find('recipe.lua:1:'), msg)\nassert(msg:find('coincide'), msg)\n"
           "bliskrun.interpolate_curve({{0,0,0},{0,0,0}})\n");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("recipe.lua:5:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("zero-length chord"), std::string::npos) << r.output;
}

class OptionValidation : public ::testing::TestWithParam<RecipeErrorCase> {};

TEST_P(OptionValidation, ErrorNamesFileLineAndKey) {
  TempDir dir;
  EXPECT_TRUE(fails_at_line_2(dir, GetParam()));
}

INSTANTIATE_TEST_SUITE_P(
    Kinds, OptionValidation,
    ::testing::Values(
        RecipeErrorCase{"unknown_key", "bliskrun.point_grid{rows=2, cols=2, points={}, colz=3}",
                   "unknown option 'colz'; valid options: cols, points, rows"},
        RecipeErrorCase{"wrong_type", "bliskrun.point_grid{rows='two', cols=2, points={}}",
                   "option 'rows': expected integer, got string"},
        RecipeErrorCase{"not_integer", "bliskrun.point_grid{rows=2.5, cols=2, points={}}",
                   "option 'rows': expected integer, got number"},
        RecipeErrorCase{"out_of_range", "bliskrun.point_grid{rows=1, cols=2, points={}}",
                   "option 'rows': 1 is out of range [2, 1e+06]"},
        RecipeErrorCase{"missing_required", "bliskrun.point_grid{rows=2, cols=2}",
                   "missing required option 'points'"},
        RecipeErrorCase{"not_a_table", "bliskrun.point_grid(5)", "expected an option table, got number"},
        RecipeErrorCase{"positional_key", "bliskrun.point_grid{2, rows=2, cols=2, points={}}",
                   "option keys must be names, got [1]"},
        RecipeErrorCase{"nan", "bliskrun.point_grid{rows=0/0, cols=2, points={}}",
                   "option 'rows': expected a finite number"}),
    error_case_name);

class Sandbox : public ::testing::TestWithParam<RecipeErrorCase> {};

TEST_P(Sandbox, Refuses) {
  TempDir dir;
  dir.write("secret.txt", "x");
  const RecipeResult r = run_recipe_text(dir, GetParam().call);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(GetParam().expected), std::string::npos) << r.output;
}

INSTANTIATE_TEST_SUITE_P(
    Refusals, Sandbox,
    ::testing::Values(
        RecipeErrorCase{"os_execute", "os.execute('true')", "attempt to call a nil value (field 'execute')"},
        RecipeErrorCase{"os_remove", "os.remove('x')", "(field 'remove')"},
        RecipeErrorCase{"os_exit", "os.exit(0)", "(field 'exit')"},
        RecipeErrorCase{"io", "io.open('/etc/passwd')", "attempt to index a nil value (global 'io')"},
        RecipeErrorCase{"io_popen", "io.popen('ls')", "(global 'io')"},
        RecipeErrorCase{"package_loadlib", "package.loadlib('libc.so.6', 'system')", "(global 'package')"},
        RecipeErrorCase{"debug", "debug.getregistry()", "(global 'debug')"},
        RecipeErrorCase{"dofile", "dofile('/etc/passwd')", "(global 'dofile')"},
        RecipeErrorCase{"loadfile", "loadfile('/etc/passwd')", "(global 'loadfile')"},
        RecipeErrorCase{"string_dump", "string.dump(print)", "(field 'dump')"},
        RecipeErrorCase{"binary_chunk", "assert(load('\\27Lua', 'x', 'b'))", "only text chunks"},
        RecipeErrorCase{"binary_chunk_default_mode", "assert(load('\\27LuaT\\0'))", "attempt to load a binary chunk"},
        RecipeErrorCase{"require_c_module", "require('socket.core')", "module 'socket.core' not found"},
        RecipeErrorCase{"require_path", "require('../../etc/passwd')", "is not a module name"},
        RecipeErrorCase{"collectgarbage_stop", "collectgarbage('stop')", "option 'stop' is not allowed"},
        RecipeErrorCase{"read_outside", "bliskrun.read_text('/etc/passwd')", "outside the folders a recipe may read"},
        RecipeErrorCase{"read_dotdot", "bliskrun.read_text('../../../../etc/passwd')", "outside the folders"},
        RecipeErrorCase{"write_dotdot", "bliskrun.write_text('../escape.txt', 'x')", "outside the out folder"},
        RecipeErrorCase{"write_absolute", "bliskrun.write_text('/tmp/escape.txt', 'x')", "outside the out folder"}),
    error_case_name);

TEST(Runner, RecipeMayReadItsFolderAndRequireItsModules) {
  TempDir dir;
  dir.write("data.txt", "hello");
  dir.write("helpers.lua", "return { twice = function(x) return 2 * x end }");
  const RecipeResult r = run_recipe_text(
      dir, "assert(bliskrun.read_text('data.txt') == 'hello')\n"
           "local h = require('helpers')\nassert(h.twice(21) == 42)\n"
           "assert(require('helpers') == h)\n");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(Runner, TextLoadStillWorks) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, "local f = assert(load('return 1 + 2'))\nassert(f() == 3)\n");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(Runner, TimeLimitStopsAnEndlessLoop) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, "local i = 0\nwhile true do i = i + 1 end\n", true, 0.5);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("time limit of 0.5 s exceeded"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("recipe.lua:2:"), std::string::npos) << r.output;
}

TEST(Runner, MemoryLimitStopsUnboundedAllocation) {
  TempDir dir;
  const RecipeResult r =
      run_recipe_text(dir, "local t = {}\nlocal i = 0\nwhile true do i = i + 1; t[i] = {i} end\n", true, 60, 64);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("memory limit of 64 MB exceeded"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("recipe.lua:3"), std::string::npos) << r.output;
}

TEST(Runner, WriteJsonIsAtomicAndDeterministic) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(
      dir, "bliskrun.write_json('r.json', {b = 1, a = {1.5, 2, 3}, c = 'x'})\n"
           "bliskrun.write_json('r.json', {b = 1, a = {1.5, 2, 3}, c = 'x', d = print})\n");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("recipe.lua:2: write_json: value.d is a function"), std::string::npos) << r.output;
  // The failed second write left the first file intact, and no temporary.
  std::ifstream in(dir.path() + "/out/r.json");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(text, "{\n  \"a\": [\n    1.5,\n    2,\n    3\n  ],\n  \"b\": 1,\n  \"c\": \"x\"\n}\n");
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir.path() + "/out")) files += e.is_regular_file();
  EXPECT_EQ(files, 1);
}

TEST(Cli, UsageErrorsExitTwo) {
  EXPECT_EQ(run_bliskrun({}).exit_code, 2);
  EXPECT_EQ(run_bliskrun({"--frobnicate", "x.lua"}).exit_code, 2);
  EXPECT_EQ(run_bliskrun({"/nonexistent/recipe.lua"}).exit_code, 2);
  EXPECT_EQ(run_bliskrun({"x.lua", "--set", "novalue"}).exit_code, 2);
  const RecipeResult help = run_bliskrun({"--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("usage: bliskrun"), std::string::npos);
}

TEST(Cli, SetValuesReachTheRecipeAsArgs) {
  TempDir dir;
  const std::string recipe = dir.write(
      "r.lua", "assert(args.blades == 22 and math.type(args.blades) == 'integer', tostring(args.blades))\n"
               "assert(args.tol == 0.002)\nassert(args.fast == true)\nassert(args.name == 'R67')\n");
  const RecipeResult r = run_bliskrun({recipe, "--out", dir.path() + "/out", "--set", "blades=22", "--set",
                                       "tol=0.002", "--set", "fast=true", "--set", "name=R67"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(Cli, DataFolderIsReadableAndCommandLineNamesIt) {
  TempDir dir, data;
  data.write("part/grid.txt", "abc");
  const std::string recipe = dir.write("r.lua", "assert(bliskrun.read_text('part/grid.txt') == 'abc')\n");
  EXPECT_EQ(run_bliskrun({recipe, "--out", dir.path() + "/out"}).exit_code, 1);
  const RecipeResult r = run_bliskrun({recipe, "--out", dir.path() + "/out", "--data", data.path()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(Cli, RecipeErrorExitsOneWithLocation) {
  TempDir dir;
  const std::string recipe = dir.write("bad.lua", "\n\nlocal x = nil + 1\n");
  const RecipeResult r = run_bliskrun({recipe, "--out", dir.path() + "/out"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("bad.lua:3:"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace bliskrun::test

namespace bliskrun::test {
namespace {

TEST(Cli, VerifyPrintsTheReadBackOfEveryPostedProgram) {
  TempDir dir;
  const std::string recipe = std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/blisk_post.lua";
  const RecipeResult r = run_bliskrun({recipe, "--out", dir.path(), "--quiet", "--verify"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("read-back verification: 2 program(s)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("max tip deviation"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace bliskrun::test
