// The whole Lua API under libFuzzer: the input picks, three bytes at a time,
// a function or method reachable from `bliskrun` (found at run time by
// tests/lua_api/api_fuzz/api_walk.lua, so new bindings are covered without
// edits) and two hostile arguments. Every run must end with exit 0 or 1; a
// crash, a sanitizer report or a hang past libFuzzer's -timeout is a finding.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "fuzz_recipe.h"
#include "lua_api/runner.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 3 * 64) size = 3 * 64;  // bounded per input: at most 64 calls
  static const char* hex = "0123456789abcdef";
  std::string plan = "p";
  for (size_t i = 0; i < size; ++i) {
    plan += hex[data[i] >> 4];
    plan += hex[data[i] & 15];
  }
  bliskrun::lua_api::RunOptions o;
  o.recipe_path = BLISKRUN_SOURCE_DIR "/tests/lua_api/api_fuzz/api_walk.lua";
  o.out_dir = bliskrun::fuzz::scratch() + "/out";
  o.quiet = true;
  o.time_limit_s = 5;
  o.memory_limit_mb = 512;
  o.sets = {{"plan", plan}};
  std::ostringstream err;
  const int code = bliskrun::lua_api::run_recipe(o, err);
  if (code != 0 && code != 1) __builtin_trap();
  return 0;
}
