// bliskrun.machine / bliskrun.post through the recipe runner: errors land at
// the recipe's (or machine file's, or program's) line and name what failed.
#include <gtest/gtest.h>

#include "test_support.h"

namespace bliskrun::test {
namespace {

const char* kPath = R"lua(
local function path(tilts)
  local p = {{kind = "rapid", tip = {30, 0, 20}, axis = {0, 0, 1}}}
  for i, t in ipairs(tilts) do
    local a = math.rad(t)
    p[#p + 1] = {kind = "feed", tip = {30, i, 5}, axis = {0, -math.sin(a), math.cos(a)}, feed = 700, row = 2}
  end
  return p
end
)lua";

TEST(MachineLua, MachineFileErrorIsAtItsLine) {
  TempDir dir;
  dir.write("mine.lua",
            "-- my machine\n"
            "return generic \"table_table_ac\" {\n"
            "  name = \"mine\",\n"
            "  a_limits = {-90, 20},\n"
            "}\n");
  const RecipeResult r = run_recipe_text(dir, "local m = bliskrun.machine.load(\"mine.lua\")\n");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("mine.lua:2: unknown machine parameter 'a_limits', expected one of: a, a_pivot"),
            std::string::npos) << r.output;
}

TEST(MachineLua, UnreachableMoveIsNamedAtTheRecipeLine) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, std::string(kPath) +
      "local m = bliskrun.machine.load(\"dmg_like_ac_trunnion\")\n"
      "bliskrun.post.write{machine = m, post = \"fanuc\", path = path({10, 60, 125}), file = \"x.nc\",\n"
      "                    tool = {number = 1, length = 80}}\n");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("recipe.lua:11:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("A: move 4 (row 2)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("outside travel [-120.000, 30.000] deg"), std::string::npos) << r.output;
}

TEST(MachineLua, EditedProgramFailsVerificationAtItsLine) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, std::string(kPath) +
      "local m = bliskrun.machine.load(\"dmg_like_ac_trunnion\")\n"
      "local r = bliskrun.post.write{machine = m, post = \"siemens840d\", path = path({10, 12, 14}), file = \"x.mpf\",\n"
      "                              tool = {number = 1, length = 80}}\n"
      "local text = bliskrun.read_text(\"x.mpf\")\n"
      "assert(bliskrun.post.verify{program = r.program}.moves == r.moves)\n"
      "local edited = text:gsub(\"Y3%.000\", \"Y3.100\")\n"
      "bliskrun.write_text(\"edited.mpf\", edited)\n"
      "bliskrun.post.verify{program = r.program, file = \"out/edited.mpf\"}\n");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("edited.mpf:15: the replayed tool is 0.1"), std::string::npos) << r.output;
}

TEST(MachineLua, PostWriteOptionsAreValidated) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir,
      "local m = bliskrun.machine.load(\"dmg_like_ac_trunnion\")\n"
      "bliskrun.post.write{machine = m, post = \"fanuc\", path = {}, file = \"x.nc\", tool = {number = 1, length = 80},\n"
      "                    chord_tolerance = 0.001}\n");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("recipe.lua:2:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("chord_tolerance"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace bliskrun::test
