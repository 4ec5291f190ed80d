#include "lua_api/machine_host.h"

#include <algorithm>
#include <cstring>
#include <cmath>
#include <set>
#include <sstream>
#include <vector>

#include "core/common/error.h"
#include "core/common/fixed_text.h"

namespace bliskrun::lua_api {

namespace {

constexpr const char* kParametricName = "bliskrun.ParametricMachine";

// parametric { parameters = { name = { default = v, doc = "..." }, ... },
//              build = function(p) return machine { ... } end }
// returns a callable table: def { name = value, ... } builds the machine from
// the defaults and the given values. The call itself is l_parametric_call, a
// C function, so that `return generic "x" { ... }` (a tail call) still has
// the machine file's frame to put the line of an unknown parameter on.
constexpr const char* kParametricSource = R"lua(
local call = ...
return function(spec)
  if type(spec) ~= "table" or type(spec.parameters) ~= "table" or type(spec.build) ~= "function" then
    error("parametric: expected { parameters = { ... }, build = function(p) ... end }", 2)
  end
  for k in pairs(spec) do
    if k ~= "parameters" and k ~= "build" and k ~= "doc" then
      error("parametric: unknown key '" .. tostring(k) .. "', expected one of: build, doc, parameters", 2)
    end
  end
  local names = {}
  for k, v in pairs(spec.parameters) do
    if type(k) ~= "string" or type(v) ~= "table" or v.default == nil then
      error("parametric: parameter '" .. tostring(k) .. "' must be { default = ..., doc = \"...\" }", 2)
    end
    names[#names + 1] = k
  end
  table.sort(names)
  local mt = { __name = "bliskrun.ParametricMachine", __call = call }
  return setmetatable({ parameters = spec.parameters, names = table.concat(names, ", "),
                        build = spec.build, doc = spec.doc }, mt)
end
)lua";

// def { ... }: upvalue-free; argument 1 the parametric table, 2 the values.
int l_parametric_call(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);
  if (lua_isnoneornil(L, 2)) {
    lua_settop(L, 1);
    lua_newtable(L);
  }
  if (!lua_istable(L, 2)) return luaL_error(L, "expected a table of machine parameters");
  lua_settop(L, 2);
  lua_getfield(L, 1, "parameters");  // 3
  lua_newtable(L);                   // 4: the parameters build sees
  lua_pushnil(L);
  while (lua_next(L, 2)) {
    // key -2, value -1
    lua_pushvalue(L, -2);
    const bool is_name = lua_type(L, -1) == LUA_TSTRING;
    lua_gettable(L, 3);  // declaration or nil
    if (!is_name || lua_isnil(L, -1)) {
      lua_getfield(L, 1, "names");
      return luaL_error(L, "unknown machine parameter '%s', expected one of: %s",
                        is_name ? lua_tostring(L, -4) : luaL_typename(L, -4), lua_tostring(L, -1));
    }
    lua_getfield(L, -1, "default");
    const int default_type = lua_type(L, -1);
    const bool default_false = default_type == LUA_TBOOLEAN && !lua_toboolean(L, -1);
    const bool value_false = lua_isboolean(L, -3) && !lua_toboolean(L, -3);
    if (!default_false && !value_false && lua_type(L, -3) != default_type)
      return luaL_error(L, "machine parameter '%s': expected a %s, got %s", lua_tostring(L, -4),
                        lua_typename(L, default_type), luaL_typename(L, -3));
    lua_pop(L, 2);
    lua_pushvalue(L, -2);
    lua_insert(L, -2);
    lua_settable(L, 4);
  }
  lua_pushnil(L);
  while (lua_next(L, 3)) {
    lua_pushvalue(L, -2);
    lua_gettable(L, 4);
    const bool given = !lua_isnil(L, -1);
    lua_pop(L, 1);
    if (!given) {
      lua_getfield(L, -1, "default");
      lua_pushvalue(L, -3);
      lua_insert(L, -2);
      lua_settable(L, 4);
    }
    lua_pop(L, 1);
  }
  lua_getfield(L, 1, "build");
  lua_pushvalue(L, 4);
  lua_call(L, 1, 1);
  return 1;
}

// A problem in a definition table; raised as a Lua error once out of C++
// scopes that own resources.
struct TableError {
  std::string message;
};

[[noreturn]] void table_error(const std::string& message) { throw TableError{message}; }

const char* type_of(lua_State* L, int idx) { return luaL_typename(L, idx); }

double read_number(lua_State* L, int idx, const std::string& what) {
  if (!lua_isnumber(L, idx)) table_error(what + ": expected a number, got " + type_of(L, idx));
  const double v = lua_tonumber(L, idx);
  if (!std::isfinite(v)) table_error(what + ": expected a finite number");
  return v;
}

Vec3 read_vec3(lua_State* L, int idx, const std::string& what) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx)) table_error(what + ": expected {x, y, z}, got " + type_of(L, idx));
  if (lua_rawlen(L, idx) != 3) table_error(what + ": expected {x, y, z} (three numbers)");
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    lua_rawgeti(L, idx, i + 1);
    v[i] = read_number(L, -1, what + "[" + std::to_string(i + 1) + "]");
    lua_pop(L, 1);
  }
  return v;
}

// {min, max}
std::pair<double, double> read_range(lua_State* L, int idx, const std::string& what) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx) || lua_rawlen(L, idx) != 2)
    table_error(what + ": expected {min, max}, got " + type_of(L, idx));
  lua_rawgeti(L, idx, 1);
  const double lo = read_number(L, -1, what + "[1]");
  lua_rawgeti(L, idx, 2);
  const double hi = read_number(L, -1, what + "[2]");
  lua_pop(L, 2);
  if (!(lo < hi)) table_error(what + ": expected min < max");
  return {lo, hi};
}

