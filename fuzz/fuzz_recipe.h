#pragma once
// Shared by the fuzz targets that drive the recipe runner: one scratch folder
// for the whole fuzzing run, and a bounded, quiet run of a recipe in it whose
// outcome must be a clean exit (0 or 1) — anything else traps, so libFuzzer
// saves the input.
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "lua_api/runner.h"

namespace bliskrun::fuzz {

inline const std::string& scratch() {
  static const std::string dir = [] {
    char name[] = "/tmp/bliskrun_fuzz_XXXXXX";
    return std::string(mkdtemp(name));
  }();
  return dir;
}

inline void run_recipe_or_trap(const std::string& recipe) {
  lua_api::RunOptions o;
  o.recipe_path = scratch() + "/recipe.lua";
  std::ofstream(o.recipe_path) << recipe;
  o.out_dir = scratch() + "/out";
  o.quiet = true;
  o.time_limit_s = 2;
  o.memory_limit_mb = 256;
  std::ostringstream err;
  const int code = lua_api::run_recipe(o, err);
  if (code != 0 && code != 1) __builtin_trap();
}

}  // namespace bliskrun::fuzz
