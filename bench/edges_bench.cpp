// Cost of blade-edge finishing with a flat-end bottom (issue 14) on the
// built-in blisk's leading edge of blade 1, tool R = 3, r = 0.5, band
// (-0.001, 0.02) mm, chord 0.001 mm: the strip width of one pose (condition
// ① over 81 x 5 strip samples, 21 x 41 over the region and 21 x 12 on each
// flank beyond it), the φ/l optimisation and checks of one row, and each
// whole edge as blade_edges.lua plans it (the whole span fitted to the hub
// and casing, shank and holder clearances 0.1 / 0.5 mm: rows, side-edge
// rows, tilting, partial rows, world checks with the neighbours' flanks,
// the hub and the blade itself for the shank, links). The budget is per
// emitted pose (issue 38 item 6: a budget per edge does not scale with the
// part): ms_per_pose is the process CPU time of the plan (every thread)
// over the poses emitted; the recipe's final simulation is not in it.
#include <benchmark/benchmark.h>

#include <ctime>
#include <memory>

#include "core/geometry/mesh.h"
#include "core/geometry/revolution.h"
#include "core/geometry/revolution_distance.h"
#include "core/parts/builtin_blisk.h"
#include "core/parts/edge_region.h"
#include "core/planning/edge_finish.h"

namespace bliskrun {
namespace {

struct EdgeSetup {
  BuiltinBlisk blisk;
  EdgeRegion edge, trailing;
  std::shared_ptr<const Surface> first, second;
  Tool tool = Tool::flat_end_mill({3, 0.5, 9, {6, 50}, {12, 40}});
  CollisionWorld hub_only, world;
  std::shared_ptr<const SurfaceOfRevolution> hub = std::make_shared<SurfaceOfRevolution>(blisk.hub_meridian()),
                                             casing = std::make_shared<SurfaceOfRevolution>(blisk.casing_meridian());

