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
  EXPECT_NE(r.output.find("edited.mpf:21: the replayed tool is 0.1"), std::string::npos) << r.output;
}

// One program, two tools: the second tool's moves follow a tool change
// (TCP off, T7 M6, length compensation on again), the read-back replays each
// move with its own tool and checks the tool number, and a program whose
// tool call was edited fails at that move's line.
TEST(MachineLua, TwoToolsInOneProgramAreChangedAndVerified) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, std::string(kPath) +
      "local m = bliskrun.machine.load(\"monoblock_like_head_table\")\n"
      "local p = path({10, 12, 14})\n"
      "for _, move in ipairs(path({20, 22})) do move.tool = 7; p[#p + 1] = move end\n"
      "local r = bliskrun.post.write{machine = m, post = \"heidenhain\", path = p, file = \"two.h\",\n"
      "  tools = {{number = 3, length = 80, spindle_rpm = 9000}, {number = 7, length = 120}}}\n"
      "local text = bliskrun.read_text(\"two.h\")\n"
      "assert(text:find(\"TOOL CALL 3 Z S9000\", 1, true) and text:find(\"TOOL CALL 7 Z\", 1, true))\n"
      "assert(text:find(\"FUNCTION RESET TCPM\\n%d+ TOOL CALL 7\"))\n"
      "assert(r.moves == 7)\n"
      "bliskrun.write_text(\"edited.h\", (text:gsub(\"TOOL CALL 7\", \"TOOL CALL 3\")))\n"
      "bliskrun.post.verify{program = r.program, file = \"out/edited.h\"}\n");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("recipe.lua:20:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("expected tool 7 here (plan move 5), the program has tool 3"), std::string::npos) << r.output;
}

// post.write's cycle time: the machine file's limits (monoblock: tool
// change 7 s), two tool changes (the first tool call is one), positioning,
// cutting and tool changes adding up to the total, per operation in the
// order they run, and each axis word's range over the program.
TEST(MachineLua, PostWriteEstimatesTheCycleTimePerOperation) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, std::string(kPath) +
      "local m = bliskrun.machine.load(\"monoblock_like_head_table\")\n"
      "local p = path({10, 12, 14})\n"
      "for _, move in ipairs(p) do move.operation = \"rough\" end\n"
      "for _, move in ipairs(path({20, 22})) do move.tool = 7; move.operation = \"finish\"; p[#p + 1] = move end\n"
      "local r = bliskrun.post.write{machine = m, post = \"heidenhain\", path = p, file = \"two.h\",\n"
      "  tools = {{number = 3, length = 80, spindle_rpm = 9000}, {number = 7, length = 120}}}\n"
      "local c = r.cycle_time\n"
      "assert(c.tool_changes == 2 and c.tool_change_s == 14, c.tool_changes .. ' ' .. c.tool_change_s)\n"
      "assert(c.rapid_s > 0 and c.cut_s > 0)\n"
      "assert(math.abs(c.total_s - c.rapid_s - c.cut_s - c.tool_change_s) < 1e-9)\n"
      "assert(#c.per_operation == 2 and c.per_operation[1].operation == 'rough' and c.per_operation[2].operation == 'finish')\n"
      "local sum = 0\n"
      "for _, o in ipairs(c.per_operation) do sum = sum + o.total_s end\n"
      "assert(math.abs(sum - c.total_s) < 1e-9)\n"
      "assert(c.per_operation[2].tool_change_s == 7)\n"
      "-- The feed moves: 1 mm steps at F700 (11.7 mm/s) take at least 1/11.7 s each.\n"
      "assert(c.cut_s >= 3 / (700 / 60), c.cut_s)\n"
      "local x = r.axis_ranges.X\n"
      "assert(x[1] <= x[2] and r.axis_ranges.B and r.axis_ranges.C, 'axis ranges')\n");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// post.write_all posts several programs at once — a post named by its file