std::string read_string(lua_State* L, int idx, const std::string& what) {
  if (lua_type(L, idx) != LUA_TSTRING) table_error(what + ": expected a string, got " + type_of(L, idx));
  return lua_tostring(L, idx);
}

std::string read_choice(lua_State* L, int idx, const std::string& what,
                        const std::vector<std::string>& choices) {
  const std::string s = read_string(L, idx, what);
  if (std::find(choices.begin(), choices.end(), s) == choices.end()) {
    std::string list;
    for (const std::string& c : choices) list += (list.empty() ? "'" : ", '") + c + "'";
    table_error(what + ": expected one of " + list + ", got '" + s + "'");
  }
  return s;
}

// Rejects keys not in `allowed`, listing them.
void check_keys(lua_State* L, int idx, const std::string& what, const std::set<std::string>& allowed) {
  idx = lua_absindex(L, idx);
  lua_pushnil(L);
  while (lua_next(L, idx)) {
    lua_pop(L, 1);
    const std::string key = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "";
    if (!allowed.count(key)) {
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      std::string shown = key;
      if (key.empty()) shown = lua_type(L, -1) == LUA_TNUMBER ? "[" + std::to_string(lua_tointeger(L, -1)) + "]" : "?";
      lua_pop(L, 1);
      table_error(what + "unknown key '" + shown + "', expected one of: " + list);
    }
  }
}

RotaryAxis read_rotary(lua_State* L, int idx, const std::string& what) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx)) table_error(what + ": expected a table, got " + type_of(L, idx));
  check_keys(L, idx, what + ": ", {"name", "carrier", "direction", "pivot", "travel", "iso841", "speed"});
  RotaryAxis a;
  lua_getfield(L, idx, "name");
  if (lua_isnil(L, -1)) table_error(what + ": missing name (A, B or C)");
  a.name = read_choice(L, -1, what + ".name", {"A", "B", "C"});
  lua_getfield(L, idx, "carrier");
  if (lua_isnil(L, -1)) table_error(what + ": missing carrier ('part' for a table, 'tool' for a head)");
  a.carrier = read_choice(L, -1, what + ".carrier", {"part", "tool"}) == "part" ? AxisCarrier::Part
                                                                            : AxisCarrier::Tool;
  lua_getfield(L, idx, "direction");
  if (lua_isnil(L, -1)) table_error(what + ": missing direction {x, y, z}");
  const Vec3 d = read_vec3(L, -1, what + ".direction");
  if (d.norm() < 1e-12) table_error(what + ".direction: expected a non-zero vector");
  a.direction = d.normalized();
  lua_getfield(L, idx, "pivot");
  if (!lua_isnil(L, -1)) a.pivot_mm = read_vec3(L, -1, what + ".pivot");
  lua_getfield(L, idx, "travel");
  if (!lua_isnil(L, -1) && !(lua_isboolean(L, -1) && !lua_toboolean(L, -1))) {
    const auto [lo, hi] = read_range(L, -1, what + ".travel");
    a.min_rad = deg_to_rad(lo);
    a.max_rad = deg_to_rad(hi);
  }
  lua_getfield(L, idx, "iso841");
  if (!lua_isnil(L, -1)) {
    if (!lua_isboolean(L, -1))
      table_error(what + ".iso841: expected true (a positive angle turns the tool relative to the part as "
                         "ISO 841 says) or false (the reverse), got " + type_of(L, -1));
    a.iso841_sense = lua_toboolean(L, -1) ? 1 : -1;
  }
  lua_getfield(L, idx, "speed");
  if (!lua_isnil(L, -1)) {
    const double deg_per_min = read_number(L, -1, what + ".speed");
    if (!(deg_per_min > 0)) table_error(what + ".speed: expected the axis' top speed > 0 deg/min");
    a.max_speed_rad_per_min = deg_to_rad(deg_per_min);
  }
  lua_pop(L, 7);
  return a;
}

// `dynamics = {X = {max_velocity=, max_accel=, max_jerk=}, ..., <rotary name>
// = {...}, tool_change_s=}`: linear axes in mm/min, mm/s^2, mm/s^3, rotary
// axes in deg/min, deg/s^2, deg/s^3 (the cycle-time estimate's limits; what
// is not stated takes MachineDynamics' defaults).
static void read_dynamics(lua_State* L, int idx, MachineDefinition& m) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx))
    table_error("dynamics: expected { X = {max_velocity=, max_accel=, max_jerk=}, ..., tool_change_s = s }");
  std::set<std::string> keys = {"X", "Y", "Z", "tool_change_s"};
  for (const RotaryAxis& r : m.rotary) keys.insert(r.name);
  check_keys(L, idx, "dynamics: ", keys);
  for (size_t i = 0; i < 5; ++i) {
    const bool rotary = i >= 3;
    const std::string name = rotary ? m.rotary[i - 3].name : m.linear[i].name;
    lua_getfield(L, idx, name.c_str());
    if (!lua_isnil(L, -1)) {
      const std::string what = "dynamics." + name;
      if (!lua_istable(L, -1)) table_error(what + ": expected { max_velocity=, max_accel=, max_jerk= }");
      check_keys(L, -1, what + ": ", {"max_velocity", "max_accel", "max_jerk"});
      const char* unit = rotary ? "deg" : "mm";
      double* targets[3] = {&m.dynamics.axes[i].velocity_per_min, &m.dynamics.axes[i].accel_per_s2,
                            &m.dynamics.axes[i].jerk_per_s3};
      const char* fields[3] = {"max_velocity", "max_accel", "max_jerk"};
      const char* units[3] = {"/min", "/s^2", "/s^3"};
      for (int k = 0; k < 3; ++k) {
        lua_getfield(L, -1, fields[k]);
        if (!lua_isnil(L, -1)) {
          const double v = read_number(L, -1, what + "." + fields[k]);
          if (!(v > 0)) table_error(what + "." + fields[k] + ": expected > 0 " + unit + units[k]);
          *targets[k] = rotary ? deg_to_rad(v) : v;
        }
        lua_pop(L, 1);
      }
    }
    lua_pop(L, 1);
  }
  lua_getfield(L, idx, "tool_change_s");
  if (!lua_isnil(L, -1)) {
    const double v = read_number(L, -1, "dynamics.tool_change_s");
    if (!(v >= 0)) table_error("dynamics.tool_change_s: expected >= 0 s (chip to chip)");
    m.dynamics.tool_change_s = v;
  }
  lua_pop(L, 1);
}

