#pragma once
// Section shapes with known answers for the repair tests: points at equal arc
// length around a closed profile, so the true order is the index.
#include <cmath>
#include <random>
#include <vector>

#include "core/common/types.h"

namespace bliskrun::test {

// `n` points at equal arc length around the closed polyline `dense` (first
// point not repeated), starting at dense[0]; with `jitter` each moved along
// the loop by up to that fraction of the spacing (uneven sampling, the order
// kept).
inline std::vector<Vec3> resample_closed(const std::vector<Vec3>& dense, int n, double jitter = 0,
                                         unsigned seed = 0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  std::vector<double> s(dense.size() + 1, 0.0);
  for (size_t i = 0; i < dense.size(); ++i) s[i + 1] = s[i] + (dense[(i + 1) % dense.size()] - dense[i]).norm();
  std::vector<Vec3> out;
  size_t k = 0;
  for (int j = 0; j < n; ++j) {
    const double target = s.back() * (j + (j > 0 ? u(rng) : 0.0)) / n;
    while (s[k + 1] < target) ++k;
    const double f = (target - s[k]) / (s[k + 1] - s[k]);
    out.push_back((1 - f) * dense[k] + f * dense[(k + 1) % dense.size()]);
  }
  return out;
}

inline std::vector<Vec3> ellipse(double a, double b, int n, double z = 0) {
  std::vector<Vec3> dense;
  for (int i = 0; i < 20000; ++i) {
    const double th = 2 * kPi * i / 20000;
    dense.emplace_back(a * std::cos(th), b * std::sin(th), z);
  }
  return resample_closed(dense, n);
}

// A thin cambered blade section: 60 mm chord, 4 mm thickest, round edges of
// 0.15 mm radius (0.3 mm thick at the edges), 6 mm of camber, as five dense
// open polylines: the suction side from mid-chord to the LE, the LE, the
// pressure side, the TE, the suction side back to mid-chord. Counter-
// clockwise about +Z.
inline std::vector<std::vector<Vec3>> blade_pieces(double z) {
  const double chord = 60, edge = 0.15, thickest = 2.0, camber = 6;
  const auto centre = [&](double x) { return Vec3(x, camber * std::sin(kPi * x / chord), z); };
  const auto tangent = [&](double x) { return Vec3(1, camber * kPi / chord * std::cos(kPi * x / chord), 0).normalized(); };
  const auto normal = [&](double x) { return Vec3(-tangent(x).y(), tangent(x).x(), 0); };  // to the suction side
  const auto half = [&](double x) { return edge + (thickest - edge) * std::pow(std::sin(kPi * x / chord), 2); };
  const auto side = [&](double x0, double x1, double sign) {
    std::vector<Vec3> piece;
    for (int i = 0; i < 20000; ++i) {
      const double x = x0 + (x1 - x0) * i / 20000;
      piece.push_back(centre(x) + sign * half(x) * normal(x));
    }
    return piece;
  };
  // Around an edge from one side to the other over its tip (`ahead`: the
  // direction of the tip from the edge circle's centre along the camber).
  const auto edge_arc = [&](double x, double from_sign, double ahead) {
    std::vector<Vec3> piece;
    for (int i = 0; i < 400; ++i) {
      const double a = kPi * i / 400;
      piece.push_back(centre(x) + edge * (from_sign * std::cos(a) * normal(x) + ahead * std::sin(a) * tangent(x)));
    }
    return piece;
  };
  return {side(chord / 2, 0, 1), edge_arc(0, 1, -1), side(0, chord, -1), edge_arc(chord, -1, 1),
          side(chord, chord / 2, 1)};
}

// `n` points at equal arc length around the blade section, starting at the
// middle of the suction side (see resample_closed for `jitter`).
inline std::vector<Vec3> blade_profile(int n, double z = 0, double jitter = 0, unsigned seed = 0) {
  std::vector<Vec3> dense;
  for (const auto& piece : blade_pieces(z)) dense.insert(dense.end(), piece.begin(), piece.end());
  return resample_closed(dense, n, jitter, seed);
}

// The blade section probed as a CMM program might: the suction side and the
// edges every `step_mm`, the pressure side every `pressure_step_mm`.
inline std::vector<Vec3> blade_scanned(double step_mm, double pressure_step_mm) {
  std::vector<Vec3> out;
  const std::vector<std::vector<Vec3>> pieces = blade_pieces(0);
  for (size_t k = 0; k < pieces.size(); ++k) {
    const double step = k == 2 ? pressure_step_mm : step_mm;
    double along = 0, next = 0;
    for (size_t i = 0; i + 1 < pieces[k].size(); ++i) {
      const double h = (pieces[k][i + 1] - pieces[k][i]).norm();
      while (next < along + h) {
        out.push_back(pieces[k][i] + (next - along) / h * (pieces[k][i + 1] - pieces[k][i]));
        next += step;
      }
      along += h;
    }
  }
  return out;
}

// Moves every point by Gaussian noise of `sigma` mm in the section plane (XY).
inline void add_noise(std::vector<Vec3>& points, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, sigma);
  for (Vec3& p : points) p += Vec3(g(rng), g(rng), 0);
}

}  // namespace bliskrun::test
