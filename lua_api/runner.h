#pragma once
// Running a recipe: one sandboxed Lua state per run, with the paths and
// limits the command line gave.
#include <lua.hpp>

#include <iosfwd>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/common/progress.h"

namespace bliskrun::lua_api {

struct RunOptions {
  std::string recipe_path;
  std::string out_dir = "out";
  std::vector<std::string> data_dirs;  // --data DIR (repeatable), read-only
  std::vector<std::pair<std::string, std::string>> sets;  // --set key=value
  bool quiet = false;
  double time_limit_s = 3600;      // wall time of the whole run; 0 = none
  double memory_limit_mb = 8192;   // Lua heap of the recipe; 0 = none
  bool verify_report = false;      // --verify: print every posted program's read-back
  // Last resort of the time limit: when the run has not stopped by itself
  // 2 s after --time-limit (code that reaches no cancellation point), the
  // watchdog prints the message and ends the whole process with exit 1. The
  // bliskrun command sets it; in-process callers (tests, fuzzers) do not.
  bool hard_time_limit = false;
  // SIGINT and SIGTERM stop the run like the time limit does (the recipe
  // line raises, core loops cancel at their next point), remove the
  // temporaries of unfinished writes and exit with 128 + the signal; a
  // second signal, or a run still going 5 s after the first, ends the
  // process at once (temporaries removed too). The bliskrun command sets it.
  bool handle_signals = false;
  int threads = 2;                 // --threads: planning/simulation workers; outputs do not depend on it
  // `bliskrun RECIPE.lua --help`: run the recipe only up to its option
  // declaration (scripts/lib/recipe_options.lua), print the options on
  // stdout and exit 0; nothing is planned or written.
  bool recipe_help = false;
  // Tests only, not reachable from the command line: "FILE:LINE:N" cancels
  // the run at the N-th cancellation point (core/common/progress.h) after a
  // core call is first made from line LINE of FILE (a path's tail, e.g.
  // "recipe.lua:7", on any level of the Lua stack). The call then stops
  // part-way by an amount of work, as a time limit would stop it, whatever
  // the machine's speed; its error reads "cancelled: test cancellation after
  // N cancellation points of the call at FILE:LINE".
  std::string test_cancel_at;
};

// What a running recipe may touch, and where progress goes. One per Lua
// state, reachable from any wrapper through context(L).
struct RunContext {
  RunOptions options;
  std::string recipe_dir;  // absolute folder of the recipe
  std::string out_dir;     // absolute, created on first write
  std::vector<std::string> data_dirs;  // absolute
  Progress progress;
  // One line per NC program posted during the run: its read-back verification
  // (post.write proves every program before writing it). Printed by --verify.
  std::vector<std::string> verified_programs;
  // The job's step (bliskrun.progress_step): the whole run's one progress
  // line names it; 0 steps = no job going on.
  struct JobStep {
    long step = 0, steps = 0;
    std::string what;
    double started_s = 0;  // steady-clock seconds when step 1 began
  } job;
  bool progress_terminal = false;          // progress redrawn in place (stderr is a terminal)
  std::ostream* progress_stream = nullptr;  // where progress goes
  // A --help run: the recipe's option listing, once it has declared them.
  std::string options_help;
  bool options_declared = false;

  // Resolves a path a recipe wants to read: relative paths are tried against
  // the recipe folder then each data folder; the result must lie inside the
  // recipe, data or out folder. Raises a Lua error otherwise.
  std::string resolve_read(lua_State* L, const std::string& path) const;
  // Resolves a path a recipe wants to write: relative to the out folder, and
  // must stay inside it. Raises a Lua error otherwise.
  std::string resolve_write(lua_State* L, const std::string& path) const;
};

RunContext& context(lua_State* L);

// A Lua state for recipe work on another thread (post.write_all posts each
// program in its own): the recipe's sandbox (the same libraries, require and
// limits) without the bliskrun module, its heap counted in the run's memory
// budget, and the run's time limit raised as a Lua error by the same count
// hook. Made from the recipe's state on the recipe's thread; then used by one
// other thread only, while the recipe's state waits.
class WorkerLuaState {
 public:
  explicit WorkerLuaState(lua_State* recipe_state);
  ~WorkerLuaState();
  WorkerLuaState(const WorkerLuaState&) = delete;
  WorkerLuaState& operator=(const WorkerLuaState&) = delete;
  lua_State* get() const { return L_; }

 private:
  struct Heap;
  std::unique_ptr<Heap> heap_;
  lua_State* L_ = nullptr;
};

// Exit codes of the bliskrun command.
enum ExitCode { kExitOk = 0, kExitRecipeError = 1, kExitUsage = 2 };  // a signal: 128 + its number (SIGINT 130)

// Runs the recipe; writes errors (and, unless quiet, progress) to `err`.
int run_recipe(const RunOptions& options, std::ostream& err);

}  // namespace bliskrun::lua_api
