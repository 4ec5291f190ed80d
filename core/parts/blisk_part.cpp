#include "core/parts/blisk_part.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace bliskrun {

namespace {

// A flank restricted to the span: (w, v) in [0, 1]^2 with w = 0 on the hub
// cone and w = 1 on the casing cone along each iso-v line. The box makes the
// in-span constraint simple bounds, so a minimum on the hub line is found as
// exactly as one inside.
class SpanFlank {
 public:
  SpanFlank(const FlankPoint& flank, const MeridianRadius& hub, const MeridianRadius& casing)
      : flank_(flank), hub_(hub), casing_(casing) {}

  Vec3 at(double w, double v) const {
    // The crossings depend on v alone, and the search asks for few v's many
    // times (a sample column, a projection's steps in w): kept per v. A
    // hub of revolution from CAD finds its radius by a root search, so
    // without this the passage took 16 times the built-in blisk's time.
    auto it = crossings_.find(v);
    if (it == crossings_.end()) it = crossings_.emplace(v, std::make_pair(crossing(v, true), crossing(v, false))).first;
    const double uh = it->second.first, uc = it->second.second;
    return flank_(uh + w * (uc - uh), v);
  }

  // Closest point to q over the box, from a seed: Gauss-Newton with
  // central-difference Jacobian; a coordinate on a bound whose step points
  // out of the box is held there (active set).
  Vec2 project(const Vec3& q, Vec2 wv) const {
    constexpr double h = 1e-6;
    for (int it = 0; it < 60; ++it) {
      const Vec3 p = at(wv.x(), wv.y());
      Eigen::Matrix<double, 3, 2> J;
      J.col(0) = (at(wv.x() + h, wv.y()) - at(wv.x() - h, wv.y())) / (2 * h);
      J.col(1) = (at(wv.x(), wv.y() + h) - at(wv.x(), wv.y() - h)) / (2 * h);
      const Vec3 r = q - p;
      Vec2 step = (J.transpose() * J).ldlt().solve(J.transpose() * r);
      for (int k = 0; k < 2; ++k) {
        const bool held = (wv[k] <= 0 && step[k] < 0) || (wv[k] >= 1 && step[k] > 0);
        if (held) {
          const int f = 1 - k;
          step[k] = 0;
          step[f] = J.col(f).dot(r) / J.col(f).squaredNorm();
        }
      }
      const Vec2 next = (wv + step).cwiseMax(0.0).cwiseMin(1.0);
      const double moved = (next - wv).norm();
      wv = next;
      if (moved < 1e-12) break;
    }
    return wv;
  }

 private:
  // u where the iso-v line meets the hub (or casing): the radial
  // offset is monotonic in u along a flank row, so secant + bisection.
  double crossing(double v, bool hub) const {
    auto f = [&](double u) {
      const Vec3 q = flank_(u, v);
      const double r = std::hypot(q.x(), q.y());
      return r - (hub ? hub_(q.z()) : casing_(q.z()));
    };
    double a = 0, b = 1, fa = f(a), fb = f(b);
    for (int it = 0; it < 100 && b - a > 1e-15; ++it) {
      double m = a - fa * (b - a) / (fb - fa);
      if (!(m > a && m < b)) m = 0.5 * (a + b);
      const double fm = f(m);
      if (fm == 0) return m;
      if ((fm < 0) == (fa < 0)) {
        a = m;
        fa = fm;
      } else {
        b = m;
        fb = fm;
      }
      if (std::abs(fm) < 1e-13) return m;
    }
    return 0.5 * (a + b);
  }

  const FlankPoint& flank_;
  const MeridianRadius& hub_;
  const MeridianRadius& casing_;
  mutable std::unordered_map<double, std::pair<double, double>> crossings_;
};

}  // namespace

double narrowest_span_passage(const FlankPoint& suction_flank, const FlankPoint& pressure_flank,
                              const MeridianRadius& hub, const MeridianRadius& casing) {
  const SpanFlank suction(suction_flank, hub, casing), pressure(pressure_flank, hub, casing);

  // Dense samples of both flanks between hub and casing.
  constexpr int kRows = 40, kCols = 160;
  struct Sample { Vec2 wv; Vec3 p; };
  auto sample = [&](const SpanFlank& s) {
    std::vector<Sample> out;
    for (int i = 0; i < kRows; ++i)
      for (int j = 0; j < kCols; ++j) {
        const Vec2 wv(double(i) / (kRows - 1), double(j) / (kCols - 1));
        out.push_back({wv, s.at(wv.x(), wv.y())});
      }
    return out;
  };
  const std::vector<Sample> ss = sample(suction), ps = sample(pressure);

  struct Candidate { double d2; size_t s, p; };
  std::vector<Candidate> best;
  for (size_t a = 0; a < ss.size(); ++a) {
    Candidate c{std::numeric_limits<double>::infinity(), a, 0};
    for (size_t b = 0; b < ps.size(); ++b) {
      const double d2 = (ss[a].p - ps[b].p).squaredNorm();
      if (d2 < c.d2) c = {d2, a, b};
    }
    best.push_back(c);
  }
  constexpr size_t kRefine = 6;
  const size_t n_refine = std::min(kRefine, best.size());
  std::partial_sort(best.begin(), best.begin() + n_refine, best.end(),
                    [](const Candidate& x, const Candidate& y) { return x.d2 < y.d2; });

  // Refine each candidate pair by alternating constrained point inversion:
  // the distance never increases, and a fixed point is a pair where each
  // point is the closest to the other within the span (a common normal, or a
  // boundary point).
  double result = std::sqrt(best.front().d2);
  for (size_t k = 0; k < n_refine; ++k) {
    Vec2 a = ss[best[k].s].wv, b = ps[best[k].p].wv;
    double d = std::sqrt(best[k].d2);
    for (int it = 0; it < 500; ++it) {
      b = pressure.project(suction.at(a.x(), a.y()), b);
      a = suction.project(pressure.at(b.x(), b.y()), a);
      const double next = (suction.at(a.x(), a.y()) - pressure.at(b.x(), b.y())).norm();
      const bool converged = d - next < 1e-12;
      d = std::min(d, next);
      if (converged) break;
    }
    result = std::min(result, d);
  }
  return result;
}

}  // namespace bliskrun