// { name=, frame=, box = {{x,y,z}, {x,y,z}} | cylinder = {from, to} | cone =
// {base, apex}, radius= } (machine_bodies.h); `frame` defaults to
// `default_frame`.
MachineBody read_body(lua_State* L, int idx, const std::string& what, const std::string& default_frame) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx)) table_error(what + ": expected a body table, got " + type_of(L, idx));
  check_keys(L, idx, what + ": ", {"name", "frame", "box", "cylinder", "cone", "radius"});
  MachineBody b;
  lua_getfield(L, idx, "name");
  if (lua_isnil(L, -1)) table_error(what + ": missing name");
  b.name = read_string(L, -1, what + ".name");
  lua_getfield(L, idx, "frame");
  b.frame = lua_isnil(L, -1) ? default_frame : read_string(L, -1, what + ".frame");
  lua_pop(L, 2);
  int shapes = 0;
  for (const char* key : {"box", "cylinder", "cone"}) {
    lua_getfield(L, idx, key);
    if (!lua_isnil(L, -1)) {
      ++shapes;
      const std::string field = what + "." + key;
      if (!lua_istable(L, -1) || lua_rawlen(L, -1) != 2)
        table_error(field + std::string(": expected two points {{x, y, z}, {x, y, z}} (") +
                    (key[1] == 'o' ? "the corners" : key[1] == 'y' ? "the axis' end centres" : "base centre, apex") + ")");
      lua_rawgeti(L, -1, 1);
      const Vec3 p = read_vec3(L, -1, field + "[1]");
      lua_rawgeti(L, -2, 2);
      const Vec3 q = read_vec3(L, -1, field + "[2]");
      lua_pop(L, 2);
      if (key[1] == 'o' && key[0] == 'b') {
        b.shape = BodyShape::Box;
        b.min_mm = p.cwiseMin(q);
        b.max_mm = p.cwiseMax(q);
      } else {
        b.shape = key[1] == 'y' ? BodyShape::Cylinder : BodyShape::Cone;
        b.from_mm = p;
        b.to_mm = q;
      }
    }
    lua_pop(L, 1);
  }
  if (shapes != 1) table_error(what + ": expected exactly one of box, cylinder, cone");
  lua_getfield(L, idx, "radius");
  if (b.shape == BodyShape::Box) {
    if (!lua_isnil(L, -1)) table_error(what + ".radius: a box has no radius");
  } else {
    if (lua_isnil(L, -1)) table_error(what + ": missing radius (mm)");
    b.radius_mm = read_number(L, -1, what + ".radius");
  }
  lua_pop(L, 1);
  return b;
}

std::vector<MachineBody> read_bodies(lua_State* L, int idx, const std::string& what, const std::string& default_frame) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx)) table_error(what + ": expected a list of bodies, got " + type_of(L, idx));
  std::vector<MachineBody> out;
  const lua_Unsigned n = lua_rawlen(L, idx);
  for (lua_Unsigned i = 1; i <= n; ++i) {
    lua_rawgeti(L, idx, static_cast<lua_Integer>(i));
    out.push_back(read_body(L, -1, what + "[" + std::to_string(i) + "]", default_frame));
    lua_pop(L, 1);
  }
  return out;
}

// slides = { tool = {"X", "Z"}, part = {"Y"} }: base outwards on each side.
void read_slides(lua_State* L, int idx, MachineDefinition& m) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx)) table_error("slides: expected { tool = {\"X\", ...}, part = {...} }");
  check_keys(L, idx, "slides: ", {"tool", "part"});
  for (const char* side : {"tool", "part"}) {
    std::vector<int>& list = side[0] == 't' ? m.tool_slides : m.part_slides;
    list.clear();
    lua_getfield(L, idx, side);
    if (!lua_isnil(L, -1)) {
      if (!lua_istable(L, -1)) table_error(std::string("slides.") + side + ": expected a list of axis names");
      const lua_Unsigned n = lua_rawlen(L, -1);
      for (lua_Unsigned i = 1; i <= n; ++i) {
        lua_rawgeti(L, -1, static_cast<lua_Integer>(i));
        const std::string name = read_choice(L, -1, std::string("slides.") + side + "[" + std::to_string(i) + "]", {"X", "Y", "Z"});
        list.push_back(name[0] - 'X');
        lua_pop(L, 1);
      }
    }
    lua_pop(L, 1);
  }
}