// in a worker's own Lua state, a post table edited in the recipe on the
// recipe's state — and gives every file and report post.write gives each
// alone, in list order.
TEST(MachineLua, WriteAllGivesWhatWriteGivesEachProgram) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, std::string(kPath) +
      "local ac = bliskrun.machine.load(\"dmg_like_ac_trunnion\")\n"
      "local bc = bliskrun.machine.load(\"monoblock_like_head_table\")\n"
      "local edited = bliskrun.post.load(\"fanuc\")\n"
      "edited.program_number = 2000\n"
      "local function programs(prefix)\n"
      "  local two = path({10, 12, 14})\n"
      "  for _, move in ipairs(path({20, 22})) do move.tool = 7; two[#two + 1] = move end\n"
      "  return {{machine = ac, post = \"fanuc\", path = path({10, 12, 14}), file = prefix .. \"a.nc\", name = \"p\",\n"
      "           tool = {number = 1, length = 80}},\n"
      "          {machine = bc, post = \"heidenhain\", path = two, file = prefix .. \"b.h\", name = \"p\",\n"
      "           tools = {{number = 3, length = 80, spindle_rpm = 9000}, {number = 7, length = 120}}},\n"
      "          {machine = ac, post = edited, path = path({5, 6, 7, 8}), file = prefix .. \"c.nc\", name = \"p\",\n"
      "           tool = {number = 1, length = 80}}}\n"
      "end\n"
      "local alone = {}\n"
      "for i, o in ipairs(programs(\"alone_\")) do alone[i] = bliskrun.post.write(o) end\n"
      "local all = bliskrun.post.write_all(programs(\"all_\"))\n"
      "assert(#all == 3)\n"
      "for i, name in ipairs({\"a.nc\", \"b.h\", \"c.nc\"}) do\n"
      "  assert(bliskrun.read_text(\"alone_\" .. name) == bliskrun.read_text(\"all_\" .. name), name)\n"
      "  assert(all[i].moves == alone[i].moves and all[i].max_position == alone[i].max_position, name)\n"
      "  assert(all[i].positioning == alone[i].positioning and all[i].seconds.post >= 0, name)\n"
      "  assert(bliskrun.post.verify{program = all[i].program}.moves == all[i].moves, name)\n"
      "end\n"
      "assert(bliskrun.read_text(\"all_c.nc\"):find(\"O2000\", 1, true))\n"
      "assert(bliskrun.read_text(\"all_b.h\"):find(\"TOOL CALL 7 Z\", 1, true))\n"
      "assert(all[1].moves == 24 and all[2].moves == 7 and all[3].moves == 17)\n");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// A failure in post.write_all names the program (its index and file) and
