// core/common/parallel.h: parallel_for_index visits every index once and
// rethrows the exception a plain loop would have met first.
#include "core/common/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

namespace bliskrun {
namespace {

TEST(ParallelForIndex, VisitsEveryIndexOnceOnAnyThreadCount) {
  for (int threads : {1, 2, 3, 8}) {
    std::vector<std::atomic<int>> seen(1000);
    for (auto& s : seen) s.store(0);
    parallel_for_index(seen.size(), threads, [&](size_t i) { seen[i].fetch_add(1); });
    for (size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i].load(), 1) << "index " << i << ", " << threads << " threads";
  }
  int calls = 0;
  parallel_for_index(0, 2, [&](size_t) { ++calls; });
  EXPECT_EQ(calls, 0);
}

TEST(ParallelForIndex, RethrowsTheLowestFailingIndex) {
  // Indices 300 and 700 fail: on two threads they fall to different
  // workers, and whichever fails first in time, 300 is what comes back.
  for (int threads : {1, 2, 4}) {
    try {
      parallel_for_index(1000, threads, [](size_t i) {
        if (i == 300 || i == 700) throw std::runtime_error(std::to_string(i));
      });
      ADD_FAILURE() << "nothing thrown";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "300") << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace bliskrun
