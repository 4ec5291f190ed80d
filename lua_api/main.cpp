// bliskrun RECIPE.lua [options]: runs a recipe. See README.md and
// docs/lua_api.md.
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <string>

#include "lua_api/runner.h"

namespace {

const char* const kUsage =
    "usage: bliskrun RECIPE.lua [--out DIR] [--data DIR]... [--set KEY=VALUE]...\n"
    "                [--quiet] [--verify] [--time-limit SECONDS] [--memory-limit MB]\n"
    "                [--threads N]\n"
    "\n"
    "  --out DIR            folder the recipe writes to (default: out)\n"
    "  --data DIR           folder of part data the recipe may read (repeatable;\n"
    "                       default: $BLISKRUN_DATA if set)\n"
    "  --set KEY=VALUE      value for the recipe as args.KEY (numbers and\n"
    "                       true/false are converted)\n"
    "  --quiet              no progress on stderr\n"
    "  --time-limit S       stop the run after S seconds of wall time (default 3600, 0 = none)\n"
    "  --memory-limit MB    limit the run's memory, Lua and core heap (default 8192, 0 = none)\n"
    "  --threads N          worker threads for planning and simulation (default 2;\n"
    "                       outputs do not depend on it)\n"
    "  --verify             after the run, print the read-back verification of every\n"
    "                       NC program the recipe posted (each is replayed through the\n"
    "                       machine's kinematics before it is written)\n"
    "  --help               with a recipe: list the options it declares (name, type,\n"
    "                       unit, default, range) and exit without planning\n"
    "  --version\n"
    "\n"
    "exit codes: 0 ok, 1 recipe or data error, 2 usage error, 130/143 stopped by\n"
    "SIGINT/SIGTERM (unfinished files removed)\n";

int usage_error(const std::string& message) {
  std::cerr << "bliskrun: " << message << "\n" << kUsage;
  return bliskrun::lua_api::kExitUsage;
}

bool parse_number(const std::string& text, double& out) {
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return !text.empty() && end && *end == '\0' && out >= 0;
}

}  // namespace

int main(int argc, char** argv) {
  bliskrun::lua_api::RunOptions options;
  if (const char* data = std::getenv("BLISKRUN_DATA")) options.data_dirs.push_back(data);
  bool explicit_data = false;
  bool help = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](const char* flag) -> const char* {
      if (i + 1 >= argc) return nullptr;
      (void)flag;
      return argv[++i];
    };
    if (arg == "--help" || arg == "-h") {
      help = true;  // with a recipe: its options; without: this usage
    } else if (arg == "--version") {
      std::cout << "bliskrun 0.1.0\n";
      return 0;
    } else if (arg == "--verify") {
      options.verify_report = true;
    } else if (arg == "--quiet" || arg == "-q") {
      options.quiet = true;
    } else if (arg == "--out") {
      const char* v = value("--out");
      if (!v) return usage_error("--out needs a folder");
      options.out_dir = v;
    } else if (arg == "--data") {
      const char* v = value("--data");
      if (!v) return usage_error("--data needs a folder");
      if (!explicit_data) options.data_dirs.clear();  // the command line wins over $BLISKRUN_DATA
      explicit_data = true;
      options.data_dirs.push_back(v);
    } else if (arg == "--set") {
      const char* v = value("--set");
      const std::string kv = v ? v : "";
      const auto eq = kv.find('=');
      if (eq == std::string::npos || eq == 0) return usage_error("--set needs KEY=VALUE, got '" + kv + "'");
      options.sets.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
    } else if (arg == "--time-limit" || arg == "--memory-limit") {
      const char* v = value(arg.c_str());
      double x = 0;
      if (!v || !parse_number(v, x)) return usage_error(arg + " needs a non-negative number");
      (arg == "--time-limit" ? options.time_limit_s : options.memory_limit_mb) = x;
    } else if (arg == "--threads") {
      const char* v = value("--threads");
      double x = 0;
      if (!v || !parse_number(v, x) || x < 1 || x > 256 || x != static_cast<int>(x))
        return usage_error("--threads needs a whole number from 1 to 256");
      options.threads = static_cast<int>(x);
    } else if (!arg.empty() && arg[0] == '-') {
      return usage_error("unknown option '" + arg + "'");
    } else if (options.recipe_path.empty()) {
      options.recipe_path = arg;
    } else {
      return usage_error("more than one recipe given ('" + options.recipe_path + "' and '" + arg + "')");
    }
  }
  if (help && options.recipe_path.empty()) {
    std::cout << kUsage;
    return 0;
  }
  if (options.recipe_path.empty()) return usage_error("no recipe given");
  options.recipe_help = help;
  options.hard_time_limit = true;
  options.handle_signals = true;
  // A file-size limit (ulimit -f) then fails the write with EFBIG, reported
  // as a clean error naming the file, instead of killing the process.
  std::signal(SIGXFSZ, SIG_IGN);
  return bliskrun::lua_api::run_recipe(options, std::cerr);
}
