// Option-table validation under arbitrary input: the fuzz input is the body
// of a Lua table constructor handed to several validated API calls inside a
// sandboxed run. Every outcome must be a clean exit (0 or 1) with any error
// positioned at the recipe line — never a crash.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "lua_api/runner.h"

namespace {

// One scratch folder for the whole fuzzing run.
const std::string& scratch() {
  static const std::string dir = [] {
    char name[] = "/tmp/bliskrun_fuzz_XXXXXX";
    return std::string(mkdtemp(name));
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string body(reinterpret_cast<const char*>(data), size);
  // Newlines in the input would move the calls' lines; keep the table on one.
  if (body.find('\n') != std::string::npos || body.find('\r') != std::string::npos) return 0;
  const std::string recipe = "local ok, t = pcall(load('return {" + std::string() + "' .. [==[" + body +
                             "]==] .. '}', 't', 't'))\n"
                             "if not ok or type(t) ~= 'table' then return end\n"
                             "pcall(bliskrun.point_grid, t)\n"
                             "pcall(bliskrun.drum_wheel, t)\n"
                             "pcall(bliskrun.design_drum_wheel, t)\n"
                             "pcall(bliskrun.flat_end_mill, t)\n";
  if (body.find("]==]") != std::string::npos) return 0;
  bliskrun::lua_api::RunOptions o;
  o.recipe_path = scratch() + "/recipe.lua";
  std::ofstream(o.recipe_path) << recipe;
  o.out_dir = scratch() + "/out";
  o.quiet = true;
  o.time_limit_s = 2;
  o.memory_limit_mb = 256;
  std::ostringstream err;
  const int code = bliskrun::lua_api::run_recipe(o, err);
  if (code != 0 && code != 1) __builtin_trap();
  return 0;
}
