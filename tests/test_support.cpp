#include "test_support.h"

#include <cmath>
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

std::vector<AptMove> read_apt_moves(const std::string& path) {
  std::ifstream in(path);
  std::vector<AptMove> moves;
  std::string line;
  bool rapid = false;
  while (std::getline(in, line)) {
    if (line == "RAPID") rapid = true;
    if (line.rfind("GOTO/", 0) != 0) continue;
    std::istringstream s(line.substr(5));
    double x[6];
    char comma;
    for (int i = 0; i < 6; ++i) {
      s >> x[i];
      if (i < 5) s >> comma;
    }
    moves.push_back({Vec3(x[0], x[1], x[2]), Vec3(x[3], x[4], x[5]).normalized(), rapid});
    rapid = false;
  }
  return moves;
}

std::string shared_data_dir() {
  if (const char* env = std::getenv("BLISKRUN_SHARED_DATA"))
    if (fs::is_directory(env)) return env;
  const fs::path beside = fs::path(BLISKRUN_SOURCE_DIR) / ".." / "shared" / "data";
  return fs::is_directory(beside) ? fs::canonical(beside).string() : "";
}

::testing::AssertionResult has_run_report(const std::string& out, const std::string& pvd) {
  namespace fs = std::filesystem;
  auto slurp = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), {});
  };
  const std::string html = slurp(fs::path(out) / "report.html");
  if (html.empty()) return ::testing::AssertionFailure() << "no report.html in " << out;
  if (html.find("<table") == std::string::npos || html.find("</html>") == std::string::npos)
    return ::testing::AssertionFailure() << "report.html has no table or is cut short";
  // Issue 37: every run's page opens with its verdict, above the contents.
  const size_t verdict = html.find("<section id=\"verdict\"");
  if (verdict == std::string::npos || verdict > html.find("<nav>"))
    return ::testing::AssertionFailure() << "report.html does not open with the verdict";
  for (const char* external : {"src=\"http", "href=\"http", "src=\"//", "<script"})
    if (html.find(external) != std::string::npos)
      return ::testing::AssertionFailure() << "report.html is not self-contained: " << external;
  const std::string collection = slurp(fs::path(out) / pvd);
  if (collection.empty()) return ::testing::AssertionFailure() << "no " << pvd << " in " << out;
  int listed = 0;
  for (size_t at = collection.find("file=\""); at != std::string::npos; at = collection.find("file=\"", at + 1)) {
    const size_t begin = at + 6, end = collection.find('"', begin);
    const std::string file = collection.substr(begin, end - begin);
    if (!fs::exists(fs::path(out) / file)) return ::testing::AssertionFailure() << pvd << " lists " << file << ", absent";
    ++listed;
  }
  if (listed == 0) return ::testing::AssertionFailure() << pvd << " lists no data set";
  return ::testing::AssertionSuccess();
}

Tool flat_end_mill(double radius_mm, double corner_mm, double flute_mm, double shank_mm, double holder_mm) {
  FlatEndMillSpec s;
  s.radius_mm = radius_mm;
  s.corner_radius_mm = corner_mm;
  s.flute_length_mm = flute_mm;
  s.shank = {2 * radius_mm, shank_mm};
  if (holder_mm > 0) s.holder = {6 * radius_mm, holder_mm};
  return Tool::flat_end_mill(s);
}

Tool paper_drum_wheel() { return Tool::drum_wheel({8, 50, 4, {6, 96}, {}}); }

ToolPose tilted_pose(const Vec3& tip, double tilt_rad, double azimuth_rad) {
  return {tip, Vec3(std::sin(tilt_rad) * std::cos(azimuth_rad), std::sin(tilt_rad) * std::sin(azimuth_rad),
                    std::cos(tilt_rad))};
}

}  // namespace bliskrun::test
