// Cost of hub and blade-root finishing (issue 18 item 2) on the built-in
// blisk: blade 1's root strip and the channel floor to blade 2 with the
// recipe's tapered ball end (r 1.5, 2.5 deg, 40 mm flute), planned and
// checked on 1 and 2 threads (every pose tilted clear of the world, the ball
// and cone through the gouge guards, the flute against both blades, steps
// and links proved), the root alone and the channel alone, and the
// simulation of the plan (root strip and floor, the neighbours' copies
// included). Wall time (UseRealTime): the target is a few seconds on the
// 2-core machine, one blade and one channel of the 22-blade job.
#include <benchmark/benchmark.h>

#include <memory>

#include "core/parts/builtin_blisk.h"
#include "core/planning/hub_finish.h"

namespace bliskrun {
namespace {

struct HubSetup {
  BuiltinBlisk blisk;
  Tool tool = Tool::tapered_ball_end_mill({1.5, 2.5 * kPi / 180, 40, {8, 30}, {32, 40}});
  HubFinishRequest rq;
  HubSetup() {
    const int n = blisk.blade_count();
    rq.blade = {blisk.flank_surface(0, FlankSide::kPressure), blisk.flank_surface(0, FlankSide::kSuction)};
    rq.next = {blisk.flank_surface(1, FlankSide::kPressure), blisk.flank_surface(1, FlankSide::kSuction)};
    rq.previous = {blisk.flank_surface(n - 1, FlankSide::kPressure), blisk.flank_surface(n - 1, FlankSide::kSuction)};
    rq.hub = std::make_shared<const SurfaceOfRevolution>(blisk.hub_meridian());
    rq.tool = &tool;
  }
};

HubSetup& setup() {
  static HubSetup s;
  return s;
}

// Arg 0: threads; arg 1: 0 both, 1 root only, 2 channel only.
void BM_HubFinishPlan(benchmark::State& state) {
  HubFinishRequest rq = setup().rq;
  rq.threads = static_cast<int>(state.range(0));
  rq.root = state.range(1) != 2;
  rq.channel = state.range(1) != 1;
  int poses = 0, refusals = 0;
  for (auto _ : state) {
    const HubFinishResult r = plan_hub_finish(rq);
    poses = r.root.poses + r.channel.poses;
    refusals = static_cast<int>(r.refusals.size());
    benchmark::DoNotOptimize(poses);
  }
  state.counters["poses"] = poses;
  state.counters["refusals"] = refusals;
}
BENCHMARK(BM_HubFinishPlan)
    ->Args({1, 0})
    ->Args({2, 0})
    ->Args({2, 1})
    ->Args({2, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

void BM_HubFinishSimulate(benchmark::State& state) {
  HubFinishRequest rq = setup().rq;
  rq.threads = 2;
  const HubFinishResult r = plan_hub_finish(rq);
  HubFinishSimOptions so;
  so.threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    const HubFinishSimulation s = simulate_hub_finish(r, rq, so);
    benchmark::DoNotOptimize(s.strip.left_max_mm);
  }
}
BENCHMARK(BM_HubFinishSimulate)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
}  // namespace bliskrun