// what failed as post.write would, at the recipe line; of several failures
// the first in list order is raised, whatever the thread that ran it. A
// post's own error inside a worker's state keeps its file and line.
TEST(MachineLua, WriteAllNamesTheFirstFailingProgram) {
  TempDir dir;
  const std::string programs =
      "local ac = bliskrun.machine.load(\"dmg_like_ac_trunnion\")\n"
      "local function program(file, tilts, post)\n"
      "  return {machine = ac, post = post or \"fanuc\", path = path(tilts), file = file, tool = {number = 1, length = 80}}\n"
      "end\n";
  const RecipeResult travel = run_recipe_text(dir, std::string(kPath) + programs +
      "bliskrun.post.write_all{program(\"a.nc\", {10, 12}), program(\"b.nc\", {10, 60, 125}),\n"
      "                        program(\"c.nc\", {10, 125, 126, 127, 128})}\n");
  EXPECT_EQ(travel.exit_code, 1);
  EXPECT_NE(travel.output.find("recipe.lua:14: bliskrun.post.write_all: programs[2] (b.nc):"), std::string::npos)
      << travel.output;
  EXPECT_NE(travel.output.find("A: move 4 (row 2)"), std::string::npos) << travel.output;
  EXPECT_NE(travel.output.find("outside travel [-120.000, 30.000] deg"), std::string::npos) << travel.output;

  dir.write("bad_post.lua",
            "local P = extend \"fanuc\"\n"
            "function P.header(self, job, out) error(\"no header for \" .. job.name) end\n"
            "return P\n");
  const RecipeResult post = run_recipe_text(dir, std::string(kPath) + programs +
      "bliskrun.post.write_all{program(\"a.nc\", {10, 12}), program(\"b.nc\", {10, 12}, \"bad_post.lua\")}\n");
  EXPECT_EQ(post.exit_code, 1);
  EXPECT_NE(post.output.find("programs[2] (b.nc): "), std::string::npos) << post.output;
  EXPECT_NE(post.output.find("bad_post.lua:2: no header for b"), std::string::npos) << post.output;
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

// The header's options: the work offset within 1-99 and within what the
// post's controller has; coolant one of four and one the post has a code
// for; the program number within what the controller numbers; the setup's keys and clocking range; notes one line
// each (a line break would make the rest of a note a block). The header
// states each where the options put it.
TEST(MachineLua, PostWriteHeaderOptionsAreValidatedAndWritten) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir,
      "local m = bliskrun.machine.load(\"dmg_like_ac_trunnion\")\n"
      "local path = {{kind = \"rapid\", tip = {40, 0, 30}, axis = {0, 0, 1}},\n"
      "              {kind = \"feed\", tip = {40, 1, 5}, axis = {0, 0, 1}, feed = 800}}\n"
      "local function post(extra, name)\n"
      "  local o = {machine = m, post = name or \"fanuc\", path = path, file = \"x.nc\", tool = {number = 1, length = 80}}\n"
      "  for k, v in pairs(extra) do o[k] = v end\n"
      "  return pcall(bliskrun.post.write, o)\n"
      "end\n"
      "local ok, err = post{work_offset = 0}\n"
      "assert(not ok and err:find(\"option 'work_offset': 0 is out of range [1, 99]\", 1, true), err)\n"
      "ok, err = post{work_offset = 1.5}\n"
      "assert(not ok and err:find(\"option 'work_offset': expected integer\", 1, true), err)\n"
      "ok, err = post({work_offset = 7}, \"siemens840d\")\n"
      "assert(ok, err)\n"
      "ok, err = post{coolant = \"air\"}\n"
      "assert(not ok and err:find(\"option 'coolant': 'air' is not one of 'flood', 'mist', 'through', 'off'\", 1, true), err)\n"
      "ok, err = post({coolant = \"through\"}, \"linuxcnc\")\n"
      "assert(not ok and err:find(\"linuxcnc: coolant 'through': this post has no code for it; it has flood (M8), mist (M7)\", 1, true), err)\n"
      "ok, err = post{program_number = 0}\n"
      "assert(not ok and err:find(\"option 'program_number': 0 is out of range\", 1, true), err)\n"
      "ok, err = post{program_number = 12345}\n"
      "assert(not ok and err:find(\"fanuc: program_number 12345: O-numbers are 1-9999\", 1, true), err)\n"
      "ok, err = post({work_offset = 10}, \"linuxcnc\")\n"
      "assert(not ok and err:find(\"linuxcnc: work_offset 10: LinuxCNC has work offsets 1-9\", 1, true), err)\n"
      "ok, err = post{setup = {name = \"a\", flipped = true}}\n"
      "assert(not ok and err:find(\"bliskrun.post.write setup: unknown option 'flipped'; valid options: clocking_deg, \"\n"
      "                           .. \"flip, name\", 1, true), err)\n"
      "ok, err = post{setup = {clocking_deg = 400}}\n"
      "assert(not ok and err:find(\"option 'clocking_deg': 400 is out of range [-360, 360]\", 1, true), err)\n"
      "ok, err = post{notes = {\"one\", \"two\\nG0 Z-10\"}}\n"
      "assert(not ok and err:find(\"notes[2]: a note is one line (no line breaks)\", 1, true), err)\n"
      "ok, err = post{notes = {\"one\", 5}}\n"
      "assert(not ok and err:find(\"notes[2]: expected a string\", 1, true), err)\n"
      "ok, err = post{notes = {first = \"one\"}}\n"
      "assert(not ok and err:find(\"notes: expected a list of strings\", 1, true), err)\n"
      "ok, err = post{work_offset = 6, setup = {name = \"op 2\", flip = true, clocking_deg = -22.5},\n"
      "               notes = {\"clamp (on the arm)\"}}\n"
      "assert(ok, err)\n"
      "local text = bliskrun.read_text(\"x.nc\")\n"
      "for _, line in ipairs{\"(SETUP: OP 2)\", \"(PART TURNED OVER: 180 DEG ABOUT X, MODEL +Z ALONG PART FRAME -Z)\",\n"
      "                      \"(CLOCKING -22.500 DEG: MODEL TURNED -22.500 DEG ABOUT PART FRAME +Z AFTER TURNING OVER)\",\n"
      "                      \"(CLAMP ON THE ARM)\", \"N20 G59\", \"(WORK OFFSET G59: THE MACHINE ZERO\"} do\n"
      "  assert(text:find(line, 1, true), line .. \" not in:\\n\" .. text)\n"
      "end\n");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// job:post carries its setup into the program: the moves turned over
