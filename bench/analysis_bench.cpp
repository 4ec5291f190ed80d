// Curvature statistics over a reconstructed flank (the paper's 100 x 500 and
// a doubled 200 x 1000 sampling: cost should grow linearly with samples) and
// built-in blisk grid generation.
#include <benchmark/benchmark.h>

#include "core/analysis/curvature_stats.h"
#include "core/geometry/interpolation.h"
#include "core/parts/builtin_blisk.h"

namespace {

using namespace bliskrun;

const BSplineSurface& pressure_flank() {
  static const BSplineSurface flank =
      interpolate_grid(BuiltinBlisk().flank_grid(0, FlankSide::kPressure));
  return flank;
}

void BM_CurvatureStats(benchmark::State& state) {
  const BSplineSurface& flank = pressure_flank();
  CurvatureStatsOptions o;
  o.samples_u = static_cast<int>(state.range(0));
  o.samples_v = static_cast<int>(state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(curvature_stats(flank, o).ke_max.value);
  state.SetItemsProcessed(state.iterations() * o.samples_u * o.samples_v);
}
BENCHMARK(BM_CurvatureStats)->Args({100, 500})->Args({200, 1000})->Unit(benchmark::kMillisecond);

void BM_BliskFlankGrid(benchmark::State& state) {
  const BuiltinBlisk blisk;
  for (auto _ : state)
    benchmark::DoNotOptimize(blisk.flank_grid(3, FlankSide::kSuction).points.data());
  state.SetItemsProcessed(state.iterations() * 100 * 500);
}
BENCHMARK(BM_BliskFlankGrid)->Unit(benchmark::kMillisecond);

void BM_BliskNarrowestPassage(benchmark::State& state) {
  const BuiltinBlisk blisk;
  for (auto _ : state) benchmark::DoNotOptimize(blisk.narrowest_passage_mm());
}
BENCHMARK(BM_BliskNarrowestPassage)->Unit(benchmark::kMillisecond);

}  // namespace
