#include "lua_api/runner.h"

#include <memory>

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <condition_variable>
#include <filesystem>
#include <functional>
#include <iostream>
#include <mutex>
#include <regex>
#include <sstream>
#include <thread>

#include "core/common/atomic_file.h"
#include "core/common/cancel_after.h"
#include "core/common/error.h"
#include "core/common/memory_budget.h"
#include "lua_api/luax.h"
#include "lua_api/modules.h"

namespace bliskrun::lua_api {

namespace fs = std::filesystem;

namespace {

const char* const kContextKey = "bliskrun.context";
const char* const kModulesKey = "bliskrun.modules";  // require's cache

// ---- paths ---------------------------------------------------------------------

std::string canonical(const std::string& path) { return fs::weakly_canonical(fs::absolute(path)).string(); }

bool inside(const std::string& path, const std::string& root) {
  const fs::path p(path), r(root);
  auto pi = p.begin();
  for (auto ri = r.begin(); ri != r.end(); ++ri, ++pi) {
    if (ri->empty()) continue;  // trailing separator
    if (pi == p.end() || *pi != *ri) return false;
  }
  return true;
}

std::string scripts_dir() {
  if (const char* env = std::getenv("BLISKRUN_SCRIPTS")) return canonical(env);
  return canonical(BLISKRUN_SCRIPTS_DIR);
}

// ---- memory limit: a counting allocator ------------------------------------------

// The Lua heap counts into the run's memory budget (core/common/memory_budget.h)
// together with the C++ heap, so --memory-limit bounds both at once.
struct Allocator {
  size_t used = 0;         // the Lua heap
  bool exceeded = false;   // a Lua allocation was refused for the budget
};

void* limited_alloc(void* ud, void* ptr, size_t old_size, size_t new_size) {
  auto* a = static_cast<Allocator*>(ud);
  if (ptr == nullptr) old_size = 0;  // old_size then encodes the object type
  if (new_size == 0) {
    std::free(ptr);
    a->used -= old_size;
    release_memory(old_size);
    return nullptr;
  }
  if (new_size > old_size && !reserve_memory(new_size - old_size)) {
    a->exceeded = true;
    return nullptr;  // Lua raises "not enough memory"
  }
  void* p = std::realloc(ptr, new_size);
  if (!p) {
    if (new_size > old_size) release_memory(new_size - old_size);
    return nullptr;
  }
  if (new_size < old_size) release_memory(old_size - new_size);
  a->used = a->used - old_size + new_size;
  return p;
}

// ---- time limit ----------------------------------------------------------------------

// Watches the wall clock from its own thread so that long core loops (which
// run no Lua) are cancelled too; the Lua hook turns the same deadline into a
// Lua error at the recipe line. That cooperative path is the normal one, but
// it cannot stop code that reaches neither a hook nor a cancellation point (a
// pathological string.find inside Lua's C library, FCL, a third-party call):
// with a hard stop, once the limit plus kHardStopGrace has passed the
// watchdog itself prints the message (with the last recipe line the hook
// saw), removes unfinished temporary files and ends the process with exit 1.
// Atomic writes guarantee that no output is half-written.
class Watchdog {
 public:
  static constexpr double kHardStopGrace = 2.0;  // seconds after the limit
  using HardStop = std::function<void(const std::string& message)>;

  Watchdog(Progress& progress, double seconds, HardStop hard_stop = {})
      : progress_(progress), hard_stop_(std::move(hard_stop)) {
    clear_cancel_all();
    if (seconds <= 0) return;
    auto after = [](double s) {
      return std::chrono::steady_clock::now() +
             std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(s));
    };
    deadline_ = after(seconds);
    seconds_ = seconds;
    thread_ = std::thread([this, after] {
      std::unique_lock<std::mutex> lock(mutex_);
      if (cv_.wait_until(lock, deadline_, [this] { return done_; })) return;
      expired_ = true;
      progress_.cancel(message());
      request_cancel_all(message());  // loops that take no Progress
      if (!hard_stop_) return;
      if (cv_.wait_until(lock, after(kHardStopGrace), [this] { return done_; })) return;
      hard_stop_(message());
    });
  }
  ~Watchdog() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
    clear_cancel_all();  // the next run in this process starts clean
  }
  bool expired() const { return expired_.load(); }
  // Stops the run now, for `reason` (a signal), as the deadline would.
  void interrupt(const std::string& reason) {
    {
      std::lock_guard<std::mutex> lock(reason_mutex_);
      if (reason_.empty()) reason_ = reason;
    }
    expired_ = true;
    progress_.cancel(reason);
    request_cancel_all(reason);
  }
  std::string message() const {
    {
      std::lock_guard<std::mutex> lock(reason_mutex_);
      if (!reason_.empty()) return reason_;
    }
    std::ostringstream s;
    s << "time limit of " << seconds_ << " s exceeded (--time-limit)";
    return s.str();
  }