  EdgeSetup() {
    EdgeRegionRequest er;
    er.first = blisk.flank_surface(0, FlankSide::kPressure);
    er.second = blisk.flank_surface(0, FlankSide::kSuction);
    edge = build_edge_region(er);
    first = er.first;
    second = er.second;
    EdgeRegionRequest te;  // the flank whose edge end is at v = 0 first: suction for the TE
    te.first = er.second;
    te.second = er.first;
    trailing = build_edge_region(te);
    const TriangleMesh hub_mesh = tessellate(*hub, 0.01);
    hub_only.add("hub", hub_mesh);
    world.add("hub", std::make_shared<RevolutionDistance>(*hub, 0.01));
    for (int b : {1, 21})
      for (FlankSide s : {FlankSide::kPressure, FlankSide::kSuction})
        world.add("blade " + std::to_string(b) + (s == FlankSide::kPressure ? " p" : " s"),
                  tessellate(*blisk.flank_surface(b, s), 0.01));
    CheckSurfaceOptions own;
    own.parts.cutter = false;
    own.margin_mm = 0.05;
    world.add("own p", tessellate(*blisk.flank_surface(0, FlankSide::kPressure), 0.05), own);
    world.add("own s", tessellate(*blisk.flank_surface(0, FlankSide::kSuction), 0.05), own);
  }
  EdgeFinishRequest request(const CollisionWorld& w, double v0, double v1) const {
    EdgeFinishRequest rq;
    rq.edge = edge.surface;
    rq.first = first;
    rq.second = second;
    rq.tool = &tool;
    rq.world = &w;
    rq.sampling.half_width_mm = 4;
    rq.sampling.gouge_half_mm = 4;
    rq.v0 = v0;
    rq.v1 = v1;
    return rq;
  }
  // As blade_edges.lua plans it: the window fitted to the hub and casing,
  // the recipe's clearances (shank 0.1 mm, holder 0.5 mm).
  EdgeFinishRequest recipe_request(bool trailing_edge) const {
    EdgeFinishRequest rq = request(world, 0, 1);
    if (trailing_edge) {
      rq.edge = trailing.surface;
      rq.first = second;
      rq.second = first;
    }
    rq.hub = hub;
    rq.casing = casing;
    rq.clearances.shank_mm = 0.1;
    rq.clearances.holder_mm = 0.5;
    return rq;
  }
};

EdgeSetup& setup() {
  static EdgeSetup s;
  return s;
}

void BM_EdgeStripWidthOnePose(benchmark::State& state) {
  EdgeSetup& s = setup();
  const EdgeFinishRequest rq = s.request(s.hub_only, 0.1, 0.9);
  const EdgeFrame f = edge_frame(s.edge.surface->eval(0.5, 0.5));
  StripSamples smp = sample_strip(*s.edge.surface, 0.5, 0.5, rq.sampling);
  add_flank_samples(smp, *s.first, 0.5, 0.0, rq.sampling);
  add_flank_samples(smp, *s.second, 0.5, 1.0, rq.sampling);
  const ContactStrip strip(s.tool, f, smp, rq.band);
  double phi = -1.2;
  for (auto _ : state) {
    const StripWidth w = strip.width({EdgeContact::Bottom, 2.0, 0, phi});
    benchmark::DoNotOptimize(w.width_mm);
    phi = phi < -1.0 ? phi + 0.01 : -1.2;
  }
  state.counters["samples"] = static_cast<double>(smp.p.size() + smp.gouge_p.size());
}
BENCHMARK(BM_EdgeStripWidthOnePose)->Unit(benchmark::kMicrosecond);

// Sampling one contact (edge region and both flanks beyond it): paid once per contact.
void BM_EdgeStripSamplesOneContact(benchmark::State& state) {
  EdgeSetup& s = setup();
  const EdgeFinishRequest rq = s.request(s.hub_only, 0.1, 0.9);
  for (auto _ : state) {
    StripSamples smp = sample_strip(*s.edge.surface, 0.5, 0.5, rq.sampling);
    add_flank_samples(smp, *s.first, 0.5, 0.0, rq.sampling);
    add_flank_samples(smp, *s.second, 0.5, 1.0, rq.sampling);
    benchmark::DoNotOptimize(smp.p.data());
  }
}
BENCHMARK(BM_EdgeStripSamplesOneContact)->Unit(benchmark::kMillisecond);

// One row: contacts by chord height, the φ search at each l_j, the
// averaged φ, l balancing, corner contacts, the side-edge row, checks.
void BM_EdgeOneRow(benchmark::State& state) {
  EdgeSetup& s = setup();
  const EdgeFinishRequest rq = s.request(s.hub_only, 0.5, 0.5001);
  for (auto _ : state) {
    const EdgeFinishResult r = plan_edge_finish(rq);
    benchmark::DoNotOptimize(r.total_poses);
    state.counters["rows"] = static_cast<double>(r.rows.size());
    state.counters["poses"] = r.total_poses;
  }
}
BENCHMARK(BM_EdgeOneRow)->Unit(benchmark::kMillisecond)->Iterations(3);

// Args: the edge (0 leading, 1 trailing) and the planner's threads (a
// row's contacts and guard sweeps; the rest runs on one). ms_per_pose: the
// process's CPU (every thread) per emitted pose; "Time" is wall.
void BM_EdgeWholeEdge(benchmark::State& state) {
  EdgeSetup& s = setup();
  EdgeFinishRequest rq = s.recipe_request(state.range(0) == 1);
  rq.threads = static_cast<int>(state.range(1));
  for (auto _ : state) {
    const std::clock_t cpu0 = std::clock();
    const EdgeFinishResult r = plan_edge_finish(rq);
    const double cpu_s = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
    benchmark::DoNotOptimize(r.total_poses);
    const EdgeProgramStats st = edge_program_stats(r);
    state.counters["cpu_s"] = cpu_s;
    state.counters["ms_per_pose"] = r.total_poses > 0 ? 1e3 * cpu_s / r.total_poses : 0;
    state.counters["passes"] = st.passes;
    state.counters["rows"] = static_cast<double>(r.rows.size());
    state.counters["side_rows"] = r.side_rows;
    state.counters["poses"] = r.total_poses;
    state.counters["refused"] = r.total_refusals + r.refused_links;
    state.counters["rows_s"] = r.rows_seconds;
    state.counters["side_s"] = r.side_seconds;
    state.counters["clear_s"] = r.clear_seconds;
    state.counters["checks_s"] = r.checks_seconds;
    state.counters["sim_s"] = r.simulation_seconds;
    state.counters["links_s"] = r.links_seconds;
    state.counters["tilted"] = 0;
    for (const EdgeFinishRow& row : r.rows) state.counters["tilted"] += row.tilted_contacts;
  }
}
BENCHMARK(BM_EdgeWholeEdge)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Args({0, 1})
    ->Args({1, 1})
    ->Args({0, 2})
    ->UseRealTime();

}  // namespace
}  // namespace bliskrun
