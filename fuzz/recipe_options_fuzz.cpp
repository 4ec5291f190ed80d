// Option-table validation under arbitrary input: the fuzz input is the body
// of a Lua table constructor handed to several validated API calls inside a
// sandboxed run. Every outcome must be a clean exit (0 or 1) with any error
// positioned at the recipe line — never a crash.
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "fuzz_recipe.h"

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
                             "pcall(bliskrun.flat_end_mill, t)\n"
                             "pcall(bliskrun.drum_finish, t)\n"
                             "pcall(bliskrun.drum_finish_all, t)\n";
  if (body.find("]==]") != std::string::npos) return 0;
  bliskrun::fuzz::run_recipe_or_trap(recipe);
  return 0;
}
