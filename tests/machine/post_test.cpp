// The shipped machine files and posts (scripts/machines, scripts/posts) run
// through the Lua host on a plain Lua state: literal expected programs for a
// short path, and the read-back of every post's output.
#include <gtest/gtest.h>

#include <cstdlib>
#include <functional>
#include <fstream>
#include <memory>
#include <sstream>

#include "core/common/error.h"
#include "core/machine/program_reader.h"
#include "core/machine/verify.h"
#include "lua_api/machine_host.h"

namespace bliskrun {
namespace {


std::string scripts() { return std::string(BLISKRUN_SOURCE_DIR) + "/scripts"; }

struct LuaState {
  LuaState() : L(luaL_newstate()) { luaL_openlibs(L); }
  ~LuaState() { lua_close(L); }
  lua_State* L;
};

// Runs `body` in protected mode; returns the Lua error message or "".
template <class F>
std::string protect(lua_State* L, F body) {
  struct Call {
    F* body;
    static int run(lua_State* S) {
      auto* call = static_cast<Call*>(lua_touserdata(S, 1));
      (*call->body)(S);
      return 0;
    }
  } call{&body};
  lua_pushcfunction(L, &Call::run);
  lua_pushlightuserdata(L, &call);
  if (lua_pcall(L, 1, 0, 0) == LUA_OK) return "";
  std::string message = lua_tostring(L, -1);
  lua_pop(L, 1);
  return message;
}

MachineDefinition load_machine(lua_State* L, const std::string& file) {
  MachineDefinition def;
  const std::string error = protect(L, [&](lua_State* S) {
    lua_api::load_machine_file(S, scripts() + "/machines/" + file, 0, scripts() + "/machines");
    def = lua_api::test_machine(S, -1)->definition;
  });
  if (!error.empty()) throw Error(error);
  return def;
}

// A short path: rapid approach, three feed moves that tilt and turn the tool.
std::vector<PlannedMove> short_path() {
  std::vector<PlannedMove> path;
  auto add = [&](MoveKind kind, Vec3 tip, double tilt_deg, double azimuth_deg) {
    PlannedMove m;
    m.kind = kind;
    m.feed_mm_per_min = 800;
    m.row = 0;
    m.pose.tip = tip;
    m.pose.axis = Vec3(std::sin(tilt_deg * kDeg) * std::cos(azimuth_deg * kDeg),
                       std::sin(tilt_deg * kDeg) * std::sin(azimuth_deg * kDeg), std::cos(tilt_deg * kDeg));
    path.push_back(m);
  };
  add(MoveKind::Rapid, Vec3(40, 0, 30), 20, 90);
  add(MoveKind::Feed, Vec3(40, 0, 5), 20, 90);
  add(MoveKind::Feed, Vec3(40, 2, 5), 21, 92);
  add(MoveKind::Feed, Vec3(40, 4, 5.5), 22, 94);
  return path;
}

struct Written {
  std::string text;
  MachineProgram plan;
  std::unique_ptr<Kinematics> kin;
  bool tcp_always = false;
};

// `job` fills in what the test states beyond the name and the tool.
Written write_program(lua_State* L, const std::string& machine_file, const std::string& post, bool tcp,
              const std::function<void(lua_api::PostJob&)>& job_of = {}) {
  Written w;
  w.kin = std::make_unique<Kinematics>(load_machine(L, machine_file), 80.0);
  const std::string error = protect(L, [&](lua_State* S) {
    lua_api::load_post_file(S, scripts() + "/posts/" + post + ".lua", scripts() + "/posts");
    lua_pushboolean(S, tcp);
    lua_setfield(S, -2, "tcp");
    MotionOptions options;
    options.tcp = lua_api::post_wants_tcp(S, -1);
    options.start.rotary_rad = {0, 0};
    w.tcp_always = lua_api::post_tcp_always(S, -1);
    w.plan = plan_machine_motion(*w.kin, short_path(), options);
    lua_api::PostJob job;
    job.name = "blade 1";
    job.tools.push_back({3, 80, 12000});
    if (job_of) job_of(job);
    w.text = lua_api::run_post(S, -1, *w.kin, w.plan, job);
  });
  if (!error.empty()) throw Error(error);
  return w;
}

// Literal programs: any change to a post's wording shows up here.
TEST(MachinePosts, FanucMachineAxesProgramIsLiteral) {
  LuaState lua;
  const Written w = write_program(lua.L, "dmg_like_ac_trunnion.lua", "fanuc", false);
  EXPECT_EQ(w.text,
            "%\n"
            "O1000 (BLADE 1)\n"
            "(VERDICT: @VERDICT@)\n"
            "(MACHINE DMG-LIKE A/C TRUNNION 650)\n"
            "(PART NOT TURNED OVER: MODEL +Z ALONG PART FRAME +Z)\n"
            "(CLOCKING 0.000 DEG: MODEL +X ALONG PART FRAME +X)\n"
            "(ROTARY A TABLE: A+ TURNS THE PART RIGHT-HANDED ABOUT +X, THE TOOL RELATIVE TO THE PART LEFT-HANDED: AGAINST ISO 841)\n"
            "(ROTARY C TABLE: C+ TURNS THE PART RIGHT-HANDED ABOUT +Z, THE TOOL RELATIVE TO THE PART LEFT-HANDED: AGAINST ISO 841)\n"
            "(TOOL 3 LENGTH 80.000 S12000)\n"
            "(WORK OFFSET G54: THE MACHINE ZERO OF THE MACHINE FILE; THE PART FRAME ORIGIN MUST LIE AT X0.000 Y0.000 Z120.000 FROM IT WITH ALL AXES AT 0)\n"
            "(RAPIDS THAT TURN A ROTARY AXIS OR MOVE MORE THAN ONE LINEAR AXIS ARE FEED MOVES AT F30000 MM/MIN)\n"
            "(THE FIRST MOVE POSITIONS FROM THE TOOL CHANGE POINT: START WITH THE TOOL CLEAR OF THE PART)\n"
            "(BETWEEN BLOCKS THE CONTROLLER MOVES JOINT-LINEAR: THE PROGRAM WAS SPLIT AND SWEPT FOR THAT)\n"
            "N10 G90 G17 G21 G40 G49 G80 G93\n"
            "N20 G54\n"
            "N30 T3 M6\n"
            "N40 S12000 M3\n"
            "N50 G43 H3\n"
            "N60 G0 X40.000 Y-68.414 Z137.933 A20.000 C0.000\n"
            "N70 G1 Y-59.863 Z114.440 F32.000\n"
            "N80 X40.011 Y-61.021 Z114.014 A20.497 C-1.023 F800.000\n"
            "N90 X40.045 Y-62.162 Z113.586 A21.000 C-2.000 F800.000\n"
            "N100 X40.102 Y-63.406 Z113.377 A21.497 C-3.022 F776.114\n"
            "N110 X40.181 Y-64.642 Z113.163 A22.000 C-4.000 F776.114\n"
            "N120 G49\n"
            "N130 M5\n"
            "N140 M30\n"
            "%\n");
  // The two 1-degree swings were split in two to hold the 5 um chord.
  EXPECT_EQ(w.plan.inserted_moves, 2);
}

TEST(MachinePosts, FanucTcpProgramIsLiteral) {
  LuaState lua;
  // The second setup of a job: turned over, another work offset, a second
  // tool the header lists though this short path never calls it, a note.
  const Written w = write_program(lua.L, "dmg_like_ac_trunnion.lua", "fanuc", true, [](lua_api::PostJob& job) {
    job.tools.push_back({7, 95.25, 0});
    job.work_offset = 2;
    job.setup = {"turned over (inlet up)", true, 0};
    job.notes = {"fixture BR-22 (inlet side)"};
  });
  EXPECT_EQ(w.text,
            "%\n"
            "O1000 (BLADE 1)\n"
            "(VERDICT: @VERDICT@)\n"
            "(MACHINE DMG-LIKE A/C TRUNNION 650)\n"
            "(SETUP: TURNED OVER INLET UP)\n"
            "(PART TURNED OVER: 180 DEG ABOUT X, MODEL +Z ALONG PART FRAME -Z)\n"
            "(CLOCKING 0.000 DEG: MODEL +X ALONG PART FRAME +X)\n"
            "(ROTARY A TABLE: A+ TURNS THE PART RIGHT-HANDED ABOUT +X, THE TOOL RELATIVE TO THE PART LEFT-HANDED: AGAINST ISO 841)\n"
            "(ROTARY C TABLE: C+ TURNS THE PART RIGHT-HANDED ABOUT +Z, THE TOOL RELATIVE TO THE PART LEFT-HANDED: AGAINST ISO 841)\n"
            "(TOOL 3 LENGTH 80.000 S12000)\n"
            "(TOOL 7 LENGTH 95.250)\n"
            "(WORK OFFSET G55: THE PART FRAME ORIGIN; IT LIES AT X0.000 Y0.000 Z120.000 FROM THE MACHINE ZERO OF THE MACHINE FILE WITH ALL AXES AT 0)\n"
            "(RAPIDS THAT TURN A ROTARY AXIS OR MOVE MORE THAN ONE LINEAR AXIS ARE FEED MOVES AT F30000 MM/MIN)\n"
            "(THE FIRST MOVE POSITIONS FROM THE TOOL CHANGE POINT: START WITH THE TOOL CLEAR OF THE PART)\n"
            "(BETWEEN BLOCKS THE CONTROLLER MOVES TCP, ROTARIES LINEAR: THE PROGRAM WAS SPLIT AND SWEPT FOR THAT)\n"
            "(FIXTURE BR-22 INLET SIDE)\n"
            "N10 G90 G17 G21 G40 G49 G80 G94\n"
            "N20 G55\n"
            "N30 T3 M6\n"
            "N40 S12000 M3\n"
            "N50 G43.4 H3\n"
            "N60 G0 X40.000 Y0.000 Z30.000 A20.000 C0.000\n"
            "N70 G1 Z5.000 F800.0\n"
            "N80 Y2.000 A21.000 C-2.000\n"
            "N90 Y4.000 Z5.500 A22.000 C-4.000\n"
            "N100 G49\n"
            "N110 M5\n"
            "N120 M30\n"
            "%\n");
}

// The shop's options (issue 37 item 4): program number, coolant, the
// additional work offsets. Each word where the controller needs it: the
// O-number / PGM name first, coolant on after the spindle starts (every
// tool change) and off after the last move before the spindle stops.
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Index of the first line that ends with `tail` (block numbers vary), or -1.
int line_ending(const std::vector<std::string>& lines, const std::string& tail) {
  for (size_t i = 0; i < lines.size(); ++i)
    if (lines[i].size() >= tail.size() && lines[i].compare(lines[i].size() - tail.size(), tail.size(), tail) == 0)
      return static_cast<int>(i);
  return -1;
}

TEST(MachinePosts, FanucShopOptions) {
  LuaState lua;
  const Written w = write_program(lua.L, "dmg_like_ac_trunnion.lua", "fanuc", true, [](lua_api::PostJob& job) {
    job.work_offset = 9;  // G54.1 P3
    job.coolant = "through";
    job.program_number = 4711;
  });
  const auto lines = lines_of(w.text);
  ASSERT_GE(lines.size(), 3u);
  EXPECT_EQ(lines[1], "O4711 (BLADE 1)");
  EXPECT_NE(w.text.find("(WORK OFFSET G54.1 P3: "), std::string::npos) << w.text;
  const int offset = line_ending(lines, " G54.1 P3"), spindle = line_ending(lines, " S12000 M3"),
            on = line_ending(lines, " M88"), first_move = line_ending(lines, " G43.4 H3"),
            tcp_off = line_ending(lines, " G49"), off = line_ending(lines, " M89"), stop = line_ending(lines, " M5");
  EXPECT_TRUE(offset > 0 && spindle > offset && on == spindle + 1 && first_move == on + 1) << w.text;
  EXPECT_TRUE(off == tcp_off + 1 && stop == off + 1) << w.text;
  // It reads back with the offset it selects.
  const std::vector<ProgramMove> read = read_program(w.text, w.kin->machine(), ProgramReadOptions{});
  ASSERT_FALSE(read.empty());
  EXPECT_EQ(read.front().work_offset, 9);
}

TEST(MachinePosts, HeidenhainShopOptions) {
  LuaState lua;
  const Written w = write_program(lua.L, "monoblock_like_head_table.lua", "heidenhain", true, [](lua_api::PostJob& job) {
    job.coolant = "flood";
    job.program_number = 1234;
  });
  const auto lines = lines_of(w.text);
  EXPECT_EQ(lines.front(), "0 BEGIN PGM 1234 MM");
  EXPECT_EQ(lines.back(), std::to_string(lines.size() - 2) + " END PGM 1234 MM");
  const int m3 = line_ending(lines, " M3"), on = line_ending(lines, " M8"), off = line_ending(lines, " M9"),
            stop = line_ending(lines, " M5"), reset = line_ending(lines, " FUNCTION RESET TCPM");
  EXPECT_TRUE(m3 > 0 && on == m3 + 1 && off == reset + 1 && stop == off + 1) << w.text;
  EXPECT_EQ(read_program(w.text, w.kin->machine(), ProgramReadOptions{}).size(), 4u);
}

TEST(MachinePosts, SiemensShopOptionsAndOff) {
  LuaState lua;
  const Written w = write_program(lua.L, "gantry_head_head.lua", "siemens840d", true, [](lua_api::PostJob& job) {
    job.coolant = "mist";
    job.program_number = 42;
  });
  const auto lines = lines_of(w.text);
  EXPECT_EQ(lines[1], "; program number 42");
  EXPECT_EQ(line_ending(lines, " M7"), line_ending(lines, " S12000 M3") + 1) << w.text;
  EXPECT_EQ(line_ending(lines, " M9"), line_ending(lines, " TRAFOOF") + 1) << w.text;
  // "off": coolant off after the tool change, nothing to switch off at the end.
  LuaState again;
  const Written off = write_program(again.L, "gantry_head_head.lua", "siemens840d", true,
                            [](lua_api::PostJob& job) { job.coolant = "off"; });
  const auto off_lines = lines_of(off.text);
  const int m9 = line_ending(off_lines, " M9");
  EXPECT_EQ(m9, line_ending(off_lines, " S12000 M3") + 1) << off.text;
  EXPECT_EQ(off.text.find(" M9", off.text.find(" M9") + 1), std::string::npos) << off.text;
}

TEST(MachinePosts, SiemensTraoriProgramIsLiteral) {
  LuaState lua;
  // Work offset 5 is the first settable frame past G57; a part clocked on
  // its fixture; a note whose trailing '~' would have continued the block.
  const Written w = write_program(lua.L, "gantry_head_head.lua", "siemens840d", true, [](lua_api::PostJob& job) {
    job.work_offset = 5;
    job.setup = {"", false, 16.3636};
    job.notes = {"blade 1 at the fixture's pin ~"};
  });
  EXPECT_EQ(w.text,
            "; blade 1\n"
            "; VERDICT: @VERDICT@\n"
            "; machine gantry C/A fork head\n"
            "; part not turned over: model +Z along part frame +Z\n"
            "; clocking 16.364 deg: model turned 16.364 deg about part frame +Z\n"
            "; rotary C head: C+ turns the tool right-handed about +Z: as ISO 841\n"
            "; rotary A head: A+ turns the tool right-handed about +X: as ISO 841\n"
            "; tool 3 length 80.000 S12000\n"
            "; work offset G505: the part frame origin; it lies at X0.000 Y0.000 Z0.000 from the machine zero of the machine file with all axes at 0\n"
            "; rapids that turn a rotary axis or move more than one linear axis are feed moves at F20000 mm/min\n"
            "; the first move positions from the tool change point: start with the tool clear of the part\n"
            "; between blocks the controller moves TCP, rotaries linear: the program was split and swept for that\n"
            "; blade 1 at the fixture's pin\n"
            "N10 G90 G17 G71 G40 G94\n"
            "N20 G505\n"
            "N30 T3 D1\n"
            "N40 M6\n"
            "N50 S12000 M3\n"
            "N60 TRAORI\n"
            "N70 G0 X40.000 Y0.000 Z30.000 C0.000 A-20.000\n"
            "N80 G1 Z5.000 F800.0\n"
            "N90 Y2.000 C2.000 A-21.000\n"
            "N100 Y4.000 Z5.500 C4.000 A-22.000\n"
            "N110 TRAFOOF\n"
            "N120 M5\n"
            "N130 M30\n");
}

TEST(MachinePosts, HeidenhainTcpmProgramIsLiteral) {
  LuaState lua;
  const Written w = write_program(lua.L, "monoblock_like_head_table.lua", "heidenhain", true, [](lua_api::PostJob& job) {
    job.tools.push_back({9, 112.5, 6000});
    job.work_offset = 3;
    job.setup = {"turned over (inlet up)", true, 0};
  });
  EXPECT_EQ(w.text,
            "0 BEGIN PGM BLADE_1 MM\n"
            "1 ; VERDICT: @VERDICT@\n"
            "2 ; machine monoBLOCK-like B head / C table\n"
            "3 ; setup: turned over (inlet up)\n"
            "4 ; part turned over: 180 deg about X, model +Z along part frame -Z\n"
            "5 ; clocking 0.000 deg: model +X along part frame +X\n"
            "6 ; rotary C table: C+ turns the part right-handed about +Z, the tool relative to the part left-handed: against ISO 841\n"
            "7 ; rotary B head: B+ turns the tool right-handed about +Y: as ISO 841\n"
            "8 ; tool 3 length 80.000 S12000\n"
            "9 ; tool 9 length 112.500 S6000\n"
            "10 ; work offset preset 3: the part frame origin; it lies at X0.000 Y0.000 Z100.000 from the machine zero of the machine file with all axes at 0\n"
            "11 ; rapids that turn a rotary axis are feed moves at F30000 mm/min\n"
            "12 ; the first move positions from the tool change point: start with the tool clear of the part\n"
            "13 ; between blocks the controller moves TCP, rotaries linear: the program was split and swept for that\n"
            "14 CYCL DEF 247 DATUM SETTING ~\n"
            "    Q339=+3    ;DATUM NUMBER\n"
            "15 TOOL CALL 3 Z S12000\n"
            "16 M3\n"
            "17 FUNCTION TCPM F TCP AXIS POS PATHCTRL AXIS\n"
            "18 L X+40.000 Y+0.000 Z+30.000 C-90.000 B+20.000 R0 FMAX\n"
            "19 L Z+5.000 F800.0\n"
            "20 L Y+2.000 C-92.000 B+21.000\n"
            "21 L Y+4.000 Z+5.500 C-94.000 B+22.000\n"
            "22 FUNCTION RESET TCPM\n"
            "23 M5\n"
            "24 M30\n"
            "25 END PGM BLADE_1 MM\n");
  // The program reads back with the preset it selects.
  const std::vector<ProgramMove> read = read_program(w.text, w.kin->machine(), ProgramReadOptions{});
  ASSERT_EQ(read.size(), 4u);
  EXPECT_EQ(read.front().work_offset, 3);
  EXPECT_EQ(read.front().line, 20);
  LuaState again;
  EXPECT_THROW(write_program(again.L, "monoblock_like_head_table.lua", "heidenhain", false), Error);
}

TEST(MachinePosts, LinuxcncTrtProgramIsLiteral) {
  LuaState lua;
  const Written w = write_program(lua.L, "dmg_like_ac_trunnion.lua", "linuxcnc", false,  // trt: TCP anyway
                          [](lua_api::PostJob& job) { job.work_offset = 8; });
  EXPECT_TRUE(w.tcp_always);
  EXPECT_EQ(w.text,
            "%\n"
            "(blade 1)\n"
            "(VERDICT: @VERDICT@)\n"
            "(machine DMG-like A/C trunnion 650, kinematics xyzac-trt)\n"
            "(part not turned over: model +Z along part frame +Z)\n"
            "(clocking 0.000 deg: model +X along part frame +X)\n"
            "(rotary A table: A+ turns the part right-handed about +X, the tool relative to the part left-handed: against ISO 841)\n"
            "(rotary C table: C+ turns the part right-handed about +Z, the tool relative to the part left-handed: against ISO 841)\n"
            "(tool 3 length 80.000 S12000)\n"
            "(work offset G59.2: the part frame origin; it lies at X0.000 Y0.000 Z120.000 from the machine zero of the machine file with all axes at 0)\n"
            "(rapids that turn a rotary axis or move more than one linear axis are feed moves at F30000 mm/min)\n"
            "(the first move positions from the tool change point: start with the tool clear of the part)\n"
            "(between blocks the controller moves TCP, rotaries linear: the program was split and swept for that)\n"
            "G21 G90 G17 G40 G49 G94\n"
            "G59.2\n"
            "T3 M6\n"
            "G43 H3\n"
            "S12000 M3\n"
            "G0 X40.000 Y0.000 Z30.000 A20.000 C0.000\n"
            "G1 Z5.000 F800.0\n"
            "Y2.000 A21.000 C-2.000\n"
            "Y4.000 Z5.500 A22.000 C-4.000\n"
            "G49\n"
            "M5\n"
            "M30\n"
            "%\n");
  LuaState other;
  EXPECT_THROW(write_program(other.L, "monoblock_like_head_table.lua", "linuxcnc", true), Error);
}

// Every post's program reads back and replays onto the plan, on every
// shipped machine it can drive; output twice is byte-identical.
TEST(MachinePosts, EveryPostReadsBackWithinTolerance) {
  struct Case { const char* machine; const char* post; bool tcp; };
  const Case cases[] = {
      {"dmg_like_ac_trunnion.lua", "fanuc", false}, {"dmg_like_ac_trunnion.lua", "fanuc", true},
      {"bc_trunnion_hermle_like.lua", "fanuc", false}, {"monoblock_like_head_table.lua", "fanuc", false},
      {"gantry_head_head.lua", "fanuc", false}, {"gantry_head_head.lua", "siemens840d", true},
      {"bc_trunnion_hermle_like.lua", "siemens840d", false}, {"monoblock_like_head_table.lua", "heidenhain", true},
      {"dmg_like_ac_trunnion.lua", "linuxcnc", true}};
  for (const Case& c : cases) {
    LuaState lua;
    const Written w = write_program(lua.L, c.machine, c.post, c.tcp);
    VerifyOptions options;
    options.read.file_name = std::string(c.post) + ".nc";
    options.read.tcp = w.tcp_always;
    const VerifyReport report = verify_program(w.text, *w.kin, w.plan, options);
    EXPECT_EQ(report.moves, static_cast<long>(w.plan.moves.size())) << c.machine << " " << c.post;
    EXPECT_LT(report.max_position_mm, 0.005) << c.machine << " " << c.post;
    LuaState lua2;
    EXPECT_EQ(write_program(lua2.L, c.machine, c.post, c.tcp).text, w.text);
  }
}

// Machine files: errors name the file and line and what was expected.
TEST(MachinePosts, MachineFileErrorsNameFileAndLine) {
  const std::string dir = ::testing::TempDir() + "/bliskrun_machine_files";
  std::system(("mkdir -p '" + dir + "'").c_str());
  auto error_of = [&](const std::string& body) {
    const std::string path = dir + "/m.lua";
    std::ofstream(path) << body;
    LuaState lua;
    return protect(lua.L, [&](lua_State* S) {
      lua_api::load_machine_file(S, path, 0, scripts() + "/machines");
    });
  };
  const std::string path = dir + "/m.lua";
  const std::string good_rotary =
      "  rotary = { { name = 'A', carrier = 'part', direction = {1, 0, 0}, travel = {-120, 30} },\n"
      "             { name = 'C', carrier = 'part', direction = {0, 0, 1} } },\n";
  EXPECT_EQ(error_of("return machine {\n  name = 'm',\n  linear = { X = {-1, 1}, Y = {-1, 1}, Z = {-1, 1} },\n" +
                     good_rotary + "}\n"), "");
  EXPECT_EQ(error_of("-- comment\nreturn machine {\n  name = 'm', speed = 3,\n  linear = { X = {-1, 1}, Y = {-1, 1}, Z = {-1, 1} },\n" +
                     good_rotary + "}\n"),
            path + ":2: machine: unknown key 'speed', expected one of: bodies, dynamics, feed, linear, name, part_origin, "
                   "rapid, resolution, rotary, safe_z, slides, spindle, tool_length");
  EXPECT_EQ(error_of("return machine {\n  name = 'm',\n  linear = { X = {-1, 1}, Z = {-1, 1} },\n" + good_rotary + "}\n"),
            path + ":1: machine: linear: missing axis Y");
  EXPECT_EQ(error_of("return machine {\n  name = 'm',\n  linear = { X = {-1, 1}, Y = {-1, 1}, Z = {-1, 1} },\n"
                     "  rotary = { { name = 'A', carrier = 'part', direction = {1, 0, 0} },\n"
                     "             { name = 'C', carrier = 'part', direction = {1, 0, 0} } },\n}\n"),
            path + ":1: machine: rotary[2].direction: parallel to rotary[1]: the two rotary axes cannot orient the tool");
  EXPECT_EQ(error_of("return generic 'table_table_ac' {\n  name = 'x', a_travel = {0, 1} }\n"),
            path + ":1: unknown machine parameter 'a_travel', expected one of: a, a_pivot, bodies, c, c_pivot, dynamics, feed, "
                   "name, part_origin, rapid, resolution, safe_z, slides, speed, table_radius, tool_length, x, y, z");
  // A bad body names itself and its key at the file's line.
  EXPECT_EQ(error_of("return machine {\n  name = 'm',\n  linear = { X = {-1, 1}, Y = {-1, 1}, Z = {-1, 1} },\n" +
                     good_rotary + "  bodies = { { name = 'head', frame = 'spindle', cylinder = { {0, 0, 0}, {0, 0, 9} } } },\n}\n"),
            path + ":1: machine: bodies[1]: missing radius (mm)");
  EXPECT_EQ(error_of("return machine {\n  name = 'm',\n  linear = { X = {-1, 1}, Y = {-1, 1}, Z = {-1, 1} },\n" +
                     good_rotary + "  bodies = { { name = 'cradle', frame = 'B', box = { {0, 0, 0}, {1, 1, 1} } } },\n}\n"),
            path + ":1: machine: bodies[1].frame: 'B' is no frame of this machine, expected one of: base, X, Y, Z, A, C, "
                   "spindle, part");
  EXPECT_NE(error_of("return 42\n").find("expected the file to return machine"), std::string::npos);
  // The cycle-time limits name the axis and the unit; axes are the machine's own.
  const std::string xyz = "  linear = { X = {-1, 1}, Y = {-1, 1}, Z = {-1, 1} },\n";
  EXPECT_EQ(error_of("return machine {\n  name = 'm',\n" + xyz + good_rotary + "  dynamics = { B = {} } }\n"),
            path + ":1: machine: dynamics: unknown key 'B', expected one of: A, C, X, Y, Z, tool_change_s");
  EXPECT_EQ(error_of("return machine {\n  name = 'm',\n" + xyz + good_rotary + "  dynamics = { C = { max_accel = 0 } } }\n"),
            path + ":1: machine: dynamics.C.max_accel: expected > 0 deg/s^2");
  EXPECT_EQ(error_of("return machine {\n  name = 'm',\n" + xyz + good_rotary + "  dynamics = { X = { max_jerk = -1 } } }\n"),
            path + ":1: machine: dynamics.X.max_jerk: expected > 0 mm/s^3");
}

// machine_lib "five_axis" (scripts/machines/lib/) serves a machine file of
// one's own outside the scripts folder as it serves the generic files: its
// parameters, rotary axes and the trunnion bodies, in the order given.
TEST(MachinePosts, MachineLibServesMachineFilesOfYourOwn) {
  const std::string path = ::testing::TempDir() + "/bliskrun_machine_lib.lua";
  auto load = [&](const std::string& body, MachineDefinition* def) {
    std::ofstream(path) << body;
    LuaState lua;
    return protect(lua.L, [&](lua_State* S) {
      lua_api::load_machine_file(S, path, 0, scripts() + "/machines");
      if (def) *def = lua_api::test_machine(S, -1)->definition;
    });
  };
  // The docs' example (docs/lua_api/machines_and_posts.md), its column on the bed.
  const std::string own =
      "local five_axis = machine_lib 'five_axis'\n"
      "local function plausible_bodies(p)\n"
      "  local za = p.a_pivot[3]\n"
      "  return five_axis.concat(five_axis.trunnion_bodies(p, 'a'),\n"
      "                          { { name = 'column', frame = 'base', box = { { -400, 600, za - 200 }, { 400, 1000, 1500 } } } },\n"
      "                          five_axis.trunnion_tool_side())\n"
      "end\n"
      "return parametric {\n"
      "  parameters = five_axis.parameters(\n"
      "    { name = 'mine', x = { -300, 300 }, y = { -250, 250 }, z = { -300, 300 },\n"
      "      feed = 'inverse_time', rotaries = { 'a', 'c' } },\n"
      "    five_axis.trunnion_parameters('a', { -120, 30 })),\n"
      "  build = function(p)\n"
      "    p.speed, p.table_radius = { a = 5000 }, 150\n"
      "    return machine(five_axis.definition(p, five_axis.trunnion_rotary(p, 'a'), plausible_bodies))\n"
      "  end,\n"
      "}\n";
  MachineDefinition m;
  ASSERT_EQ(load(own, &m), "");
  EXPECT_EQ(m.name, "mine");
  EXPECT_EQ(configuration_name(m), "table-table");
  EXPECT_EQ(m.feed, FeedMode::InverseTime);
  EXPECT_NEAR(m.rotary[0].min_rad, -120 * kDeg, 1e-15);
  EXPECT_NEAR(m.rotary[0].max_speed_rad_per_min, 5000 * kDeg, 1e-12);
  EXPECT_TRUE(m.rotary[1].continuous());
  ASSERT_EQ(m.bodies.size(), 11u);
  const char* names[] = {"C table", "cradle", "cradle cheek +X", "cradle cheek -X", "trunnion support +X",
                         "trunnion support -X", "bed", "column", "spindle nose", "spindle housing", "Z ram"};
  for (size_t i = 0; i < 11; ++i) EXPECT_EQ(m.bodies[i].name, names[i]);
  EXPECT_EQ(m.bodies[1].frame, "A");
  EXPECT_NEAR(m.bodies[0].radius_mm, 150, 1e-12);
  EXPECT_NEAR(m.bodies[7].min_mm.z(), -250, 1e-12);  // the A axis 50 mm below the table face
  // A cheek about X stands at +X, R + 21 .. R + 80 from the A axis.
  EXPECT_NEAR(m.bodies[2].min_mm.x(), 171, 1e-12);
  EXPECT_NEAR(m.bodies[2].max_mm.x(), 230, 1e-12);
  // Only names of shipped modules; a parameter of its own must not shadow a common one.
  EXPECT_NE(load("local x = machine_lib '../five_axis'\n", nullptr).find("machine_lib: '../five_axis' is not a name"),
            std::string::npos);
  EXPECT_NE(load("return machine_lib 'five_axis'.parameters({ rotaries = {} }, { feed = { default = 1 } })\n", nullptr)
                .find("'feed' is a common parameter"),
            std::string::npos);
}

// Every shipped concrete machine loads and is the configuration it says.
TEST(MachinePosts, ShippedMachinesLoad) {
  LuaState lua;
  EXPECT_EQ(configuration_name(load_machine(lua.L, "dmg_like_ac_trunnion.lua")), "table-table");
  EXPECT_EQ(configuration_name(load_machine(lua.L, "bc_trunnion_hermle_like.lua")), "table-table");
  EXPECT_EQ(configuration_name(load_machine(lua.L, "monoblock_like_head_table.lua")), "head-table");
  EXPECT_EQ(configuration_name(load_machine(lua.L, "gantry_head_head.lua")), "head-head");
  const MachineDefinition ac = load_machine(lua.L, "dmg_like_ac_trunnion.lua");
  EXPECT_NEAR(ac.rotary[0].min_rad, -120 * kDeg, 1e-15);
  EXPECT_TRUE(ac.rotary[1].continuous());
  EXPECT_EQ(ac.feed, FeedMode::InverseTime);
  // Generic definitions build with their defaults.
  for (const char* generic : {"table_table_ac.lua", "table_table_bc.lua", "head_table_bc.lua", "head_head.lua"})
    EXPECT_NO_THROW(load_machine(lua.L, generic)) << generic;
}

// ISO 841: every shipped machine file states the sense of both rotary axes,
// and the statement holds for the motion the kinematics produce: a small
// positive angle turns the tool axis, seen from the part, right-handed about
// the machine axis the name denotes (+X for A, +Y for B, +Z for C) exactly
// when the file says iso841 = true.
TEST(MachinePosts, ShippedMachinesStateTheirRotarySensesAgainstIso841) {
  LuaState lua;
  for (const char* file : {"dmg_like_ac_trunnion.lua", "bc_trunnion_hermle_like.lua",
                           "monoblock_like_head_table.lua", "gantry_head_head.lua", "table_table_ac.lua",
                           "table_table_bc.lua", "head_table_bc.lua", "head_head.lua"}) {
    const MachineDefinition m = load_machine(lua.L, file);
    const Kinematics kin(m, 80.0);
    for (int i = 0; i < 2; ++i) {
      const RotaryAxis& a = m.rotary[i];
      ASSERT_NE(a.iso841_sense, 0) << file << " does not state iso841 for " << a.name;
      const Vec3 machine_axis = a.name == "A" ? Vec3::UnitX() : a.name == "B" ? Vec3::UnitY() : Vec3::UnitZ();
      // From home, or with the other axis tilted where the tool would lie
      // along this one. In the shipped configurations that tilt does not move
      // this axis' line as seen from the part: it stays the home direction.
      Vec3 turn = Vec3::Zero();
      for (double other : {0.0, 0.4}) {
        std::array<double, 2> q0{0.0, 0.0};
        q0[1 - i] = other;
        std::array<double, 2> q1 = q0;
        q1[i] += 1e-4;
        turn = kin.tool_axis(q0).cross(kin.tool_axis(q1));
        if (turn.norm() > 1e-7) break;
      }
      ASSERT_GT(turn.norm(), 1e-7) << file << " " << a.name;
      const Vec3 line = machine_axis;
      const int sense = turn.dot(line) > 0 ? 1 : -1;
      EXPECT_EQ(sense, a.iso841_sense) << file << " " << a.name;
      EXPECT_EQ(sense, iso841_sense(m, i)) << file << " " << a.name;
    }
  }
  // A wrong statement is refused where it is made.
  const std::string path = std::string(::testing::TempDir()) + "/bliskrun_iso841.lua";
  std::ofstream(path) << "return machine {\n  name = 'm',\n  linear = { X = {-1, 1}, Y = {-1, 1}, Z = {-1, 1} },\n"
                         "  rotary = { { name = 'A', carrier = 'part', direction = {1, 0, 0}, iso841 = true },\n"
                         "             { name = 'C', carrier = 'part', direction = {0, 0, 1} } },\n}\n";
  const std::string error = protect(lua.L, [&](lua_State* S) {
    lua_api::load_machine_file(S, path, 0, scripts() + "/machines");
  });
  EXPECT_NE(error.find("rotary[1].iso841: stated true, but as defined (a table turning the part right-handed "
                       "about its direction) a positive A turns the tool relative to the part left-handed about +X"),
            std::string::npos) << error;
}

}  // namespace
}  // namespace bliskrun
