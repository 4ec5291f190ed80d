// Geometry kernel speed: grid interpolation (blisk paper's 100 x 500) and
// its growth with the grid, surface evaluation with curvature, projection.
#include <benchmark/benchmark.h>

#include <cmath>

#include "core/geometry/differential.h"
#include "core/geometry/interpolation.h"
#include "core/geometry/projection.h"

namespace bliskrun {
namespace {

PointGrid blade_grid(int rows, int cols) {
  PointGrid g(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const double a = 30.0 * i / (rows - 1), b = 40.0 * j / (cols - 1);
      const double twist = 0.6 * a / 30, camber = 3.0 * std::sin(kPi * b / 40);
      g.at(i, j) = Vec3((b - 20) * std::cos(twist) - camber * std::sin(twist),
                        (b - 20) * std::sin(twist) + camber * std::cos(twist), a);
    }
  return g;
}

void BM_InterpolateGrid(benchmark::State& state) {
  const PointGrid g = blade_grid(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  for (auto _ : state) benchmark::DoNotOptimize(interpolate_grid(g));
  state.SetItemsProcessed(state.iterations() * state.range(0) * state.range(1));
}
BENCHMARK(BM_InterpolateGrid)->Args({100, 500})->Args({200, 1000})->Unit(benchmark::kMillisecond);

void BM_CurvatureOverGrid(benchmark::State& state) {
  const BSplineSurface s = interpolate_grid(blade_grid(100, 500));
  const int nu = static_cast<int>(state.range(0)), nv = static_cast<int>(state.range(1));
  for (auto _ : state) {
    double k = 0;
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) k = std::max(k, curvature(s.eval(i / (nu - 1.0), j / (nv - 1.0))).k1);
    benchmark::DoNotOptimize(k);
  }
  state.SetItemsProcessed(state.iterations() * nu * nv);
}
BENCHMARK(BM_CurvatureOverGrid)->Args({100, 500})->Args({200, 1000})->Unit(benchmark::kMillisecond);

void BM_ProjectToSurface(benchmark::State& state) {
  const BSplineSurface s = interpolate_grid(blade_grid(100, 500));
  int k = 0;
  for (auto _ : state) {
    const double u = (k % 97) / 97.0, v = (k % 89) / 89.0;
    benchmark::DoNotOptimize(project_to_surface(s, s.point(u, v) + Vec3(0.3, -0.2, 0.1)));
    ++k;
  }
}
BENCHMARK(BM_ProjectToSurface)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace bliskrun
