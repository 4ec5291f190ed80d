// Impeller flank finishing (issue 12 item 8): build the 17-blade built-in
// model, plan one face with interference (neighbouring blades and splitters,
// this face and the hub), and the residual map of one face at 100 x 400.
// Channel roughing (issue 13 items 2-3): the channel between main blade 1
// and splitter 1 notched and widened, geometry alone at 41 stations and
// with every pose, motion and link checked at `stations` (the argument).
#include <algorithm>
#include <benchmark/benchmark.h>

#include "core/geometry/mesh.h"
#include "core/parts/impeller.h"
#include "core/planning/channel_roughing.h"
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

// Issue 40 item 0: time per pose of the two-contact axis (flank_axis, then
// balanced as the recipes do is not separable here) and of its fit
// (optimise_flank_axis against the same face, ball on the hub): 20 stations
// of the built-in main blade's plus face. Arg: 0 = two-contact only, 1 = fit.
void BM_ImpellerFlankAxisPerPose(benchmark::State& state) {
  const Impeller imp(builtin_impeller_definition());
  const auto face = imp.face(BladeKind::kMain, 0, CamberSide::kPlus);
  const FlankCutter cutter(cutter_tool(), 3);
  const bool fit = state.range(0) == 1;
  FlankFitOptions o;
  o.check_points = 40;
  double worst_before = 0, worst_after = 0, evaluations = 0;
  for (auto _ : state) {
    for (int j = 0; j < 20; ++j) {
      const FlankAxis ax = flank_axis(*face, (j + 0.5) / 20, &imp.hub(), cutter);
      if (!fit) {
        benchmark::DoNotOptimize(ax);
        continue;
      }
      const FlankAxisFit f = optimise_flank_axis(*face, ax, &imp.hub(), cutter, o);
      worst_before = std::max(worst_before, f.before.max_abs_mm);
      worst_after = std::max(worst_after, f.after.max_abs_mm);
      evaluations += f.evaluations;
    }
  }
  state.SetItemsProcessed(state.iterations() * 20);
  if (fit) {
    state.counters["before_um"] = worst_before * 1000;
    state.counters["after_um"] = worst_after * 1000;
    state.counters["evaluations_per_pose"] = evaluations / (20.0 * state.iterations());
  }
}
BENCHMARK(BM_ImpellerFlankAxisPerPose)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The outer channel on main 1's side of splitter 1, as the recipe plans it
// (stock 0.5, least stock 0.2, h 0.01, 5 mm levels).
ChannelRequest outer_channel(const Impeller& imp, const FlankCutter& cutter, const std::shared_ptr<const Surface>& left,
                             const std::shared_ptr<const Surface>& right) {
  ChannelRequest rq;
  rq.left = {left.get(), 0.35, 1};  // roughly from the splitter's leading edge
  rq.right = {right.get(), 1, 0};
  rq.hub = &imp.hub();
  rq.cutter = &cutter;
  rq.stock_mm = 0.5;
  rq.clearances.cutter_mm = 0.2;
  rq.clearances.shank_mm = rq.clearances.holder_mm = 0.5;
  return rq;
}

void BM_ImpellerChannelGeometry41Stations(benchmark::State& state) {
  const Impeller imp(builtin_impeller_definition());
  const auto left = imp.face(BladeKind::kMain, 0, CamberSide::kMinus);
  const auto right = imp.face(BladeKind::kSplitter, 0, CamberSide::kPlus);
  const FlankCutter cutter(cutter_tool(), 3);
  const ChannelRequest rq = outer_channel(imp, cutter, left, right);
  ChannelPlan plan;
  for (auto _ : state) plan = plan_channel(rq);
  state.counters["poses"] = static_cast<double>(plan.poses);
  state.counters["paths"] = static_cast<double>(plan.widen_left + plan.widen_right);
}
BENCHMARK(BM_ImpellerChannelGeometry41Stations)->Unit(benchmark::kMillisecond);

void BM_ImpellerChannelChecked(benchmark::State& state) {
  const Impeller imp(builtin_impeller_definition());
  const auto left = imp.face(BladeKind::kMain, 0, CamberSide::kMinus);
  const auto right = imp.face(BladeKind::kSplitter, 0, CamberSide::kPlus);
  const FlankCutter cutter(cutter_tool(), 3);
  const ToolBody body(cutter.tool());
  CollisionWorld world;
  CheckSurfaceOptions all;
  all.margin_mm = 0.05;
  world.add("hub", tessellate(imp.hub(), 0.05), all);
  for (auto [kind, k] : {std::pair{BladeKind::kMain, 0}, std::pair{BladeKind::kMain, 1}, std::pair{BladeKind::kSplitter, 0}})
    for (CamberSide side : {CamberSide::kPlus, CamberSide::kMinus})
      world.add(std::to_string(int(kind)) + std::to_string(k) + std::to_string(int(side)),
                tessellate(*imp.face(kind, k, side), 0.05), all);
  ChannelRequest rq = outer_channel(imp, cutter, left, right);
  rq.world = &world;
  rq.body = &body;
  rq.stations = static_cast<int>(state.range(0));
  ChannelPlan plan;
  for (auto _ : state) plan = plan_channel(rq);
  state.counters["poses"] = static_cast<double>(plan.poses);
  state.counters["refused"] = static_cast<double>(plan.refusals.size());
  state.counters["complete"] = plan.complete;
}
BENCHMARK(BM_ImpellerChannelChecked)->Arg(11)->Iterations(1)->Unit(benchmark::kMillisecond);

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