 private:
  Progress& progress_;
  HardStop hard_stop_;
  std::chrono::steady_clock::time_point deadline_;
  double seconds_ = 0;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool done_ = false;
  std::atomic<bool> expired_{false};
  mutable std::mutex reason_mutex_;  // not mutex_: the thread holds that while it calls message()
  std::string reason_;               // an interrupt's, which message() reports instead of the limit
};

// SIGINT and SIGTERM, taken synchronously by a thread of their own (no
// async-signal-safety to worry about): the first interrupts the run through
// the watchdog's cooperative path; a second one, or a run not stopped
// within kGrace, ends the process at once through `hard_stop`. The signals
// are blocked in the calling thread before any other thread of the run is
// started (the watchdog, the workers), so that every thread inherits the
// mask and only this one receives them.
class SignalStop {
 public:
  static constexpr double kGrace = 5.0;  // seconds: generous for a loaded machine
  using HardStop = std::function<void(int signal)>;

  // Blocks the signals; watch() starts taking them.
  explicit SignalStop(bool enabled) : enabled_(enabled) {
    sigemptyset(&set_);
    sigaddset(&set_, SIGINT);
    sigaddset(&set_, SIGTERM);
    if (enabled_) pthread_sigmask(SIG_BLOCK, &set_, &old_mask_);
  }
  void watch(Watchdog& watchdog, HardStop hard_stop) {
    if (!enabled_) return;
    thread_ = std::thread([this, &watchdog, hard_stop = std::move(hard_stop)] {
      std::chrono::steady_clock::time_point deadline{};
      while (!done_.load()) {
        const timespec poll{0, 50 * 1000 * 1000};  // 50 ms: how soon the run's end is seen
        const int sig = sigtimedwait(&set_, nullptr, &poll);
        if (sig > 0) {
          if (signal_.load() != 0) hard_stop(signal_.load());  // a second signal: now
          signal_ = sig;
          watchdog.interrupt(std::string("interrupted by ") + (sig == SIGINT ? "SIGINT" : "SIGTERM"));
          deadline = std::chrono::steady_clock::now() +
                     std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                         std::chrono::duration<double>(kGrace));
        }
        if (signal_.load() != 0 && !done_.load() && std::chrono::steady_clock::now() > deadline)
          hard_stop(signal_.load());
      }
    });
  }
  // Called when the run has stopped: no hard stop after this.
  void finish() {
    done_ = true;
    if (thread_.joinable()) thread_.join();
  }
  ~SignalStop() {
    finish();
    if (enabled_) pthread_sigmask(SIG_SETMASK, &old_mask_, nullptr);
  }
  int signal() const { return signal_.load(); }

 private:
  bool enabled_;
  sigset_t set_{}, old_mask_{};
  std::thread thread_;
  std::atomic<bool> done_{false};
  std::atomic<int> signal_{0};
};

// RunOptions::test_cancel_at, parsed; armed at most once per run.
struct TestCancel {
  std::string at;     // "recipe.lua:7"; empty = none
  long points = 0;
  bool armed = false;
};

struct RunState {
  RunContext* context;
  Allocator* allocator;
  Watchdog* watchdog;
  TestCancel test_cancel;
  // "recipe.lua:12", refreshed by the count hook; read by the watchdog's
  // hard stop from its own thread, hence the mutex.
  std::string last_position;
  std::mutex position_mutex;

  std::string position() {
    std::lock_guard<std::mutex> lock(position_mutex);
    return last_position;
  }
};

