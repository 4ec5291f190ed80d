// Impeller flank finishing (issue 12 item 8): build the 17-blade built-in
// model, plan one face with interference (neighbouring blades and splitters,
// this face and the hub), and the residual map of one face at 100 x 400.
#include <benchmark/benchmark.h>

#include "core/geometry/mesh.h"
#include "core/parts/impeller.h"
#include "core/planning/flank_milling.h"

namespace bliskrun {
namespace {

Tool cutter_tool() {
  TaperedBallEndMillSpec s;
  s.tip_radius_mm = 3;
  s.half_angle_rad = deg_to_rad(2);
  s.flute_length_mm = 90;
  s.shank = {16, 60};
  s.holder = {50, 60};
  return Tool::tapered_ball_end_mill(s);
}

void BM_ImpellerModelBuild(benchmark::State& state) {
  for (auto _ : state) {
    const Impeller imp(builtin_impeller_definition());
    benchmark::DoNotOptimize(imp.face(BladeKind::kMain, 16, CamberSide::kPlus)->point(0.5, 0.5));
  }
}
BENCHMARK(BM_ImpellerModelBuild)->Unit(benchmark::kMillisecond);

void BM_ImpellerPlanOneFace(benchmark::State& state) {
  const Impeller imp(builtin_impeller_definition());
  const int n = imp.blade_count();
  const auto face = imp.face(BladeKind::kMain, 0, CamberSide::kPlus);
  CollisionWorld world;
  CheckSurfaceOptions own;
  own.parts.cutter = false;
  own.margin_mm = 0.05;
  CheckSurfaceOptions all;
  all.margin_mm = 0.05;
  world.add("this face", tessellate(*face, 0.05), own);
  world.add("hub", tessellate(imp.hub(), 0.05), own);
  for (auto [kind, k] : {std::pair{BladeKind::kMain, 1}, std::pair{BladeKind::kMain, n - 1},
                         std::pair{BladeKind::kSplitter, 0}, std::pair{BladeKind::kSplitter, n - 1}})
    for (CamberSide side : {CamberSide::kPlus, CamberSide::kMinus})
      world.add(std::to_string(int(kind)) + std::to_string(k) + std::to_string(int(side)),
                tessellate(*imp.face(kind, k, side), 0.05), all);
  const FlankCutter cutter(cutter_tool(), 3);
  const ToolBody body(cutter.tool());
  FlankFaceRequest rq;
  rq.face = face.get();
  rq.hub = &imp.hub();
  rq.cutter = &cutter;
  rq.world = &world;
  rq.body = &body;
  rq.clearances.shank_mm = rq.clearances.holder_mm = 0.5;
  rq.steps.chord_tol_mm = 0.01;  // ~200 axis positions
  rq.residual_points = 40;
  FlankFacePlan plan;
  for (auto _ : state) plan = plan_flank_face(rq);
  state.counters["poses"] = static_cast<double>(plan.axes.size());
  state.counters["refused"] = static_cast<double>(plan.refusals.size());
  state.counters["residual_max_um"] = plan.residual.stats.max_mm * 1000;
  state.counters["residual_min_um"] = plan.residual.stats.min_mm * 1000;
}
BENCHMARK(BM_ImpellerPlanOneFace)->Unit(benchmark::kMillisecond);

void BM_ImpellerResidualMap100x400(benchmark::State& state) {
  const Impeller imp(builtin_impeller_definition());
  const auto face = imp.face(BladeKind::kMain, 0, CamberSide::kPlus);
  const FlankCutter cutter(cutter_tool(), 3);
  std::vector<FlankAxis> axes;
  for (int j = 0; j < 100; ++j) axes.push_back(flank_axis(*face, j / 99.0, &imp.hub(), cutter));
  for (auto _ : state) benchmark::DoNotOptimize(flank_residual(*face, axes, cutter, 400));
}
BENCHMARK(BM_ImpellerResidualMap100x400)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace bliskrun
