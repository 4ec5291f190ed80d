// One progress line for a whole job (issue 37 item 6): while a job goes on
// (bliskrun.progress_step, which j:run calls per operation, simulation,
// posting and report) the run prints the step it is at - k of n, what,
// elapsed, remaining - and not a line per core task; outside a job the
// core tasks report as before.
#include <gtest/gtest.h>

#include <sstream>

#include "test_support.h"

namespace bliskrun::test {
namespace {

TEST(ProgressLine, AJobPrintsItsStepsNotItsTasks) {
  TempDir dir;
  const std::string recipe = dir.write(
      "job.lua",
      "local f = bliskrun.blisk{}:flank(1, 'pressure')\n"
      "bliskrun.curvature_stats(f, {samples_u = 20, samples_v = 20})  -- outside a job\n"
      "for k = 1, 3 do\n"
      "  bliskrun.progress_step(k, 3, 'plan drum finish, blade ' .. k .. ', pressure')\n"
      "  bliskrun.curvature_stats(f, {samples_u = 20, samples_v = 20})\n"
      "end\n"
      "bliskrun.progress_step()\n"
      "local ok, err = pcall(bliskrun.progress_step, 4, 3, 'x')\n"
      "assert(not ok and err:find('expected 1 <= step <= steps, got 4 of 3', 1, true), err)\n");
  // stderr is not a terminal here: plain lines.
  const RecipeResult r = run_bliskrun({recipe, "--out", dir.path() + "/out"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::istringstream lines(r.output);
  std::vector<std::string> steps;
  int task_lines_before = 0, task_lines_in_job = 0;
  bool in_job = false, ended = false;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("[step ", 0) == 0) {
      in_job = true;
      steps.push_back(line);
    } else if (line.rfind("[job] 3 steps done in ", 0) == 0) {
      ended = true;
      in_job = false;
    } else if (line.rfind("[curvature analysis]", 0) == 0) {
      (in_job ? task_lines_in_job : task_lines_before)++;
    }
  }
  ASSERT_EQ(steps.size(), 3u) << r.output;
  EXPECT_EQ(steps[0].rfind("[step 1/3] plan drum finish, blade 1, pressure  elapsed ", 0), 0u) << steps[0];
  EXPECT_EQ(steps[0].find("remaining"), std::string::npos) << "nothing done yet, no estimate: " << steps[0];
  EXPECT_EQ(steps[1].rfind("[step 2/3] plan drum finish, blade 2, pressure  elapsed ", 0), 0u) << steps[1];
  EXPECT_NE(steps[2].find("  remaining ~"), std::string::npos) << steps[2];
  EXPECT_TRUE(ended) << r.output;
  EXPECT_GT(task_lines_before, 0) << r.output;
  EXPECT_EQ(task_lines_in_job, 0) << r.output;
}

}  // namespace
}  // namespace bliskrun::test
