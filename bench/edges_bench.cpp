// Cost of blade-edge finishing with a flat-end bottom (issue 14) on the
// built-in blisk's leading edge of blade 1, tool R = 3, r = 0.5, band
// (-0.001, 0.02) mm, chord 0.001 mm: the strip width of one pose (condition
// ① over 81 x 5 strip samples, 21 x 41 over the region and 21 x 12 on each
// flank beyond it), the φ/l optimisation and checks of one row, and each
// whole edge as blade_edges.lua plans it (the whole span fitted to the hub
// and casing, shank and holder clearances 0.1 / 0.5 mm: rows, side-edge
// rows, tilting, partial rows, world checks with the neighbours' flanks and edge rounds,
// the hub and the blade itself (flanks and edge rounds) for the shank, links). The budget is per
// emitted pose (issue 38 item 6: a budget per edge does not scale with the
// part): ms_per_pose is the process CPU time of the plan (every thread)
// over the poses emitted; the recipe's final simulation is not in it.
// BM_EdgeWholeEdgeRotor67: the same on NASA Rotor 67's blade 1 as the
// recipe builds it (flanks lofted to the edge points with cosine columns,
// both neighbours, the hub measured analytically, a 120 mm shank); skipped without
// ../shared/data.
#include <benchmark/benchmark.h>

#include <ctime>
#include <filesystem>
#include <memory>
#include <string>

