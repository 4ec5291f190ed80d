// Files and messages: bliskrun.write_json, write_text, read_text, out_dir,
// log, progress. Every write goes through write_file_atomic into the out
// folder; reads only from the recipe, data and out folders.
#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>
#include <vector>

#include "core/common/atomic_file.h"
#include "lua_api/luax.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"

namespace bliskrun::lua_api {

namespace {

// A Lua value as JSON: tables with keys 1..n are arrays, tables with string
// keys are objects (sorted keys, so output is deterministic). The recursion is
// bounded by kMaxJsonDepth (documented in docs/lua_api.md), tables already on
// the current path are a cycle named by both key paths, and the Lua stack is
// grown explicitly (without lua_checkstack a deep table overran it and
// crashed the process).
constexpr int kMaxJsonDepth = 64;

struct JsonWalk {
  lua_State* L;
  std::vector<std::pair<const void*, std::string>> path;  // tables being converted, outermost first
};

nlohmann::json to_json(JsonWalk& walk, int idx, const std::string& where) {
  lua_State* L = walk.L;
  idx = lua_absindex(L, idx);
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
    case LUA_TSTRING: {
      size_t len = 0;
      const char* text = lua_tolstring(L, idx, &len);
      return std::string(text, len);
    }
    case LUA_TTABLE: {
      const void* self = lua_topointer(L, idx);
      for (const auto& [table, at] : walk.path)
        if (table == self) luax::error(L, "write_json: " + where + " is " + at + " again (a cycle)");
      if (static_cast<int>(walk.path.size()) >= kMaxJsonDepth)
        luax::error(L, "write_json: " + where + " nests deeper than " + std::to_string(kMaxJsonDepth) +
                           " tables (the limit of write_json)");
      if (!lua_checkstack(L, 4)) luax::error(L, "write_json: " + where + ": Lua stack exhausted");
      walk.path.emplace_back(self, where);
      const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, idx));
      size_t count = 0;
      bool string_keys = true;
      lua_pushnil(L);
      while (lua_next(L, idx)) {
        ++count;
        if (lua_type(L, -2) != LUA_TSTRING) string_keys = false;
        lua_pop(L, 1);
      }
      nlohmann::json out = nlohmann::json::object();
      if (count == 0) {
      } else if (n > 0 && static_cast<size_t>(n) == count) {
        out = nlohmann::json::array();
        for (lua_Integer i = 1; i <= n; ++i) {
          lua_rawgeti(L, idx, i);
          out.push_back(to_json(walk, -1, where + "[" + std::to_string(i) + "]"));
          lua_pop(L, 1);
        }
      } else {
        if (!string_keys) luax::error(L, "write_json: " + where + " mixes array entries and named keys");
        lua_pushnil(L);
        while (lua_next(L, idx)) {
          size_t len = 0;
          const char* text = lua_tolstring(L, -2, &len);  // a string key: no conversion, lua_next stays valid
          const std::string key(text, len);
          out[key] = to_json(walk, -1, where + "." + key);
          lua_pop(L, 1);
        }
      }
      walk.path.pop_back();
      return out;
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
  JsonWalk walk{L, {}};
  const nlohmann::json j = to_json(walk, 2, "value");
  return luax::guarded(L, [&] {
    // Strings are Lua bytes, not necessarily UTF-8: replace invalid sequences
    // rather than let dump() throw.
    // A run's verdict is the first thing its report says (issue 37): a
    // top-level "verdict" is written before the other keys, which stay sorted.
    if (j.is_object() && j.contains("verdict")) {
      const auto replace = nlohmann::json::error_handler_t::replace;
      nlohmann::ordered_json first = nlohmann::ordered_json::object();
      first["verdict"] = nlohmann::ordered_json::parse(j["verdict"].dump(-1, ' ', false, replace));
      for (const auto& [key, value] : j.items())
        if (key != "verdict") first[key] = nlohmann::ordered_json::parse(value.dump(-1, ' ', false, replace));
      write_file_atomic(target, first.dump(2, ' ', false, replace) + "\n");
    } else {
      write_file_atomic(target, j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
    }
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
