// Cost of blisk flank finishing with a drum wheel (issue 4): planning one
// flank of the built-in blisk (trim, rows, steps, tilt-until-clear with
// swept checks, links), simulating it at 200 x 1000 samples, and planning
// both flanks of every blade on two threads. Wheel 2 of the blisk paper's
// Table 3 (D_t 8, R_c 50, L_c 4, shank 6 x 96), residual 14 um, chord 2 um,
// variable chord height.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "core/parts/builtin_blisk.h"
#include "core/planning/drum_finish.h"
#include "core/sim/undercut.h"

namespace bliskrun {
namespace {

// The paper's C +-30 deg about the radial direction through the flank's
// middle (as scripts/lib/blisk_finish.lua).
RotaryAxisLimit c_limit(const Surface& flank) {
  const Vec3 p = flank.point(0.5, 0.5);
  const double a = std::atan2(p.y(), p.x());
  RotaryAxisLimit l;
  l.rotary_axis = Vec3(-std::sin(a), std::cos(a), 0);
  l.reference = Vec3(std::cos(a), std::sin(a), 0);
  return l;
}

// The built-in blisk with its hub and casing, and the check surfaces around
// each blade (neighbours' flanks and the hub), built once.
struct BliskSetup {
  BuiltinBlisk blisk;
  SurfaceOfRevolution hub{blisk.hub_meridian()}, casing{blisk.casing_meridian()};
  Tool wheel = Tool::drum_wheel({8, 50, 4, {6, 96}, {}});
  TriangleMesh hub_mesh = tessellate(hub, 0.01);
  std::vector<TriangleMesh> flank_meshes[2];  // per side, per blade
  std::vector<TriangleMesh> own_meshes[2];    // coarse (0.05 mm), for the shank
  std::vector<CollisionWorld> worlds;         // per blade

  BliskSetup() {
    const int n = blisk.blade_count();
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < n; ++k)
      {
        const auto flank = blisk.flank_surface(k, side ? FlankSide::kSuction : FlankSide::kPressure);
        flank_meshes[side].push_back(tessellate(*flank, 0.01));
        own_meshes[side].push_back(tessellate(*flank, 0.05));
      }
    worlds.resize(n);
    for (int k = 0; k < n; ++k) {
      for (int nb : {(k + n - 1) % n, (k + 1) % n})
        for (int side = 0; side < 2; ++side)
          worlds[k].add("blade " + std::to_string(nb) + (side ? " suction" : " pressure"),
                        flank_meshes[side][nb]);
      worlds[k].add("hub", hub_mesh);
      // The blade itself, for the shank only (as scripts/lib/blisk_world.lua).
      PartMask shank_only;
      shank_only.cutter = false;
      for (int side = 0; side < 2; ++side)
        worlds[k].add(std::string("own ") + (side ? "suction" : "pressure"), own_meshes[side][k], {shank_only, 0.05});
    }
  }

  DrumFinishRequest request(int blade, FlankSide side) const {
    DrumFinishRequest rq;
    rq.flank = blisk.flank_surface(blade, side);
    rq.hub = &hub;
    rq.casing = &casing;
    rq.tool = &wheel;
    rq.world = &worlds[blade];
    rq.residual_height_mm = 0.014;
    rq.steps.chord_tol_mm = 0.002;
    rq.tilt.clearances = {0, 0.1, 1};  // as scripts/lib/blisk_finish.lua
    rq.tilt.axis_limit = make_axis_limit(c_limit(*rq.flank));
    return rq;
  }
};

const BliskSetup& setup() {
  static const BliskSetup s;
  return s;
}

void BM_PlanOneFlank(benchmark::State& state) {
  const BliskSetup& s = setup();
  const DrumFinishRequest rq = s.request(0, state.range(0) ? FlankSide::kSuction : FlankSide::kPressure);
  DrumFinishResult r;
  for (auto _ : state) r = plan_drum_finish(rq);
  state.counters["rows"] = static_cast<double>(r.rows.size());
  state.counters["poses"] = r.total_poses;
  state.counters["refusals"] = r.total_refusals;
  state.counters["refused_links"] = r.refused_links;
  state.counters["first_row_u"] = r.first_row_u;
  state.counters["max_dev_um"] = 1e3 * r.max_deviation_mm;
  state.counters["tilt_s"] = r.tilt_seconds;
  state.counters["inserted_rows"] = r.inserted_rows;
  state.counters["trim_s"] = r.trim_seconds;
  state.counters["rows_s"] = r.rows_seconds;
  state.counters["link_s"] = r.link_seconds;
}
BENCHMARK(BM_PlanOneFlank)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_SimulateOneFlank(benchmark::State& state) {
  const BliskSetup& s = setup();
  const DrumFinishRequest rq = s.request(0, FlankSide::kPressure);
  const DrumFinishResult plan = plan_drum_finish(rq);
  UndercutOptions o;
  o.u0 = plan.first_row_u;
  o.threads = static_cast<int>(state.range(0));
  o.search_above_mm = o.search_below_mm = state.range(1) * 1e-3;
  o.sweep_step_mm = state.range(2) * 1e-3;
  UndercutResult r;
  for (auto _ : state) r = simulate_undercut(*plan.trimmed, s.wheel, drum_finish_passes(plan).passes, o);
  state.counters["undercut_max_um"] = 1e3 * r.undercut_max_mm;
  state.counters["undercut_std_um"] = 1e3 * r.undercut_std_mm;
  state.counters["overcut_um"] = 1e3 * r.overcut_mm;
  state.counters["untouched"] = r.untouched;
  state.counters["positions"] = static_cast<double>(r.tool_positions);
  state.counters["lines"] = static_cast<double>(r.line_evaluations);
}
BENCHMARK(BM_SimulateOneFlank)->Args({1, 100, 50})->Args({2, 100, 50})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PlanAllBlades(benchmark::State& state) {
  const BliskSetup& s = setup();
  std::vector<DrumFinishRequest> requests;
  for (int k = 0; k < s.blisk.blade_count(); ++k)
    for (FlankSide side : {FlankSide::kPressure, FlankSide::kSuction}) requests.push_back(s.request(k, side));
  long poses = 0;
  for (auto _ : state) {
    poses = 0;
    for (const DrumFinishResult& r : plan_drum_finish_all(requests, static_cast<int>(state.range(0))))
      poses += r.total_poses;
  }
  state.counters["flanks"] = static_cast<double>(requests.size());
  state.counters["poses"] = static_cast<double>(poses);
}
BENCHMARK(BM_PlanAllBlades)->Arg(2)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace
}  // namespace bliskrun