RunState& state(lua_State* L) {
  lua_getfield(L, LUA_REGISTRYINDEX, kContextKey);
  auto* s = static_cast<RunState*>(lua_touserdata(L, -1));
  lua_pop(L, 1);
  return *s;
}

// Every few thousand instructions: remember where the recipe is (a memory
// error unwinds the stack before it can be reported) and stop at the deadline.
// Remembers the innermost Lua line on the stack as the run's position.
void record_position(lua_State* L, RunState& s) {
  lua_Debug ar;
  for (int level = 0; lua_getstack(L, level, &ar); ++level) {
    lua_getinfo(L, "Sl", &ar);
    if (ar.currentline > 0) {
      std::string at = std::string(ar.short_src) + ":" + std::to_string(ar.currentline);
      std::lock_guard<std::mutex> lock(s.position_mutex);
      s.last_position = std::move(at);
      return;
    }
  }
}

// Whether some level of L's stack is at `at` ("recipe.lua:7"): a frame's
// "source:line" ends with it, after a folder separator or nothing.
bool stack_is_at(lua_State* L, const std::string& at) {
  lua_Debug ar;
  for (int level = 0; lua_getstack(L, level, &ar); ++level) {
    lua_getinfo(L, "Sl", &ar);
    if (ar.currentline <= 0) continue;
    const std::string here = std::string(ar.short_src) + ":" + std::to_string(ar.currentline);
    if (here.size() < at.size() || here.compare(here.size() - at.size(), at.size(), at) != 0) continue;
    if (here.size() == at.size() || here[here.size() - at.size() - 1] == '/') return true;
  }
  return false;
}

// Before each core call (luax::guarded): the line that made it, so that the
// watchdog's last resort can name it even when no hook ran in between; and
// the test cancellation, armed by the first call from its line.
void observe_call(lua_State* L) {
  lua_getfield(L, LUA_REGISTRYINDEX, kContextKey);
  auto* s = static_cast<RunState*>(lua_touserdata(L, -1));
  lua_pop(L, 1);
  if (!s) return;
  // A --help run that reaches the core before the recipe declared its
  // options would plan: the recipe reads args itself, so it cannot say.
  if (s->context->options.recipe_help)
    luax::error(L, "this recipe declares no options (scripts/lib/recipe_options.lua), so --help cannot list "
                   "them without running it; read its header for the --set values it takes");
  record_position(L, *s);
  // A stopped run (a signal, the time limit) makes no further core call:
  // a loop of short calls (writes) may run few Lua instructions between
  // them, so the count hook alone would see the stop late.
  if (s->watchdog && s->watchdog->expired()) luax::error(L, s->watchdog->message());
  TestCancel& t = s->test_cancel;
  if (!t.at.empty() && !t.armed && stack_is_at(L, t.at)) {
    t.armed = true;
    request_cancel_all_after(t.points, "test cancellation after " + std::to_string(t.points) +
                                           " cancellation points of the call at " + t.at);
  }
}

void count_hook(lua_State* L, lua_Debug*) {
  RunState& s = state(L);
  record_position(L, s);
  if (s.watchdog->expired()) {
    // luaL_where cannot see the recipe line from inside a hook: name it here.
    const std::string at = s.position();
    lua_pushfstring(L, "%s%s%s", at.c_str(), at.empty() ? "" : ": ", s.watchdog->message().c_str());
    lua_error(L);
  }
}

// ---- the sandbox ---------------------------------------------------------------------

// load(chunk [, name [, mode [, env]]]) restricted to text chunks.
int sandboxed_load(lua_State* L) {
  const int top = lua_gettop(L);
  if (top >= 3 && !lua_isnil(L, 3)) {
    const char* mode = luaL_checkstring(L, 3);
    if (std::string(mode) != "t") return luaL_error(L, "load: only text chunks (mode 't') are allowed in a recipe");
  }
  size_t len = 0;
  const char* chunk = lua_tolstring(L, 1, &len);
  if (!chunk) return luaL_error(L, "load: expected a string chunk (functions and binary chunks are not allowed)");
  const char* name = luaL_optstring(L, 2, "=(load)");
  if (luaL_loadbufferx(L, chunk, len, name, "t") != LUA_OK) {
    lua_pushnil(L);
    lua_insert(L, -2);
    return 2;  // nil, message
  }
  if (top >= 4) {
    lua_pushvalue(L, 4);
    if (!lua_setupvalue(L, -2, 1)) lua_pop(L, 1);
  }
  return 1;
}

