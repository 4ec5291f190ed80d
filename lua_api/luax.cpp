#include "lua_api/luax.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <new>
#include <sstream>

#include "core/common/memory_budget.h"

namespace bliskrun::luax {

void error(lua_State* L, const std::string& message) {
  luaL_where(L, 1);
  lua_pushlstring(L, message.data(), message.size());
  lua_concat(L, 2);
  lua_error(L);
  // lua_error does not return; the C++ build of Lua throws from it.
  std::terminate();
}

namespace {
std::atomic<void (*)(lua_State*)> call_observer{nullptr};
}  // namespace

void set_call_observer(void (*observer)(lua_State* L)) { call_observer.store(observer); }

int guarded(lua_State* L, const std::function<int()>& body) {
  if (auto* observe = call_observer.load(std::memory_order_relaxed)) observe(L);
  std::string message;
  try {
    return body();
  } catch (const std::bad_alloc&) {
    // A C++ allocation refused for the run's budget (or by the system).
    if (memory_budget_exceeded()) {
      std::ostringstream text;
      text << "memory limit of " << memory_budget() / (1024.0 * 1024.0) << " MB exceeded (--memory-limit)";
      message = text.str();
    } else {
      message = "out of memory";
    }
  } catch (const std::exception& e) {
    // Lua's own errors (C++ build) are not std::exceptions and pass through
    // untouched; only core's errors are converted, after the catch block has
    // been left so that the exception object is gone before Lua unwinds.
    message = e.what();
  }
  error(L, message);
}

// ---- argument checks -------------------------------------------------------

namespace {

std::string type_of(lua_State* L, int idx) { return luaL_typename(L, idx); }

[[noreturn]] void bad_argument(lua_State* L, int idx, const char* name, const std::string& expected) {
  error(L, std::string("argument ") + std::to_string(idx) + " '" + name + "': expected " + expected +
               ", got " + type_of(L, idx));
}

}  // namespace

double check_number(lua_State* L, int idx, const char* name) {
  if (lua_type(L, idx) != LUA_TNUMBER) bad_argument(L, idx, name, "number");
  const double x = lua_tonumber(L, idx);
  if (!std::isfinite(x)) error(L, std::string("argument '") + name + "': expected a finite number");
  return x;
}

long long check_integer(lua_State* L, int idx, const char* name) {
  if (!lua_isinteger(L, idx)) {
    if (lua_type(L, idx) == LUA_TNUMBER) {
      const double x = lua_tonumber(L, idx);
      if (std::isfinite(x) && x == std::floor(x) && std::abs(x) < 9e15) return static_cast<long long>(x);
    }
    bad_argument(L, idx, name, "integer");
  }
  return lua_tointeger(L, idx);
}

std::string check_string(lua_State* L, int idx, const char* name) {
  if (lua_type(L, idx) != LUA_TSTRING) bad_argument(L, idx, name, "string");
  size_t len = 0;
  const char* s = lua_tolstring(L, idx, &len);
  return std::string(s, len);
}

namespace {

// Reads {x, y, z} or {x=, y=, z=} at idx; false if the shape is wrong.
bool read_vec3(lua_State* L, int idx, Vec3& out) {
  if (lua_type(L, idx) != LUA_TTABLE) return false;
  idx = lua_absindex(L, idx);
  for (int k = 0; k < 3; ++k) {
    lua_rawgeti(L, idx, k + 1);
    if (lua_type(L, -1) != LUA_TNUMBER) {
      lua_pop(L, 1);
      static const char* names[3] = {"x", "y", "z"};
      lua_getfield(L, idx, names[k]);
      if (lua_type(L, -1) != LUA_TNUMBER) {
        lua_pop(L, 1);
        return false;
      }
    }
    out[k] = lua_tonumber(L, -1);
    lua_pop(L, 1);
  }
  return out.allFinite();
}

}  // namespace

Vec3 check_vec3(lua_State* L, int idx, const char* name) {
  Vec3 v;
  if (!read_vec3(L, idx, v)) bad_argument(L, idx, name, "a vector {x, y, z} of finite numbers");
  return v;
}

// ---- pushing ---------------------------------------------------------------

void push(lua_State* L, double value) { lua_pushnumber(L, value); }

void push(lua_State* L, const std::string& value) { lua_pushlstring(L, value.data(), value.size()); }

void push(lua_State* L, const Vec3& v) {
  lua_createtable(L, 3, 3);
  static const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    lua_pushnumber(L, v[k]);
    lua_rawseti(L, -2, k + 1);
    lua_pushnumber(L, v[k]);
    lua_setfield(L, -2, names[k]);
  }
}