MachineDefinition read_definition(lua_State* L, int idx) {
  idx = lua_absindex(L, idx);
  if (!lua_istable(L, idx)) table_error(std::string("expected a table, got ") + type_of(L, idx));
  check_keys(L, idx, "", {"name", "linear", "rotary", "spindle", "part_origin", "tool_length", "feed",
                          "rapid", "resolution", "safe_z", "dynamics", "bodies", "slides"});
  MachineDefinition m;
  lua_getfield(L, idx, "name");
  if (lua_isnil(L, -1)) table_error("missing name");
  m.name = read_string(L, -1, "name");
  lua_pop(L, 1);

  lua_getfield(L, idx, "linear");
  if (!lua_istable(L, -1)) table_error("linear: expected { X = {min, max}, Y = ..., Z = ... }");
  check_keys(L, -1, "linear: ", {"X", "Y", "Z"});
  for (const char* name : {"X", "Y", "Z"}) {
    lua_getfield(L, -1, name);
    if (lua_isnil(L, -1)) table_error(std::string("linear: missing axis ") + name);
    const auto [lo, hi] = read_range(L, -1, std::string("linear.") + name);
    m.linear.push_back({name, lo, hi});
    lua_pop(L, 1);
  }
  lua_pop(L, 1);

  lua_getfield(L, idx, "rotary");
  if (!lua_istable(L, -1)) table_error("rotary: expected a list of two rotary axes in chain order");
  const lua_Unsigned n = lua_rawlen(L, -1);
  if (n != 2)
    table_error("rotary: expected two rotary axes (a 5-axis machine), got " + std::to_string(n));
  for (int i = 1; i <= 2; ++i) {
    lua_rawgeti(L, -1, i);
    m.rotary.push_back(read_rotary(L, -1, "rotary[" + std::to_string(i) + "]"));
    lua_pop(L, 1);
  }
  lua_pop(L, 1);

  lua_getfield(L, idx, "spindle");
  if (!lua_isnil(L, -1)) {
    const Vec3 s = read_vec3(L, -1, "spindle");
    if (s.norm() < 1e-12) table_error("spindle: expected a non-zero vector");
    m.spindle = s.normalized();
  }
  lua_getfield(L, idx, "part_origin");
  if (!lua_isnil(L, -1)) m.part_origin_mm = read_vec3(L, -1, "part_origin");
  lua_getfield(L, idx, "tool_length");
  if (!lua_isnil(L, -1))
    m.tool_length = read_choice(L, -1, "tool_length", {"tip", "gauge"}) == "tip" ? ToolLengthMode::Tip
                                                                                : ToolLengthMode::Gauge;
  lua_getfield(L, idx, "feed");
  if (!lua_isnil(L, -1))
    m.feed = read_choice(L, -1, "feed", {"per_minute", "inverse_time"}) == "per_minute"
                 ? FeedMode::PerMinute
                 : FeedMode::InverseTime;
  lua_getfield(L, idx, "rapid");
  if (!lua_isnil(L, -1)) {
    if (!lua_istable(L, -1)) table_error("rapid: expected { feed = mm/min, linear = true|false }");
    check_keys(L, -1, "rapid: ", {"feed", "linear"});
    lua_getfield(L, -1, "feed");
    if (!lua_isnil(L, -1)) m.rapid.feed_mm_per_min = read_number(L, -1, "rapid.feed");
    lua_getfield(L, -2, "linear");
    if (!lua_isnil(L, -1)) {
      if (!lua_isboolean(L, -1))
        table_error(std::string("rapid.linear: expected true (the controller interpolates rapids linearly) or false, got ") +
                    type_of(L, -1));
      m.rapid.linear = lua_toboolean(L, -1);
    }
    lua_pop(L, 2);
  }
  lua_pop(L, 1);
  lua_getfield(L, idx, "safe_z");
  if (!lua_isnil(L, -1)) m.safe_z_mm = read_number(L, -1, "safe_z");
  lua_pop(L, 1);
  lua_getfield(L, idx, "resolution");
  if (!lua_isnil(L, -1)) {
    if (!lua_istable(L, -1)) table_error("resolution: expected { linear = mm, rotary = deg }");
    check_keys(L, -1, "resolution: ", {"linear", "rotary"});
    lua_getfield(L, -1, "linear");
    if (!lua_isnil(L, -1)) m.linear_resolution_mm = read_number(L, -1, "resolution.linear");
    lua_getfield(L, -2, "rotary");
    if (!lua_isnil(L, -1)) m.rotary_resolution_rad = deg_to_rad(read_number(L, -1, "resolution.rotary"));
    lua_pop(L, 2);
  }
  lua_pop(L, 5);
  lua_getfield(L, idx, "dynamics");
  if (!lua_isnil(L, -1)) read_dynamics(L, -1, m);
  lua_pop(L, 1);
  lua_getfield(L, idx, "slides");
  if (!lua_isnil(L, -1)) read_slides(L, -1, m);
  lua_getfield(L, idx, "bodies");
  if (!lua_isnil(L, -1)) m.bodies = read_bodies(L, -1, "bodies", "base");
  lua_pop(L, 2);
  try {
    validate(m);
  } catch (const ParameterError& e) {
    table_error(e.what());
  }
  return m;
}

bool is_parametric(lua_State* L, int idx) {
  if (!lua_istable(L, idx) || !lua_getmetatable(L, idx)) return false;
  lua_getfield(L, -1, "__name");
  const bool yes = lua_type(L, -1) == LUA_TSTRING && std::string(lua_tostring(L, -1)) == kParametricName;
  lua_pop(L, 2);
  return yes;
}

