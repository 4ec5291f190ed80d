// The hostile-recipe corpus (tests/lua_api/hostile/*.lua): each recipe is run
// through the bliskrun executable with the limits its header names, under an
// outer `timeout` so that a run ignoring its limits fails the test instead of
// hanging it. Header lines:
//   -- expect-exit: N        exit code (1 for every hostile recipe so far)
//   -- expect: REGEX         searched in stderr
//   -- args: ...             extra command-line arguments (limits)
//   -- ulimit-f: BLOCKS      file-size limit of the run (sh ulimit -f)
// Every run must also leave no temporary file in its out folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "test_support.h"

namespace bliskrun::test {
namespace {

namespace fs = std::filesystem;

struct Hostile {
  std::string name, path;
};

std::vector<Hostile> hostile_corpus() {
  std::vector<Hostile> out;
  for (const auto& e : fs::directory_iterator(std::string(BLISKRUN_SOURCE_DIR) + "/tests/lua_api/hostile"))
    if (e.path().extension() == ".lua") out.push_back({e.path().stem().string(), e.path().string()});
  std::sort(out.begin(), out.end(), [](const Hostile& a, const Hostile& b) { return a.name < b.name; });
  return out;
}

std::string header(const std::string& text, const std::string& key) {
  const std::string tag = "-- " + key + ": ";
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind(tag, 0) == 0) return line.substr(tag.size());
  return "";
}

class HostileRecipe : public ::testing::TestWithParam<Hostile> {};

TEST_P(HostileRecipe, EndsCleanlyWithItsMessage) {
  std::ifstream in(GetParam().path);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::string expect_exit = header(text, "expect-exit"), expect = header(text, "expect");
  ASSERT_FALSE(expect_exit.empty() || expect.empty()) << GetParam().path << " lacks expect-exit/expect";
  TempDir dir;
  std::string cmd;
  if (const std::string blocks = header(text, "ulimit-f"); !blocks.empty()) cmd += "ulimit -f " + blocks + "; ";
  cmd += "timeout -s KILL 60 '" + std::string(BLISKRUN_EXE) + "' '" + GetParam().path + "' --quiet --out '" +
         dir.path() + "/out' " + header(text, "args") + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buf[4096];
  for (size_t n; (n = fread(buf, 1, sizeof buf, pipe)) > 0;) output.append(buf, n);
  const int status = pclose(pipe);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by a signal:\n" << output;
  EXPECT_EQ(WEXITSTATUS(status), std::stoi(expect_exit)) << output;
  EXPECT_TRUE(std::regex_search(output, std::regex(expect))) << "no match for /" << expect << "/ in:\n" << output;
  if (fs::is_directory(dir.path() + "/out"))
    for (const auto& e : fs::directory_iterator(dir.path() + "/out"))
      EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << "left behind: " << e.path();
}

INSTANTIATE_TEST_SUITE_P(Corpus, HostileRecipe, ::testing::ValuesIn(hostile_corpus()),
                         [](const ::testing::TestParamInfo<Hostile>& info) { return info.param.name; });

// The previous file survives a failed write (file_size_limit.lua).
TEST(HostileRecipeFiles, FailedWriteKeepsThePreviousFile) {
  TempDir dir;
  const std::string recipe = std::string(BLISKRUN_SOURCE_DIR) + "/tests/lua_api/hostile/file_size_limit.lua";
  const std::string cmd = "ulimit -f 64; '" + std::string(BLISKRUN_EXE) + "' '" + recipe + "' --quiet --out '" +
                          dir.path() + "/out' >/dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  std::ifstream in(dir.path() + "/out/big.txt");
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(text, "previous contents\n");
}

}  // namespace
}  // namespace bliskrun::test