void push(lua_State* L, const std::vector<double>& values) {
  lua_createtable(L, static_cast<int>(values.size()), 0);
  for (size_t i = 0; i < values.size(); ++i) {
    lua_pushnumber(L, values[i]);
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
}

void set_number(lua_State* L, const char* key, double value) {
  lua_pushnumber(L, value);
  lua_setfield(L, -2, key);
}

void set_integer(lua_State* L, const char* key, long long value) {
  lua_pushinteger(L, static_cast<lua_Integer>(value));
  lua_setfield(L, -2, key);
}

void set_numbers(lua_State* L, const char* key, const std::vector<double>& values) {
  push(L, values);
  lua_setfield(L, -2, key);
}

void set_bool(lua_State* L, const char* key, bool value) {
  lua_pushboolean(L, value);
  lua_setfield(L, -2, key);
}

void set_string(lua_State* L, const char* key, const std::string& value) {
  push(L, value);
  lua_setfield(L, -2, key);
}

void set_vec3(lua_State* L, const char* key, const Vec3& value) {
  push(L, value);
  lua_setfield(L, -2, key);
}

// ---- option tables -----------------------------------------------------------

namespace {

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::Number: return "number";
    case Kind::Integer: return "integer";
    case Kind::Boolean: return "boolean";
    case Kind::String: return "string";
    case Kind::Table: return "table";
    case Kind::Vec3: return "vector {x, y, z}";
    case Kind::Any: return "any value";
  }
  return "?";
}

std::string format_number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

std::string with_doc(const Field& f) { return f.doc.empty() ? "" : " (" + f.doc + ")"; }

}  // namespace

Options::Options(lua_State* L, int idx, std::string what, std::vector<Field> fields)
    : L_(L), idx_(lua_absindex(L, idx)), what_(std::move(what)), fields_(std::move(fields)) {
  const int t = lua_type(L, idx_);
  if (t == LUA_TNONE || t == LUA_TNIL) {
    if (t == LUA_TNONE) lua_settop(L, idx_);  // make the slot exist
    lua_newtable(L);
    lua_replace(L, idx_);  // an empty table in its place
  } else if (t != LUA_TTABLE) {
    error(L, what_ + ": expected an option table, got " + type_of(L, idx_));
  }
  auto find = [&](const std::string& key) -> const Field* {
    for (const Field& f : fields_)
      if (f.name == key) return &f;
    return nullptr;
  };
  auto valid_list = [&] {
    std::vector<std::string> names;
    for (const Field& f : fields_) names.push_back(f.name);
    std::sort(names.begin(), names.end());
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
    return s.empty() ? std::string("none") : s;
  };
  lua_pushnil(L);
  while (lua_next(L, idx_) != 0) {
    if (lua_type(L, -2) != LUA_TSTRING) {
      const std::string shown = lua_type(L, -2) == LUA_TNUMBER ? "[" + format_number(lua_tonumber(L, -2)) + "]"
                                                               : type_of(L, -2);
      lua_pop(L, 2);
      error(L, what_ + ": option keys must be names, got " + shown + "; valid options: " + valid_list());
    }
    const std::string key = lua_tostring(L, -2);
    const Field* f = find(key);
    if (!f) {
      lua_pop(L, 2);
      error(L, what_ + ": unknown option '" + key + "'; valid options: " + valid_list());
    }
    const int vt = lua_type(L, -1);
    auto wrong = [&](const std::string& expected) {
      const std::string got = type_of(L, -1);
      lua_pop(L, 2);
      error(L, what_ + ": option '" + key + "': expected " + expected + ", got " + got + with_doc(*f));
    };
    switch (f->kind) {
      case Kind::Number:
      case Kind::Integer: {
        if (vt != LUA_TNUMBER) wrong(kind_name(f->kind));
        const double x = lua_tonumber(L, -1);
        if (!std::isfinite(x)) wrong("a finite number");
        if (f->kind == Kind::Integer && x != std::floor(x)) wrong("integer");
        if ((f->min && x < *f->min) || (f->max && x > *f->max)) {
          const std::string lo = f->min ? format_number(*f->min) : "-inf";
          const std::string hi = f->max ? format_number(*f->max) : "inf";
          lua_pop(L, 2);
          error(L, what_ + ": option '" + key + "': " + format_number(x) + " is out of range [" + lo +
                       ", " + hi + "]" + with_doc(*f));
        }
        break;
      }
      case Kind::Boolean:
        if (vt != LUA_TBOOLEAN) wrong("boolean");
        break;
      case Kind::String: {
        if (vt != LUA_TSTRING) wrong("string");
        if (!f->choices.empty()) {
          const std::string s = lua_tostring(L, -1);
          if (std::find(f->choices.begin(), f->choices.end(), s) == f->choices.end()) {
            std::string list;
            for (const auto& c : f->choices) list += (list.empty() ? "'" : ", '") + c + "'";
            lua_pop(L, 2);
            error(L, what_ + ": option '" + key + "': '" + s + "' is not one of " + list + with_doc(*f));
          }
        }
        break;
      }
      case Kind::Table:
        if (vt != LUA_TTABLE) wrong("table");
        break;
      case Kind::Vec3: {
        Vec3 v;
        if (!read_vec3(L, -1, v)) wrong("a vector {x, y, z} of finite numbers");
        break;
      }
      case Kind::Any:
        break;
    }
    lua_pop(L, 1);
  }
  for (const Field& f : fields_) {
    if (!f.required) continue;
    lua_getfield(L, idx_, f.name.c_str());
    const bool missing = lua_isnil(L, -1);
    lua_pop(L, 1);
    if (missing) error(L, what_ + ": missing required option '" + f.name + "'" + with_doc(f));
  }
}

