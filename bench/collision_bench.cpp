// Cost of the interference checks: per-pose clearance of a drum wheel with
// shank (blisk paper Table 3, wheel 2) against a passage of two cambered,
// twisted blade flanks and a hub, each tessellated into N triangles, and the
// swept check between consecutive poses of a row. First arg = N in
// thousands; second = query horizon in µm (-1: unbounded, exact distances);
// third = gap between the wheel and blade k+1 in µm; fourth = the tool's
// tessellation tolerance in µm.
#include <benchmark/benchmark.h>

#include <cmath>
#include <limits>

#include "core/collision/collision_world.h"
#include "core/collision/fast_check.h"

namespace bliskrun {
namespace {

// A blade-like flank: chord 40 mm along x, span 30 mm along z, camber 4 mm
// and a twist growing with the span.
Vec3 flank(double u, double v) {
  const double c = 40 * (v - 0.5);
  return Vec3(c, 4 * (1 - (2 * v - 1) * (2 * v - 1)) + 0.1 * c * u, 30 * u);
}

Vec3 flank_normal(double u, double v) {
  const double h = 1e-6;
  const Vec3 du = (flank(u + h, v) - flank(u - h, v)), dv = (flank(u, v + h) - flank(u, v - h));
  return dv.cross(du).normalized();
}

TriangleMesh flank_mesh(long triangles) {
  const int n = static_cast<int>(std::lround(std::sqrt(triangles / 2.0)));
  TriangleMesh m;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) m.vertices.push_back(flank(double(i) / n, double(j) / n));
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const int a = i * (n + 1) + j;
      m.triangles.emplace_back(a, a + n + 1, a + n + 2);
      m.triangles.emplace_back(a, a + n + 2, a + 1);
    }
  }
  return m;
}

// A row of poses along the chord at 40 % span, the wheel's widest ring
// `gap_mm` off the flank, axis up the span.
std::vector<ToolPose> row_poses(int count, double gap_mm) {
  std::vector<ToolPose> poses;
  for (int k = 0; k < count; ++k) {
    const double v = 0.1 + 0.8 * k / (count - 1);
    const Vec3 a = Vec3(0, 0.05, 1).normalized();
    poses.push_back(ToolPose{flank(0.4, v) + (4 + gap_mm) * flank_normal(0.4, v) - 2 * a, a});
  }
  return poses;
}

ToolBody wheel(double tol_mm) { return ToolBody(Tool::drum_wheel({8, 50, 4, {6, 96}, {}}), tol_mm); }

// Blade k+1 (the flank the wheel works beside, 1 mm off), blade k-1 one
// pitch away and the hub below, each of about N triangles.
CollisionWorld passage(long triangles) {
  CollisionWorld world;
  TriangleMesh blade = flank_mesh(triangles);
  world.add("blade k+1", blade);
  for (Vec3& v : blade.vertices) v.y() -= 14;
  world.add("blade k-1", blade);
  TriangleMesh hub = flank_mesh(triangles);
  for (Vec3& v : hub.vertices) v = Vec3(v.x(), -7 + 20 * (v.z() / 30 - 0.5), -1 - 0.02 * v.x() * v.x() / 40);
  world.add("hub", hub);
  return world;
}

double horizon_of(const benchmark::State& state) {
  return state.range(1) < 0 ? std::numeric_limits<double>::infinity() : state.range(1) * 1e-3;
}

void BM_PoseClearance(benchmark::State& state) {
  const CollisionWorld world = passage(state.range(0) * 1000);
  const std::vector<ToolPose> poses = row_poses(640, state.range(2) * 1e-3);
  const ToolBody body = wheel(state.range(3) * 1e-3);
  const Clearances clearances{0.5, 0.5, 0};
  const double horizon = horizon_of(state);
  size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(world.check(body, poses[k++ % poses.size()], clearances, horizon));
  }
  state.counters["poses/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["triangles"] = static_cast<double>(world.triangle_count(0) + world.triangle_count(1) + world.triangle_count(2));
}
BENCHMARK(BM_PoseClearance)
    ->Args({10, 0, 2500, 1})->Args({100, 0, 2500, 1})->Args({400, 0, 2500, 1})
    ->Args({100, 0, 1000, 1})->Args({100, 0, 2500, 5})->Args({100, 0, 1000, 5})
    ->Args({100, 1000, 2500, 1})
    ->Args({10, -1, 2500, 1})->Args({100, -1, 2500, 1})->Args({400, -1, 2500, 1})
    ->Unit(benchmark::kMicrosecond);

// 10,000 consecutive poses of a row 0.05 mm apart, each motion checked.
void BM_SweptCheck(benchmark::State& state) {
  const CollisionWorld world = passage(state.range(0) * 1000);
  const std::vector<ToolPose> poses = row_poses(10001, state.range(2) * 1e-3);
  const ToolBody body = wheel(state.range(3) * 1e-3);
  const Clearances clearances{0.5, 0.5, 0};
  long samples = 0, motions = 0;
  for (auto _ : state) {
    for (size_t i = 0; i + 1 < poses.size(); ++i) {
      const MotionCheck m = world.check_motion(body, poses[i], poses[i + 1], clearances, 1e-3);
      samples += m.samples;
      ++motions;
      benchmark::DoNotOptimize(m);
    }
  }
  state.counters["motions/s"] = benchmark::Counter(static_cast<double>(motions), benchmark::Counter::kIsRate);
  state.counters["samples/motion"] = static_cast<double>(samples) / motions;
}
BENCHMARK(BM_SweptCheck)->Args({100, 0, 2500, 1})->Args({100, 0, 1000, 1})->Unit(benchmark::kMillisecond)->Iterations(1);

// The paper's point check (eq. 20) over every vertex of the passage: linear
// in the point count, against the FCL query's logarithmic cost.
void BM_FastCheck(benchmark::State& state) {
  const long triangles = state.range(0) * 1000;
  std::vector<Vec3> points = flank_mesh(triangles).vertices;
  for (const Vec3& v : flank_mesh(triangles).vertices) points.push_back(v - Vec3(0, 14, 0));
  const std::vector<ToolPose> poses = row_poses(640, 2.5);
  const Tool tool = Tool::drum_wheel({8, 50, 4, {6, 96}, {}});
  const Clearances clearances{0.5, 0.5, 0};
  size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(fast_check(tool, poses[k++ % poses.size()], points, clearances));
  }
  state.counters["poses/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["points"] = static_cast<double>(points.size());
}
BENCHMARK(BM_FastCheck)->Arg(10)->Arg(100)->Unit(benchmark::kMicrosecond);

void BM_BuildWorld(benchmark::State& state) {
  const TriangleMesh mesh = flank_mesh(state.range(0) * 1000);
  for (auto _ : state) {
    CollisionWorld world;
    world.add("blade", mesh);
    benchmark::DoNotOptimize(world);
  }
}
BENCHMARK(BM_BuildWorld)->Arg(100)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace bliskrun
