// bliskrun.machine and bliskrun.post: machine definitions, kinematics,
// posting a toolpath with a Lua post and proving the program by read-back.
// Degrees and mm at this boundary; core works in radians.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>

#include "core/common/atomic_file.h"
#include "core/common/error.h"
#include "core/machine/verify.h"
#include <sstream>
#include "lua_api/lua_tool.h"
#include "lua_api/luax.h"
#include "lua_api/machine_host.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"

namespace bliskrun {

// A posted program, kept for post.verify: the plan and how to read it.
struct PostedProgram {
  MachineDefinition machine;
  std::vector<double> tool_lengths_mm;  // per tool index of the plan's moves
  std::vector<int> tool_numbers;
  MachineProgram plan;
  bool tcp_always = false;
  std::string file;  // absolute path of the written program
};

namespace luax {
template <>
struct TypeName<PostedProgram> {
  static constexpr const char* name = "bliskrun.PostedProgram";
};
}  // namespace luax

namespace lua_api {

std::string scripts_folder() {
  if (const char* env = std::getenv("BLISKRUN_SCRIPTS")) return env;
  return BLISKRUN_SCRIPTS_DIR;
}

// "name" -> scripts/<kind>/name.lua; anything with a '/' or ".lua" is a
// recipe path (resolved and confined by the runner).
std::string resolve_script(lua_State* L, const std::string& what, const std::string& kind) {
  const bool is_name = what.find('/') == std::string::npos &&
                       (what.size() < 4 || what.substr(what.size() - 4) != ".lua");
  if (is_name) {
    const std::string path = scripts_folder() + "/" + kind + "/" + what + ".lua";
    if (!std::filesystem::exists(path)) luax::error(L, "no " + kind.substr(0, kind.size() - 1) + " named '" + what + "' in scripts/" + kind);
    return path;
  }
  return context(L).resolve_read(L, what);
}

int push_post_option(lua_State* L, const luax::Options& o, const std::string& what) {
  o.push_raw("post");
  if (lua_type(L, -1) == LUA_TSTRING) {
    const std::string name = lua_tostring(L, -1);
    lua_pop(L, 1);
    load_post_file(L, resolve_script(L, name, "posts"), scripts_folder() + "/posts");
  } else if (!lua_istable(L, -1)) {
    luax::error(L, what + ": expected a post name or a post table (bliskrun.post.load)");
  }
  return lua_gettop(L);
}

namespace {

namespace fs = std::filesystem;

MachineValue& check_machine(lua_State* L, int idx) {
  return *static_cast<MachineValue*>(luaL_checkudata(L, idx, kMachineType));
}

MachineAxes check_axes(lua_State* L, int idx, const MachineDefinition& m, const char* name) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx)) luax::error(L, std::string(name) + ": expected a table of axis values {X=, Y=, Z=, " + m.rotary[0].name + "=, " + m.rotary[1].name + "=}");
  MachineAxes q;
  auto get = [&](const std::string& axis) {
    lua_getfield(L, idx, axis.c_str());
    if (!lua_isnumber(L, -1)) luax::error(L, std::string(name) + "." + axis + ": expected a number");
    const double v = lua_tonumber(L, -1);
    lua_pop(L, 1);
    return v;
  };
  for (int i = 0; i < 3; ++i) q.linear_mm[i] = get(m.linear[i].name);
  for (int i = 0; i < 2; ++i) q.rotary_rad[i] = deg_to_rad(get(m.rotary[i].name));
  return q;
}

void push_axes(lua_State* L, const MachineAxes& q, const MachineDefinition& m) {
  lua_createtable(L, 0, 5);
  for (int i = 0; i < 3; ++i) {
    lua_pushnumber(L, q.linear_mm[i]);
    lua_setfield(L, -2, m.linear[i].name.c_str());
  }
  for (int i = 0; i < 2; ++i) {
    lua_pushnumber(L, rad_to_deg(q.rotary_rad[i]));
    lua_setfield(L, -2, m.rotary[i].name.c_str());
  }
}

// ---- bliskrun.machine ------------------------------------------------------

int w_machine_load(lua_State* L) {
  const std::string what = luax::check_string(L, 1, "machine");
  if (!lua_isnoneornil(L, 2)) luaL_checktype(L, 2, LUA_TTABLE);
  const std::string path = resolve_script(L, what, "machines");
  load_machine_file(L, path, lua_isnoneornil(L, 2) ? 0 : 2, scripts_folder() + "/machines");
  return 1;
}

int w_machine_define(lua_State* L) {
  MachineValue value{check_machine_table(L, 1), ""};
  push_machine(L, std::move(value));
  return 1;
}

int w_machine_name(lua_State* L) {
  luax::push(L, check_machine(L, 1).definition.name);
  return 1;
}

