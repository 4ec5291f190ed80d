// Outputs are never half-written: a run killed (SIGKILL, no chance to clean
// up) in the middle of rewriting a file leaves one of its complete versions.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_support.h"

namespace bliskrun::test {
namespace {

TEST(AtomicWrite, KilledRunLeavesACompleteFile) {
  TempDir dir;
  // Rewrites a 4 MB file with alternating contents until it is killed.
  const std::string recipe = dir.write("rewrite.lua",
                                       "local a, b = string.rep('A', 4 << 20), string.rep('B', 4 << 20)\n"
                                       "bliskrun.write_text('big.txt', a)\n"
                                       "while true do bliskrun.write_text('big.txt', b); bliskrun.write_text('big.txt', a) end\n");
  int seen = 0;
  for (const char* after : {"0.3", "0.45", "0.6", "0.75", "0.9"}) {
    const std::string cmd = std::string("timeout -s KILL ") + after + " " + BLISKRUN_EXE + " '" + recipe +
                            "' --quiet --out '" + dir.path() + "/out' >/dev/null 2>&1";
    const int status = std::system(cmd.c_str());
    (void)status;  // killed: 137
    std::ifstream in(dir.path() + "/out/big.txt", std::ios::binary);
    if (!in) continue;  // killed before the first write finished: nothing written is fine too
    ++seen;
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    ASSERT_EQ(text.size(), 4u << 20) << "partial file after a kill at " << after << " s";
    EXPECT_TRUE(text.find_first_not_of(text[0]) == std::string::npos) << "mixed contents";
  }
  EXPECT_GT(seen, 0) << "no run lived long enough to write once";
}

}  // namespace
}  // namespace bliskrun::test