int sandboxed_collectgarbage(lua_State* L) {
  const std::string opt = luaL_optstring(L, 1, "collect");
  if (opt == "count") {
    const int kb = lua_gc(L, LUA_GCCOUNT, 0), b = lua_gc(L, LUA_GCCOUNTB, 0);
    lua_pushnumber(L, kb + b / 1024.0);
    return 1;
  }
  if (opt == "collect") {
    lua_gc(L, LUA_GCCOLLECT, 0);
    lua_pushinteger(L, 0);
    return 1;
  }
  if (opt == "step") {
    lua_pushboolean(L, lua_gc(L, LUA_GCSTEP, 0));
    return 1;
  }
  return luaL_error(L, "collectgarbage: option '%s' is not allowed in a recipe (allowed: collect, count, step)",
                    opt.c_str());
}

// require(name): Lua modules only, from the recipe's folder or scripts/lib.
int sandboxed_require(lua_State* L) {
  const std::string name = luaL_checkstring(L, 1);
  static const std::regex valid("[A-Za-z_][A-Za-z0-9_]*(\\.[A-Za-z_][A-Za-z0-9_]*)*");
  if (!std::regex_match(name, valid))
    return luaL_error(L, "require: '%s' is not a module name (letters, digits, _ and dots)", name.c_str());
  lua_getfield(L, LUA_REGISTRYINDEX, kModulesKey);
  lua_getfield(L, -1, name.c_str());
  if (!lua_isnil(L, -1)) return 1;
  lua_pop(L, 1);
  std::string rel = name;
  std::replace(rel.begin(), rel.end(), '.', '/');
  rel += ".lua";
  const RunContext& ctx = context(L);
  std::string found;
  std::string tried;
  for (const std::string& dir : {ctx.recipe_dir, scripts_dir() + "/lib"}) {
    const std::string candidate = dir + "/" + rel;
    tried += "\n\t" + candidate;
    if (fs::is_regular_file(candidate)) {
      found = candidate;
      break;
    }
  }
  if (found.empty())
    return luaL_error(L, "require: module '%s' not found (only Lua modules in the recipe's folder and scripts/lib); tried:%s",
                      name.c_str(), tried.c_str());
  if (luaL_loadfilex(L, found.c_str(), "t") != LUA_OK) return lua_error(L);
  lua_pushstring(L, name.c_str());
  lua_call(L, 1, 1);
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    lua_pushboolean(L, 1);
  }
  lua_pushvalue(L, -1);
  lua_setfield(L, -3, name.c_str());
  return 1;
}

void open_sandbox(lua_State* L) {
  static const luaL_Reg libs[] = {{LUA_GNAME, luaopen_base},          {LUA_TABLIBNAME, luaopen_table},
                                  {LUA_STRLIBNAME, luaopen_string},   {LUA_MATHLIBNAME, luaopen_math},
                                  {LUA_UTF8LIBNAME, luaopen_utf8},    {LUA_COLIBNAME, luaopen_coroutine},
                                  {LUA_OSLIBNAME, luaopen_os},        {nullptr, nullptr}};
  for (const luaL_Reg* lib = libs; lib->func; ++lib) {
    luaL_requiref(L, lib->name, lib->func, 1);
    lua_pop(L, 1);
  }
  // Base library: no file loading, text-only load, limited collectgarbage.
  for (const char* name : {"dofile", "loadfile"}) {
    lua_pushnil(L);
    lua_setglobal(L, name);
  }
  lua_pushcfunction(L, sandboxed_load);
  lua_setglobal(L, "load");
  lua_pushcfunction(L, sandboxed_collectgarbage);
  lua_setglobal(L, "collectgarbage");
  lua_pushcfunction(L, sandboxed_require);
  lua_setglobal(L, "require");
  // string.dump would hand out bytecode, which load refuses anyway.
  lua_getglobal(L, LUA_STRLIBNAME);
  lua_pushnil(L);
  lua_setfield(L, -2, "dump");
  lua_pop(L, 1);
  // os: only the clock and calendar.
  lua_getglobal(L, LUA_OSLIBNAME);
  lua_newtable(L);
  for (const char* keep : {"clock", "time", "date", "difftime"}) {
    lua_getfield(L, -2, keep);
    lua_setfield(L, -2, keep);
  }
  lua_setglobal(L, LUA_OSLIBNAME);
  lua_pop(L, 1);
  // Remembered modules live in the registry, out of the recipe's reach.
  lua_newtable(L);
  lua_setfield(L, LUA_REGISTRYINDEX, kModulesKey);
}