// machine:placed{part_origin = {x, y, z}} -> a copy of the machine with the
// part frame's origin elsewhere in its program zero: the setup's work offset
// (a different fixture), without a second machine file.
int w_machine_placed(lua_State* L) {
  const MachineValue& m = check_machine(L, 1);
  const luax::Options o(L, 2, "machine:placed",
                        {luax::Field{"part_origin", luax::Kind::Table, true, std::nullopt, std::nullopt,
                                     "the part frame's origin in the machine's program zero, {x, y, z} mm", {}}});
  o.push_raw("part_origin");
  const Vec3 origin = luax::check_vec3(L, -1, "machine:placed: option 'part_origin'");
  lua_pop(L, 1);
  MachineValue copy = m;
  copy.definition.part_origin_mm = origin;
  push_machine(L, std::move(copy));
  return 1;
}

int w_machine_configuration(lua_State* L) {
  luax::push(L, configuration_name(check_machine(L, 1).definition));
  return 1;
}

int w_machine_axes(lua_State* L) {
  const MachineDefinition& m = check_machine(L, 1).definition;
  lua_createtable(L, 5, 0);
  int i = 0;
  for (const LinearAxis& a : m.linear) { luax::push(L, a.name); lua_rawseti(L, -2, ++i); }
  for (const RotaryAxis& a : m.rotary) { luax::push(L, a.name); lua_rawseti(L, -2, ++i); }
  return 1;
}

// m:travel() -> {X = {min, max}, ..., A = {min, max}, C = false (continuous)}
int w_machine_travel(lua_State* L) {
  const MachineDefinition& m = check_machine(L, 1).definition;
  lua_createtable(L, 0, 5);
  auto range = [&](double lo, double hi) {
    lua_createtable(L, 2, 0);
    lua_pushnumber(L, lo);
    lua_rawseti(L, -2, 1);
    lua_pushnumber(L, hi);
    lua_rawseti(L, -2, 2);
  };
  for (const LinearAxis& a : m.linear) { range(a.min_mm, a.max_mm); lua_setfield(L, -2, a.name.c_str()); }
  for (const RotaryAxis& a : m.rotary) {
    if (a.continuous()) lua_pushboolean(L, 0); else range(rad_to_deg(a.min_rad), rad_to_deg(a.max_rad));
    lua_setfield(L, -2, a.name.c_str());
  }
  return 1;
}

const std::vector<luax::Field>& kinematics_fields() {
  static const std::vector<luax::Field> fields = {
      {"tool_length", luax::Kind::Number, true, 0.0, std::nullopt, "tool tip to spindle gauge point, mm", {}},
      {"previous", luax::Kind::Table, false, std::nullopt, std::nullopt, "axes of the previous move (continuity), {X=, ..., C=}", {}},
  };
  return fields;
}

// m:solve(pose, {tool_length =, previous =}) -> axes
int w_machine_solve(lua_State* L) {
  const MachineValue& m = check_machine(L, 1);
  const ToolPose pose = pose_from_table(L, 2, "pose");
  const luax::Options o(L, 3, "machine:solve", kinematics_fields());
  MachineAxes previous;
  if (o.has("previous")) {
    o.push_raw("previous");
    previous = check_axes(L, -1, m.definition, "previous");
    lua_pop(L, 1);
  }
  return luax::guarded(L, [&] {
    const Kinematics kin(m.definition, o.number("tool_length", 0));
    push_axes(L, kin.inverse(pose, previous), m.definition);
    return 1;
  });
}

// m:forward(axes, {tool_length =}) -> pose
int w_machine_forward(lua_State* L) {
  const MachineValue& m = check_machine(L, 1);
  const MachineAxes q = check_axes(L, 2, m.definition, "axes");
  const luax::Options o(L, 3, "machine:forward", kinematics_fields());
  return luax::guarded(L, [&] {
    const Kinematics kin(m.definition, o.number("tool_length", 0));
    push_pose(L, kin.forward(q));
    return 1;
  });
}

// m:reachable(axis) -> boolean: some rotary position within travel gives it.
int w_machine_reachable(lua_State* L) {
  const MachineValue& m = check_machine(L, 1);
  const Vec3 axis = luax::check_vec3(L, 2, "axis");
  return luax::guarded(L, [&] {
    const Kinematics kin(m.definition, 0.0);
    lua_pushboolean(L, kin.reachable(axis));
    return 1;
  });
}

int w_machine_tostring(lua_State* L) {
  const MachineDefinition& m = check_machine(L, 1).definition;
  lua_pushfstring(L, "Machine(%s, %s %s/%s)", m.name.c_str(), configuration_name(m).c_str(),
                  m.rotary[0].name.c_str(), m.rotary[1].name.c_str());
  return 1;
}

// ---- bliskrun.post -------------------------------------------------------