#include "core/geometry/interpolation.h"
#include "core/geometry/mesh.h"
#include "core/geometry/revolution.h"
#include "core/geometry/revolution_distance.h"
#include "core/io/rotor67_reader.h"
#include "core/parts/blade_model.h"
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
    for (int b : {1, 21}) {
      for (FlankSide s : {FlankSide::kPressure, FlankSide::kSuction})
        world.add("blade " + std::to_string(b) + (s == FlankSide::kPressure ? " p" : " s"),
                  tessellate(*blisk.flank_surface(b, s), 0.01));
      for (bool leading : {true, false})
        world.add("blade " + std::to_string(b) + (leading ? " LE" : " TE"), tessellate(*edge_round(b, leading), 0.01));
    }
    CheckSurfaceOptions own;
    own.parts.cutter = false;
    own.margin_mm = 0.05;
    world.add("own p", tessellate(*blisk.flank_surface(0, FlankSide::kPressure), 0.05), own);
    world.add("own s", tessellate(*blisk.flank_surface(0, FlankSide::kSuction), 0.05), own);
    world.add("own LE", tessellate(*edge_round(0, true), 0.05), own);
    world.add("own TE", tessellate(*edge_round(0, false), 0.05), own);
  }
  // Blade b's edge round as blisk_world.edge_round builds it: no overlap,
  // from the hub row up to where the edge end leaves the casing.
  std::shared_ptr<const Surface> edge_round(int b, bool leading) const {
    EdgeRegionRequest r;
    r.first = blisk.flank_surface(b, leading ? FlankSide::kPressure : FlankSide::kSuction);
    r.second = blisk.flank_surface(b, leading ? FlankSide::kSuction : FlankSide::kPressure);
    r.overlap_mm = 0;
    auto beyond = [&](double u) { return casing->radial_offset(r.first->point(u, 0)) > 0; };
    double lo = 0, hi = 1;
    if (beyond(1))
      for (int k = 0; k < 40; ++k) (beyond(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
    r.span_u1 = hi;
    return build_edge_region(r).surface;
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

// NASA Rotor 67 blade 1 as scripts/recipes/blade_edges.lua builds it.
struct Rotor67Setup {
  std::shared_ptr<const Surface> pressure, suction;
  EdgeRegion leading, trailing;
  std::shared_ptr<const SurfaceOfRevolution> hub, casing;
  Tool tool = Tool::flat_end_mill({3, 0.5, 9, {6, 120}, {12, 40}});
  CollisionWorld world;

  explicit Rotor67Setup(const std::string& file) {
    const BladeSections blade = blade_sections(read_rotor67(file));
    LoftOptions lo;
    lo.edge_margin = 0;
    lo.spacing = ColumnSpacing::cosine;
    const BladeLoft loft = loft_blade(blade, lo);
    pressure = std::make_shared<BSplineSurface>(interpolate_grid(loft.pressure));
    suction = std::make_shared<BSplineSurface>(interpolate_grid(loft.suction));
    auto distinct = [](const std::vector<Vec2>& m) {
      std::vector<Vec2> out;
      for (const Vec2& p : m)
        if (out.empty() || (p - out.back()).norm() > 1e-9) out.push_back(p);
      return out;
    };
    hub = std::make_shared<SurfaceOfRevolution>(distinct(blade.hub_meridian));
    casing = std::make_shared<SurfaceOfRevolution>(distinct(blade.casing_meridian));
    const double pitch = 2 * kPi / blade.blade_count;
    for (double turn : {-pitch, pitch})
      for (const PointGrid* g : {&loft.pressure, &loft.suction}) {
        PointGrid r = *g;
        const Eigen::AngleAxisd rot(turn, Vec3::UnitZ());
        for (Vec3& p : r.points) p = rot * p;
        world.add(std::string(turn < 0 ? "blade before " : "blade after ") + (g == &loft.pressure ? "p" : "s"),
                  tessellate(interpolate_grid(r), 0.01));
      }
    world.add("hub", std::make_shared<RevolutionDistance>(*hub, 0.01));
    CheckSurfaceOptions own;
    own.parts.cutter = false;
    own.margin_mm = 0.05;
    world.add("own p", tessellate(*pressure, 0.05), own);
    world.add("own s", tessellate(*suction, 0.05), own);
    EdgeRegionRequest le;
    le.first = pressure;
    le.second = suction;
    leading = build_edge_region(le);
    EdgeRegionRequest te;
    te.first = suction;
    te.second = pressure;
    trailing = build_edge_region(te);
  }
  EdgeFinishRequest request(bool trailing_edge) const {
    EdgeFinishRequest rq;
    rq.edge = trailing_edge ? trailing.surface : leading.surface;
    rq.first = trailing_edge ? suction : pressure;
    rq.second = trailing_edge ? pressure : suction;
    rq.tool = &tool;
    rq.world = &world;
    rq.sampling.half_width_mm = 4;
    rq.sampling.gouge_half_mm = 4;
    rq.hub = hub;
    rq.casing = casing;
    rq.clearances.shank_mm = 0.1;
    rq.clearances.holder_mm = 0.5;
    return rq;
  }
};

const std::string kRotor67 = std::string(BLISKRUN_SOURCE_DIR) + "/../shared/data/nasa_rotor67/rotor67geometry.dat";

Rotor67Setup& rotor67() {
  static Rotor67Setup s(kRotor67);
  return s;
}

// ms_per_pose and the rest as BM_EdgeWholeEdge.
void whole_edge_counters(benchmark::State& state, const EdgeFinishRequest& rq) {
  for (auto _ : state) {
    const std::clock_t cpu0 = std::clock();
    const EdgeFinishResult r = plan_edge_finish(rq);
    const double cpu_s = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
    benchmark::DoNotOptimize(r.total_poses);
    const EdgeProgramStats st = edge_program_stats(r);
    state.counters["cpu_s"] = cpu_s;
    state.counters["ms_per_pose"] = r.total_poses > 0 ? 1e3 * cpu_s / r.total_poses : 0;
    state.counters["passes"] = st.passes;
    state.counters["lifted"] = st.lifted_links;
    state.counters["cut_mm"] = st.cutting_mm;
    state.counters["noncut_mm"] = st.non_cutting_mm;
    state.counters["lift_mm"] = st.lift_mm;
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

// Args: the edge (0 leading, 1 trailing), the planner's threads (a row's
// contacts and guard sweeps; the rest runs on one) and the short lift in um
// (EdgeFinishRequest::short_lift_mm; 0: off, the default). ms_per_pose: the
// process's CPU (every thread) per emitted pose; "Time" is wall.
void BM_EdgeWholeEdge(benchmark::State& state) {
  EdgeSetup& s = setup();
  EdgeFinishRequest rq = s.recipe_request(state.range(0) == 1);
  rq.threads = static_cast<int>(state.range(1));
  rq.short_lift_mm = 1e-3 * static_cast<double>(state.range(2));
  whole_edge_counters(state, rq);
}
BENCHMARK(BM_EdgeWholeEdge)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Args({0, 1, 0})
    ->Args({1, 1, 0})
    ->Args({0, 2, 0})
    ->Args({0, 1, 200})
    ->Args({1, 1, 200})
    ->UseRealTime();

// Args: the edge (0 leading, 1 trailing), the planner's threads, the short
// lift in um (as BM_EdgeWholeEdge).
void BM_EdgeWholeEdgeRotor67(benchmark::State& state) {
  if (!std::filesystem::exists(kRotor67)) return state.SkipWithError("../shared/data not present");
  EdgeFinishRequest rq = rotor67().request(state.range(0) == 1);
  rq.threads = static_cast<int>(state.range(1));
  rq.short_lift_mm = 1e-3 * static_cast<double>(state.range(2));
  whole_edge_counters(state, rq);
}
BENCHMARK(BM_EdgeWholeEdgeRotor67)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Args({0, 1, 0})
    ->Args({1, 1, 0})
    ->Args({0, 1, 200})
    ->Args({1, 1, 200})
    ->UseRealTime();

}  // namespace
}  // namespace bliskrun
