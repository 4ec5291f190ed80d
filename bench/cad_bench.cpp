// CAD reading (issue 36 item 8: the E3 blade's IGES <= 50 ms) and a STEP
// round trip of a bicubic B-spline face. The E3 file is in ../shared/data
// beside the clone (BLISKRUN_SHARED_DATA overrides); without it the bench
// says so and skips.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "core/cad/cad.h"

namespace bliskrun {
namespace {

std::string e3_blade() {
  namespace fs = std::filesystem;
  const char* env = std::getenv("BLISKRUN_SHARED_DATA");
  const fs::path data = env ? fs::path(env) : fs::path(BLISKRUN_SOURCE_DIR) / ".." / "shared" / "data";
  const fs::path p = data / "e3_hpt_stage1" / "hpt_stator1.igs";  // the rotor blade (names swapped)
  return fs::exists(p) ? p.string() : "";
}

void BM_ReadE3BladeIges(benchmark::State& state) {
  const std::string path = e3_blade();
  if (path.empty()) {
    state.SkipWithError("../shared/data/e3_hpt_stage1 not present");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(read_cad(path));
}
BENCHMARK(BM_ReadE3BladeIges)->Unit(benchmark::kMillisecond);

void BM_ReadStepBSplineFace(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  std::vector<Vec3> ctrl;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) ctrl.emplace_back(i, j, std::sin(0.3 * i) * std::cos(0.2 * j));
  std::vector<double> knots(n + 4);
  for (int k = 0; k < n + 4; ++k) knots[k] = std::clamp(k - 3, 0, n - 3) / double(n - 3);
  const NurbsSurface s(3, 3, knots, knots, n, n, ctrl, std::vector<double>(ctrl.size(), 1.0));
  const std::string path = (std::filesystem::temp_directory_path() / "bliskrun_bench_face.step").string();
  write_step(path, {&s});
  for (auto _ : state) benchmark::DoNotOptimize(read_cad(path));
  std::filesystem::remove(path);
}
BENCHMARK(BM_ReadStepBSplineFace)->Arg(100)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace bliskrun
