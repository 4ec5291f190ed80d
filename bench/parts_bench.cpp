// Real parts from ../shared/data: read the file, loft both flanks from the
// section loops (edge circles, resampling, span extension, fit of every given
// point by point inversion), interpolate the flank surfaces and build hub and
// casing as surfaces of revolution - what bliskrun.read_rotor67 and friends
// do before a recipe sees the part. Skipped without the data.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "core/geometry/interpolation.h"
#include "core/geometry/revolution.h"
#include "core/io/hecc_reader.h"
#include "core/io/rotor37_reader.h"
#include "core/io/rotor67_reader.h"
#include "core/parts/blade_model.h"

namespace bliskrun {
namespace {

const std::string kData = std::string(BLISKRUN_SOURCE_DIR) + "/../shared/data";

void rebuild(benchmark::State& state, const BladeSections& blade) {
  const BladeLoft loft = loft_blade(blade);
  benchmark::DoNotOptimize(interpolate_grid(loft.pressure));
  benchmark::DoNotOptimize(interpolate_grid(loft.suction));
  benchmark::DoNotOptimize(SurfaceOfRevolution(blade.hub_meridian));
  benchmark::DoNotOptimize(SurfaceOfRevolution(blade.casing_meridian));
  state.counters["fit_max_um"] = loft.fit.max_mm * 1000;
}

void BM_Rotor67ReadAndRebuild(benchmark::State& state) {
  const std::string file = kData + "/nasa_rotor67/rotor67geometry.dat";
  if (!std::filesystem::exists(file)) return state.SkipWithError("../shared/data not present");
  for (auto _ : state) rebuild(state, blade_sections(read_rotor67(file)));
}
BENCHMARK(BM_Rotor67ReadAndRebuild)->Unit(benchmark::kMillisecond);

void BM_Rotor37ReadAndRebuild(benchmark::State& state) {
  const std::string dir = kData + "/nasa_rotor37/agard_table/";
  if (!std::filesystem::exists(dir)) return state.SkipWithError("../shared/data not present");
  for (auto _ : state) rebuild(state, read_rotor37(dir + "rotor37geometry.dat", dir + "rotor37hub-shroud.dat"));
}
BENCHMARK(BM_Rotor37ReadAndRebuild)->Unit(benchmark::kMillisecond);

void BM_HeccMainReadAndRebuild(benchmark::State& state) {
  const std::string dir = kData + "/nasa_hecc_impeller";
  if (!std::filesystem::exists(dir)) return state.SkipWithError("../shared/data not present");
  for (auto _ : state) rebuild(state, read_hecc_impeller(dir, HeccSet::design_intent, HeccBlade::main));
}
BENCHMARK(BM_HeccMainReadAndRebuild)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace bliskrun