// Names of shipped files: letters, digits and '_' only, so no path escapes.
void check_file_name(lua_State* L, const std::string& name, const char* what) {
  const bool ok = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
  if (!ok) luaL_error(L, "%s: '%s' is not a name (letters, digits, '_')", what, name.c_str());
}

// Loads `path` as a text chunk with `env` (at env_idx) as its _ENV and calls
// it; leaves its first result.
void run_file(lua_State* L, const std::string& path, int env_idx) {
  env_idx = lua_absindex(L, env_idx);
  if (luaL_loadfilex(L, path.c_str(), "t") != LUA_OK) lua_error(L);
  lua_pushvalue(L, env_idx);
  lua_setupvalue(L, -2, 1);
  lua_call(L, 0, 1);
}

int l_machine(lua_State* L) {
  std::string problem;
  try {
    MachineValue value{read_definition(L, 1), ""};
    push_machine(L, std::move(value));
    return 1;
  } catch (const TableError& e) {
    problem = e.message;
  }
  return luaL_error(L, "machine: %s", problem.c_str());
}

// The calls that run a shipped file by name (generic, machine_lib, extend):
// runs <upvalue 1>/<sub>/<name>.lua, the name the call's argument 1, with
// upvalue 2 as its environment; leaves its result and returns the path.
// `what` names the call in errors.
std::string run_named_file(lua_State* L, const char* what, const char* sub) {
  const std::string name = luaL_checkstring(L, 1);
  check_file_name(L, name, what);
  std::string path = std::string(lua_tostring(L, lua_upvalueindex(1))) + "/" + sub;
  if (*sub) path += "/";
  path += name + ".lua";
  run_file(L, path, lua_upvalueindex(2));
  return path;
}

// generic "name": upvalue 1 = machines folder, 2 = the environment.
int l_generic(lua_State* L) {
  const std::string path = run_named_file(L, "generic", "");
  if (!is_parametric(L, -1))
    return luaL_error(L, "generic: %s does not return parametric { ... }", path.c_str());
  return 1;
}

// machine_lib "name": what machine files share (scripts/machines/lib/name.lua,
// e.g. five_axis: the generic files' common parameters and bodies), run in
// the machine environment; the same upvalues as generic.
int l_machine_lib(lua_State* L) {
  run_named_file(L, "machine_lib", "lib");
  return 1;
}

void push_machine_env(lua_State* L, const std::string& machines_dir) {
  lua_newtable(L);  // env
  lua_newtable(L);  // its metatable: read the sandbox's globals
  lua_pushglobaltable(L);
  lua_setfield(L, -2, "__index");
  lua_setmetatable(L, -2);
  lua_pushcfunction(L, l_machine);
  lua_setfield(L, -2, "machine");
  lua_pushstring(L, machines_dir.c_str());
  lua_pushvalue(L, -2);
  lua_pushcclosure(L, l_generic, 2);
  lua_setfield(L, -2, "generic");
  lua_pushstring(L, machines_dir.c_str());
  lua_pushvalue(L, -2);
  lua_pushcclosure(L, l_machine_lib, 2);
  lua_setfield(L, -2, "machine_lib");
  if (luaL_loadbufferx(L, kParametricSource, std::char_traits<char>::length(kParametricSource),
                       "=parametric", "t") != LUA_OK)
    lua_error(L);
  lua_pushcfunction(L, l_parametric_call);
  lua_call(L, 1, 1);
  lua_setfield(L, -2, "parametric");
}

// extend "name": upvalue 1 = posts folder, 2 = the environment.
int l_extend(lua_State* L) {
  const std::string path = run_named_file(L, "extend", "");
  if (!lua_istable(L, -1)) return luaL_error(L, "extend: %s does not return a post table", path.c_str());
  // A copy, so the extending post never changes the one it extends.
  lua_newtable(L);
  lua_pushnil(L);
  while (lua_next(L, -3)) {
    lua_pushvalue(L, -2);
    lua_insert(L, -2);
    lua_settable(L, -4);
  }
  return 1;
}

// fixed(value, decimals): string.format("%.<decimals>f", value) exactly,
// without the sign of a value that rounds to zero (core/common/fixed_text.h);
// the number words of a post, five or six a block.
int l_fixed(lua_State* L) {
  const double value = luaL_checknumber(L, 1);
  const lua_Integer decimals = luaL_checkinteger(L, 2);
  if (decimals < 0 || decimals > 17) return luaL_error(L, "fixed: decimals must be 0..17, got %d", static_cast<int>(decimals));
  const std::string text = fixed_text(value, static_cast<int>(decimals));
  lua_pushlstring(L, text.data(), text.size());
  return 1;
}

// ---- running a post ------------------------------------------------------

struct PostContext {
  const Kinematics* kin = nullptr;
  const MachineProgram* program = nullptr;
  std::string* text = nullptr;
  bool valid = false;
};
constexpr const char* kPostContextType = "bliskrun.PostContext";

PostContext& context_at(lua_State* L, int idx) {
  auto* c = static_cast<PostContext*>(luaL_checkudata(L, idx, kPostContextType));
  if (!c->valid) luaL_error(L, "post: the program this refers to has been written already");
  return *c;
}

int l_out_line(lua_State* L) {
  PostContext& c = context_at(L, lua_upvalueindex(1));
  size_t len = 0;
  const char* s = luaL_checklstring(L, 2, &len);
  c.text->append(s, len);
  c.text->push_back('\n');
  return 0;
}

