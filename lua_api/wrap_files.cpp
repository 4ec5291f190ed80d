// Files and messages: bliskrun.write_json, write_text, read_text, out_dir,
// log, progress. Every write goes through write_file_atomic into the out
// folder; reads only from the recipe, data and out folders.
#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/common/atomic_file.h"
#include "lua_api/luax.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"

namespace bliskrun::lua_api {

namespace {

// A Lua value as JSON: tables with keys 1..n are arrays, tables with string
// keys are objects (sorted keys, so output is deterministic).
nlohmann::json to_json(lua_State* L, int idx, const std::string& where, int depth) {
  idx = lua_absindex(L, idx);
  if (depth > 64) luax::error(L, "write_json: " + where + " nests deeper than 64 levels (a cycle?)");
  switch (lua_type(L, idx)) {
    case LUA_TNIL:
      return nullptr;
    case LUA_TBOOLEAN:
      return static_cast<bool>(lua_toboolean(L, idx));
    case LUA_TNUMBER: {
      if (lua_isinteger(L, idx)) return static_cast<long long>(lua_tointeger(L, idx));
      const double x = lua_tonumber(L, idx);
      if (!std::isfinite(x)) luax::error(L, "write_json: " + where + " is not a finite number");
      return x;
    }
    case LUA_TSTRING:
      return std::string(lua_tostring(L, idx));
    case LUA_TTABLE: {
      const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, idx));
      size_t count = 0;
      bool string_keys = true;
      lua_pushnil(L);
      while (lua_next(L, idx)) {
        ++count;
        if (lua_type(L, -2) != LUA_TSTRING) string_keys = false;
        lua_pop(L, 1);
      }
      if (count == 0) return nlohmann::json::object();
      if (n > 0 && static_cast<size_t>(n) == count) {
        nlohmann::json arr = nlohmann::json::array();
        for (lua_Integer i = 1; i <= n; ++i) {
          lua_rawgeti(L, idx, i);
          arr.push_back(to_json(L, -1, where + "[" + std::to_string(i) + "]", depth + 1));
          lua_pop(L, 1);
        }
        return arr;
      }
      if (!string_keys) luax::error(L, "write_json: " + where + " mixes array entries and named keys");
      nlohmann::json obj = nlohmann::json::object();
      lua_pushnil(L);
      while (lua_next(L, idx)) {
        const std::string key = lua_tostring(L, -2);
        obj[key] = to_json(L, -1, where + "." + key, depth + 1);
        lua_pop(L, 1);
      }
      return obj;
    }
    default:
      luax::error(L, std::string("write_json: ") + where + " is a " + luaL_typename(L, idx) +
                         ", which JSON cannot hold");
  }
}

int w_write_json(lua_State* L) {
  const std::string path = luax::check_string(L, 1, "path");
  luaL_checktype(L, 2, LUA_TTABLE);
  const std::string target = context(L).resolve_write(L, path);
  const nlohmann::json j = to_json(L, 2, "value", 0);
  return luax::guarded(L, [&] {
    write_file_atomic(target, j.dump(2) + "\n");
    lua_pushstring(L, target.c_str());
    return 1;
  });
}

int w_write_text(lua_State* L) {
  const std::string path = luax::check_string(L, 1, "path");
  const std::string text = luax::check_string(L, 2, "text");
  const std::string target = context(L).resolve_write(L, path);
  return luax::guarded(L, [&] {
    write_file_atomic(target, text);
    lua_pushstring(L, target.c_str());
    return 1;
  });
}

int w_read_text(lua_State* L) {
  const std::string path = luax::check_string(L, 1, "path");
  const std::string source = context(L).resolve_read(L, path);
  std::ifstream in(source, std::ios::binary);
  if (!in) luax::error(L, "cannot read '" + path + "'");
  std::ostringstream s;
  s << in.rdbuf();
  luax::push(L, s.str());
  return 1;
}

int w_threads(lua_State* L) {
  lua_pushinteger(L, context(L).options.threads);
  return 1;
}

int w_out_dir(lua_State* L) {
  lua_pushstring(L, context(L).out_dir.c_str());
  return 1;
}

// log(...): like print, to stderr, silenced by --quiet.
int w_log(lua_State* L) {
  const int n = lua_gettop(L);
  std::string line;
  for (int i = 1; i <= n; ++i) {
    if (i > 1) line += "\t";
    line += luaL_tolstring(L, i, nullptr);
    lua_pop(L, 1);
  }
  if (!context(L).options.quiet) std::cerr << line << "\n";
  return 0;
}

int w_progress(lua_State* L) {
  const std::string task = luax::check_string(L, 1, "task");
  const long long done = luax::check_integer(L, 2, "done");
  const long long total = luax::check_integer(L, 3, "total");
  return luax::guarded(L, [&] {
    Progress& p = context(L).progress;
    if (done <= 0) p.begin(task, static_cast<long>(total));
    else if (done >= total) p.end();
    else p.step(static_cast<long>(done));
    return 0;
  });
}

}  // namespace

void open_files(lua_State* L) {
  static const luaL_Reg functions[] = {{"write_json", w_write_json}, {"write_text", w_write_text},
                                       {"read_text", w_read_text},   {"out_dir", w_out_dir}, {"threads", w_threads},
                                       {"log", w_log},               {"progress", w_progress},
                                       {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