// (180 deg about X) and clocked (about Z) as the setup says, and the header
// says so; the work offset and the notes go through too. A planned move at
// (10, 150, -60) with axis (0, -0.6, -0.8) — below the blisk, outside its
// clearance can — turned over: (10, -150, 60) and (0, 0.6, 0.8); then
// clocked 90 deg: (150, 10, 60) and (-0.6, 0, 0.8). The program comes in
// and leaves at the safe height (Retract, Rotate, Position, Descend ... Lift).
TEST(MachineLua, JobPostCarriesItsSetupIntoTheProgram) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir,
      "local job = require(\"job\")\n"
      "local mill = bliskrun.flat_end_mill{radius = 3, corner_radius = 0.5, flute_length = 9,\n"
      "                                    shank = {diameter = 6, length = 50}}\n"
      "local j = job.new{name = \"setup test\", part = bliskrun.blisk{}, clearance_radius = 110,\n"
      "                  tools = {mill = {number = 7, length = 100, spindle_rpm = 12000, tool = mill}},\n"
      "                  operations = {{kind = \"edge_finish\", tool = \"mill\"}}}\n"
      "j.planned = {moves = {\n"
      "  {kind = \"rapid\", tip = {10, 150, -30}, axis = {0, -0.6, -0.8}, tool = 7},\n"
      "  {kind = \"feed\", tip = {10, 150, -60}, axis = {0, -0.6, -0.8}, tool = 7, feed = 500},\n"
      "  {kind = \"feed\", tip = {11, 150, -60}, axis = {0, -0.6, -0.8}, tool = 7, feed = 500}}}\n"
      "local setup = {name = \"turned over\", first = 2, last = 3, flip = true, clocking_deg = 90}\n"
      "local o = {machine = \"monoblock_like_head_table\", post = \"heidenhain\", file = \"s.h\", setup = setup}\n"
      "local path, offset = j:program_path(o, 1)\n"
      "assert(#path == 2 and offset == 1)\n"
      "local function near(a, b) return math.abs(a[1] - b[1]) + math.abs(a[2] - b[2]) + math.abs(a[3] - b[3]) < 1e-12 end\n"
      "assert(near(path[1].tip, {150, 10, 60}) and near(path[1].axis, {-0.6, 0, 0.8}), table.concat(path[1].tip, ' '))\n"
      "assert(near(path[2].tip, {150, 11, 60}) and j.planned.moves[2].tip[2] == 150)\n"
      "o.work_offset, o.notes = 4, {\"check the clocking pin\"}\n"
      "local report = j:post(o)\n"
      "assert(report.moves == 6 and report.safe_moves == 3 and report.unswept == 0, report.moves)\n"
      "local text = bliskrun.read_text(\"s.h\")\n"
      "for _, line in ipairs{\"; setup: turned over\\n\", \"; part turned over: 180 deg about X\",\n"
      "                      \"; clocking 90.000 deg: model turned 90.000 deg about part frame +Z after turning over\",\n"
      "                      \"; tool 7 length 100.000 S12000\", \"; check the clocking pin\", \"Q339=+4 \"} do\n"
      "  assert(text:find(line, 1, true), line .. \" not in:\\n\" .. text)\n"
      "end\n");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// machine:placed moves the part's origin in the program zero: at home