void set_vec3(lua_State* L, const Vec3& v, const char* field) {
  lua_createtable(L, 3, 0);
  for (int i = 0; i < 3; ++i) {
    lua_pushnumber(L, v[i]);
    lua_rawseti(L, -2, i + 1);
  }
  lua_setfield(L, -2, field);
}

// Iterator: upvalue 1 = context, 2 = next index.
int l_moves_next(lua_State* L) {
  PostContext& c = context_at(L, lua_upvalueindex(1));
  const lua_Integer i = lua_tointeger(L, lua_upvalueindex(2));
  const auto& moves = c.program->moves;
  if (i >= static_cast<lua_Integer>(moves.size())) return 0;
  lua_pushinteger(L, i + 1);
  lua_replace(L, lua_upvalueindex(2));
  const MachineMove& m = moves[static_cast<size_t>(i)];
  const MachineDefinition& def = c.kin->machine();
  lua_createtable(L, 0, 12);
  lua_pushstring(L, m.kind == MoveKind::Rapid ? "rapid" : "feed");
  lua_setfield(L, -2, "kind");
  // Under TCP the linear words are the tip in the part frame, except on
  // the way in at the safe height, which runs with TCP off.
  const bool machine_words = m.safe == SafeMove::Retract || m.safe == SafeMove::Rotate;
  const Vec3 xyz = c.program->tcp && !machine_words ? m.pose.tip : m.axes.linear_mm;
  for (int a = 0; a < 3; ++a) {
    lua_pushnumber(L, xyz[a]);
    lua_setfield(L, -2, def.linear[a].name.c_str());
  }
  for (int a = 0; a < 2; ++a) {
    lua_pushnumber(L, rad_to_deg(m.axes.rotary_rad[a]));
    lua_setfield(L, -2, def.rotary[a].name.c_str());
  }
  if (m.kind == MoveKind::Feed) {
    luax::set_number(L, "F", m.feed);
  }
  luax::set_integer(L, "index", i + 1);
  luax::set_integer(L, "source", m.source + 1);
  if (m.row >= 0) {
    luax::set_integer(L, "row", m.row);
  }
  luax::set_bool(L, "inserted", m.inserted);
  luax::set_bool(L, "positioning", m.positioning);
  luax::set_integer(L, "tool", m.tool + 1);  // index into job.tools
  if (m.safe != SafeMove::None) {
    lua_pushstring(L, to_string(m.safe));
    lua_setfield(L, -2, "safe");
  }
  if (m.rotary_reset[0] != 0 || m.rotary_reset[1] != 0) {
    // The rotary axes whose display is reset before this move (M94).
    lua_createtable(L, 2, 0);
    int k = 0;
    for (int a = 0; a < 2; ++a) {
      if (m.rotary_reset[a] == 0) continue;
      lua_pushstring(L, def.rotary[a].name.c_str());
      lua_rawseti(L, -2, ++k);
    }
    lua_setfield(L, -2, "reset");
  }
  // tip and axis are made when a post reads them (none of ours does, and
  // two tables a block were a tenth of the post's time on a million blocks).
  lua_pushvalue(L, lua_upvalueindex(3));
  lua_setmetatable(L, -2);
  return 1;
}

// A move's __index: upvalue 1 = context. Makes move.tip and move.axis from
// the move's index, once.
int l_move_index(lua_State* L) {
  PostContext& c = context_at(L, lua_upvalueindex(1));
  const char* key = lua_tostring(L, 2);
  if (!key || (std::strcmp(key, "tip") != 0 && std::strcmp(key, "axis") != 0)) return 0;
  lua_getfield(L, 1, "index");
  const lua_Integer i = lua_tointeger(L, -1) - 1;
  lua_pop(L, 1);
  if (i < 0 || i >= static_cast<lua_Integer>(c.program->moves.size())) return 0;
  const MachineMove& m = c.program->moves[static_cast<size_t>(i)];
  lua_pushvalue(L, 1);
  set_vec3(L, m.pose.tip, "tip");
  set_vec3(L, m.pose.axis, "axis");
  lua_getfield(L, -1, key);
  return 1;
}

// job:moves(): upvalue 1 = context.
int l_job_moves(lua_State* L) {
  context_at(L, lua_upvalueindex(1));
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_pushinteger(L, 0);
  lua_createtable(L, 0, 1);  // the moves' metatable
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_pushcclosure(L, l_move_index, 1);
  lua_setfield(L, -2, "__index");
  lua_pushcclosure(L, l_moves_next, 3);
  return 1;
}

bool post_flag(lua_State* L, int post_idx, const char* field) {
  lua_getfield(L, post_idx, field);
  const bool v = lua_toboolean(L, -1);
  lua_pop(L, 1);
  return v;
}

}  // namespace

void ensure_machine_type(lua_State* L) {
  if (luaL_newmetatable(L, kMachineType)) {
    lua_pushcfunction(L, [](lua_State* S) {
      static_cast<MachineValue*>(lua_touserdata(S, 1))->~MachineValue();
      return 0;
    });
    lua_setfield(L, -2, "__gc");
  }
  lua_pop(L, 1);
}

MachineValue& push_machine(lua_State* L, MachineValue value) {
  ensure_machine_type(L);
  void* mem = lua_newuserdatauv(L, sizeof(MachineValue), 0);
  auto* obj = new (mem) MachineValue(std::move(value));
  luaL_setmetatable(L, kMachineType);
  return *obj;
}

MachineValue* test_machine(lua_State* L, int idx) {
  return static_cast<MachineValue*>(luaL_testudata(L, idx, kMachineType));
}

