// bliskrun.post: posting a toolpath with a Lua post, proving the program
// by reading it back and sweeping every block as its controller moves it,
// cycle time and axis ranges. Degrees and mm at this boundary.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <tuple>

#include <time.h>

#include "core/machine/machine_picture.h"
#include "core/analysis/part_picture.h"
#include "core/common/atomic_file.h"
#include "core/common/error.h"
#include "core/common/parallel.h"
#include "core/machine/cycle_time.h"
#include "core/machine/machine_sim.h"
#include "core/machine/verify.h"
#include "lua_api/lua_tool.h"
#include "lua_api/luax.h"
#include "lua_api/machine_host.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun {

// A posted program, kept for post.verify: the plan and how to read it.
struct PostedProgram {
  MachineDefinition machine;
  std::vector<double> tool_lengths_mm;  // per tool index of the plan's moves
  std::vector<int> tool_numbers;
  std::vector<ToolReach> reaches;       // per tool index; zero reach: tip only
  MachineProgram plan;
  bool tcp_always = false;
  MachineAxes start;                    // the axes before the first block
  double chord_tol_mm = 0.005, body_tol_mm = 0.05;  // the sweep's tolerances
  std::string file;  // absolute path of the written program
};

namespace luax {
template <>
struct TypeName<PostedProgram> {
  static constexpr const char* name = "bliskrun.PostedProgram";
};
}  // namespace luax

namespace lua_api {
namespace {

namespace fs = std::filesystem;

// ---- bliskrun.post -------------------------------------------------------

int w_post_load(lua_State* L) {
  const std::string what = luax::check_string(L, 1, "post");
  load_post_file(L, resolve_script(L, what, "posts"), scripts_folder() + "/posts");
  return 1;
}

// The toolpath: a list of {kind = "rapid"|"feed", tip =, axis =, feed =, row =,
// tool =, operation =}. `tool_numbers` receives each move's tool number (0
// where absent: the tool of the move before, or the first tool);
// `operations` each move's operation (a name, or "operation n" for a
// number; that of the move before where absent) for the cycle time per
// operation.
std::vector<PlannedMove> check_path(lua_State* L, int idx, std::vector<int>* tool_numbers = nullptr,
                                    std::vector<std::string>* operations = nullptr) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx)) luax::error(L, "path: expected a list of moves {kind=, tip=, axis=, feed=}");
  const lua_Unsigned n = lua_rawlen(L, idx);
  std::vector<PlannedMove> path;
  path.reserve(n);
  for (lua_Unsigned i = 1; i <= n; ++i) {
    lua_rawgeti(L, idx, static_cast<lua_Integer>(i));
    const std::string where = "path[" + std::to_string(i) + "]";
    if (!lua_istable(L, -1)) luax::error(L, where + ": expected a move table");
    PlannedMove m;
    lua_getfield(L, -1, "kind");
    const std::string kind = lua_isstring(L, -1) ? lua_tostring(L, -1) : "";
    if (kind != "rapid" && kind != "feed") luax::error(L, where + ".kind: expected 'rapid' or 'feed'");
    m.kind = kind == "rapid" ? MoveKind::Rapid : MoveKind::Feed;
    lua_getfield(L, -2, "tip");
    m.pose.tip = luax::check_vec3(L, -1, (where + ".tip").c_str());
    lua_getfield(L, -3, "axis");
    m.pose.axis = luax::check_vec3(L, -1, (where + ".axis").c_str());
    lua_getfield(L, -4, "feed");
    if (m.kind == MoveKind::Feed) {
      if (!lua_isnumber(L, -1) || !(lua_tonumber(L, -1) > 0) || !std::isfinite(lua_tonumber(L, -1)))
        luax::error(L, where + ".feed: expected a finite feed > 0 mm/min");
      m.feed_mm_per_min = lua_tonumber(L, -1);
    }
    lua_getfield(L, -5, "row");
    if (lua_isinteger(L, -1)) m.row = static_cast<long>(lua_tointeger(L, -1));
    lua_getfield(L, -6, "tool");
    if (!lua_isnil(L, -1) && !lua_isinteger(L, -1))
      luax::error(L, where + ".tool: expected a tool number (an integer)");
    if (tool_numbers) tool_numbers->push_back(lua_isinteger(L, -1) ? static_cast<int>(lua_tointeger(L, -1)) : 0);
    lua_getfield(L, -7, "operation");
    if (operations) {
      std::string op = operations->empty() ? "" : operations->back();
      if (lua_isinteger(L, -1))
        op = "operation " + std::to_string(lua_tointeger(L, -1));
      else if (lua_type(L, -1) == LUA_TSTRING)
        op = lua_tostring(L, -1);
      else if (!lua_isnil(L, -1))
        luax::error(L, where + ".operation: expected an operation's name or number");
      operations->push_back(op);
    }
    lua_pop(L, 8);
    path.push_back(m);
  }
  return path;
}

// Wall seconds of post.write's stages: reading the path from Lua, the
// machine motion (inverse kinematics, splitting), the Lua post, the
// read-back and replay, writing the file.
struct PostSeconds {
  double read = 0, motion = 0, post = 0, verify = 0, machine = 0, write = 0;
  double machine_cpu = 0;  // the machine simulation's CPU time on its thread
};

