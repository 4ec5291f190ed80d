#include "test_support.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "lua_api/runner.h"

namespace bliskrun::test {

namespace fs = std::filesystem;

TempDir::TempDir() {
  std::random_device rd;
  for (int attempt = 0; attempt < 100; ++attempt) {
    const fs::path p = fs::temp_directory_path() / ("bliskrun_test_" + std::to_string(rd()));
    if (fs::create_directory(p)) {
      path_ = fs::canonical(p).string();
      return;
    }
  }
  throw std::runtime_error("cannot create a temporary folder");
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

std::string TempDir::write(const std::string& name, const std::string& contents) const {
  const fs::path p = fs::path(path_) / name;
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << contents;
  return p.string();
}

RecipeResult run_recipe_text(const TempDir& dir, const std::string& lua, bool quiet, double time_limit_s,
                             double memory_limit_mb) {
  lua_api::RunOptions o;
  o.recipe_path = dir.write("recipe.lua", lua);
  o.out_dir = dir.path() + "/out";
  o.quiet = quiet;
  o.time_limit_s = time_limit_s;
  o.memory_limit_mb = memory_limit_mb;
  std::ostringstream err;
  RecipeResult r;
  r.exit_code = lua_api::run_recipe(o, err);
  r.output = err.str();
  return r;
}

::testing::AssertionResult fails_at_line_2(const TempDir& dir, const RecipeErrorCase& c) {
  const RecipeResult r = run_recipe_text(dir, std::string("-- line 1\n") + c.call + "\n");
  if (r.exit_code != 1)
    return ::testing::AssertionFailure() << "exit code " << r.exit_code << ", expected 1:\n" << r.output;
  if (r.output.find("recipe.lua:2:") == std::string::npos)
    return ::testing::AssertionFailure() << "message does not name recipe.lua:2:\n" << r.output;
  if (r.output.find(c.expected) == std::string::npos)
    return ::testing::AssertionFailure() << "message lacks '" << c.expected << "':\n" << r.output;
  return ::testing::AssertionSuccess();
}

RecipeResult run_bliskrun(const std::vector<std::string>& args) {
  std::string cmd = BLISKRUN_EXE;
  for (const auto& a : args) {
    std::string quoted = "'";
    for (char c : a) quoted += (c == '\'') ? std::string("'\\''") : std::string(1, c);
    cmd += " " + quoted + "'";
  }
  cmd += " 2>&1";
  RecipeResult r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) r.output.append(buf, n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string shared_data_dir() {
  if (const char* env = std::getenv("BLISKRUN_SHARED_DATA"))
    if (fs::is_directory(env)) return env;
  const fs::path beside = fs::path(BLISKRUN_SOURCE_DIR) / ".." / "shared" / "data";
  return fs::is_directory(beside) ? fs::canonical(beside).string() : "";
}

}  // namespace bliskrun::test