void push_args(lua_State* L, const std::vector<std::pair<std::string, std::string>>& sets) {
  lua_newtable(L);
  for (const auto& [key, value] : sets) {
    if (value == "true" || value == "false") {
      lua_pushboolean(L, value == "true");
    } else {
      char* end = nullptr;
      const double x = std::strtod(value.c_str(), &end);
      if (!value.empty() && end && *end == '\0' && std::isfinite(x)) {
        if (x == std::floor(x) && std::abs(x) < 9e15) lua_pushinteger(L, static_cast<lua_Integer>(x));
        else lua_pushnumber(L, x);
      } else {
        lua_pushlstring(L, value.data(), value.size());
      }
    }
    lua_setfield(L, -2, key.c_str());
  }
  lua_setglobal(L, "args");
}

// bliskrun.options_help(text): in a `--help` run, remembers the recipe's
// option listing and ends the run (before anything is planned); in any
// other run does nothing. Called by scripts/lib/recipe_options.lua.
const char* const kHelpDone = "bliskrun.help_done";  // the error that ends a --help run

int options_help(lua_State* L) {
  const char* text = luaL_checkstring(L, 1);
  RunContext& ctx = *state(L).context;
  ctx.options_declared = true;
  if (!ctx.options.recipe_help) return 0;
  ctx.options_help = text;
  lua_pushlightuserdata(L, const_cast<char*>(kHelpDone));
  return lua_error(L);
}

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// "1m05s" / "42s": durations a person reads at a glance.
std::string duration_text(double s) {
  char text[32];
  const long whole = std::lround(std::max(0.0, s));
  if (whole >= 60) std::snprintf(text, sizeof text, "%ldm%02lds", whole / 60, whole % 60);
  else std::snprintf(text, sizeof text, "%lds", whole);
  return text;
}

// The run's one progress line while a job goes on: step k of n and what it
// does, the running core task's percent, elapsed, and the remaining time
// estimated from the steps done so far (each step counted as one unit; the
// running one by its task's fraction).
std::string job_line(const RunContext::JobStep& job, const std::string& task, double task_fraction) {
  const double elapsed = now_s() - job.started_s;
  const double done = static_cast<double>(job.step - 1) + std::clamp(task_fraction, 0.0, 1.0);
  std::ostringstream line;
  line << "[step " << job.step << "/" << job.steps << "] " << job.what;
  if (!task.empty()) line << " - " << task << " " << static_cast<int>(task_fraction * 100) << "%";
  line << "  elapsed " << duration_text(elapsed);
  if (done > 0) line << "  remaining ~" << duration_text(elapsed * (job.steps - done) / done);
  return line.str();
}

// bliskrun.progress_step(k, n, what): the run is at step k of n of a job,
// doing `what` ("plan drum_finish: blade 1 pressure, suction"); while a job
// goes on, the run's progress is one line naming the step instead of one
// per core task. bliskrun.progress_step() ends the job.
int progress_step(lua_State* L) {
  RunContext& ctx = *state(L).context;
  RunContext::JobStep& job = ctx.job;
  const bool terminal = ctx.progress_terminal;
  std::ostream& err = *ctx.progress_stream;
  if (lua_gettop(L) == 0) {
    if (job.steps > 0 && !ctx.options.quiet)
      err << (terminal ? "\r\x1b[K" : "") << "[job] " << job.steps << " steps done in "
          << duration_text(now_s() - job.started_s) << "\n" << std::flush;
    job = RunContext::JobStep{};
    return 0;
  }
  const lua_Integer k = luaL_checkinteger(L, 1), n = luaL_checkinteger(L, 2);
  const char* what = luaL_checkstring(L, 3);
  if (n < 1 || k < 1 || k > n) return luaL_error(L, "progress_step: expected 1 <= step <= steps, got %d of %d",
                                                 static_cast<int>(k), static_cast<int>(n));
  if (job.steps == 0 || k == 1) job.started_s = now_s();
  job.step = k;
  job.steps = n;
  job.what = what;
  if (!ctx.options.quiet)
    err << (terminal ? "\r" : "") << job_line(job, "", 0) << (terminal ? "\x1b[K" : "\n") << std::flush;
  return 0;
}