int w_post_load(lua_State* L) {
  const std::string what = luax::check_string(L, 1, "post");
  load_post_file(L, resolve_script(L, what, "posts"), scripts_folder() + "/posts");
  return 1;
}

// The toolpath: a list of {kind = "rapid"|"feed", tip =, axis =, feed =, row =,
// tool =}. `tool_numbers` receives each move's tool number (0 where absent:
// the tool of the move before, or the first tool).
std::vector<PlannedMove> check_path(lua_State* L, int idx, std::vector<int>* tool_numbers = nullptr) {
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
    lua_pop(L, 7);
    path.push_back(m);
  }
  return path;
}

// Wall seconds of post.write's stages: reading the path from Lua, the
// machine motion (inverse kinematics, splitting), the Lua post, the
// read-back and replay, writing the file.
struct PostSeconds {
  double read = 0, motion = 0, post = 0, verify = 0, write = 0;
};

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
  luax::push(L, p.file);
  lua_setfield(L, -2, "file");
}

VerifyReport verify_posted(lua_State* L, const PostedProgram& p, const std::string& text, double tol_mm,
                           double angle_tol_deg) {
  VerifyOptions options;
  options.tol_mm = tol_mm;
  options.angle_tol_rad = deg_to_rad(angle_tol_deg);
  options.read.file_name = p.file;
  options.read.tcp = p.tcp_always;
  VerifyReport report;
  options.tool_numbers = p.tool_numbers;
  luax::guarded(L, [&] {
    std::vector<Kinematics> kins;
    for (double length : p.tool_lengths_mm) kins.emplace_back(p.machine, length);
    std::vector<const Kinematics*> pointers;
    for (const Kinematics& k : kins) pointers.push_back(&k);
    report = verify_program(text, pointers, p.plan, options);
    return 0;
  });
  return report;
}

