// Geometry kernel speed: grid interpolation (blisk paper's 100 x 500) and
// its growth with the grid, surface evaluation with curvature, projection.
#include <benchmark/benchmark.h>

#include <random>

#include <cmath>

#include "core/geometry/registration.h"
#include "core/geometry/differential.h"
#include "core/geometry/interpolation.h"
#include "core/geometry/nurbs.h"
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

// Issue 36 item 8: a NURBS point with derivatives to second order costs at
// most 1.5x the non-rational B-spline's. Same bicubic 100 x 500 net; the
// rational one with weights 0.5..1.5, so no shortcut for unit weights runs.
NurbsSurface rational_blade() {
  const BSplineSurface b = interpolate_grid(blade_grid(100, 500));
  std::vector<Vec3> ctrl;
  std::vector<double> w;
  for (int i = 0; i < b.rows(); ++i)
    for (int j = 0; j < b.cols(); ++j) {
      ctrl.push_back(b.control_point(i, j));
      w.push_back(1.0 + 0.5 * std::sin(0.37 * i + 0.11 * j));
    }
  return NurbsSurface(b.degree_u(), b.degree_v(), b.knots_u(), b.knots_v(), b.rows(), b.cols(),
                      ctrl, w);
}

template <class S>
void eval_sweep(benchmark::State& state, const S& s) {
  int k = 0;
  for (auto _ : state) {
    const double u = (k % 997) / 997.0, v = (k % 991) / 991.0;
    benchmark::DoNotOptimize(s.eval(u, v));
    ++k;
  }
  state.SetItemsProcessed(state.iterations());
}
void BM_EvalBSplineDerivs(benchmark::State& state) {
  eval_sweep(state, interpolate_grid(blade_grid(100, 500)));
}
BENCHMARK(BM_EvalBSplineDerivs)->Unit(benchmark::kNanosecond);
void BM_EvalNurbsDerivs(benchmark::State& state) { eval_sweep(state, rational_blade()); }
BENCHMARK(BM_EvalNurbsDerivs)->Unit(benchmark::kNanosecond);

}  // namespace
}  // namespace bliskrun

namespace bliskrun {
namespace {

// Scan registration (issue 15 item 4: ICP of a 200k-point scan <= 1 s): a
// 200 000-point scan of an ellipsoid patch, 5 um noise, 0.5 deg / 0.5 mm off,
// against a 360 000-sample model.
void BM_RegisterScan200k(benchmark::State& state) {
  ModelSample model;
  const int n = 600;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double th = 0.3 + 1.1 * i / (n - 1), ph = -1.2 + 2.4 * j / (n - 1);
      const Vec3 p(60 * std::sin(th) * std::cos(ph), 40 * std::sin(th) * std::sin(ph), 25 * std::cos(th));
      model.points.push_back(p);
      model.normals.push_back(Vec3(p.x() / 3600, p.y() / 1600, p.z() / 625).normalized());
    }
  Frame truth = Frame::Identity();
  truth.linear() = Eigen::AngleAxisd(deg_to_rad(0.5), Vec3(1, 2, 3).normalized()).toRotationMatrix();
  truth.translation() = Vec3(0.3, 0.4, -0.2);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0, 0.005);
  std::vector<Vec3> scan;
  for (size_t k = 0; k < model.points.size() && scan.size() < 200000; k += 1 + k % 2)
    scan.push_back(truth * (model.points[k] + noise(rng) * model.normals[k]));
  int iterations = 0;
  for (auto _ : state) {
    const RegistrationResult r = register_points(scan, model);
    iterations = r.iterations;
    benchmark::DoNotOptimize(r);
  }
  state.counters["scan_points"] = static_cast<double>(scan.size());
  state.counters["iterations"] = iterations;
}
BENCHMARK(BM_RegisterScan200k)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace bliskrun
