// bliskrun.machine: machine definitions and their kinematics (solve,
// forward, travel, reachability). Posting and read-back: wrap_post.cpp.
// Degrees and mm at this boundary; core works in radians.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "core/common/error.h"
#include "core/machine/machine_sim.h"
#include "lua_api/lua_tool.h"
#include "lua_api/luax.h"
#include "lua_api/machine_host.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"

namespace bliskrun {
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

namespace {

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
  auto range = [&](double lo, double hi) { luax::push(L, std::vector<double>{lo, hi}); };
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

// m:body_clearance(axes, {tool_length =}) -> {distance=, a=, b=, bodies=}:
// the nearest two of the machine's bodies that can meet (machine_sim.h),
// standing at `axes`; distance < 0 is a penetration; nil without bodies.
int w_machine_body_clearance(lua_State* L) {
  const MachineValue& m = check_machine(L, 1);
  const MachineAxes q = check_axes(L, 2, m.definition, "axes");
  const luax::Options o(L, 3, "machine:body_clearance", kinematics_fields());
  return luax::guarded(L, [&] {
    ProgramMove at;
    at.axes = q;
    at.tool = 1;
    MachineSimOptions options;
    options.start = q;
    const MachineSimReport r =
        simulate_machine({at}, m.definition, {SimTool{1, o.number("tool_length", 0), nullptr}}, {}, options);
    if (r.closest.empty()) {
      lua_pushnil(L);
      return 1;
    }
    lua_createtable(L, 0, 4);
    luax::set_number(L, "distance", r.closest.front().distance_mm);
    luax::push(L, r.closest.front().a);
    lua_setfield(L, -2, "a");
    luax::push(L, r.closest.front().b);
    lua_setfield(L, -2, "b");
    luax::set_number(L, "pairs", static_cast<double>(r.pairs));
    return 1;
  });
}

int w_machine_tostring(lua_State* L) {
  const MachineDefinition& m = check_machine(L, 1).definition;
  lua_pushfstring(L, "Machine(%s, %s %s/%s)", m.name.c_str(), configuration_name(m).c_str(),
                  m.rotary[0].name.c_str(), m.rotary[1].name.c_str());
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
      {"reachable", w_machine_reachable}, {"placed", w_machine_placed},
      {"body_clearance", w_machine_body_clearance}, {nullptr, nullptr}};
  lua_newtable(L);
  luaL_setfuncs(L, methods, 0);
  lua_setfield(L, -2, "__index");
  lua_pushcfunction(L, w_machine_tostring);
  lua_setfield(L, -2, "__tostring");
  lua_pop(L, 1);
  static const luaL_Reg machine_functions[] = {
      {"load", w_machine_load}, {"define", w_machine_define}, {nullptr, nullptr}};
  lua_newtable(L);
  luaL_setfuncs(L, machine_functions, 0);
  lua_setfield(L, -2, "machine");
}

}  // namespace lua_api
}  // namespace bliskrun