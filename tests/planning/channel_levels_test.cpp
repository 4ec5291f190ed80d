// Issue 41: the levels planner's refusals (core/planning/channel_levels.h).
// Its recipe-size check — one built-in channel planned at 13 stations and
// swept independently — is tests/recipes/channel_levels_sweep_test.cpp
// (Release only: ~40 s).
#include "core/planning/channel_levels.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/collision/collision_world.h"
#include "core/common/error.h"
#include "core/geometry/mesh.h"
#include "core/geometry/projection.h"
#include "core/geometry/revolution.h"
#include "core/parts/builtin_blisk.h"
#include "core/parts/edge_region.h"
#include "core/planning/trimmed_surface.h"
#include "core/sim/undercut.h"
#include "tests/planning/builtin_channel.h"

namespace bliskrun {
namespace {

using test_channel::Channel;
using test_channel::kStock;

constexpr double kTolerance = 0.05;  // the stock's band (issue 41)


TEST(ChannelLevels, RefusesImpossibleRequests) {
  const Channel ch;
  ChannelLevelsRequest rq = ch.request(5);
  rq.world = nullptr;
  rq.top = nullptr;
  EXPECT_THROW(plan_channel_levels(rq), ParameterError);
  rq = ch.request(5);
  rq.world = nullptr;
  rq.step_over_mm = 7;  // wider than the ball
  EXPECT_THROW(plan_channel_levels(rq), ParameterError);
  rq.step_over_mm = 2;
  rq.hub_stock_mm = 0.6;  // more than the faces' stock
  EXPECT_THROW(plan_channel_levels(rq), ParameterError);
  // A ball too big for the channel: its stock and it do not fit.
  TaperedBallEndMillSpec s;
  s.tip_radius_mm = 6;
  s.half_angle_rad = 0;
  s.flute_length_mm = 36;
  const Tool big = Tool::tapered_ball_end_mill(s);
  const FlankCutter cutter(big, 6);
  rq = ch.request(5);
  rq.world = nullptr;
  rq.cutter = &cutter;
  EXPECT_THROW(plan_channel_levels(rq), Error);
}

}  // namespace
}  // namespace bliskrun
