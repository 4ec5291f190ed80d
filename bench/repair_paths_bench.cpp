// Cost of the repair toolpaths (issue 16 §2) at real size: the built-in
// blisk's blade 1 closed around its section (r 63 -> 93 mm, 31 sections),
// a ball-end mill R 3 (shank 6 x 60, holder 25 x 50), the blade (shank and
// holder, 0.05 mm mesh) and a fixture cylinder at the root (every part) as
// the world; finishing layer only (deposit 0), scallop 5 um, chord 2 um:
//   - the tip spiral above 85 % of the span (scripts/recipes/blade_repair_paths.lua);
//   - the leading-edge zigzag, 4 mm either side of the apex, 30-60 % span.
#include <benchmark/benchmark.h>

#include <memory>

#include "core/geometry/mesh.h"
#include "core/geometry/revolution.h"
#include "core/parts/builtin_blisk.h"
#include "core/parts/closed_blade.h"
#include "core/planning/repair_paths.h"

namespace bliskrun {
namespace {

struct RepairSetup {
  BuiltinBlisk blisk;
  ClosedBlade blade;
  std::shared_ptr<const Surface> design;
  SurfaceOfRevolution fixture{std::vector<Vec2>{Vec2(-30, 63), Vec2(30, 63)}};
  Tool tool = Tool::ball_end_mill({3, 12, {6, 60}, {25, 50}});
  CollisionWorld world;

  RepairSetup() {
    auto u_of = [&](double r) {
      return (r - blisk.grid_radius_min_mm()) / (blisk.grid_radius_max_mm() - blisk.grid_radius_min_mm());
    };
    ClosedBladeOptions o;
    o.u0 = u_of(63);
    o.u1 = u_of(93);
    blade = close_blade(*blisk.flank_surface(0, FlankSide::kPressure), *blisk.flank_surface(0, FlankSide::kSuction), o);
    design = std::make_shared<BSplineSurface>(blade.loft.surface);
    CheckSurfaceOptions own;
    own.parts.cutter = false;
    own.margin_mm = 0.05;
    world.add("blade", tessellate(*design, 0.05), own);
    world.add("fixture", tessellate(fixture, 0.01));
  }
};

RepairSetup& setup() {
  static RepairSetup s;
  return s;
}

void BM_RepairFinishingLayer(benchmark::State& state) {
  RepairSetup& s = setup();
  RepairPathRequest rq;
  rq.design = s.design;
  rq.tool = &s.tool;
  rq.world = &s.world;
  rq.deposit_mm = rq.stock_mm = 0;
  rq.tilt.clearances.shank_mm = rq.tilt.clearances.holder_mm = 0.5;
  if (state.range(0) == 0) {
    rq.pattern = RepairPattern::Spiral;
    rq.u0 = 0.85;
  } else {
    const double w = 4 / s.blade.perimeter_mm;
    rq.u0 = 0.3;
    rq.u1 = 0.6;
    rq.v0 = s.blade.le_v - w;
    rq.v1 = s.blade.le_v + w;
  }
  RepairPathResult r;
  for (auto _ : state) {
    r = plan_repair_paths(rq);
    benchmark::DoNotOptimize(r.passes.data());
  }
  int poses = 0;
  for (const RepairPass& p : r.passes) poses += static_cast<int>(p.poses.size());
  state.counters["poses"] = poses;
  state.counters["passes"] = static_cast<double>(r.passes.size());
  state.counters["refusals"] = static_cast<double>(r.refusals.size());
  state.counters["gouge_splits"] = r.gouge_splits;
}
BENCHMARK(BM_RepairFinishingLayer)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace bliskrun