// Error handler: the message plus the recipe frames of the traceback.
int traceback(lua_State* L) {
  const char* msg = lua_tostring(L, 1);
  if (!msg) msg = luaL_typename(L, 1);
  luaL_traceback(L, L, nullptr, 1);
  std::istringstream lines(lua_tostring(L, -1));
  std::string out = msg, line;
  bool any = false;
  while (std::getline(lines, line)) {
    if (line.find(".lua:") == std::string::npos) continue;
    out += (any ? "\n" : "\nrecipe traceback:\n") + line;
    any = true;
  }
  lua_pushstring(L, out.c_str());
  return 1;
}

}  // namespace

// ---- RunContext --------------------------------------------------------------------------

RunContext& context(lua_State* L) { return *state(L).context; }

std::string RunContext::resolve_read(lua_State* L, const std::string& path) const {
  std::vector<std::string> candidates;
  if (fs::path(path).is_absolute()) {
    candidates.push_back(path);
  } else {
    candidates.push_back(recipe_dir + "/" + path);
    for (const auto& d : data_dirs) candidates.push_back(d + "/" + path);
    candidates.push_back(out_dir + "/" + path);
  }
  std::vector<std::string> roots = {recipe_dir, out_dir};
  roots.insert(roots.end(), data_dirs.begin(), data_dirs.end());
  std::string first_allowed;
  for (const auto& c : candidates) {
    const std::string abs = canonical(c);
    bool allowed = false;
    for (const auto& r : roots) allowed = allowed || inside(abs, r);
    if (!allowed) continue;
    if (first_allowed.empty()) first_allowed = abs;
    if (fs::exists(abs)) return abs;
  }
  std::string where;
  for (const auto& r : roots) where += "\n\t" + r;
  if (first_allowed.empty())
    luax::error(L, "'" + path + "' is outside the folders a recipe may read:" + where);
  luax::error(L, "cannot find '" + path + "' in the folders a recipe may read:" + where);
}

std::string RunContext::resolve_write(lua_State* L, const std::string& path) const {
  const std::string abs = canonical(fs::path(path).is_absolute() ? path : out_dir + "/" + path);
  if (!inside(abs, out_dir) || abs == out_dir)
    luax::error(L, "'" + path + "' is outside the out folder " + out_dir + " (recipes write only there)");
  return abs;
}

// ---- worker states -------------------------------------------------------------------------

struct WorkerLuaState::Heap {
  Allocator allocator;  // this state's own count; the budget is the run's
};

WorkerLuaState::WorkerLuaState(lua_State* recipe_state) : heap_(std::make_unique<Heap>()) {
  RunState& run = state(recipe_state);
  L_ = lua_newstate(limited_alloc, &heap_->allocator);
  if (!L_) throw std::bad_alloc();
  // The recipe's RunState: require reads its folders; the count hook records
  // the position under its mutex and reads the watchdog's atomic flag, so a
  // post line can be named by a time-limit stop. Protected: the budget may
  // refuse the libraries' memory.
  lua_pushcfunction(L_, [](lua_State* S) {
    lua_pushvalue(S, 1);
    lua_setfield(S, LUA_REGISTRYINDEX, kContextKey);
    open_sandbox(S);
    return 0;
  });
  lua_pushlightuserdata(L_, &run);
  if (lua_pcall(L_, 1, 0, 0) != LUA_OK) {
    const std::string message = lua_tostring(L_, -1) ? lua_tostring(L_, -1) : "cannot open a worker's Lua state";
    lua_close(L_);
    L_ = nullptr;
    throw Error(message);
  }
  lua_sethook(L_, count_hook, LUA_MASKCOUNT, 10000);
}