MachineDefinition check_machine_table(lua_State* L, int idx) {
  std::string problem;
  try {
    return read_definition(L, idx);
  } catch (const TableError& e) {
    problem = e.message;
  }
  luaL_error(L, "machine: %s", problem.c_str());
  return {};
}

void run_script_file(lua_State* L, const std::string& path, int env_idx) { run_file(L, path, env_idx); }

std::vector<MachineBody> check_bodies(lua_State* L, int idx, const std::string& what, const std::string& default_frame) {
  std::string problem;
  try {
    return read_bodies(L, idx, what, default_frame);
  } catch (const TableError& e) {
    problem = e.message;
  }
  luaL_error(L, "%s", problem.c_str());
  return {};
}

void load_machine_file(lua_State* L, const std::string& path, int params_idx,
                       const std::string& machines_dir) {
  if (params_idx != 0) params_idx = lua_absindex(L, params_idx);
  push_machine_env(L, machines_dir);
  run_file(L, path, -1);
  lua_remove(L, -2);  // env
  if (is_parametric(L, -1)) {
    if (params_idx != 0) lua_pushvalue(L, params_idx); else lua_newtable(L);
    lua_call(L, 1, 1);
  } else if (params_idx != 0 && !lua_isnil(L, params_idx)) {
    luaL_error(L, "%s: parameters given, but the file is not a parametric definition", path.c_str());
  }
  MachineValue* m = test_machine(L, -1);
  if (!m) luaL_error(L, "%s: expected the file to return machine { ... } or parametric { ... }", path.c_str());
  m->source = path;
}

void load_post_file(lua_State* L, const std::string& path, const std::string& posts_dir) {
  lua_newtable(L);  // env
  lua_newtable(L);
  lua_pushglobaltable(L);
  lua_setfield(L, -2, "__index");
  lua_setmetatable(L, -2);
  lua_pushstring(L, posts_dir.c_str());
  lua_pushvalue(L, -2);
  lua_pushcclosure(L, l_extend, 2);
  lua_setfield(L, -2, "extend");
  lua_pushcfunction(L, l_fixed);
  lua_setfield(L, -2, "fixed");
  run_file(L, path, -1);
  lua_remove(L, -2);
  if (!lua_istable(L, -1)) luaL_error(L, "%s: expected the post file to return its table", path.c_str());
  lua_getfield(L, -1, "write");
  if (!lua_isfunction(L, -1)) luaL_error(L, "%s: the post has no write function (extend \"base\")", path.c_str());
  lua_pop(L, 1);
}

bool post_wants_tcp(lua_State* L, int post_idx) {
  post_idx = lua_absindex(L, post_idx);
  return post_flag(L, post_idx, "tcp") || post_flag(L, post_idx, "tcp_always");
}

bool post_tcp_always(lua_State* L, int post_idx) {
  return post_flag(L, lua_absindex(L, post_idx), "tcp_always");
}

PostTraits post_traits(lua_State* L, int post_idx) {
  post_idx = lua_absindex(L, post_idx);
  PostTraits t;
  t.tcp = post_wants_tcp(L, post_idx);
  t.tcp_always = post_tcp_always(L, post_idx);
  t.rotary_reset = post_flag(L, post_idx, "resets_rotary_display");
  lua_getfield(L, post_idx, "orientation");
  if (!lua_isnil(L, -1)) {
    const char* o = lua_tostring(L, -1);
    if (!o || (std::strcmp(o, "axis") != 0 && std::strcmp(o, "vector") != 0))
      luaL_error(L, "post: field 'orientation': expected \"axis\" (rotaries linear) or \"vector\" (great circle)");
    t.vector = std::strcmp(o, "vector") == 0;
  }
  lua_pop(L, 1);
  lua_getfield(L, post_idx, "rotary_input_limit");
  if (!lua_isnil(L, -1)) {
    if (!lua_isnumber(L, -1) || !(lua_tonumber(L, -1) > 360))
      luaL_error(L, "post: field 'rotary_input_limit': expected the controller's largest rotary value, > 360 deg");
    t.rotary_input_limit_deg = lua_tonumber(L, -1);
  }
  lua_pop(L, 1);
  return t;
}

int decimals_for(double resolution) {
  return std::clamp(static_cast<int>(std::lround(-std::log10(resolution))), 0, 9);
}