// orientation the same part point is reached 10 mm further along X, the
// rotary axes unchanged; the original machine keeps its origin.
TEST(MachineLua, PlacedMovesThePartOriginAndLeavesTheOriginalAlone) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir,
      "local m = bliskrun.machine.load(\"table_table_bc\")\n"
      "local moved = m:placed{part_origin = {10, 0, 0}}\n"
      "local pose = {tip = {5, -3, 20}, axis = {0, 0, 1}}\n"
      "local a = m:solve(pose, {tool_length = 100})\n"
      "local b = moved:solve(pose, {tool_length = 100})\n"
      "assert(math.abs(math.abs(b.X - a.X) - 10) < 1e-9, b.X - a.X)\n"
      "assert(math.abs(b.Y - a.Y) < 1e-9 and math.abs(b.Z - a.Z) < 1e-9)\n"
      "assert(math.abs(b.B - a.B) < 1e-9 and math.abs(b.C - a.C) < 1e-9)\n"
      "local again = m:solve(pose, {tool_length = 100})\n"
      "assert(again.X == a.X)\n"
      "local ok, err = pcall(m.placed, m, {part_origin = {1, 2}})\n"
      "assert(not ok and err:find(\"part_origin\"), err)\n"
      "ok, err = pcall(m.placed, m, {origin = {1, 2, 3}})\n"
      "assert(not ok and err:find(\"unknown option 'origin'\"), err)\n");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// The way in from the safe height, as each post writes it: Fanuc (machine
// axes) with its length compensation on before the first Z; the TNC with
// TCPM off for Z and the rotaries, on for the rest; the verdict filled in;
// every block swept. A descent longer than the plan proved is refused.
TEST(MachineLua, PostsWriteTheWayInFromTheSafeHeight) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir,
      "local path = {}\n"
      "for i = 0, 10 do\n"
      "  path[#path + 1] = {kind = i == 0 and 'rapid' or 'feed', tip = {40, i, 5}, axis = {0, -0.5, 0.8660254}, feed = 500}\n"
      "end\n"
      "local mill = bliskrun.flat_end_mill{radius = 3, corner_radius = 0.5, flute_length = 9,\n"
      "                                    shank = {diameter = 6, length = 50}}\n"
      "local tool = {number = 1, length = 80, body = mill}\n"
      "local m = bliskrun.machine.load('dmg_like_ac_trunnion')\n"
      "local r = bliskrun.post.write{machine = m, post = 'fanuc', path = path, file = 'a.nc', tool = tool,\n"
      "                              approach = {proved = 2000}}\n"
      "local text = bliskrun.read_text('a.nc')\n"
      "local g43, z = text:find('N%d+ G43 H1'), text:find('N%d+ G0 Z')\n"
      "assert(g43 and z and g43 < z, text:sub(1, 1500))\n"
      "assert(r.safe_moves == 3 and r.unswept == 0 and r.swept == r.moves - 3, r.swept)\n"
      "assert(r.swept_tool > 0 and r.swept_cutter <= 0.005 + 0.01, r.swept_cutter)\n"
      "assert(text:find('(VERDICT: PROVED, EVERY BLOCK', 1, true))\n"
      "local h = bliskrun.machine.load('monoblock_like_head_table')\n"
      "bliskrun.post.write{machine = h, post = 'heidenhain', path = path, file = 'a.h', tool = tool,\n"
      "                    approach = {proved = 2000, proved_up = 2000}}\n"
      "local tnc = bliskrun.read_text('a.h')\n"
      "local up, rotate, tcpm = tnc:find('\\n%d+ L Z%+[%d.]+ R0 FMAX\\n'), tnc:find('\\n%d+ L C[-+][%d.]+ B[-+][%d.]+ R0 FMAX'),\n"
      "                         tnc:find('FUNCTION TCPM F TCP')\n"
      "assert(up and rotate and tcpm and up < rotate and rotate < tcpm, tnc:sub(1, 2000))\n"
      "assert(tnc:find('; VERDICT: PROVED, every block', 1, true), tnc:sub(1, 400))\n"
      "local ok, err = pcall(bliskrun.post.write, {machine = m, post = 'fanuc', path = path, file = 'b.nc', tool = tool,\n"
      "                                            approach = {proved = 10}})\n"
      "assert(not ok and tostring(err):find('the plan proved 10 mm of it clear'), tostring(err))\n");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

}  // namespace
}  // namespace bliskrun::test
