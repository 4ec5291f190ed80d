#pragma once
// Channel 0 of the built-in blisk as the roughing tests see it (issue 41):
// the rougher, both blades as the part has them and the hub as the world
// the levels planner proves against, and its request. Shared by the unit
// test (tests/planning/channel_levels_test.cpp) and the recipe-size sweep
// (tests/recipes/channel_levels_sweep_test.cpp).
#include <memory>
#include <string>
#include <vector>

#include "core/collision/collision_world.h"
#include "core/geometry/mesh.h"
#include "core/geometry/revolution.h"
#include "core/parts/builtin_blisk.h"
#include "core/parts/edge_region.h"
#include "core/planning/channel_levels.h"
#include "core/planning/trimmed_surface.h"

namespace bliskrun::test_channel {

inline constexpr double kStock = 0.5;

inline Tool rougher() {
  TaperedBallEndMillSpec s;
  s.tip_radius_mm = 3;
  s.half_angle_rad = deg_to_rad(1.5);
  s.flute_length_mm = 36;
  s.shank = {10, 40};
  s.holder = {32, 40};
  return Tool::tapered_ball_end_mill(s);
}

// An edge round of a built-in blade from the hub row up to the casing
// (blisk_world.edge_round): `first` the flank whose edge end is at v = 0.
inline std::shared_ptr<const Surface> edge_round(const std::shared_ptr<const Surface>& first,
                                                 const std::shared_ptr<const Surface>& second,
                                                 const SurfaceOfRevolution& casing) {
  double lo = 0, hi = 1;
  for (int k = 0; k < 40; ++k) {
    const double m = 0.5 * (lo + hi);
    (casing.radial_offset(first->point(m, 0)) > 0 ? hi : lo) = m;
  }
  EdgeRegionRequest rq;
  rq.first = first;
  rq.second = second;
  rq.overlap_mm = 0;
  rq.span_u1 = hi;
  return build_edge_region(rq).surface;
}

// Blade 0's suction flank and blade 1's pressure flank bound channel 0.
// Each blade as the part has it — both flanks from the hub to the casing
// (the grids reach past it, where no material is) and both edge rounds —
// and the hub make the world (as blisk_world.around_channel builds it) and
// the surfaces the independent check measures.
struct Channel {
  BuiltinBlisk blisk;
  SurfaceOfRevolution hub{blisk.hub_meridian()}, casing{blisk.casing_meridian()};
  // The blank's top: the casing, or the hub raised radially by
  // `top_over_hub_mm` (a shallower channel for a lean test).
  SurfaceOfRevolution top;
  static std::vector<Vec2> raised(std::vector<Vec2> m, double by_mm) {
    for (Vec2& p : m) p.y() += by_mm;  // (z, r)
    return m;
  }
  std::shared_ptr<const Surface> flank[2][2] = {
      {blisk.flank_surface(0, FlankSide::kPressure), blisk.flank_surface(0, FlankSide::kSuction)},
      {blisk.flank_surface(1, FlankSide::kPressure), blisk.flank_surface(1, FlankSide::kSuction)}};
  std::shared_ptr<const Surface> left = flank[0][1], right = flank[1][0];
  // blade b: pressure and suction trimmed, leading and trailing edge
  std::vector<std::shared_ptr<const Surface>> part[2];
  Tool tool = rougher();
  FlankCutter cutter{tool, 3};
  ToolBody body{tool};
  CollisionWorld world;
  explicit Channel(double top_over_hub_mm = 0)
      : top{top_over_hub_mm > 0 ? raised(blisk.hub_meridian(), top_over_hub_mm) : blisk.casing_meridian()} {
    for (int b = 0; b < 2; ++b) {
      for (int side = 0; side < 2; ++side) part[b].push_back(trim_between(flank[b][side], hub, casing, 200));
      part[b].push_back(edge_round(flank[b][0], flank[b][1], casing));  // leading: the pressure flank's v = 0
      part[b].push_back(edge_round(flank[b][1], flank[b][0], casing));  // trailing: the suction flank's v = 0
      const char* names[] = {"pressure", "suction", "leading edge", "trailing edge"};
      for (size_t k = 0; k < part[b].size(); ++k)
        world.add("blade " + std::to_string(b) + " " + names[k], tessellate(*part[b][k], 0.01));
    }
    world.add("hub", tessellate(hub, 0.01));
  }
  ChannelLevelsRequest request(int stations) const {
    ChannelLevelsRequest rq;
    rq.left = {left.get(), 1, 0, {part[0][2].get(), part[0][3].get(), flank[0][0].get()}};
    rq.right = {right.get(), 0, 1, {part[1][2].get(), part[1][3].get(), flank[1][1].get()}};
    rq.hub = &hub;
    rq.top = &top;
    rq.cutter = &cutter;
    rq.world = &world;
    rq.body = &body;
    rq.clearances.cutter_mm = kStock - 0.035;
    rq.clearances.shank_mm = rq.clearances.holder_mm = kStock + 0.5;
    rq.stations = stations;
    rq.stock_mm = kStock;
    rq.threads = 2;
    return rq;
  }
};

}  // namespace bliskrun::test_channel
