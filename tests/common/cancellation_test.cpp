// Cancellation reaches every long core loop, also the ones that take no
// Progress: the run's watchdog requests it process-wide (request_cancel_all,
// from its own thread) and the loop throws Cancelled at its next
// cancellation point. One test per subsystem. The request here takes effect
// part-way by a count of cancellation points (request_cancel_all_after), not
// after a delay, so the test does not depend on the machine's speed; each
// workload passes far more points than that, and finishing instead of
// throwing fails the test.
#include <gtest/gtest.h>

#include <functional>
#include <sstream>

#include "core/analysis/passage.h"
#include "core/common/cancel_after.h"
#include "core/common/error.h"
#include "core/common/progress.h"
#include "core/geometry/interpolation.h"
#include "core/geometry/projection.h"
#include "core/io/point_grid_reader.h"
#include "core/parts/builtin_blisk.h"
#include "geometry/analytic_surfaces.h"

namespace bliskrun {
namespace {

// Runs `work` with cancellation requested to take effect at its 50th
// cancellation point; expects Cancelled, and clears the request afterwards.
void expect_cancelled(const std::function<void()>& work) {
  request_cancel_all_after(50, "test");
  EXPECT_THROW(work(), Cancelled);
  clear_cancel_all();
}

TEST(Cancellation, ReadersStopWhileParsing) {
  // 1500 x 1500 points (~80 MB of text): seconds of parsing.
  std::ostringstream text;
  text << "# grid 1500 1500 order=row\n";
  for (int i = 0; i < 1500 * 1500; ++i) text << i % 97 << " " << i % 89 << " " << i % 83 << "\n";
  const std::string data = text.str();
  expect_cancelled([&] { parse_point_grid(data, "big.txt"); });
}

TEST(Cancellation, GridInterpolationStops) {
  PointGrid g(2000, 2000);
  for (int i = 0; i < g.rows; ++i)
    for (int j = 0; j < g.cols; ++j) g.at(i, j) = Vec3(i, j, 0.001 * i * j);
  expect_cancelled([&] { interpolate_grid(g); });
}

TEST(Cancellation, ProjectionSearchStops) {
  const test::Sphere sphere(20);
  ProjectionOptions o;
  o.seed_samples_u = o.seed_samples_v = 4000;  // 16 million seed samples
  expect_cancelled([&] { project_to_surface(sphere, Vec3(1, 2, 30), o); });
}

TEST(Cancellation, NarrowestPassageStops) {
  const BuiltinBlisk blisk;
  const auto a = blisk.flank_surface(1, FlankSide::kSuction);
  const auto b = blisk.flank_surface(2, FlankSide::kPressure);
  expect_cancelled([&] { narrowest_passage(*a, *b, 100, 200); });
}

TEST(Cancellation, PartGridsStop) {
  BliskParams p;
  p.grid_rows = 2000;
  p.grid_cols = 2000;
  const BuiltinBlisk blisk(p);
  expect_cancelled([&] { blisk.flank_grid(1, FlankSide::kPressure); });
}

// Progress::none(), which loops get when the caller passes no Progress,
// answers the process-wide request too; a counted request takes effect at
// its count and not before.
TEST(Cancellation, ProgressNoneAnswersTheRequest) {
  clear_cancel_all();
  EXPECT_NO_THROW(Progress::none().check());
  request_cancel_all("test");
  EXPECT_THROW(Progress::none().check(), Cancelled);
  EXPECT_THROW(cancellation_point(), Cancelled);
  clear_cancel_all();
  EXPECT_NO_THROW(cancellation_point());

  request_cancel_all_after(3, "test");
  EXPECT_FALSE(cancel_all_requested());
  EXPECT_NO_THROW(Progress::none().check());  // 1
  EXPECT_NO_THROW(cancellation_point());      // 2
  EXPECT_THROW(cancellation_point(), Cancelled);  // 3
  EXPECT_TRUE(cancel_all_requested());
  EXPECT_THROW(Progress::none().check(), Cancelled);
  clear_cancel_all();
  EXPECT_NO_THROW(cancellation_point());
}

}  // namespace
}  // namespace bliskrun