// CPU seconds this thread has used: what a stage costs on a shared machine,
// whatever else runs beside it.
double thread_cpu_seconds() {
  timespec t{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void push_report(lua_State* L, const VerifyReport& r, const PostedProgram& p) {
  lua_createtable(L, 0, 8);
  lua_pushinteger(L, r.moves);
  lua_setfield(L, -2, "moves");
  lua_pushnumber(L, r.max_position_mm);
  lua_setfield(L, -2, "max_position");
  lua_pushnumber(L, rad_to_deg(r.max_angle_rad));
  lua_setfield(L, -2, "max_angle");
  lua_pushinteger(L, r.worst_position_line);
  lua_setfield(L, -2, "worst_line");
  lua_pushinteger(L, p.plan.inserted_moves);
  lua_setfield(L, -2, "inserted");
  lua_pushinteger(L, p.plan.positioning_moves);
  lua_setfield(L, -2, "positioning");
  lua_pushnumber(L, p.plan.max_deviation_mm);
  lua_setfield(L, -2, "max_deviation");
  // The sweep of the program read back, as the controller moves it.
  lua_pushstring(L, to_string(p.plan.controller));
  lua_setfield(L, -2, "controller");
  lua_pushnumber(L, r.max_cutter_mm);
  lua_setfield(L, -2, "swept_cutter");
  lua_pushnumber(L, r.max_body_mm);
  lua_setfield(L, -2, "swept_tool");
  lua_pushinteger(L, r.worst_cutter_line);
  lua_setfield(L, -2, "swept_worst_line");
  // The block nearest its allowance: {deviation, allowed} (mm), cutter and tool.
  for (const auto& [name, value, allowed] :
       {std::tuple<const char*, double, double>{"swept_cutter_tightest", r.tightest_cutter_mm,
                                                r.tightest_cutter_allowed_mm},
        {"swept_tool_tightest", r.tightest_body_mm, r.tightest_body_allowed_mm}}) {
    lua_createtable(L, 2, 0);
    lua_pushnumber(L, value);
    lua_rawseti(L, -2, 1);
    lua_pushnumber(L, allowed);
    lua_rawseti(L, -2, 2);
    lua_setfield(L, -2, name);
  }
  lua_pushinteger(L, r.swept_moves);
  lua_setfield(L, -2, "swept");
  lua_pushinteger(L, r.unswept_moves);
  lua_setfield(L, -2, "unswept");
  lua_pushinteger(L, r.safe_moves);
  lua_setfield(L, -2, "safe_moves");
  lua_pushnumber(L, p.chord_tol_mm);
  lua_setfield(L, -2, "chord_tol");
  lua_pushnumber(L, p.body_tol_mm);
  lua_setfield(L, -2, "body_tol");
  // Feed at the cutter and rotary speeds.
  lua_pushinteger(L, p.plan.slowed_moves);
  lua_setfield(L, -2, "slowed");
  lua_pushinteger(L, p.plan.untimed_moves);
  lua_setfield(L, -2, "untimed");
  lua_pushnumber(L, p.plan.max_cutter_speed_ratio);
  lua_setfield(L, -2, "cutter_speed_ratio");
  lua_createtable(L, 0, 2);
  for (int i = 0; i < 2; ++i) {
    lua_pushnumber(L, rad_to_deg(p.plan.max_rotary_speed_rad_per_min[i]));
    lua_setfield(L, -2, p.machine.rotary[i].name.c_str());
  }
  lua_setfield(L, -2, "rotary_speed");  // deg/min, the fastest block of each axis
  lua_pushinteger(L, p.plan.rotary_resets);
  lua_setfield(L, -2, "rotary_resets");
  lua_pushnumber(L, p.plan.minutes);
  lua_setfield(L, -2, "feed_minutes");  // the feed moves' time as the F words ask it
  lua_pushnumber(L, p.plan.tip_feed_minutes);
  lua_setfield(L, -2, "tip_feed_minutes");  // ... and with the tip alone at the planned feeds
  double largest = 0;
  for (const MachineMove& m : p.plan.moves)
    for (int i = 0; i < 2; ++i) largest = std::max(largest, std::abs(rad_to_deg(m.axes.rotary_rad[i])));
  lua_pushnumber(L, largest);
  lua_setfield(L, -2, "rotary_largest");  // deg: the largest rotary word written
  luax::push(L, p.file);
  lua_setfield(L, -2, "file");
}

// The program's verdict for its header (the post's `VERDICT: @VERDICT@`
// line): what was proved, in words a setter reads. Upper case where the
// line is (Fanuc comments are read upper case); no parentheses.
std::string verdict_text(const VerifyReport& r, const PostedProgram& p) {
  std::ostringstream v;
  v.precision(2);
  v.setf(std::ios::fixed);
  v << "PROVED, every block read back and swept as the controller moves it, " << to_string(p.plan.controller)
    << ": cutter within " << 1e3 * r.max_cutter_mm << " um, tool within " << 1e3 * r.max_body_mm
    << " um of the proved motion, tolerances " << 1e3 * p.chord_tol_mm << " / " << 1e3 * p.body_tol_mm
    << " um plus output resolution; " << r.safe_moves << " blocks at the safe height";
  if (r.unswept_moves > 0) v << "; " << r.unswept_moves << " blocks from the tool change position NOT proved";
  std::string text = v.str();
  for (char& c : text) if (c == '(' || c == ')') c = ' ';
  return text;
}

std::string with_verdict(std::string text, const std::string& verdict) {
  const std::string token = "@VERDICT@";
  const size_t at = text.find(token);
  if (at == std::string::npos) return text;
  // A header without a lower-case letter (Fanuc: comments are read upper
  // case) gets the verdict in upper case.
  bool lower = false;
  const size_t header_end = std::min(text.size(), at + 3000);
  for (size_t i = 0; i < header_end; ++i) {
    if (i >= at && i < at + token.size()) continue;
    lower = lower || std::islower(static_cast<unsigned char>(text[i]));
  }
  std::string v = verdict;
  if (!lower)
    for (char& c : v) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  text.replace(at, token.size(), v);
  return text;
}

// The read-back and replay of a posted program (throws core's errors).
VerifyReport verify_text(const PostedProgram& p, const std::string& text, double tol_mm, double angle_tol_deg) {
  VerifyOptions options;
  options.tol_mm = tol_mm;
  options.angle_tol_rad = deg_to_rad(angle_tol_deg);
  options.read.file_name = p.file;
  options.read.tcp = p.tcp_always;
  options.read.start = p.start;
  options.tool_numbers = p.tool_numbers;
  options.reaches = p.reaches;
  options.chord_tol_mm = p.chord_tol_mm;
  options.body_tol_mm = p.body_tol_mm;
  std::vector<Kinematics> kins;
  for (double length : p.tool_lengths_mm) kins.emplace_back(p.machine, length);
  std::vector<const Kinematics*> pointers;
  for (const Kinematics& k : kins) pointers.push_back(&k);
  return verify_program(text, pointers, p.plan, options);
}

VerifyReport verify_posted(lua_State* L, const PostedProgram& p, const std::string& text, double tol_mm,
                           double angle_tol_deg) {
  VerifyReport report;
  luax::guarded(L, [&] {
    report = verify_text(p, text, tol_mm, angle_tol_deg);
    return 0;
  });
  return report;
}

const std::vector<luax::Field>& post_write_fields() {
  static const std::vector<luax::Field> fields = {
      {"machine", luax::Kind::Any, true, {}, {}, "Machine (bliskrun.machine.load)", {}},
      {"post", luax::Kind::Any, true, {}, {}, "post name ('fanuc'), file, or a loaded post table", {}},
      {"path", luax::Kind::Table, true, {}, {}, "moves {kind=, tip=, axis=, feed=, row=}", {}},
      {"file", luax::Kind::String, true, {}, {}, "program file, relative to the out folder", {}},
      {"tool", luax::Kind::Table, false, {}, {}, "{number=, length= mm, spindle_rpm=} (one tool)", {}},
      {"tools", luax::Kind::Table, false, {}, {}, "{{number=, length=, spindle_rpm=}, ...}: moves name theirs by tool = number", {}},
      {"name", luax::Kind::String, false, {}, {}, "program name (default: the file name)", {}},
      {"chord_tol", luax::Kind::Number, false, 1e-6, 10.0, "tip departure allowed between blocks, mm", {}},
      {"tcp", luax::Kind::Boolean, false, {}, {}, "write under TCP control (default: the post's choice)", {}},
      {"verify_tol", luax::Kind::Number, false, 0.0, 10.0, "read-back tolerance beyond resolution, mm", {}},
      {"start", luax::Kind::Table, false, {}, {}, "axes before the first move {X=, ..., C=}", {}},
      {"body_tol", luax::Kind::Number, false, 1e-6, 10.0, "departure of shank and holder allowed between blocks, mm", {}},
      {"cutter_feed_factor", luax::Kind::Number, false, 1.0, 100.0,
       "no cutter point faster than this times the planned feed", {}},
      {"approach", luax::Kind::Table, false, {}, {},
       "{proved = mm, safe_z = mm}: the safe way in and out along the tool axis (the plan proved `proved` mm)", {}},
      {"work_offset", luax::Kind::Integer, false, 1.0, 99.0,
       "work offset the program selects: 1 = G54 / preset 1; Fanuc 7.. = G54.1 P1..", {}},
      {"coolant", luax::Kind::String, false, {}, {},
       "coolant on after each tool change, off at the end (default: no coolant words)",
       {"flood", "mist", "through", "off"}},
      {"program_number", luax::Kind::Integer, false, 1.0, 99999999.0,
       "program number: Fanuc O-number (default 1000), the TNC's PGM name, a header line elsewhere", {}},
      {"setup", luax::Kind::Table, false, {}, {}, "{name=, flip=, clocking_deg=}: how the part sits, for the header", {}},
      {"notes", luax::Kind::Table, false, {}, {}, "{'text', ...}: header lines of the recipe's own", {}},
      {"machine_check", luax::Kind::Boolean, false, {}, {},
       "replay the program with the machine's bodies, fixture and stock (default true; false skips, with a warning)", {}},
      {"machine_clearance", luax::Kind::Number, false, 1e-3, 100.0,
       "machine simulation: no contact deeper than this is missed, closest approaches within it, mm (default 0.5)", {}},
      {"machine_near_zone", luax::Kind::Number, false, 1e-3, 1e6,
       "machine simulation: closest approaches are measured within this zone; a pair beyond it is only proved to "
       "stay out of it, mm (default 10, at least machine_clearance)", {}},
      {"fixture", luax::Kind::Table, false, {}, {}, "bodies {name=, box=|cylinder=|cone=, radius=} in the part frame", {}},
      {"stock", luax::Kind::Table, false, {}, {}, "the blank's bodies, part frame (the tool may cut them)", {}},
      {"part", luax::Kind::Table, false, {}, {},
       "the part's own bodies {name=, mesh=|meshes=, margin=}: meshes in the part's frame, placed by `setup`", {}},
      {"machine_picture", luax::Kind::String, false, {}, {},
       "PNG of the machine at the closest approach (or the collision), relative to the out folder; "
       "written where POV-Ray is installed", {}},
  };
  return fields;
}

// post.write's header options into `job`: the work offset, the setup and
// the notes. Each note is one comment line, so a line break is refused
// (the rest of the note would be a block the controller runs).
void read_post_header(lua_State* L, const luax::Options& o, const std::string& what, PostJob& job) {
  job.work_offset = static_cast<int>(o.integer("work_offset", 1));
  job.coolant = o.string("coolant", "");
  job.program_number = static_cast<long>(o.integer("program_number", 0));
  if (o.has("setup")) {
    o.push_raw("setup");
    const luax::Options setup(L, lua_gettop(L), what + " setup", {
        {"name", luax::Kind::String, false, {}, {}, "which setup this is", {}},
        {"flip", luax::Kind::Boolean, false, {}, {}, "the part turned over: 180 deg about X", {}},
        {"clocking_deg", luax::Kind::Number, false, -360.0, 360.0, "then turned about the part frame's +Z, deg", {}},
    });
    job.setup.name = setup.string("name", "");
    job.setup.flip = setup.boolean("flip", false);
    job.setup.clocking_deg = setup.number("clocking_deg", 0);
    lua_pop(L, 1);
  }
  if (o.has("notes")) {
    o.push_raw("notes");
    const int notes_idx = lua_gettop(L);
    const lua_Unsigned n = lua_rawlen(L, notes_idx);
    lua_Unsigned entries = 0;
    for (lua_pushnil(L); lua_next(L, notes_idx) != 0; lua_pop(L, 1)) ++entries;
    if (entries != n) luax::error(L, what + " notes: expected a list of strings {'...', ...}");
    for (lua_Unsigned i = 1; i <= n; ++i) {
      lua_rawgeti(L, notes_idx, static_cast<lua_Integer>(i));
      const std::string where = what + " notes[" + std::to_string(i) + "]";
      if (lua_type(L, -1) != LUA_TSTRING) luax::error(L, where + ": expected a string");
      std::string note = lua_tostring(L, -1);
      if (note.find_first_of("\r\n") != std::string::npos)
        luax::error(L, where + ": a note is one line (no line breaks)");
      job.notes.push_back(std::move(note));
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }
}

// One program to post, read on the recipe's state from post.write's options:
// everything but the post itself is plain C++, so that a program whose post
// is named by its file can be posted on another thread, in a Lua state of
// its own.
struct PostRequest {
  MachineDefinition machine;
  std::string post_file;  // the post's file when the option names one; empty for a post table
  bool set_tcp = false, tcp = false;  // the tcp option, when given
  PostJob job;
  std::vector<PlannedMove> path;
  std::vector<int> tool_of;  // each move's index into job.tools
  std::vector<std::string> operations;  // each move's operation ("" where none is named)
  std::string file, target;
  MotionOptions motion;      // all but .tcp, which is the post's
  std::vector<ToolReach> reaches;  // per job tool: from its `body`, or tip only
  double verify_tol = 0.001;
  double read_seconds = 0;
  // The machine simulation (machine_sim.h).
  bool machine_check = true;
  double machine_clearance_mm = 0.5;
  double machine_near_zone_mm = 10;
  MachineSetupBodies setup_bodies;
  std::string machine_picture;  // resolved for writing; empty: none asked
  std::string machine_picture_name;  // as the option gave it
  std::vector<std::shared_ptr<const Tool>> tool_bodies;  // per job tool; null without `body`
};

// The part's own bodies: {{name=, mesh = Mesh | meshes = {Mesh, ...},
// margin = mm, frame = "part"}, ...}, meshes in the part's own frame and
// placed by the setup (turned over, then clocked) as j:post turns the path.
std::vector<MachineBody> read_part_bodies(lua_State* L, int idx, const std::string& what, const PostSetup& setup) {
  idx = lua_absindex(L, idx);
  std::vector<MachineBody> out;
  Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();
  if (setup.flip) placement.linear() = Vec3(1, -1, -1).asDiagonal();
  placement = Eigen::AngleAxisd(deg_to_rad(setup.clocking_deg), Vec3::UnitZ()) * placement;
  const lua_Unsigned n = lua_rawlen(L, idx);
  for (lua_Unsigned i = 1; i <= n; ++i) {
    lua_rawgeti(L, idx, static_cast<lua_Integer>(i));
    const std::string where = what + "[" + std::to_string(i) + "]";
    if (!lua_istable(L, -1)) luax::error(L, where + ": expected {name=, mesh= | meshes=, margin=}");
    const luax::Options o(L, lua_gettop(L), where, {
        {"name", luax::Kind::String, true, {}, {}, "the body's name in reports", {}},
        {"frame", luax::Kind::String, false, {}, {}, "the frame it stands on (default \"part\")", {}},
        {"mesh", luax::Kind::Any, false, {}, {}, "a bliskrun.Mesh (surface:tessellate(tol))", {}},
        {"meshes", luax::Kind::Table, false, {}, {}, "several meshes making one body (a blade's flanks)", {}},
        {"margin", luax::Kind::Number, false, 0.0, 100.0, "how far the true surface may lie from the mesh, mm", {}},
        {"mesh_names", luax::Kind::Table, false, {}, {}, "with meshes: one name per mesh, the one reports give where the body is nearest on it", {}},
    });
    if (o.has("mesh") == o.has("meshes")) luax::error(L, where + ": give exactly one of 'mesh' and 'meshes'");
    if (o.has("mesh_names") && !o.has("meshes")) luax::error(L, where + ".mesh_names: only with 'meshes'");
    MachineBody b;
    b.name = o.string("name", "");
    b.frame = o.string("frame", "part");
    b.shape = BodyShape::Mesh;
    b.margin_mm = o.number("margin", 0);
    b.placement = placement;
    auto mesh_at = [&](int at, const std::string& field) {
      const MeshHandle* m = luax::test<MeshHandle>(L, at);
      if (!m) luax::error(L, field + ": expected a bliskrun.Mesh (surface:tessellate(tol))");
      b.meshes.push_back(m->mesh);
    };
    if (o.has("mesh")) {
      o.push_raw("mesh");
      mesh_at(-1, where + ".mesh");
      lua_pop(L, 1);
    } else {
      o.push_raw("meshes");
      const lua_Unsigned m = lua_rawlen(L, -1);
      if (m == 0) luax::error(L, where + ".meshes: expected a list of at least one bliskrun.Mesh");
      for (lua_Unsigned k = 1; k <= m; ++k) {
        lua_rawgeti(L, -1, static_cast<lua_Integer>(k));
        mesh_at(-1, where + ".meshes[" + std::to_string(k) + "]");
        lua_pop(L, 1);
      }
      lua_pop(L, 1);
      if (o.has("mesh_names")) {
        o.push_raw("mesh_names");
        const lua_Unsigned names = lua_rawlen(L, -1);
        if (names != m)
          luax::error(L, where + ".mesh_names: expected one name per mesh (" + std::to_string(m) + "), got " +
                             std::to_string(names));
        for (lua_Unsigned k = 1; k <= names; ++k) {
          lua_rawgeti(L, -1, static_cast<lua_Integer>(k));
          if (lua_type(L, -1) != LUA_TSTRING)
            luax::error(L, where + ".mesh_names[" + std::to_string(k) + "]: expected a string");
          b.mesh_names.emplace_back(lua_tostring(L, -1));
          lua_pop(L, 1);
        }
        lua_pop(L, 1);
      }
    }
    out.push_back(std::move(b));
    lua_pop(L, 1);
  }
  return out;
}

// Reads the option table at `idx` (`what` names it in messages); the post
// option is left to the caller (a name is resolved into post_file here).
PostRequest read_post_request(lua_State* L, int idx, const std::string& what) {
  idx = lua_absindex(L, idx);
  const luax::Options o(L, idx, what, post_write_fields());
  PostRequest r;
  o.push_raw("machine");
  r.machine = check_machine(L, -1).definition;
  lua_pop(L, 1);
  o.push_raw("post");
  if (lua_type(L, -1) == LUA_TSTRING) {
    r.post_file = resolve_script(L, lua_tostring(L, -1), "posts");
  } else if (!lua_istable(L, -1)) {
    luax::error(L, what + " post: expected a post name or a post table (bliskrun.post.load)");
  }
  lua_pop(L, 1);
  if (o.has("tcp")) {
    r.set_tcp = true;
    r.tcp = o.boolean("tcp", false);
  }

  if (o.has("tool") == o.has("tools"))
    luax::error(L, what + ": give either 'tool' (one tool) or 'tools' (a list), not both or neither");
  auto read_tool = [&](int tool_idx, const std::string& tool_what) {
    const luax::Options tool(L, tool_idx, tool_what, {
        {"number", luax::Kind::Integer, true, 0.0, 99999.0, "tool number (T, H, TOOL CALL)", {}},
        {"length", luax::Kind::Number, true, 0.0, {}, "tip to spindle gauge point, mm", {}},
        {"spindle_rpm", luax::Kind::Integer, false, 1.0, {}, "spindle speed, 1/min", {}},
        {"body", luax::Kind::Any, false, {}, {}, "the Tool (its reach: the whole tool is swept)", {}},
        {"active_reach", luax::Kind::Number, false, 0.0, {},
         "farthest point from the tip of the cutter's part that cuts (feed at the cutter), mm", {}},
    });
    ToolReach reach;
    r.tool_bodies.emplace_back();
    if (tool.has("body")) {
      tool.push_raw("body");
      const LuaTool* body = luax::test<LuaTool>(L, -1);
      if (!body) luax::error(L, tool_what + " body: expected a Tool (bliskrun.drum_wheel{...}, flat_end_mill{...}, ...)");
      r.tool_bodies.back() = std::make_shared<const Tool>(body->tool);
      reach.body_mm = body->tool.reach();
      reach.cutter_mm = body->tool.cutter().reach();
      lua_pop(L, 1);
    }
    reach.active_mm = tool.number("active_reach", 0);
    r.reaches.push_back(reach);
    PostTool t;
    t.number = static_cast<int>(tool.integer("number", 1));
    t.length_mm = tool.number("length", 0);
    t.spindle_rpm = static_cast<long>(tool.integer("spindle_rpm", 0));
    for (const PostTool& other : r.job.tools)
      if (other.number == t.number) luax::error(L, tool_what + ": tool number " + std::to_string(t.number) + " is listed twice");
    r.job.tools.push_back(t);
  };
  if (o.has("tool")) {
    o.push_raw("tool");
    read_tool(lua_gettop(L), what + " tool");
    lua_pop(L, 1);
  } else {
    o.push_raw("tools");
    const int tools_idx = lua_gettop(L);
    const lua_Unsigned n = lua_rawlen(L, tools_idx);
    if (n == 0) luax::error(L, what + " tools: expected a list of at least one tool");
    for (lua_Unsigned i = 1; i <= n; ++i) {
      lua_rawgeti(L, tools_idx, static_cast<lua_Integer>(i));
      read_tool(lua_gettop(L), what + " tools[" + std::to_string(i) + "]");
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }

  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  o.push_raw("path");
  std::vector<int> move_tools;
  r.path = check_path(L, -1, &move_tools, &r.operations);
  r.read_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  lua_pop(L, 1);
  // Each move's tool index; a move without `tool` keeps the one before.
  r.tool_of.assign(r.path.size(), 0);
  for (size_t i = 0; i < r.path.size(); ++i) {
    if (move_tools[i] == 0) {
      r.tool_of[i] = i > 0 ? r.tool_of[i - 1] : 0;
      continue;
    }
    const auto it = std::find_if(r.job.tools.begin(), r.job.tools.end(),
                                 [&](const PostTool& t) { return t.number == move_tools[i]; });
    if (it == r.job.tools.end())
      luax::error(L, "path[" + std::to_string(i + 1) + "].tool: tool " + std::to_string(move_tools[i]) +
                         " is not in the program's tools");
    r.tool_of[i] = static_cast<int>(it - r.job.tools.begin());
  }

  r.file = o.string("file", "");
  r.target = context(L).resolve_write(L, r.file);
  r.job.name = o.string("name", fs::path(r.file).stem().string());
  r.motion.chord_tol_mm = o.number("chord_tol", 0.005);
  if (o.has("start")) {
    o.push_raw("start");
    r.motion.start = check_axes(L, -1, r.machine, "start");
    lua_pop(L, 1);
  }
  r.verify_tol = o.number("verify_tol", 0.001);
  r.motion.body_tol_mm = o.number("body_tol", 0.05);
  r.motion.cutter_feed_factor = o.number("cutter_feed_factor", 1.5);
  if (o.has("approach")) {
    o.push_raw("approach");
    const luax::Options a(L, lua_gettop(L), what + " approach", {
        {"proved", luax::Kind::Number, true, 0.0, {}, "mm along the tool axis the plan proved clear", {}},
        {"proved_up", luax::Kind::Number, false, 0.0, {}, "mm up the part frame's +Z the plan proved clear", {}},
        {"safe_z", luax::Kind::Number, false, {}, {}, "the safe height's Z word (default: the machine's)", {}},
    });
    r.motion.approach.enabled = true;
    r.motion.approach.proved_mm = a.number("proved", 0);
    r.motion.approach.proved_up_mm = a.number("proved_up", 0);
    if (a.has("safe_z")) r.motion.approach.safe_z_mm = a.number("safe_z", 0);
    lua_pop(L, 1);
  }
  read_post_header(L, o, what, r.job);
  r.machine_check = o.boolean("machine_check", true);
  r.machine_clearance_mm = o.number("machine_clearance", 0.5);
  r.machine_near_zone_mm = o.number("machine_near_zone", 10);
  if (r.machine_near_zone_mm < r.machine_clearance_mm)
    throw ParameterError("machine_near_zone", "expected at least machine_clearance (" +
                                                     std::to_string(r.machine_clearance_mm) + " mm)");
  for (const char* key : {"fixture", "stock"}) {
    if (!o.has(key)) continue;
    o.push_raw(key);
    (key[0] == 'f' ? r.setup_bodies.fixture : r.setup_bodies.stock) = check_bodies(L, -1, what + " " + key, "part");
    lua_pop(L, 1);
  }
  if (o.has("part")) {
    o.push_raw("part");
    r.setup_bodies.part = read_part_bodies(L, -1, what + " part", r.job.setup);
    lua_pop(L, 1);
  }
  if (o.has("machine_picture")) {
    r.machine_picture_name = o.string("machine_picture", "");
    r.machine_picture = context(L).resolve_write(L, r.machine_picture_name);
  }
  return r;
}

// Loads a request's post by its file into `L` (a worker's state), applies
// the tcp option and leaves the post table on the stack.
void push_request_post(lua_State* L, const PostRequest& r) {
  load_post_file(L, r.post_file, scripts_folder() + "/posts");
  if (r.set_tcp) {
    lua_pushboolean(L, r.tcp);
    lua_setfield(L, -2, "tcp");
  }
}

struct PostOutcome {
  PostedProgram posted;
  VerifyReport report;
  PostSeconds seconds;
  CycleTime cycle;
  std::vector<std::string> block_operation;  // per block of the program: its path move's operation
  // The range of each axis word over the blocks read back: X Y Z (mm), the
  // rotaries (deg), as the program writes them (with TCP: the tip, part frame).
  std::array<double, 5> axis_min{}, axis_max{};
  std::array<std::string, 5> axis_names{"X", "Y", "Z", "", ""};
  // The machine simulation; `machine_note` says why it did not run.
  bool simulated = false;
  MachineSimReport machine;
  std::string machine_note;
  // The machine's picture at the closest approach (or the collision):
  // written where asked and POV-Ray runs; else why not.
  bool picture_written = false;
  std::string picture_name, picture_note;  // the picture as the option named it
};

// The machine at the simulation's closest approach, or its first
// collision, as a picture (machine_picture.h); a failure to render is a
// note, never the post's failure.
void write_machine_picture(const PostRequest& r, const std::vector<SimTool>& tools, PostOutcome& out) {
  const MachineSimReport& m = out.machine;
  if (r.machine_picture.empty() || (!m.collided && m.closest.empty())) return;
  if (!part_renderer_available()) {
    out.picture_note = "POV-Ray not installed: the machine's picture is not drawn (apt-get install povray)";
    return;
  }
  const BodyApproach& at = m.collided ? m.first_collision : m.closest.front();
  try {
    MachinePictureOptions o;
    o.title = fs::path(r.file).filename().string() + (m.collided ? ": first collision" : ": closest approach");
    std::ostringstream footer;
    footer.setf(std::ios::fixed);
    footer.precision(2);
    footer << at.a << " / " << at.b << (at.distance_mm < 0 ? " overlap " : " ") << std::abs(at.distance_mm)
           << " mm at line " << at.line << " (block " << at.block + 1 << "), T" << at.tool << "; "
           << r.machine.name;
    o.footer = footer.str();
    write_machine_picture_png(machine_scene(r.machine, tools, r.setup_bodies, at), r.machine_picture, o);
    out.picture_written = true;
    out.picture_name = r.machine_picture_name;
  } catch (const std::exception& e) {
    out.picture_note = std::string("the machine's picture is not drawn: ") + e.what();
  }
}

// The Lua post's part: the program's text from its machine motion.
using LuaPost = std::function<std::string(const Kinematics& first_tool, const MachineProgram& plan)>;

// Posts one program: machine motion (inverse kinematics per tool, feed
// moves split to the chord tolerance), the Lua post, the read-back and
// replay, then the atomic write — the program is proved before it replaces
// anything on disk. Throws core's errors; Lua errors come from `lua_post`.
PostOutcome post_program(const PostRequest& r, const PostTraits& traits, Progress& progress,
                         const LuaPost& lua_post) {
  using Clock = std::chrono::steady_clock;
  const auto since = [](Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  PostOutcome out;
  out.seconds.read = r.read_seconds;
  PostedProgram& posted = out.posted;
  posted.machine = r.machine;
  for (const PostTool& t : r.job.tools) {
    posted.tool_lengths_mm.push_back(t.length_mm);
    posted.tool_numbers.push_back(t.number);
  }
  posted.tcp_always = traits.tcp_always;
  posted.file = r.target;
  posted.reaches = r.reaches;
  posted.start = r.motion.start;
  posted.chord_tol_mm = r.motion.chord_tol_mm;
  posted.body_tol_mm = r.motion.body_tol_mm;
  if (traits.tcp_always && r.motion.approach.enabled)
    throw ParameterError("approach", "this post's kinematics are always TCP (no machine-axis moves): it cannot "
                                     "write the way in at the safe height; post without 'approach'");
  MotionOptions motion = r.motion;
  motion.tcp = traits.tcp;
  motion.tcp_vector = traits.tcp && traits.vector;
  motion.rotary_reset = traits.rotary_reset;
  motion.rotary_input_limit_rad = deg_to_rad(traits.rotary_input_limit_deg);
  std::vector<Kinematics> kins;
  for (const PostTool& t : r.job.tools) kins.emplace_back(r.machine, t.length_mm);
  std::vector<MotionTool> tools;
  for (size_t k = 0; k < kins.size(); ++k) tools.push_back({&kins[k], r.reaches[k]});
  auto t0 = Clock::now();
  posted.plan = plan_machine_motion_tools(tools, r.path, r.tool_of, motion, progress);
  out.seconds.motion = since(t0);
  t0 = Clock::now();
  std::string text = lua_post(kins.front(), posted.plan);
  out.seconds.post = since(t0);
  t0 = Clock::now();
  out.report = verify_text(posted, text, r.verify_tol, 0.001);
  out.seconds.verify = since(t0);
  // The blocks as read back (block i is plan move i, which verify_text has
  // just proved); the verdict line replaces a token in a comment, so their
  // lines stay.
  ProgramReadOptions read;
  read.file_name = posted.file;
  read.tcp = posted.tcp_always;
  read.start = posted.start;
  const std::vector<ProgramMove> blocks = read_program(text, posted.machine, read);
  std::string verdict = verdict_text(out.report, posted);
  // The machine simulation: a collision stops the post before anything is
  // written.
  t0 = Clock::now();
  if (!r.machine_check) {
    out.machine_note = "machine simulation skipped (machine_check = false): the machine's bodies, fixture and stock were NOT checked";
  } else if (r.machine.bodies.empty() && r.setup_bodies.fixture.empty()) {
    out.machine_note = "machine simulation not run: machine " + r.machine.name + " has no bodies";
  } else {
    MachineSimOptions sim;
    sim.clearance_mm = r.machine_clearance_mm;
    sim.near_zone_mm = r.machine_near_zone_mm;
    sim.file_name = posted.file;
    sim.start = posted.start;
    std::vector<SimTool> sim_tools;
    for (size_t k = 0; k < r.job.tools.size(); ++k)
      sim_tools.push_back({r.job.tools[k].number, r.job.tools[k].length_mm, r.tool_bodies[k]});
    const double cpu0 = thread_cpu_seconds();
    out.machine = simulate_machine(blocks, r.machine, sim_tools, r.setup_bodies, sim);
    out.seconds.machine_cpu = thread_cpu_seconds() - cpu0;
    out.simulated = true;
    write_machine_picture(r, sim_tools, out);
    if (out.machine.collided)
      throw DataError(posted.file, out.machine.first_collision.line,
                      "machine simulation: " + machine_sim_summary(out.machine) + "; nothing written" +
                          (out.picture_written ? " (the collision drawn in " + r.machine_picture_name + ")" : ""));
  }
  out.seconds.machine = since(t0);
  verdict += "; machine " + (out.simulated ? machine_sim_summary(out.machine) : std::string("NOT simulated"));
  for (char& c : verdict) if (c == '(' || c == ')') c = ' ';  // it stands in a comment
  text = with_verdict(std::move(text), verdict);
  // The cycle time, each block charged to the operation of the path move
  // it ends or belongs to.
  CycleTimeOptions timing;
  timing.start = posted.start;
  for (const MachineMove& m : posted.plan.moves) timing.positioning.push_back(m.positioning);
  out.cycle = estimate_cycle_time(blocks, posted.machine, timing);
  out.axis_min.fill(std::numeric_limits<double>::infinity());
  out.axis_max.fill(-std::numeric_limits<double>::infinity());
  for (int i = 0; i < 2; ++i) out.axis_names[static_cast<size_t>(3 + i)] = posted.machine.rotary[static_cast<size_t>(i)].name;
  for (const ProgramMove& b : blocks) {
    const double words[5] = {b.axes.linear_mm.x(), b.axes.linear_mm.y(), b.axes.linear_mm.z(),
                             rad_to_deg(b.axes.rotary_rad[0]), rad_to_deg(b.axes.rotary_rad[1])};
    for (size_t k = 0; k < 5; ++k) {
      out.axis_min[k] = std::min(out.axis_min[k], words[k]);
      out.axis_max[k] = std::max(out.axis_max[k], words[k]);
    }
  }
  for (const MachineMove& m : posted.plan.moves) {
    const size_t k = static_cast<size_t>(m.source);
    out.block_operation.push_back(k < r.operations.size() ? r.operations[k] : std::string());
  }
  t0 = Clock::now();
  write_file_atomic(r.target, text);
  out.seconds.write = since(t0);
  return out;
}

// {total_s, rapid_s, cut_s, tool_change_s, tool_changes, per_operation =
// {{operation=, total_s=, rapid_s=, cut_s=, tool_change_s=}, ...}} in the
// order the operations first run; blocks of no named operation are one
// entry "" (a path without `operation`).
void push_cycle_time(lua_State* L, const CycleTime& c, const std::vector<std::string>& block_operation) {
  struct Sum {
    std::string name;
    double rapid = 0, cut = 0, change = 0;
  };
  std::vector<Sum> sums;
  for (size_t i = 0; i < c.block_s.size(); ++i) {
    const std::string& name = i < block_operation.size() ? block_operation[i] : std::string();
    auto it = std::find_if(sums.begin(), sums.end(), [&](const Sum& s) { return s.name == name; });
    if (it == sums.end()) it = sums.insert(sums.end(), Sum{name});
    // The same split as the totals: rapids and positioning feeds position.
    const bool positioning = i < c.block_positioning.size() && c.block_positioning[i];
    (positioning ? it->rapid : it->cut) += c.block_s[i];
    it->change += c.block_tool_change_s[i];
  }
  lua_createtable(L, 0, 6);
  luax::set_number(L, "total_s", c.total_s);
  luax::set_number(L, "rapid_s", c.rapid_s);
  luax::set_number(L, "cut_s", c.cut_s);
  luax::set_number(L, "tool_change_s", c.tool_change_s);
  lua_pushinteger(L, c.tool_changes);
  lua_setfield(L, -2, "tool_changes");
  lua_createtable(L, static_cast<int>(sums.size()), 0);
  for (size_t k = 0; k < sums.size(); ++k) {
    lua_createtable(L, 0, 5);
    luax::push(L, sums[k].name);
    lua_setfield(L, -2, "operation");
    luax::set_number(L, "rapid_s", sums[k].rapid);
    luax::set_number(L, "cut_s", sums[k].cut);
    luax::set_number(L, "tool_change_s", sums[k].change);
    luax::set_number(L, "total_s", sums[k].rapid + sums[k].cut + sums[k].change);
    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
  }
  lua_setfield(L, -2, "per_operation");
}

// machine_check = {verdict = "PASS" | "FAIL" | "SKIPPED", summary =,
// warning = (when not run), clearance =, near_zone =, pairs =, queries =, skipped =,
// blocks =, closest = {{a=, b=, distance=, line=, block=, t=, tool=, queries=, beyond_zone=}, ...} nearest
// first, unchecked = {"T3", ...} tools without a body}.
void push_machine_check(lua_State* L, const PostOutcome& out) {
  lua_createtable(L, 0, 10);
  if (!out.simulated) {
    luax::push(L, std::string("SKIPPED"));
    lua_setfield(L, -2, "verdict");
    luax::push(L, out.machine_note);
    lua_setfield(L, -2, "warning");
    luax::push(L, out.machine_note);
    lua_setfield(L, -2, "summary");
    return;
  }
  const MachineSimReport& m = out.machine;
  luax::push(L, std::string(m.pass() ? "PASS" : "FAIL"));
  lua_setfield(L, -2, "verdict");
  luax::push(L, machine_sim_summary(m));
  lua_setfield(L, -2, "summary");
  luax::set_number(L, "clearance", m.clearance_mm);
  luax::set_number(L, "near_zone", m.near_zone_mm);
  luax::set_number(L, "pairs", static_cast<double>(m.pairs));
  luax::set_number(L, "queries", static_cast<double>(m.queries));
  luax::set_number(L, "skipped", static_cast<double>(m.skipped));
  luax::set_number(L, "blocks", static_cast<double>(m.blocks));
  luax::set_number(L, "seconds", out.seconds.machine);
  luax::set_number(L, "cpu_seconds", out.seconds.machine_cpu);
  luax::set_number(L, "unbounded_blocks", static_cast<double>(m.unbounded_blocks));
  if (!out.picture_note.empty()) {
    luax::push(L, out.picture_note);
    lua_setfield(L, -2, "picture_note");
  }
  if (out.picture_written) {
    luax::push(L, out.picture_name);
    lua_setfield(L, -2, "picture");
  }
  lua_createtable(L, static_cast<int>(m.closest.size()), 0);
  for (size_t k = 0; k < m.closest.size(); ++k) {
    const BodyApproach& a = m.closest[k];
    lua_createtable(L, 0, 6);
    luax::push(L, a.a);
    lua_setfield(L, -2, "a");
    luax::push(L, a.b);
    lua_setfield(L, -2, "b");
    luax::set_number(L, "distance", a.distance_mm);
    luax::set_number(L, "line", a.line);
    luax::set_number(L, "block", static_cast<double>(a.block + 1));
    luax::set_number(L, "t", a.t);
    luax::set_number(L, "tool", a.tool);
    luax::set_number(L, "queries", static_cast<double>(a.queries));
    lua_pushboolean(L, a.beyond_zone);
    lua_setfield(L, -2, "beyond_zone");
    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
  }
  lua_setfield(L, -2, "closest");
  lua_createtable(L, static_cast<int>(m.unchecked.size()), 0);
  for (size_t k = 0; k < m.unchecked.size(); ++k) {
    luax::push(L, m.unchecked[k]);
    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
  }
  lua_setfield(L, -2, "unchecked");
}

// The result of post.write: the read-back report, `seconds` per stage and
// the program (for post.verify). Records the read-back for --verify.
void push_outcome(lua_State* L, PostOutcome&& out) {
  const VerifyReport& report = out.report;
  {
    std::ostringstream line;
    line << out.posted.file << ": " << report.moves << " moves, max tip deviation " << report.max_position_mm
         << " mm (line " << report.worst_position_line << "), max axis deviation "
         << rad_to_deg(report.max_angle_rad) << " deg (line " << report.worst_angle_line << ")";
    context(L).verified_programs.push_back(line.str());
  }
  push_report(L, report, out.posted);
  push_cycle_time(L, out.cycle, out.block_operation);
  lua_setfield(L, -2, "cycle_time");
  lua_createtable(L, 0, 5);  // axis_ranges = {X = {min, max}, ..., A|B|C = {min, max} (deg)}
  for (size_t k = 0; k < 5 && !out.cycle.block_s.empty(); ++k) {
    lua_createtable(L, 2, 0);
    lua_pushnumber(L, out.axis_min[k]);
    lua_rawseti(L, -2, 1);
    lua_pushnumber(L, out.axis_max[k]);
    lua_rawseti(L, -2, 2);
    lua_setfield(L, -2, out.axis_names[k].c_str());
  }
  lua_setfield(L, -2, "axis_ranges");
  const PostSeconds& seconds = out.seconds;
  lua_createtable(L, 0, 5);
  for (const auto& [name, value] : {std::pair<const char*, double>{"read", seconds.read}, {"motion", seconds.motion},
                                    {"post", seconds.post}, {"verify", seconds.verify}, {"machine", seconds.machine},
                                    {"write", seconds.write}}) {
    lua_pushnumber(L, value);
    lua_setfield(L, -2, name);
  }
  lua_setfield(L, -2, "seconds");
  push_machine_check(L, out);
  lua_setfield(L, -2, "machine_check");
  luax::push_new(L, std::move(out.posted));
  lua_setfield(L, -2, "program");
}

// post.write{machine=, post=, path=, file=, tool=, chord_tol=, tcp=, name=, verify=}
int w_post_write(lua_State* L) {
  const PostRequest r = read_post_request(L, 1, "bliskrun.post.write");
  lua_getfield(L, 1, "post");
  int post_idx = lua_gettop(L);
  if (!r.post_file.empty()) {
    push_request_post(L, r);
    post_idx = lua_gettop(L);
  } else if (r.set_tcp) {
    lua_pushboolean(L, r.tcp);
    lua_setfield(L, post_idx, "tcp");
  }
  PostOutcome out;
  luax::guarded(L, [&] {
    out = post_program(r, post_traits(L, post_idx), context(L).progress,
                       [&](const Kinematics& kin, const MachineProgram& plan) {
                         return run_post(L, post_idx, kin, plan, r.job);
                       });
    return 0;
  });
  push_outcome(L, std::move(out));
  return 1;
}

// Posts one request on a worker thread, in a Lua state of its own: the post
// is loaded from its file there. Lua errors (the post's, the time limit)
// come back as Error with the Lua message.
PostOutcome post_on_worker(WorkerLuaState& worker, const PostRequest& r, Progress& progress) {
  lua_State* W = worker.get();
  // Calls f(data, post) protected (a C function sees its own stack frame:
  // the post table goes in as its second argument); a Lua error becomes an
  // Error with its message.
  const auto protect = [W](lua_CFunction f, void* data, int post_idx) {
    lua_pushcfunction(W, f);
    lua_pushlightuserdata(W, data);
    if (post_idx) lua_pushvalue(W, post_idx); else lua_pushnil(W);
    if (lua_pcall(W, 2, 1, 0) != LUA_OK) {
      const std::string message = lua_tostring(W, -1) ? lua_tostring(W, -1) : "error object is not a string";
      lua_pop(W, 1);
      throw Error(message);
    }
  };
  // The post table stays on the worker's stack.
  protect(
      [](lua_State* S) {
        push_request_post(S, *static_cast<const PostRequest*>(lua_touserdata(S, 1)));
        return 1;
      },
      const_cast<PostRequest*>(&r), 0);
  const int post_idx = lua_gettop(W);
  struct PostCall {
    const Kinematics* kin;
    const MachineProgram* plan;
    const PostJob* job;
    std::string text;
  };
  return post_program(r, post_traits(W, post_idx), progress,
                      [&](const Kinematics& kin, const MachineProgram& plan) {
                        PostCall call{&kin, &plan, &r.job, {}};
                        protect(
                            [](lua_State* S) {
                              auto* c = static_cast<PostCall*>(lua_touserdata(S, 1));
                              c->text = run_post(S, 2, *c->kin, *c->plan, *c->job);
                              lua_pushnil(S);
                              return 1;
                            },
                            &call, post_idx);
                        lua_pop(W, 1);
                        return std::move(call.text);
                      });
}

// post.write_all{{...post.write's options...}, ...} -> {report, ...}: the
// programs posted at once, each as post.write posts it, on up to --threads
// workers (the longest paths first); a post named by its file is loaded
// into each worker's own Lua state, a post table (edited in the recipe) runs
// here afterwards. The results and the --verify lines are in list order and
// do not depend on the thread count. A failure is raised once every program
// has stopped: the first failing program in list order, named by its index
// and file.
int w_post_write_all(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);
  const lua_Unsigned n = lua_rawlen(L, 1);
  if (n == 0) luax::error(L, "bliskrun.post.write_all: expected a list of post.write option tables");
  std::vector<PostRequest> requests;
  requests.reserve(n);
  for (lua_Unsigned i = 1; i <= n; ++i) {
    lua_rawgeti(L, 1, static_cast<lua_Integer>(i));
    const std::string what = "bliskrun.post.write_all[" + std::to_string(i) + "]";
    if (!lua_istable(L, -1)) luax::error(L, what + ": expected a post.write option table");
    requests.push_back(read_post_request(L, -1, what));
    lua_pop(L, 1);
  }
  std::vector<std::optional<PostOutcome>> outcomes(n);
  std::vector<std::string> failures(n);
  // Named posts on the workers, the longest paths first.
  std::vector<size_t> order;
  for (size_t k = 0; k < n; ++k)
    if (!requests[k].post_file.empty()) order.push_back(k);
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return requests[a].path.size() > requests[b].path.size(); });
  if (!order.empty()) {
    luax::guarded(L, [&] {
      // Made here: a worker state is made from the recipe's state, on its thread.
      std::vector<std::unique_ptr<WorkerLuaState>> workers;
      for (size_t j = 0; j < order.size(); ++j) workers.push_back(std::make_unique<WorkerLuaState>(L));
      run_parallel(order.size(), context(L).options.threads, context(L).progress, "posting",
                   [&](size_t j, Progress& own) {
                     const size_t k = order[j];
                     try {
                       outcomes[k] = post_on_worker(*workers[j], requests[k], own);
                     } catch (const std::exception& e) {
                       failures[k] = e.what();
                     }
                     workers[j].reset();  // its heap back before the next program
                   });
      return 0;
    });
  }
  // Post tables here, in list order, unless a program before has failed.
  for (size_t k = 0; k < n; ++k) {
    if (!requests[k].post_file.empty()) continue;
    if (std::any_of(failures.begin(), failures.begin() + k, [](const std::string& f) { return !f.empty(); })) break;
    lua_rawgeti(L, 1, static_cast<lua_Integer>(k + 1));
    lua_getfield(L, -1, "post");
    const int post_idx = lua_gettop(L);
    if (requests[k].set_tcp) {
      lua_pushboolean(L, requests[k].tcp);
      lua_setfield(L, post_idx, "tcp");
    }
    try {
      outcomes[k] = post_program(requests[k], post_traits(L, post_idx), context(L).progress, [&](const Kinematics& kin, const MachineProgram& plan) {
                                   return run_post(L, post_idx, kin, plan, requests[k].job);
                                 });
    } catch (const std::exception& e) {
      failures[k] = e.what();
    }
    lua_pop(L, 2);
  }
  for (size_t k = 0; k < n; ++k)
    if (!failures[k].empty())
      luax::error(L, "bliskrun.post.write_all: programs[" + std::to_string(k + 1) + "] (" + requests[k].file +
                         "): " + failures[k]);
  lua_createtable(L, static_cast<int>(n), 0);
  for (size_t k = 0; k < n; ++k) {
    push_outcome(L, std::move(*outcomes[k]));
    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
  }
  return 1;
}

// post.verify{program = result.program, file = (default: where it was written), tol =}
int w_post_verify(lua_State* L) {
  const luax::Options o(L, 1, "bliskrun.post.verify", {
      {"program", luax::Kind::Any, true, {}, {}, "the .program of a post.write result", {}},
      {"file", luax::Kind::String, false, {}, {}, "program to read (default: the one written)", {}},
      {"tol", luax::Kind::Number, false, 0.0, 10.0, "tolerance beyond output resolution, mm", {}},
      {"angle_tol", luax::Kind::Number, false, 0.0, 10.0, "tool axis tolerance beyond resolution, deg", {}},
  });
  o.push_raw("program");
  PostedProgram posted = luax::check<PostedProgram>(L, -1);
  lua_pop(L, 1);
  if (o.has("file")) posted.file = context(L).resolve_read(L, o.string("file", ""));
  std::string text;
  luax::guarded(L, [&] {
    std::ifstream in(posted.file, std::ios::binary);
    if (!in) throw Error("cannot read '" + posted.file + "'");
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return 0;
  });
  const VerifyReport report = verify_posted(L, posted, text, o.number("tol", 0.001), o.number("angle_tol", 0.001));
  push_report(L, report, posted);
  return 1;
}

}  // namespace

void open_post(lua_State* L) {
  static const luaL_Reg no_methods[] = {{nullptr, nullptr}};
  luax::register_type<PostedProgram>(L, no_methods);
  static const luaL_Reg post_functions[] = {
      {"load", w_post_load},     {"write", w_post_write},   {"write_all", w_post_write_all},
      {"verify", w_post_verify}, {nullptr, nullptr}};
  lua_newtable(L);
  luaL_setfuncs(L, post_functions, 0);
  lua_setfield(L, -2, "post");
}

}  // namespace lua_api
}  // namespace bliskrun
