#include <gtest/gtest.h>

#include "core/common/progress.h"

namespace bliskrun {
namespace {

TEST(ProgressBar, PercentBarElapsedAndRemaining) {
  // A quarter done in 3 s: 9 s to go at the same rate; 6 of 24 cells filled.
  EXPECT_EQ(progress_bar_line("simulate", 25, 100, 3.0),
            "[simulate] [######..................]  25%  elapsed 3.0 s  remaining ~9.0 s");
  EXPECT_EQ(progress_bar_line("rows", 0, 40, 0.0, 10), "[rows] [..........]   0%  elapsed 0.0 s");
  EXPECT_EQ(progress_bar_line("rows", 40, 40, 12.5, 10), "[rows] [##########] 100%  elapsed 12.5 s");
  EXPECT_EQ(progress_bar_line("rows", 50, 40, 1.0, 4), "[rows] [####] 100%  elapsed 1.0 s");  // clamped
}

}  // namespace
}  // namespace bliskrun
