// luax::guarded and luax::error on a bare Lua state, without the runner: the
// properties every wrapper relies on.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "core/common/error.h"
#include "lua_api/luax.h"

namespace bliskrun {
namespace {

// Counts destructions of objects living in a wrapper's C++ frame.
int g_destroyed = 0;
struct Sentinel {
  ~Sentinel() { ++g_destroyed; }
};

// A wrapper whose body raises a *Lua* error (luaL_error) while a C++ object
// is alive in its frame. With Lua's C++ build the error is a C++ exception
// (lua_longjmp*), which guarded must let pass, and the unwinding must run
// the destructor.
int w_lua_error_through_frame(lua_State* L) {
  return luax::guarded(L, [&] {
    Sentinel alive;
    luaL_error(L, "raised by Lua inside the wrapper");
    return 0;
  });
}

// A wrapper whose core call throws a C++ error: guarded turns it into a Lua
// error at the recipe line.
int w_core_error(lua_State* L) {
  return luax::guarded(L, [&]() -> int {
    Sentinel alive;
    throw ParameterError("blade_height", "must be positive, got -3");
  });
}

// Anything that is not a std::exception is not guarded's business.
int w_foreign_exception(lua_State* L) {
  return luax::guarded(L, []() -> int { throw 42; });
}

class LuaxGuarded : public ::testing::Test {
 protected:
  void SetUp() override {
    g_destroyed = 0;
    L = luaL_newstate();
    luaL_openlibs(L);
    lua_register(L, "lua_error_through_frame", w_lua_error_through_frame);
    lua_register(L, "core_error", w_core_error);
  }
  void TearDown() override { lua_close(L); }

  // Runs `code` as chunk "@recipe.lua"; returns the error message or "".
  std::string run(const std::string& code) {
    if (luaL_loadbufferx(L, code.data(), code.size(), "@recipe.lua", "t") != LUA_OK)
      return std::string("syntax: ") + lua_tostring(L, -1);
    if (lua_pcall(L, 0, 0, 0) == LUA_OK) return "";
    std::string message = lua_tostring(L, -1) ? lua_tostring(L, -1) : "(non-string error)";
    lua_pop(L, 1);
    return message;
  }

  lua_State* L = nullptr;
};

TEST_F(LuaxGuarded, DestructorInWrapperFrameRunsWhenLuaErrorPassesThrough) {
  const std::string message = run("local x = 1\nlua_error_through_frame()\n");
  EXPECT_EQ(g_destroyed, 1) << "the Lua error skipped a C++ destructor";
  // The message is Lua's own, unchanged: guarded did not catch and re-wrap it.
  EXPECT_EQ(message, "recipe.lua:2: raised by Lua inside the wrapper");
}

TEST_F(LuaxGuarded, LuaErrorThroughFrameCanBeCaughtByPcallInTheRecipe) {
  const std::string message = run(
      "local ok, err = pcall(lua_error_through_frame)\n"
      "assert(not ok and err:find('raised by Lua', 1, true), err)\n"
      "lua_error_through_frame()\n");
  EXPECT_EQ(g_destroyed, 2);
  EXPECT_EQ(message, "recipe.lua:3: raised by Lua inside the wrapper");
}

TEST_F(LuaxGuarded, CoreErrorBecomesLuaErrorAtTheRecipeLine) {
  const std::string message = run("\n\ncore_error()\n");
  EXPECT_EQ(g_destroyed, 1);
  EXPECT_EQ(message, "recipe.lua:3: blade_height: must be positive, got -3");
}

TEST_F(LuaxGuarded, NonStandardExceptionIsNotSwallowed) {
  lua_pushcfunction(L, w_foreign_exception);
  // Called without a protected call of Lua's: the int escapes to us intact
  // rather than being reported as some Lua error.
  EXPECT_THROW(lua_call(L, 0, 0), int);
}

}  // namespace
}  // namespace bliskrun
