#pragma once
// A few well-made helpers over the plain Lua C API (sol2 is not available
// here; see third_party_notes.md). Every wrapper in lua_api/wrap_*.cpp follows
// one shape:
//
//   int w_surface_eval(lua_State* L) {
//     return luax::guarded(L, [&] {
//       const Surface& s = luax::check<SurfaceHandle>(L, 1).get();
//       const double u = luax::check_number(L, 2, "u");
//       ...
//       luax::push(L, result);
//       return 1;
//     });
//   }
//
// A wrapper checks arguments, calls core, pushes results — nothing else.
// C++ exceptions thrown by core become Lua errors positioned at the recipe
// line that made the call (luaL_where level 1), raised only after the catch
// block has been left.
#include <lua.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <typeinfo>
#include <vector>

#include "core/common/types.h"

namespace bliskrun::luax {

// ---- errors --------------------------------------------------------------

// Raises a Lua error "<recipe file>:<line>: <message>" at the caller of the
// current C function. Never returns.
[[noreturn]] void error(lua_State* L, const std::string& message);

// Runs body(); converts any C++ exception into a Lua error at the recipe
// line. Lua errors raised inside (C++ Lua build: also exceptions) pass
// through unchanged.
int guarded(lua_State* L, const std::function<int()>& body);

// Called by guarded() before each core call with the calling state (the
// runner records the recipe line there, so that a last-resort stop inside a
// long core call can name it). Process-wide; nullptr = none.
void set_call_observer(void (*observer)(lua_State* L));

// ---- argument checks (errors name the argument) ------------------------

double check_number(lua_State* L, int idx, const char* name);
long long check_integer(lua_State* L, int idx, const char* name);
std::string check_string(lua_State* L, int idx, const char* name);
// {x, y, z} or {x=, y=, z=}
Vec3 check_vec3(lua_State* L, int idx, const char* name);

// ---- pushing values ------------------------------------------------------

void push(lua_State* L, double value);
void push(lua_State* L, const std::string& value);
void push(lua_State* L, const Vec3& value);  // {x, y, z} with .x .y .z too
void push(lua_State* L, const std::vector<double>& values);  // {v1, v2, ...}

// t[key] = value for the table on top of the stack.
void set_number(lua_State* L, const char* key, double value);
void set_integer(lua_State* L, const char* key, long long value);  // a Lua integer
void set_bool(lua_State* L, const char* key, bool value);
void set_string(lua_State* L, const char* key, const std::string& value);
void set_vec3(lua_State* L, const char* key, const Vec3& value);
void set_numbers(lua_State* L, const char* key, const std::vector<double>& values);  // {v1, v2, ...}

// t[key] = {s1, s2, ...}: the strings of any container of std::string
// (a vector, a set: in its order).
template <class Strings>
void set_strings(lua_State* L, const char* key, const Strings& values) {
  lua_createtable(L, static_cast<int>(values.size()), 0);
  lua_Integer k = 0;
  for (const std::string& s : values) {
    lua_pushstring(L, s.c_str());
    lua_rawseti(L, -2, ++k);
  }
  lua_setfield(L, -2, key);
}

// ---- option tables -------------------------------------------------------
// Declared fields, validated in one place. Unknown keys are rejected with the
// list of valid ones; wrong types, out-of-range values and missing required
// fields are errors naming the key and what was expected, at the recipe line.

enum class Kind { Number, Integer, Boolean, String, Table, Vec3, Any };

struct Field {
  std::string name;
  Kind kind = Kind::Number;
  bool required = false;
  std::optional<double> min;      // inclusive, numbers only
  std::optional<double> max;      // inclusive
  std::string doc;                // one line, with units: "blade height, mm"
  std::vector<std::string> choices;  // allowed strings (Kind::String)
};

// An optional number field: the one-liner option tables are made of.
inline Field number_field(const char* name, const char* doc, std::optional<double> min = std::nullopt,
                          std::optional<double> max = std::nullopt) {
  return Field{name, Kind::Number, false, min, max, doc, {}};
}

class Options {
 public:
  // Validates the table at `idx` (absent/nil = empty table) against `fields`.
  // `what` names the call in messages ("bliskrun.blisk"). Raises a Lua error
  // on the first problem.
  Options(lua_State* L, int idx, std::string what, std::vector<Field> fields);

  bool has(const std::string& key) const;
  double number(const std::string& key, double fallback) const;
  long long integer(const std::string& key, long long fallback) const;
  bool boolean(const std::string& key, bool fallback) const;
  std::string string(const std::string& key, const std::string& fallback) const;
  Vec3 vec3(const std::string& key, const Vec3& fallback) const;
  // A Table field holding two integers in [min, max] (sample counts), into
  // a and b; left as they are when absent. `form` names them in the error
  // ("{span, chord}").
  void integer_pair(const std::string& key, const char* form, long long min, long long max, int& a, int& b) const;
  // Pushes the raw value (or nil) onto the stack, for Table/Any fields.
  void push_raw(const std::string& key) const;

 private:
  lua_State* L_;
  int idx_;
  std::string what_;
  std::vector<Field> fields_;
};

// ---- userdata ------------------------------------------------------------
// One metatable per type, methods as __index, __gc runs the destructor,
// __tostring names the type. T is stored by value inside the userdata.

template <class T>
struct TypeName;  // specialise: template <> struct TypeName<Foo> { static constexpr const char* name = "bliskrun.Foo"; };

// Creates the metatable for T with the given methods (name -> function).
void register_type(lua_State* L, const char* type_name,
                   const luaL_Reg* methods, lua_CFunction gc,
                   lua_CFunction tostring = nullptr);

template <class T>
int gc_value(lua_State* L) {
  static_cast<T*>(lua_touserdata(L, 1))->~T();
  return 0;
}

template <class T>
void register_type(lua_State* L, const luaL_Reg* methods) {
  register_type(L, TypeName<T>::name, methods, &gc_value<T>);
}

template <class T>
T& push_new(lua_State* L, T value) {
  void* mem = lua_newuserdatauv(L, sizeof(T), 0);
  T* obj = new (mem) T(std::move(value));
  luaL_setmetatable(L, TypeName<T>::name);
  return *obj;
}

template <class T>
T& check(lua_State* L, int idx) {
  return *static_cast<T*>(luaL_checkudata(L, idx, TypeName<T>::name));
}

template <class T>
T* test(lua_State* L, int idx) {
  return static_cast<T*>(luaL_testudata(L, idx, TypeName<T>::name));
}

}  // namespace bliskrun::luax
