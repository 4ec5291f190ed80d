// bliskrun.belt_paths{...}: bad options land on the recipe line and say what
// was expected.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "test_support.h"

namespace bliskrun::test {
namespace {

// A flat face 60 x 20 mm standing in y = 0 from z = 60, and its belt paths:
// the start of the robot-program recipes below.
const std::string kFlatFaceAndPaths = R"(
local pts = {}
for i = 0, 2 do for j = 0, 6 do pts[#pts + 1] = {10 * j, 0, 60 + 10 * i} end end
local face = bliskrun.point_grid{rows = 3, cols = 7, points = pts}:surface()
local paths = bliskrun.belt_paths{face = face, wheel = bliskrun.contact_wheel{radius = 20, width = 10}, scallop = 0.05}.paths
)";

std::string read_belt_file(const std::string& path) {
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
  const RecipeResult r = run_recipe_text(dir, kFlatFaceAndPaths + R"(
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
  const std::string krl = read_belt_file(dir.path() + "/out/p.src"), rapid = read_belt_file(dir.path() + "/out/p.mod");
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
  EXPECT_NE(rapid.find("[8.000,[0.000,0.000,60.000],"), std::string::npos);
  EXPECT_NE(rapid.find("PERS wobjdata wb_p := [TRUE,TRUE,"), std::string::npos);
  EXPECT_NE(rapid.find("PERS loaddata ld_p := [0.500,"), std::string::npos);
  EXPECT_LT(rapid.find("MoveAbsJ jh_p"), rapid.find("MoveJ ["));
  EXPECT_NE(rapid.find(",tw_p\\WObj:=wb_p;"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir.path() + "/out/s_p2.src"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() + "/out/s_p2.mod"));
  EXPECT_FALSE(std::filesystem::exists(dir.path() + "/out/bad.src"));
}

// The payload (issue 39 item 2): the blade's mass properties in the blade
// frame and a stated gripper solid in the flange frame, written as KRL's
// whole load on the flange and RAPID's tload (gripper, wrist frame) plus
// GripLoad payload (blade, in the object frame of the held work object) —
// numbers checked against the closed forms of a box and a cylinder. And a
// registration that is not trusted stops the post with what to scan.
TEST(LuaRobotPrograms, ThePayloadIsTheBladeSolidAndTheGripperInTheControllersFrames) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, kFlatFaceAndPaths + R"(
local body = bliskrun.blade_body{faces = {{name = "face", surface = face}}, spacing = 1}
-- The blade's x along the flange's z, its z along the flange's y (its y along the flange's x).
local grip = {origin = {0, 0, 50}, x = {0, 0, 1}, z = {0, 1, 0}}
-- A titanium plate 40 x 120 x 10 mm (blade x, y, z) about the blade origin: 0.21264 kg.
local blade = bliskrun.mass_properties{box = {40, 120, 10}, density = 4.43}
assert(math.abs(blade.mass - 0.21264) < 1e-12 and math.abs(blade.volume - 48000) < 1e-9)
local gripper = bliskrun.mass_properties{cylinder = {radius = 80, length = 180}, mass = 15,
                                         frame = {origin = {0, 0, 90}, x = {1, 0, 0}, z = {0, 0, 1}}}
assert(math.abs(gripper.inertia[3][3] - 48000) < 1e-9 and math.abs(gripper.inertia[1][1] - 64500) < 1e-9)
-- The same plate as a closed mesh of section loops integrates to its closed form.
local loops = {}
for _, x in ipairs{-20, 0, 20} do
  loops[#loops + 1] = {{x, -60, -5}, {x, 60, -5}, {x, 60, 5}, {x, -60, 5}}
end
local lofted = bliskrun.mass_properties{loops = loops, density = 4.43}
assert(math.abs(lofted.mass - blade.mass) < 1e-12 and math.abs(lofted.inertia[2][2] - blade.inertia[2][2]) < 1e-9)
for _, c in ipairs{{"kuka_kr120_belt_cell", "kuka_krl", "p.src"}, {"abb_irb6650s_belt_cell", "abb_rapid", "p.mod"}} do
  local cell = bliskrun.robot_cell(c[1])
  local plan = cell:plan_grinding{station = "fine", grip = grip, paths = paths, blade = body}
  local w = plan:write_program{post = c[2], file = c[3], blade = blade, gripper = gripper}
  assert(math.abs(w.payload.mass - 15.21264) < 1e-12)
  local ok, why = pcall(plan.write_program, plan, {post = c[2], file = "r" .. c[3], registration = {trusted = false,
    problems = {"condition 3.2e+06 above 1e+05: the scan slides along the surface; scan both flanks and the edges"}}})
  assert(not ok and why:find("not trusted") and why:find("scan both flanks"), why)
end
)");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.path() + "/out/rp.src"));
  EXPECT_FALSE(std::filesystem::exists(dir.path() + "/out/rp.mod"));
  // The closed forms, flange frame: the cylinder (15 kg) centred at z = 90,
  // the plate (0.21264 kg) at z = 50 with its 120 mm along the flange's x,
  // 10 mm along y and 40 mm along z; both on the flange's axis, so the
  // principal axes are the flange's own.
  const double mg = 15, mb = 0.21264, m = mg + mb, zc = (mg * 90 + mb * 50) / m;
  const double parallel = mg * (90 - zc) * (90 - zc) + mb * (50 - zc) * (50 - zc);
  const double jx = 64500 + mb * (10 * 10 + 40 * 40) / 12 + parallel, jy = 64500 + mb * (120 * 120 + 40 * 40) / 12 + parallel,
               jz = 48000 + mb * (120 * 120 + 10 * 10) / 12;
  const std::string krl = read_belt_file(dir.path() + "/out/p.src");
  const size_t at = krl.find("$LOAD = ");
  ASSERT_NE(at, std::string::npos);
  double M, X, Y, Z, A, B, C, JX, JY, JZ;
  ASSERT_EQ(std::sscanf(krl.c_str() + at, "$LOAD = {M %lf,CM {X %lf,Y %lf,Z %lf,A %lf,B %lf,C %lf},J {X %lf,Y %lf,Z %lf}}",
                        &M, &X, &Y, &Z, &A, &B, &C, &JX, &JY, &JZ),
            10)
      << krl.substr(at, 120);
  EXPECT_NEAR(M, m, 5e-4);
  EXPECT_NEAR(X, 0, 5e-4);
  EXPECT_NEAR(Y, 0, 5e-4);
  EXPECT_NEAR(Z, zc, 5e-4);
  EXPECT_NEAR(std::abs(A) + std::abs(B) + std::abs(C), 0, 1e-4);
  EXPECT_NEAR(JX, 1e-6 * jx, 5e-8);
  EXPECT_NEAR(JY, 1e-6 * jy, 5e-8);
  EXPECT_NEAR(JZ, 1e-6 * jz, 5e-8);
  // RAPID: tload the gripper alone (flange frame), the payload the plate in
  // the blade frame — its centre of gravity at the blade origin, not at the
  // flange's (0, 0, 50); its moments about the blade's own axes.
  const std::string rapid = read_belt_file(dir.path() + "/out/p.mod");
  EXPECT_NE(rapid.find(",[15.000,[0.000,0.000,90.000],[1.000000000,0.000000000,0.000000000,0.000000000],0.064500000,0.064500000,0.048000000]];"),
            std::string::npos)
      << rapid.substr(0, 900);
  char plate[200];
  std::snprintf(plate, sizeof plate, "PERS loaddata ld_p := [0.213,[0.000,0.000,0.000],[1.000000000,0.000000000,0.000000000,"
                "0.000000000],%.9f,%.9f,%.9f];", 1e-6 * mb * (120 * 120 + 10 * 10) / 12, 1e-6 * mb * (40 * 40 + 10 * 10) / 12,
                1e-6 * mb * (40 * 40 + 120 * 120) / 12);
  EXPECT_NE(rapid.find(plate), std::string::npos) << plate << "\n" << rapid.substr(0, 900);
}

}  // namespace
}  // namespace bliskrun::test
