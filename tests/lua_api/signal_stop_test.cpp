// SIGINT and SIGTERM stop a run promptly and leave no unfinished temporary
// behind (issue 37 item 6): the bliskrun command, rewriting a 4 MB file in a
// loop (fsync'd, so most of its time is spent inside writes), gets the
// signal once its first write has landed; it must exit with 128 + the
// signal, say why, and leave only complete files. Nothing here depends on
// the machine's speed: the test polls for the first file and then waits
// (generously) for the exit.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "test_support.h"

extern char** environ;

namespace bliskrun::test {
namespace {

namespace fs = std::filesystem;

struct Stopped {
  int exit_code = -1;   // -1: did not exit normally
  std::string output;   // stderr
  double seconds_after_signal = 0;
};

// Starts `args` (argv[0] = the executable), waits until `ready` exists,
// sends `sig`, waits for the exit (up to `limit_s`, then SIGKILL).
Stopped run_and_signal(const std::vector<std::string>& args, const std::string& ready, int sig,
                       const std::string& log, double limit_s = 120) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  Stopped out;
  if (spawned != 0) return out;
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  int status = 0;
  bool exited = false;
  while (!fs::exists(ready)) {  // the first complete write
    if (waitpid(pid, &status, WNOHANG) == pid) {
      exited = true;
      break;
    }
    if (clock::now() - start > std::chrono::duration<double>(limit_s)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const auto signalled = clock::now();
  if (!exited) {
    kill(pid, sig);
    while (waitpid(pid, &status, WNOHANG) != pid) {
      if (clock::now() - signalled > std::chrono::duration<double>(limit_s)) {
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  out.seconds_after_signal = std::chrono::duration<double>(clock::now() - signalled).count();
  if (WIFEXITED(status)) out.exit_code = WEXITSTATUS(status);
  std::ifstream in(log);
  out.output.assign((std::istreambuf_iterator<char>(in)), {});
  return out;
}

std::vector<std::string> temporaries(const std::string& folder) {
  std::vector<std::string> found;
  std::error_code ec;
  if (!fs::exists(folder, ec)) return found;
  for (const auto& e : fs::recursive_directory_iterator(folder))
    if (e.path().filename().string().find(".tmp.") != std::string::npos) found.push_back(e.path().string());
  return found;
}

class SignalStop : public ::testing::TestWithParam<int> {};

TEST_P(SignalStop, DuringAWriteExitsWithTheSignalAndLeavesNoTemporary) {
  const int sig = GetParam();
  TempDir dir;
  // first.txt lands, then big.txt is rewritten until the signal.
  const std::string recipe = dir.write("rewrite.lua",
                                       "local a, b = string.rep('A', 4 << 20), string.rep('B', 4 << 20)\n"
                                       "bliskrun.write_text('first.txt', 'x')\n"
                                       "while true do bliskrun.write_text('big.txt', b); bliskrun.write_text('big.txt', a) end\n");
  const std::string out = dir.path() + "/out";
  const Stopped r = run_and_signal({BLISKRUN_EXE, recipe, "--quiet", "--time-limit", "0", "--out", out},
                                   out + "/first.txt", sig, dir.path() + "/stderr.txt");
  EXPECT_EQ(r.exit_code, 128 + sig) << r.output;
  const std::string name = sig == SIGINT ? "SIGINT" : "SIGTERM";
  EXPECT_NE(r.output.find("interrupted by " + name), std::string::npos) << r.output;
  EXPECT_TRUE(temporaries(out).empty()) << temporaries(out)[0];
  // What was written is whole: one of the two complete versions.
  std::ifstream in(out + "/big.txt", std::ios::binary);
  if (in) {
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    EXPECT_EQ(text.size(), 4u << 20);
    EXPECT_TRUE(text.find_first_not_of(text[0]) == std::string::npos) << "mixed contents";
  }
}

// Inside a long core loop (no Lua runs): its cancellation points stop it
// (a curvature analysis of 4 million samples, then an endless loop so that
// the run never ends by itself whatever the machine's speed).
TEST_P(SignalStop, DuringCoreWorkStopsAtACancellationPoint) {
  const int sig = GetParam();
  TempDir dir;
  const std::string recipe =
      dir.write("busy.lua",
                "local f = bliskrun.blisk{}:flank(1, 'pressure')\n"
                "bliskrun.write_text('started.txt', 'x')\n"
                "bliskrun.curvature_stats(f, {samples_u = 1000, samples_v = 4000})\n"
                "while true do end\n");
  const std::string out = dir.path() + "/out";
  const Stopped r = run_and_signal({BLISKRUN_EXE, recipe, "--quiet", "--time-limit", "0", "--out", out},
                                   out + "/started.txt", sig, dir.path() + "/stderr.txt");
  EXPECT_EQ(r.exit_code, 128 + sig) << r.output;
  EXPECT_NE(r.output.find(sig == SIGINT ? "SIGINT" : "SIGTERM"), std::string::npos) << r.output;
  EXPECT_TRUE(temporaries(out).empty());
}

INSTANTIATE_TEST_SUITE_P(Cli, SignalStop, ::testing::Values(SIGINT, SIGTERM),
                         [](const ::testing::TestParamInfo<int>& info) {
                           return std::string(info.param == SIGINT ? "Sigint" : "Sigterm");
                         });

}  // namespace
}  // namespace bliskrun::test
