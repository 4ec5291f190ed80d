// bliskrun.belt_paths{...}: bad options land on the recipe line and say what
// was expected.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_support.h"

namespace bliskrun::test {
namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

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

// Robot programs through the shipped posts: what the header and the first
// target say, and a post edited to move the part by 10 um is refused at the
// read-back with nothing written.
TEST(LuaRobotPrograms, PostsWriteReadableProgramsAndAnEditedPostIsRefused) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, R"(
local pts = {}
for i = 0, 2 do for j = 0, 6 do pts[#pts + 1] = {10 * j, 0, 60 + 10 * i} end end
local face = bliskrun.point_grid{rows = 3, cols = 7, points = pts}:surface()
local paths = bliskrun.belt_paths{face = face, wheel = bliskrun.contact_wheel{radius = 20, width = 10}, scallop = 0.05}.paths
local cell = bliskrun.robot_cell("kuka_kr120_belt_cell")
local body = bliskrun.blade_body{faces = {{name = "face", surface = face}}, spacing = 1}
local grip = {origin = {0, 0, 50}, x = {0, 0, 1}, z = {0, 1, 0}}
local ok, why = pcall(cell.plan_grinding, cell, {station = "fine", grip = grip, paths = paths})
assert(not ok and why:find("blade"), why)  -- nothing is planned unchecked against the blade
local plan = cell:plan_grinding{station = "fine", grip = grip, paths = paths, blade = body}
local rep = plan:report()
assert(#rep.refusals == 0 and rep.wheel.rejected == 0 and rep.wheel.poses > #plan:moves(), rep.wheel.first_collision)
local k = plan:write_program{post = "kuka_krl", file = "p.src", name = "flat test"}
assert(k.max_position < 1e-4 and k.moves == #plan:moves())
local abb = bliskrun.robot_cell("abb_irb6650s_belt_cell")
local aplan = abb:plan_grinding{station = "fine", grip = grip, paths = paths, blade = body}
assert(aplan:write_program{post = "abb_rapid", file = "p.mod", blade_mass = 0.5, gripper_mass = 8,
                           gripper_cog = {0, 0, 60}}.max_position < 1e-4)
-- Split within 4000 bytes a file: a station program calling its parts, read back as one.
local split = plan:write_program{post = "kuka_krl", file = "s.src", max_bytes = 4000}
assert(#split.files > 2 and split.bytes <= 4000 and split.moves == #plan:moves(), #split.files)
local asplit = aplan:write_program{post = "abb_rapid", file = "s.mod", max_bytes = 4000}
assert(#asplit.files > 2 and asplit.bytes <= 4000, #asplit.files)
local bad = bliskrun.post.load("kuka_krl")
local position = bad.position
bad.position = function(self, v) return position(self, v + 0.01) end
local ok, msg = pcall(plan.write_program, plan, {post = bad, file = "bad.src"})
assert(not ok and msg:find("does not replay the plan"), msg)
)");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string krl = read_file(dir.path() + "/out/p.src"), rapid = read_file(dir.path() + "/out/p.mod");
  // KSS: DEF names the file; INI fold; home first; the wheel is BASE data,
  // the blade TOOL data; #TCP while grinding, #BASE restored.
  EXPECT_NE(krl.find("\nDEF p( )\n"), std::string::npos);
  EXPECT_NE(krl.find("BAS (#INITMOV,0 )"), std::string::npos);
  EXPECT_LT(krl.find("PTP {A1 0.0000,A2 -90.0000,A3 90.0000"), krl.find("E6POS"));
  EXPECT_NE(krl.find("$BASE = {X 1700.0000,Y 0.0000,Z 900.0000,"), std::string::npos);
  EXPECT_LT(krl.find("$IPO_MODE = #TCP"), krl.find("PTP {E6POS: X "));
  EXPECT_GT(krl.find("$IPO_MODE = #BASE"), krl.rfind("LIN {E6POS: X "));
  for (const char* set : {"$ORI_TYPE = #VAR", "$APO.CDIS = ", "$VEL.ORI1 = ", "$VEL.ORI2 = ", "$ACC.CP = ", "$LOAD = "})
    EXPECT_NE(krl.find(set), std::string::npos) << set;
  // RAPID: no main in a station module, its data named after it, home first, the blade's load.
  EXPECT_EQ(rapid.substr(0, rapid.find('\n')), "MODULE p");
  EXPECT_EQ(rapid.find("PROC main"), std::string::npos);
  EXPECT_NE(rapid.find("PERS tooldata tw_p := [FALSE,[[2200.0000,0.0000,1000.0000],"), std::string::npos);
  EXPECT_NE(rapid.find("[8.000,[0.0,0.0,60.0],"), std::string::npos);
  EXPECT_NE(rapid.find("PERS wobjdata wb_p := [TRUE,TRUE,"), std::string::npos);
  EXPECT_NE(rapid.find("PERS loaddata ld_p := [0.500,"), std::string::npos);
  EXPECT_LT(rapid.find("MoveAbsJ jh_p"), rapid.find("MoveJ ["));
  EXPECT_NE(rapid.find(",tw_p\\WObj:=wb_p;"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir.path() + "/out/s_p2.src"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() + "/out/s_p2.mod"));
  EXPECT_FALSE(std::filesystem::exists(dir.path() + "/out/bad.src"));
}

}  // namespace
}  // namespace bliskrun::test
