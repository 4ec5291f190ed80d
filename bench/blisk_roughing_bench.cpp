// Blisk channel roughing (issue 41 item 5): channel 1 of the built-in blisk
// (blade 0's suction flank to blade 1's pressure flank) roughed in levels
// as job.rough_channels plans it — 6 mm tapered ball end, 0.5 mm stock,
// step-down 1, step-over 2, scallop 0.03, 41 stations — every pose, motion,
// step and link proved against both blades (flanks trimmed to the casing,
// edge rounds) and the hub, on `threads` (the first argument). The hub a
// mesh at 0.01 mm (second argument 0) or measured analytically as a surface
// of revolution within 0.001 mm (1: RevolutionDistance, what
// blisk_world.around_channel gives the job). Wall time (real time), poses
// and ms per pose.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <memory>
#include <string>

#include "core/collision/collision_world.h"
#include "core/geometry/mesh.h"
#include "core/geometry/revolution_distance.h"
#include "core/parts/builtin_blisk.h"
#include "core/parts/edge_region.h"
#include "core/planning/channel_levels.h"
#include "core/planning/trimmed_surface.h"

namespace bliskrun {
namespace {

std::shared_ptr<const Surface> edge_round(const std::shared_ptr<const Surface>& first,
                                          const std::shared_ptr<const Surface>& second, const SurfaceOfRevolution& casing) {
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

void BM_BliskChannelLevelsProved(benchmark::State& state) {
  const BuiltinBlisk blisk;
  const SurfaceOfRevolution hub(blisk.hub_meridian()), casing(blisk.casing_meridian());
  TaperedBallEndMillSpec spec;
  spec.tip_radius_mm = 3;
  spec.half_angle_rad = deg_to_rad(1.5);
  spec.flute_length_mm = 36;
  spec.shank = {10, 40};
  spec.holder = {32, 40};
  const FlankCutter cutter(Tool::tapered_ball_end_mill(spec), 3);
  const ToolBody body(cutter.tool());
  std::shared_ptr<const Surface> flank[2][2], rest[2][2];
  CollisionWorld world;
  for (int b = 0; b < 2; ++b) {
    flank[b][0] = blisk.flank_surface(b, FlankSide::kPressure);
    flank[b][1] = blisk.flank_surface(b, FlankSide::kSuction);
    rest[b][0] = edge_round(flank[b][0], flank[b][1], casing);  // leading
    rest[b][1] = edge_round(flank[b][1], flank[b][0], casing);  // trailing
    for (int side = 0; side < 2; ++side)
      world.add("blade " + std::to_string(b) + " flank " + std::to_string(side),
                tessellate(*trim_between(flank[b][side], hub, casing, 200), 0.01));
    for (int e = 0; e < 2; ++e) world.add("blade " + std::to_string(b) + " edge " + std::to_string(e), tessellate(*rest[b][e], 0.01));
  }
  if (state.range(1) == 0)
    world.add("hub", tessellate(hub, 0.01));
  else
    world.add("hub", std::make_shared<RevolutionDistance>(hub, 1e-3));
  ChannelLevelsRequest rq;
  rq.left = {flank[0][1].get(), 1, 0, {rest[0][0].get(), rest[0][1].get(), flank[0][0].get()}};
  rq.right = {flank[1][0].get(), 0, 1, {rest[1][0].get(), rest[1][1].get(), flank[1][1].get()}};
  rq.hub = &hub;
  rq.top = &casing;
  rq.cutter = &cutter;
  rq.world = &world;
  rq.body = &body;
  rq.clearances.cutter_mm = 0.5 - 0.035;
  rq.clearances.shank_mm = rq.clearances.holder_mm = 1.0;
  rq.threads = static_cast<int>(state.range(0));
  ChannelLevelsPlan plan;
  double wall_ms = 0, cpu_s = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();  // the process's CPU, all threads
    plan = plan_channel_levels(rq);
    cpu_s += static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    wall_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  state.counters["levels"] = plan.levels;
  state.counters["poses"] = static_cast<double>(plan.poses);
  state.counters["refused"] = static_cast<double>(plan.refusals.size());
  state.counters["complete"] = plan.complete;
  state.counters["turned"] = static_cast<double>(plan.turned);
  state.counters["inserted"] = static_cast<double>(plan.inserted);
  // The program's fingerprint (FNV-1a over every move's kind, tip and
  // axis bits, in the label): equal between two runs iff, but for a
  // collision, the same moves.
  const Toolpath moves = channel_moves(plan);
  std::uint64_t fnv = 1469598103934665603ull;
  const auto mix = [&](const void* p, size_t n) {
    for (size_t i = 0; i < n; ++i) fnv = (fnv ^ static_cast<const unsigned char*>(p)[i]) * 1099511628211ull;
  };
  for (const Move& m : moves) {
    mix(&m.kind, sizeof m.kind);
    mix(m.pose.tip.data(), 3 * sizeof(double));
    mix(m.pose.axis.data(), 3 * sizeof(double));
  }
  state.counters["moves"] = static_cast<double>(moves.size());
  char label[32];
  std::snprintf(label, sizeof label, "moves %016llx", static_cast<unsigned long long>(fnv));
  state.SetLabel(label);
  state.counters["cpu_s"] = cpu_s / static_cast<double>(state.iterations());
  state.counters["wall_ms_per_pose"] = wall_ms / static_cast<double>(state.iterations()) / static_cast<double>(plan.poses);
}
BENCHMARK(BM_BliskChannelLevelsProved)->Args({2, 0})->Args({2, 1})->Iterations(1)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace bliskrun
