// The machine-definition loader under arbitrary input: the fuzz input is the
// body of a machine{...} table, run both as a machine file (through
// bliskrun.machine.load, so in the machine host) and through
// bliskrun.machine.define in a sandboxed recipe. Every outcome must be a
// clean exit (0 or 1) with any error at a file:line — never a crash.
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "fuzz_recipe.h"

using bliskrun::fuzz::scratch;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string body(reinterpret_cast<const char*>(data), size);
  // One line, and no way out of the long bracket the recipe wraps it in.
  if (body.find('\n') != std::string::npos || body.find('\r') != std::string::npos) return 0;
  if (body.find("]==]") != std::string::npos) return 0;
  std::ofstream(scratch() + "/fuzz_machine.lua") << "return machine {" << body << "}\n";
  const std::string recipe =
      "pcall(bliskrun.machine.load, 'fuzz_machine.lua')\n"
      "local ok, t = pcall(load('return {' .. [==[" + body + "]==] .. '}', 't', 't'))\n"
      "if ok and type(t) == 'table' then pcall(bliskrun.machine.define, t) end\n"
      "local m = bliskrun.machine.load('fuzz_machine.lua')\n"
      "pcall(m.solve, m, {tip = {1, 2, 3}, axis = {0, 0.6, 0.8}}, {tool_length = 100})\n"
      "pcall(m.reachable, m, {0, 0.6, 0.8})\n";
  bliskrun::fuzz::run_recipe_or_trap(recipe);
  return 0;
}