namespace {

// job.machine.rotary_axes: {{name=, carrier = "part"|"tool", iso841 = bool}, ...}
// in chain order; iso841 from the geometry (core's iso841_sense), so it holds
// for machines whose file does not state it.
void push_rotary_senses(lua_State* L, const MachineDefinition& def) {
  lua_createtable(L, 2, 0);
  for (int i = 0; i < 2; ++i) {
    const RotaryAxis& a = def.rotary[i];
    lua_createtable(L, 0, 3);
    luax::set_string(L, "name", a.name);
    luax::set_string(L, "carrier", a.carrier == AxisCarrier::Part ? "part" : "tool");
    luax::set_bool(L, "iso841", iso841_sense(def, i) > 0);
    lua_rawseti(L, -2, i + 1);
  }
}

// job.work_offset, job.coolant, job.program_number (each only when given),
// job.setup = {name=, flip=, clocking_deg=}, job.notes = {...}
// into the job table on top of the stack.
void push_setup(lua_State* L, const PostJob& job) {
  luax::set_integer(L, "work_offset", job.work_offset);
  if (!job.coolant.empty()) luax::set_string(L, "coolant", job.coolant);
  if (job.program_number > 0) {
    luax::set_integer(L, "program_number", job.program_number);
  }
  lua_createtable(L, 0, 3);
  if (!job.setup.name.empty()) luax::set_string(L, "name", job.setup.name);
  luax::set_bool(L, "flip", job.setup.flip);
  luax::set_number(L, "clocking_deg", job.setup.clocking_deg);
  lua_setfield(L, -2, "setup");
  lua_createtable(L, static_cast<int>(job.notes.size()), 0);
  for (size_t i = 0; i < job.notes.size(); ++i) {
    luax::push(L, job.notes[i]);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setfield(L, -2, "notes");
}

}  // namespace

std::string run_post(lua_State* L, int post_idx, const Kinematics& kin,
                     const MachineProgram& program, const PostJob& job) {
  post_idx = lua_absindex(L, post_idx);
  const MachineDefinition& def = kin.machine();
  std::string text;
  auto* ctx = static_cast<PostContext*>(lua_newuserdatauv(L, sizeof(PostContext), 0));
  new (ctx) PostContext{&kin, &program, &text, true};
  luaL_newmetatable(L, kPostContextType);
  lua_setmetatable(L, -2);
  const int ctx_idx = lua_gettop(L);

  lua_getfield(L, post_idx, "write");
  lua_pushvalue(L, post_idx);

  // job
  lua_createtable(L, 0, 8);
  lua_pushstring(L, job.name.c_str());
  lua_setfield(L, -2, "name");
  lua_createtable(L, 0, 5);
  lua_pushstring(L, def.name.c_str());
  lua_setfield(L, -2, "name");
  lua_pushstring(L, configuration_name(def).c_str());
  lua_setfield(L, -2, "configuration");
  lua_pushstring(L, def.tool_length == ToolLengthMode::Tip ? "tip" : "gauge");
  lua_setfield(L, -2, "tool_length");
  lua_createtable(L, 3, 0);
  for (int i = 0; i < 3; ++i) {
    lua_pushstring(L, def.linear[i].name.c_str());
    lua_rawseti(L, -2, i + 1);
  }
  lua_setfield(L, -2, "linear");
  lua_createtable(L, 2, 0);
  for (int i = 0; i < 2; ++i) {
    lua_pushstring(L, def.rotary[i].name.c_str());
    lua_rawseti(L, -2, i + 1);
  }
  lua_setfield(L, -2, "rotary");
  lua_createtable(L, 3, 0);
  for (int i = 0; i < 3; ++i) {
    lua_pushnumber(L, def.part_origin_mm[i]);
    lua_rawseti(L, -2, i + 1);
  }
  lua_setfield(L, -2, "part_origin");
  luax::set_number(L, "rapid_feed", def.rapid.feed_mm_per_min);
  luax::set_bool(L, "linear_rapids", def.rapid.linear);
  push_rotary_senses(L, def);
  lua_setfield(L, -2, "rotary_axes");
  lua_setfield(L, -2, "machine");
  push_setup(L, job);
  // job.tools: every tool in program order; job.tool: the one in the
  // spindle (the first; base.motion moves it on at each tool change).
  lua_createtable(L, static_cast<int>(job.tools.size()), 0);
  for (size_t t = 0; t < job.tools.size(); ++t) {
    const PostTool& tool = job.tools[t];
    lua_createtable(L, 0, 3);
    luax::set_integer(L, "number", tool.number);
    luax::set_number(L, "length", tool.length_mm);
    if (tool.spindle_rpm > 0) {
      luax::set_integer(L, "spindle_rpm", tool.spindle_rpm);
    }
    lua_rawseti(L, -2, static_cast<lua_Integer>(t + 1));
  }
  lua_rawgeti(L, -1, 1);
  lua_setfield(L, -3, "tool");
  lua_setfield(L, -2, "tools");
  luax::set_bool(L, "tcp", program.tcp);
  lua_pushstring(L, to_string(program.controller));
  lua_setfield(L, -2, "controller");
  // job.approach = {safe_z =}: the program comes in and leaves at the safe
  // height (its first move is a Retract); nil when it starts wherever the
  // tool change left the machine.
  if (!program.moves.empty() && program.moves.front().safe == SafeMove::Retract) {
    lua_createtable(L, 0, 1);
    luax::set_number(L, "safe_z", program.moves.front().axes.linear_mm.z());
    lua_setfield(L, -2, "approach");
  }
  lua_pushstring(L, program.feed_mode == FeedMode::InverseTime ? "inverse_time" : "per_minute");
  lua_setfield(L, -2, "feed_mode");
  lua_createtable(L, 0, 3);
  luax::set_integer(L, "linear", decimals_for(def.linear_resolution_mm));
  luax::set_integer(L, "rotary", decimals_for(rad_to_deg(def.rotary_resolution_rad)));
  luax::set_integer(L, "feed", program.feed_mode == FeedMode::InverseTime ? 3 : 1);
  lua_setfield(L, -2, "decimals");
  lua_pushvalue(L, ctx_idx);
  lua_pushcclosure(L, l_job_moves, 1);
  lua_setfield(L, -2, "moves");

  // out
  lua_createtable(L, 0, 1);
  lua_pushvalue(L, ctx_idx);
  lua_pushcclosure(L, l_out_line, 1);
  lua_setfield(L, -2, "line");

  // post.write(post, job, out); the context dies with this call whatever
  // happens, so a post that kept the iterator cannot read freed memory.
  struct Invalidate {
    PostContext* c;
    ~Invalidate() { c->valid = false; }
  } invalidate{ctx};
  lua_call(L, 3, 0);
  lua_settop(L, ctx_idx - 1);
  return text;
}

}  // namespace bliskrun::lua_api