bool Options::has(const std::string& key) const {
  lua_getfield(L_, idx_, key.c_str());
  const bool present = !lua_isnil(L_, -1);
  lua_pop(L_, 1);
  return present;
}

double Options::number(const std::string& key, double fallback) const {
  lua_getfield(L_, idx_, key.c_str());
  const double x = lua_isnil(L_, -1) ? fallback : lua_tonumber(L_, -1);
  lua_pop(L_, 1);
  return x;
}

long long Options::integer(const std::string& key, long long fallback) const {
  lua_getfield(L_, idx_, key.c_str());
  const long long x = lua_isnil(L_, -1) ? fallback : static_cast<long long>(lua_tonumber(L_, -1));
  lua_pop(L_, 1);
  return x;
}

bool Options::boolean(const std::string& key, bool fallback) const {
  lua_getfield(L_, idx_, key.c_str());
  const bool x = lua_isnil(L_, -1) ? fallback : lua_toboolean(L_, -1);
  lua_pop(L_, 1);
  return x;
}

std::string Options::string(const std::string& key, const std::string& fallback) const {
  lua_getfield(L_, idx_, key.c_str());
  std::string x = fallback;
  if (!lua_isnil(L_, -1)) {
    size_t len = 0;
    const char* s = lua_tolstring(L_, -1, &len);
    x.assign(s, len);
  }
  lua_pop(L_, 1);
  return x;
}

Vec3 Options::vec3(const std::string& key, const Vec3& fallback) const {
  lua_getfield(L_, idx_, key.c_str());
  Vec3 v = fallback;
  if (!lua_isnil(L_, -1)) read_vec3(L_, -1, v);
  lua_pop(L_, 1);
  return v;
}

void Options::push_raw(const std::string& key) const { lua_getfield(L_, idx_, key.c_str()); }

void Options::integer_pair(const std::string& key, const char* form, long long min, long long max, int& a,
                           int& b) const {
  if (!has(key)) return;
  push_raw(key);
  const int t = lua_gettop(L_);
  const std::string where = what_ + ": option '" + key + "'";
  if (luaL_len(L_, t) != 2) error(L_, where + ": expected " + form);
  for (int k = 1; k <= 2; ++k) {
    lua_rawgeti(L_, t, k);
    int isnum = 0;
    const lua_Integer n = lua_tointegerx(L_, -1, &isnum);
    if (!isnum || n < min || n > max)
      error(L_, where + ": expected integers in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
    (k == 1 ? a : b) = static_cast<int>(n);
    lua_pop(L_, 1);
  }
  lua_pop(L_, 1);
}

// ---- userdata ----------------------------------------------------------------

namespace {

int default_tostring(lua_State* L) {
  lua_pushfstring(L, "%s: %p", luaL_typename(L, 1), lua_topointer(L, 1));
  if (luaL_getmetafield(L, 1, "__name") != LUA_TNIL) {
    lua_pushfstring(L, "%s: %p", lua_tostring(L, -1), lua_topointer(L, 1));
  }
  return 1;
}

}  // namespace

void register_type(lua_State* L, const char* type_name, const luaL_Reg* methods, lua_CFunction gc,
                   lua_CFunction tostring) {
  luaL_newmetatable(L, type_name);
  lua_newtable(L);
  if (methods) luaL_setfuncs(L, methods, 0);
  lua_setfield(L, -2, "__index");
  lua_pushcfunction(L, gc);
  lua_setfield(L, -2, "__gc");
  lua_pushcfunction(L, tostring ? tostring : default_tostring);
  lua_setfield(L, -2, "__tostring");
  lua_pop(L, 1);
}

}  // namespace bliskrun::luax
