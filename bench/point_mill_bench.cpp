// Point milling's root strip measure (issue 40) on one real face: the NASA
// HECC impeller's main blade, pressure face lofted from the archive's
// sections (as parts_bench rebuilds it), on its own hub meridian, planned
// once with the job's tapered ball (r 2, 2 deg), scallop 20 um, chord 5 um,
// rows carried down to the fillet line. Then the strip from the fillet line
// to 6 mm above the face's edge measured at 12 x 200 samples: through the
// PointIndex of the moves' centre segments (measure_root_strip) and by the
// brute force it replaced (every sample against every segment). Skipped
// without ../shared/data.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <memory>

#include "core/geometry/interpolation.h"
#include "core/geometry/revolution.h"
#include "core/io/hecc_reader.h"
#include "core/parts/blade_model.h"
#include "core/planning/point_milling.h"
#include "core/toolpath/move.h"

namespace bliskrun {
namespace {

struct PointMillBenchFace {
  std::shared_ptr<const Surface> face;
  Tool tool = Tool::tapered_ball_end_mill({2, 2 * kPi / 180, 90, {12, 60}, {40, 60}});
  PointMillRequest rq;
  PointMillResult res;
  bool ok = false;
};

const PointMillBenchFace& point_mill_bench_face() {
  static const PointMillBenchFace f = [] {
    PointMillBenchFace out;
    const std::string dir = std::string(BLISKRUN_SOURCE_DIR) + "/../shared/data/nasa_hecc_impeller";
    if (!std::filesystem::exists(dir)) return out;
    const BladeSections blade = read_hecc_impeller(dir, HeccSet::design_intent, HeccBlade::main);
    const BladeLoft loft = loft_blade(blade);
    out.face = std::make_shared<const BSplineSurface>(interpolate_grid(loft.pressure));
    const BSplineSurface suction = interpolate_grid(loft.suction);
    const SurfaceDerivs d = out.face->eval(0.5, 0.5);
    const Vec3 q = suction.eval(0.5, 0.5).p;
    out.rq.face = {"HECC main pressure face", out.face, d.pu.cross(d.pv).dot(d.p - q) < 0};
    out.rq.tool = &out.tool;
    out.rq.hub = std::make_shared<const SurfaceOfRevolution>(blade.hub_meridian);
    out.rq.hub_stop_mm = 6;
    out.rq.scallop_mm = 0.02;
    out.rq.steps.chord_tol_mm = 0.005;
    out.rq.allowed_overcut_mm = 0.005;
    out.rq.clearances = {0, 0.5, 0.5};
    out.rq.threads = 2;
    out.res = plan_point_milling(out.rq);
    out.ok = true;
    return out;
  }();
  return f;
}

void BM_PointMillRootStripIndexed(benchmark::State& state) {
  const PointMillBenchFace& f = point_mill_bench_face();
  if (!f.ok) return state.SkipWithError("../shared/data not present");
  PointMillRequest rq = f.rq;
  rq.threads = 1;
  PointMillStrip st;
  for (auto _ : state) benchmark::DoNotOptimize(st = measure_root_strip(rq, f.res, 12, 200));
  state.counters["poses"] = f.res.poses;
  state.counters["samples"] = st.samples + st.corner_samples;
  state.counters["left_max_um"] = 1e3 * st.material_max_mm;
  state.counters["corner_max_um"] = 1e3 * st.corner_max_mm;
  state.counters["height_mm"] = st.height_mm;
}
BENCHMARK(BM_PointMillRootStripIndexed)->Unit(benchmark::kMillisecond);

// The brute force it replaced, over the same band's samples (each column
// from the indexed measure's lower edge, the fillet line, up to the top):
// its figure must be the indexed one's.
void BM_PointMillRootStripBruteForce(benchmark::State& state) {
  const PointMillBenchFace& f = point_mill_bench_face();
  if (!f.ok) return state.SkipWithError("../shared/data not present");
  PointMillRequest rq = f.rq;
  rq.threads = 1;
  const PointMillStrip st = measure_root_strip(rq, f.res, 12, 200);
  const double r = f.res.ball_radius_mm;
  std::vector<std::pair<Vec3, Vec3>> segs;
  for (const std::vector<ToolPose>& pass : toolpath_passes(point_mill_moves(f.res)).passes)
    for (size_t i = 0; i < pass.size(); ++i) {
      const Vec3 c = pass[i].tip + r * pass[i].axis;
      segs.emplace_back(i == 0 ? c : Vec3(pass[i - 1].tip + r * pass[i - 1].axis), c);
    }
  std::vector<Vec3> pts;
  for (int i = 0; i < 12; ++i)
    for (size_t j = 0; j < st.v.size(); ++j)
      if (st.u1 > st.lower_u[j])
        pts.push_back(f.face->eval(st.lower_u[j] + (st.u1 - st.lower_u[j]) * i / 12, st.v[j]).p);
  double worst = 0;
  for (auto _ : state) {
    worst = -std::numeric_limits<double>::infinity();
    for (const Vec3& p : pts) {
      double best = std::numeric_limits<double>::infinity();
      for (const auto& sg : segs) {
        const Vec3 d = sg.second - sg.first;
        const double dd = d.squaredNorm();
        const double t = dd > 0 ? std::clamp((p - sg.first).dot(d) / dd, 0.0, 1.0) : 0.0;
        best = std::min(best, (p - (sg.first + t * d)).norm());
      }
      worst = std::max(worst, best - r);
    }
    benchmark::DoNotOptimize(worst);
  }
  state.counters["left_max_um"] = 1e3 * worst;  // against the indexed measure's (its samples: the same band)
  state.counters["segments"] = static_cast<double>(segs.size());
  state.counters["samples"] = static_cast<double>(pts.size());
}
BENCHMARK(BM_PointMillRootStripBruteForce)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace bliskrun