// post.write{machine=, post=, path=, file=, tool=, chord_tol=, tcp=, name=, verify=}
int w_post_write(lua_State* L) {
  const luax::Options o(L, 1, "bliskrun.post.write", {
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
  });
  o.push_raw("machine");
  const MachineValue& machine = check_machine(L, -1);
  lua_pop(L, 1);

  const int post_idx = push_post_option(L, o, "post");
  if (o.has("tcp")) {
    lua_pushboolean(L, o.boolean("tcp", false));
    lua_setfield(L, post_idx, "tcp");
  }

  if (o.has("tool") == o.has("tools"))
    luax::error(L, "bliskrun.post.write: give either 'tool' (one tool) or 'tools' (a list), not both or neither");
  PostJob job;
  auto read_tool = [&](int idx, const std::string& what) {
    const luax::Options tool(L, idx, what, {
        {"number", luax::Kind::Integer, true, 0.0, 99999.0, "tool number (T, H, TOOL CALL)", {}},
        {"length", luax::Kind::Number, true, 0.0, {}, "tip to spindle gauge point, mm", {}},
        {"spindle_rpm", luax::Kind::Integer, false, 1.0, {}, "spindle speed, 1/min", {}},
    });
    PostTool t;
    t.number = static_cast<int>(tool.integer("number", 1));
    t.length_mm = tool.number("length", 0);
    t.spindle_rpm = static_cast<long>(tool.integer("spindle_rpm", 0));
    for (const PostTool& other : job.tools)
      if (other.number == t.number) luax::error(L, what + ": tool number " + std::to_string(t.number) + " is listed twice");
    job.tools.push_back(t);
  };
  if (o.has("tool")) {
    o.push_raw("tool");
    read_tool(lua_gettop(L), "bliskrun.post.write tool");
    lua_pop(L, 1);
  } else {
    o.push_raw("tools");
    const int tools_idx = lua_gettop(L);
    const lua_Unsigned n = lua_rawlen(L, tools_idx);
    if (n == 0) luax::error(L, "bliskrun.post.write tools: expected a list of at least one tool");
    for (lua_Unsigned i = 1; i <= n; ++i) {
      lua_rawgeti(L, tools_idx, static_cast<lua_Integer>(i));
      read_tool(lua_gettop(L), "bliskrun.post.write tools[" + std::to_string(i) + "]");
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }

  // Where the time goes (seconds, wall): reported as `seconds`.
  using Clock = std::chrono::steady_clock;
  const auto since = [](Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  PostSeconds seconds;
  auto t0 = Clock::now();
  o.push_raw("path");
  std::vector<int> move_tools;
  const std::vector<PlannedMove> path = check_path(L, -1, &move_tools);
  seconds.read = since(t0);
  lua_pop(L, 1);
  // Each move's tool index; a move without `tool` keeps the one before.
  std::vector<int> tool_of(path.size(), 0);
  for (size_t i = 0; i < path.size(); ++i) {
    if (move_tools[i] == 0) {
      tool_of[i] = i > 0 ? tool_of[i - 1] : 0;
      continue;
    }
    const auto it = std::find_if(job.tools.begin(), job.tools.end(),
                                 [&](const PostTool& t) { return t.number == move_tools[i]; });
    if (it == job.tools.end())
      luax::error(L, "path[" + std::to_string(i + 1) + "].tool: tool " + std::to_string(move_tools[i]) +
                         " is not in the program's tools");
    tool_of[i] = static_cast<int>(it - job.tools.begin());
  }

  const std::string file = o.string("file", "");
  const std::string target = context(L).resolve_write(L, file);
  job.name = o.string("name", fs::path(file).stem().string());

  PostedProgram posted;
  posted.machine = machine.definition;
  for (const PostTool& t : job.tools) {
    posted.tool_lengths_mm.push_back(t.length_mm);
    posted.tool_numbers.push_back(t.number);
  }
  posted.tcp_always = post_tcp_always(L, post_idx);
  posted.file = target;
  MotionOptions motion;
  motion.chord_tol_mm = o.number("chord_tol", 0.005);
  motion.tcp = post_wants_tcp(L, post_idx);
  if (o.has("start")) {
    o.push_raw("start");
    motion.start = check_axes(L, -1, machine.definition, "start");
    lua_pop(L, 1);
  }
  std::vector<Kinematics> kins;
  t0 = Clock::now();
  luax::guarded(L, [&] {
    for (const PostTool& t : job.tools) kins.emplace_back(machine.definition, t.length_mm);
    std::vector<const Kinematics*> pointers;
    for (const Kinematics& k : kins) pointers.push_back(&k);
    posted.plan = plan_machine_motion_tools(pointers, path, tool_of, motion, context(L).progress);
    return 0;
  });
  seconds.motion = since(t0);
  t0 = Clock::now();
  const std::string text = run_post(L, post_idx, kins.front(), posted.plan, job);
  seconds.post = since(t0);
  // Prove the program before it replaces anything on disk.
  t0 = Clock::now();
  const VerifyReport report = verify_posted(L, posted, text, o.number("verify_tol", 0.001), 0.001);
  seconds.verify = since(t0);
  t0 = Clock::now();
  luax::guarded(L, [&] {
    write_file_atomic(target, text);
    return 0;
  });
  seconds.write = since(t0);
  {
    std::ostringstream line;
    line << target << ": " << report.moves << " moves, max tip deviation " << report.max_position_mm
         << " mm (line " << report.worst_position_line << "), max axis deviation "
         << rad_to_deg(report.max_angle_rad) << " deg (line " << report.worst_angle_line << ")";
    context(L).verified_programs.push_back(line.str());
  }
  push_report(L, report, posted);
  lua_createtable(L, 0, 5);
  for (const auto& [name, value] : {std::pair<const char*, double>{"read", seconds.read}, {"motion", seconds.motion},
                                    {"post", seconds.post}, {"verify", seconds.verify}, {"write", seconds.write}}) {
    lua_pushnumber(L, value);
    lua_setfield(L, -2, name);
  }
  lua_setfield(L, -2, "seconds");
  luax::push_new(L, std::move(posted));
  lua_setfield(L, -2, "program");
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

void open_machine(lua_State* L) {
  ensure_machine_type(L);
  luaL_getmetatable(L, kMachineType);
  static const luaL_Reg methods[] = {
      {"name", w_machine_name},       {"configuration", w_machine_configuration},
      {"axes", w_machine_axes},       {"travel", w_machine_travel},
      {"solve", w_machine_solve},     {"forward", w_machine_forward},
      {"reachable", w_machine_reachable}, {"placed", w_machine_placed}, {nullptr, nullptr}};
  lua_newtable(L);
  luaL_setfuncs(L, methods, 0);
  lua_setfield(L, -2, "__index");
  lua_pushcfunction(L, w_machine_tostring);
  lua_setfield(L, -2, "__tostring");
  lua_pop(L, 1);
  static const luaL_Reg no_methods[] = {{nullptr, nullptr}};
  luax::register_type<PostedProgram>(L, no_methods);

  static const luaL_Reg machine_functions[] = {
      {"load", w_machine_load}, {"define", w_machine_define}, {nullptr, nullptr}};
  lua_newtable(L);
  luaL_setfuncs(L, machine_functions, 0);
  lua_setfield(L, -2, "machine");
  static const luaL_Reg post_functions[] = {
      {"load", w_post_load}, {"write", w_post_write}, {"verify", w_post_verify}, {nullptr, nullptr}};
  lua_newtable(L);
  luaL_setfuncs(L, post_functions, 0);
  lua_setfield(L, -2, "post");
}

}  // namespace lua_api
}  // namespace bliskrun