WorkerLuaState::~WorkerLuaState() {
  if (L_) lua_close(L_);
}

// ---- running -------------------------------------------------------------------------------

int run_recipe(const RunOptions& options, std::ostream& err) {
  RunContext ctx;
  ctx.options = options;
  std::error_code ec;
  if (!fs::is_regular_file(options.recipe_path, ec)) {
    err << "bliskrun: cannot read recipe '" << options.recipe_path << "'\n";
    return kExitUsage;
  }
  ctx.recipe_dir = canonical(fs::path(options.recipe_path).parent_path().empty()
                                 ? "."
                                 : fs::path(options.recipe_path).parent_path().string());
  ctx.out_dir = canonical(options.out_dir.empty() ? "out" : options.out_dir);
  for (const auto& d : options.data_dirs) {
    if (!fs::is_directory(d, ec)) {
      err << "bliskrun: data folder '" << d << "' does not exist\n";
      return kExitUsage;
    }
    ctx.data_dirs.push_back(canonical(d));
  }
  const bool quiet = options.quiet;
  // On a terminal, one bar redrawn in place (percent, elapsed, remaining);
  // otherwise (CI logs, pipes, tests) plain lines at 0, 25, 50, 75, 100 %.
  const bool terminal = &err == &std::cerr && isatty(STDERR_FILENO);
  auto task_start = std::make_shared<std::chrono::steady_clock::time_point>(std::chrono::steady_clock::now());
  ctx.progress_terminal = terminal;
  ctx.progress_stream = &err;
  RunContext* job_ctx = &ctx;
  ctx.progress.set_reporter([&err, quiet, terminal, task_start, job_ctx](const std::string& task, long done,
                                                                          long total) {
    if (quiet || total <= 0) return;
    const RunContext::JobStep& job = job_ctx->job;
    if (job.steps > 0) {
      // Within a job: its one line, redrawn on a terminal; in a log, the
      // line each step printed as it began is enough.
      if (terminal)
        err << "\r" << job_line(job, task, static_cast<double>(done) / total) << "\x1b[K" << std::flush;
      return;
    }
    const long pct = done * 100 / total;
    if (!terminal) {
      if (pct % 25 == 0) err << "[" << task << "] " << pct << "%\n" << std::flush;
      return;
    }
    if (done == 0) *task_start = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - *task_start).count();
    err << "\r" << progress_bar_line(task, done, total, elapsed) << "\x1b[K" << (done >= total ? "\n" : "")
        << std::flush;
  });

  Allocator allocator;
  // The budget holds the Lua heap and the C++ heap together; what the
  // process already holds (the runner, the standard library) counts as well,
  // so the limit is on the process' heap, as a shop reads it.
  set_memory_budget(options.memory_limit_mb * 1024.0 * 1024.0);
  struct BudgetReset {
    ~BudgetReset() { set_memory_budget(0); }
  } budget_reset;
  RunState run_state{&ctx, &allocator, nullptr, {}, {}, {}};
  if (!options.test_cancel_at.empty()) {
    const auto colon = options.test_cancel_at.rfind(':');
    char* end = nullptr;
    const long points =
        colon == std::string::npos ? 0 : std::strtol(options.test_cancel_at.c_str() + colon + 1, &end, 10);
    if (points < 1 || !end || *end != '\0') {
      err << "bliskrun: test_cancel_at '" << options.test_cancel_at << "' is not FILE:LINE:N with N >= 1\n";
      return kExitUsage;
    }
    run_state.test_cancel.at = options.test_cancel_at.substr(0, colon);
    run_state.test_cancel.points = points;
  }
  Watchdog::HardStop hard_stop;
  if (options.hard_time_limit)
    hard_stop = [&err, &run_state](const std::string& message) {
      const std::string at = run_state.position();
      err << "bliskrun: " << (at.empty() ? "" : at + ": ") << message
          << " (stopped by the watchdog: the running code reached no cancellation point)\n"
          << std::flush;
      remove_unfinished_writes();
      std::_Exit(kExitRecipeError);
    };
  SignalStop signals(options.handle_signals);  // blocked before the watchdog's thread starts
  Watchdog watchdog(ctx.progress, options.time_limit_s, std::move(hard_stop));
  run_state.watchdog = &watchdog;
  signals.watch(watchdog, [&err, &run_state](int sig) {
    const std::string at = run_state.position();
    err << "bliskrun: " << (at.empty() ? "" : at + ": ") << "interrupted by " << (sig == SIGINT ? "SIGINT" : "SIGTERM")
        << " (stopped at once: the run did not stop within " << SignalStop::kGrace
        << " s, or a second signal came); unfinished temporary files removed\n"
        << std::flush;
    remove_unfinished_writes();
    std::_Exit(128 + sig);
  });
  struct FinishSignals {  // the watcher uses the watchdog: stopped before it goes
    SignalStop& s;
    ~FinishSignals() { s.finish(); }
  } finish_signals{signals};

  lua_State* L = lua_newstate(limited_alloc, &allocator);
  if (!L) {
    err << "bliskrun: cannot create a Lua state\n";
    return kExitRecipeError;
  }
  int status = LUA_OK;
  std::string message;
  try {
    lua_pushlightuserdata(L, &run_state);
    lua_setfield(L, LUA_REGISTRYINDEX, kContextKey);
    open_sandbox(L);
    open_all(L);
    push_args(L, options.sets);
    lua_getglobal(L, "bliskrun");
    lua_pushcfunction(L, options_help);
    lua_setfield(L, -2, "options_help");
    lua_pushcfunction(L, progress_step);
    lua_setfield(L, -2, "progress_step");
    lua_pop(L, 1);
    lua_sethook(L, count_hook, LUA_MASKCOUNT, 10000);
    luax::set_call_observer(observe_call);

    lua_pushcfunction(L, traceback);
    status = luaL_loadfilex(L, options.recipe_path.c_str(), "t");
    if (status == LUA_OK) status = lua_pcall(L, 0, 0, -2);
    if (status != LUA_OK) message = lua_tostring(L, -1) ? lua_tostring(L, -1) : "error object is not a string";
  } catch (const std::exception& e) {
    status = LUA_ERRRUN;
    message = e.what();
  }
  luax::set_call_observer(nullptr);
  lua_close(L);
  if (ctx.job.steps > 0 && terminal && !quiet) err << "\n";  // a job's line a failure left open
  signals.finish();
  if (const int sig = signals.signal()) {
    // Every write either finished or removed its temporary as it unwound;
    // this is for one a worker thread may have left.
    remove_unfinished_writes();
    if (status == LUA_OK) message = "interrupted by " + std::string(sig == SIGINT ? "SIGINT" : "SIGTERM");
    err << "bliskrun: " << message << "\nbliskrun: stopped by " << (sig == SIGINT ? "SIGINT" : "SIGTERM")
        << "; outputs written before it are complete, unfinished ones removed\n";
    return 128 + sig;
  }
  if (options.verify_report) {
    std::ostream& out = std::cout;
    out << "read-back verification: " << ctx.verified_programs.size() << " program(s)\n";
    for (const auto& line : ctx.verified_programs) out << "  " << line << "\n";
  }
  if (options.recipe_help) {
    if (ctx.options_declared) {
      std::cout << "options of " << options.recipe_path << " (--set NAME=VALUE):\n" << ctx.options_help << std::flush;
      return kExitOk;
    }
    err << "bliskrun: " << options.recipe_path << ": "
        << (status != LUA_OK ? message : "this recipe declares no options (scripts/lib/recipe_options.lua)") << "\n";
    return kExitUsage;
  }
  if (status == LUA_OK) return kExitOk;
  // A Lua allocation refused for the budget raises a bare "not enough
  // memory"; a C++ one comes through luax::guarded already worded, with the
  // recipe line. Anything else that failed after the budget ran out is
  // reported as the limit, at the last recipe line the hook saw.
  const bool worded = message.find("memory limit of ") != std::string::npos;
  if (!worded && ((allocator.exceeded && status == LUA_ERRMEM) || memory_budget_exceeded())) {
    std::ostringstream s;
    s << (run_state.position().empty() ? "" : run_state.position() + ": ") << "memory limit of "
      << options.memory_limit_mb << " MB exceeded (--memory-limit)";
    message = s.str();
  }
  err << "bliskrun: " << message << "\n";
  return kExitRecipeError;
}

}  // namespace bliskrun::lua_api
