#include "core/repair/section_points.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cstdint>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>

#include "core/common/error.h"
#include "core/common/progress.h"
#include "core/common/statistics.h"
#include "core/geometry/point_index.h"

namespace bliskrun {

namespace {

// Distance from point i to its nearest other point, in boxes growing from r.
double nearest_other_distance(const PointIndex& index, int i, double r) {
  const Vec3& p = index.points()[i];
  for (;; r *= 2) {
    double best = kInf;
    index.for_each_in_box(p - Vec3::Constant(r), p + Vec3::Constant(r), [&](int j) {
      if (j != i) best = std::min(best, (index.points()[j] - p).squaredNorm());
    });
    if (best <= r * r) return std::sqrt(best);
  }
}

// Unit principal directions of the points, by decreasing spread.
Mat3 principal_axes(const std::vector<Vec3>& points, const std::vector<int>& which) {
  Vec3 mean = Vec3::Zero();
  for (int i : which) mean += points[i];
  mean /= static_cast<double>(which.size());
  Mat3 cov = Mat3::Zero();
  for (int i : which) cov += (points[i] - mean) * (points[i] - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(cov);  // ascending eigenvalues
  Mat3 axes;
  for (int k = 0; k < 3; ++k) axes.col(k) = eig.eigenvectors().col(2 - k);
  return axes;
}

// The walk of §1.1 with a direction of travel that noise cannot turn and a
// longest step (section_points.h).
class Walker {
 public:
  Walker(const std::vector<Vec3>& p, const PointIndex& index, double max_step, double max_turn, double back)
      : p_(p), index_(index), used_(p.size(), 0), max_step_(max_step), cos_turn_(std::cos(max_turn)),
        back_(back) {}

  bool used(int i) const { return used_[i] != 0; }
  void use(int i) { used_[i] = 1; }

  // Extends `chain` from its last point until no unused point lies in the
  // cone within reach; true if it came back to `close_to` (then not added).
  bool walk(std::vector<int>& chain, const Vec3& first_direction, int close_to) const {
    for (long steps = 1;; ++steps) {
      if ((steps & 255) == 0) cancellation_point();
      Vec3 d = direction(chain);
      if (!(d.norm() > 0)) d = first_direction;
      const int j = next(chain.back(), d.normalized(), chain.size() >= 3 ? close_to : -1);
      if (j < 0) return false;
      if (j == close_to) return true;
      used_[j] = 1;
      chain.push_back(j);
    }
  }

  // A unit direction along the profile at `seed`: the main axis of the points
  // within three spacings, or towards its nearest neighbour.
  Vec3 seed_direction(int seed, double spacing) const {
    std::vector<int> near;
    const double r = 3 * spacing;
    index_.for_each_in_box(p_[seed] - Vec3::Constant(r), p_[seed] + Vec3::Constant(r), [&](int j) {
      if ((p_[j] - p_[seed]).norm() <= r) near.push_back(j);
    });
    if (near.size() >= 3) return principal_axes(p_, near).col(0);
    double best = kInf;
    Vec3 d = Vec3::UnitX();
    for (int j : near)
      if (j != seed && (p_[j] - p_[seed]).norm() < best && (p_[j] - p_[seed]).norm() > 0) {
        best = (p_[j] - p_[seed]).norm();
        d = (p_[j] - p_[seed]) / best;
      }
    return d;
  }

 private:
  // The chord from the last point at least `back_` behind to the chain's end
  // (at most 8 points back); zero for a single point.
  Vec3 direction(const std::vector<int>& chain) const {
    if (chain.size() < 2) return Vec3::Zero();
    const Vec3& end = p_[chain.back()];
    Vec3 d = Vec3::Zero();
    for (size_t k = chain.size() - 1; k-- > 0 && chain.size() - k <= 9;) {
      d = end - p_[chain[k]];
      if (d.norm() >= back_) break;
    }
    return d;
  }

  // Nearest unused point (or `close_to`) within reach whose direction from c
  // turns by at most max_turn from `dir` (unit); -1 if none.
  int next(int c, const Vec3& dir, int close_to) const {
    const Vec3& pc = p_[c];
    int best = -1;
    double best_d2 = max_step_ * max_step_;
    index_.for_each_in_box(pc - Vec3::Constant(max_step_), pc + Vec3::Constant(max_step_), [&](int j) {
      if (j == c || (used_[j] && j != close_to)) return;
      const Vec3 v = p_[j] - pc;
      const double d2 = v.squaredNorm();
      if (!(d2 > 0) || d2 > best_d2) return;  // a coincident point is left for the put-back test
      if (v.dot(dir) < cos_turn_ * std::sqrt(d2)) return;
      best = j;
      best_d2 = d2;
    });
    return best;
  }

  const std::vector<Vec3>& p_;
  const PointIndex& index_;
  mutable std::vector<char> used_;
  double max_step_, cos_turn_, back_;
};

struct PointChain {
  std::vector<int> points;
  int seed = 0;
  bool closed = false;  // the walk came back to its seed
};

// Concatenates the chains (each possibly reversed) in the order that makes
// the links between them, the closing one included, shortest: every order
// for up to 7 chains, nearest end first beyond. chain_end[k]: the link after
// position k joins two chains.
std::vector<int> join_chains(const std::vector<Vec3>& p, const std::vector<PointChain>& chains,
                             std::vector<char>& chain_end) {
  const int k = static_cast<int>(chains.size());
  const auto first = [&](int c, bool rev) { return rev ? chains[c].points.back() : chains[c].points.front(); };
  const auto last = [&](int c, bool rev) { return rev ? chains[c].points.front() : chains[c].points.back(); };
  const auto link = [&](int a, int b) { return (p[a] - p[b]).norm(); };
  std::vector<std::pair<int, bool>> best, current{{0, false}};
  std::vector<char> placed(k, 0);
  placed[0] = 1;
  if (k <= 7) {
    // Depth-first over orders and directions; chain 0 runs first, forwards.
    double best_cost = kInf;
    std::function<void(double)> search = [&](double cost) {
      if (cost >= best_cost) return;
      const int end = last(current.back().first, current.back().second);
      if (static_cast<int>(current.size()) == k) {
        if (cost + link(end, first(0, false)) < best_cost) best_cost = cost + link(end, first(0, false)), best = current;
        return;
      }
      for (int c = 1; c < k; ++c) {
        if (placed[c]) continue;
        placed[c] = 1;
        for (bool rev : {false, true}) {
          current.emplace_back(c, rev);
          search(cost + link(end, first(c, rev)));
          current.pop_back();
        }
        placed[c] = 0;
      }
    };
    search(0.0);
  } else {
    best = current;
    for (int step = 1; step < k; ++step) {
      const int end = last(best.back().first, best.back().second);
      std::pair<int, bool> choice{-1, false};
      double nearest = kInf;
      for (int c = 1; c < k; ++c)
        for (bool rev : {false, true})
          if (!placed[c] && link(end, first(c, rev)) < nearest) nearest = link(end, first(c, rev)), choice = {c, rev};
      placed[choice.first] = 1;
      best.push_back(choice);
    }
  }
  std::vector<int> loop;
  chain_end.clear();
  for (const auto& [c, rev] : best) {
    if (rev)
      loop.insert(loop.end(), chains[c].points.rbegin(), chains[c].points.rend());
    else
      loop.insert(loop.end(), chains[c].points.begin(), chains[c].points.end());
    chain_end.resize(loop.size(), 0);
    chain_end.back() = !(k == 1 && chains[0].closed);  // a walk that closed its own loop has no join
  }
  return loop;
}

// A loop in the making: input indices in order, and per link (at[k] ->
// at[k+1]) whether it is a gap: kLong (longer than max_step, follows the
// points) or kTurn (where the walks stopped because the profile turned back:
// stays while no point is put back into it).
enum GapKind : char { kNone = 0, kLong = 1, kTurn = 2 };
struct SectionLoop {
  std::vector<int> at;
  std::vector<char> gap;
};

// Whether the profile turns back across link k by more than max_turn: the
// chords over at least two spacings (at most 8 points) into its start and
// out of its end.
bool turns_back_across(const std::vector<Vec3>& p, const std::vector<int>& loop, int k, double spacing,
                       double cos_turn) {
  const int m = static_cast<int>(loop.size());
  const auto at = [&](int j) -> const Vec3& { return p[loop[((j % m) + m) % m]]; };
  const auto chord = [&](int from, int step) {
    Vec3 d = Vec3::Zero();
    for (int j = 1; j <= 8 && j < m; ++j) {
      d = at(from + step * j) - at(from);
      if (d.norm() >= 2 * spacing) break;
    }
    return d;
  };
  const Vec3 in = -chord(k, -1), out = chord(k + 1, 1);
  return in.dot(out) < cos_turn * in.norm() * out.norm();
}

struct GapRule {
  double max_step, spacing, cos_turn;
};

// Sets the kLong links, and keeps a kTurn link only while it still is one
// (longer than two spacings, the profile turning back across it): a turn
// gap that a stray point made at the end of a walk goes with the stray.
void mark_gaps(const std::vector<Vec3>& p, SectionLoop& loop, const GapRule& rule) {
  const size_t m = loop.at.size();
  for (size_t k = 0; k < m; ++k) {
    const double length = (p[loop.at[(k + 1) % m]] - p[loop.at[k]]).norm();
    if (loop.gap[k] == kTurn &&
        length > 2 * rule.spacing && turns_back_across(p, loop.at, static_cast<int>(k), rule.spacing, rule.cos_turn))
      continue;
    loop.gap[k] = length > rule.max_step ? kLong : kNone;
  }
}

// Drops the marked positions; a link that replaces dropped points is a turn
// gap if one of the links it replaces was and it still turns back.
void drop_positions(const std::vector<Vec3>& p, SectionLoop& loop, const std::vector<char>& drop, const GapRule& rule,
                    std::vector<int>& rejected) {
  SectionLoop kept;
  bool carried = false;  // a turn gap among dropped points before the first kept one
  for (size_t i = 0; i < loop.at.size(); ++i) {
    if (drop[i]) {
      rejected.push_back(loop.at[i]);
      if (loop.gap[i] == kTurn && kept.at.empty()) carried = true;
      if (loop.gap[i] == kTurn && !kept.at.empty()) kept.gap.back() = kTurn;
      continue;
    }
    kept.at.push_back(loop.at[i]);
    kept.gap.push_back(loop.gap[i]);
  }
  if (kept.at.empty()) return;
  if (carried) kept.gap.back() = kTurn;
  mark_gaps(p, kept, rule);
  loop = std::move(kept);
}

using Window = std::vector<int>;  // offsets from the point along the loop

// Distance of `point` from the quadratic (a line for a window on one side)
// through the window's points, in
// chord length along them (the point itself left out, so a stray point's
// own distance does not stretch its window), measured at its foot on the
// curve and divided by sqrt(1 + leverage) there, so that a point predicted
// by extrapolation is not called an outlier for the fit's own uncertainty;
// -1 for fewer than 3 points.
template <class At>
double deviation_from(const Vec3& point, Window window, const At& at) {
  const int count = static_cast<int>(window.size());
  if (count < 3) return -1;
  std::sort(window.begin(), window.end());
  // All on one side: a line, since a quadratic extrapolated from noisy
  // points can bend to meet a stray.
  const bool one_sided = window.front() > 0 || window.back() < 0;
  double s[8] = {0};
  for (int r = 1; r < count; ++r) s[r] = s[r - 1] + (at(window[r]) - at(window[r - 1])).norm();
  const double mid = 0.5 * s[count - 1], scale = 0.5 * s[count - 1];
  if (!(scale > 0)) return -1;
  // Normal equations by accumulation (at most 8 points: no allocation).
  Mat3 M = Mat3::Zero(), B = Mat3::Zero();
  int nearest = 0;
  for (int r = 0; r < count; ++r) {
    const double t = (s[r] - mid) / scale;
    const Eigen::Vector3d x(1, t, one_sided ? 0.0 : t * t);
    M += x * x.transpose();
    B += x * at(window[r]).transpose();
    if ((at(window[r]) - point).norm() < (at(window[nearest]) - point).norm()) nearest = r;
  }
  if (one_sided) M(2, 2) = 1;  // the unused term: decoupled, its coefficient 0
  const Eigen::FullPivLU<Mat3> lu(M);
  if (!lu.isInvertible()) return -1;
  const Mat3 Minv = lu.inverse();
  const Mat3 beta = Minv * B;  // C(t) = beta_0 + beta_1 t + beta_2 t^2
  const Vec3 c0 = beta.row(0).transpose(), c1 = beta.row(1).transpose(), c2 = beta.row(2).transpose();
  double t = (s[nearest] - mid) / scale;
  for (int it = 0; it < 8; ++it) {
    const Vec3 r = c0 + t * c1 + t * t * c2 - point, d1 = c1 + 2 * t * c2;
    const double g = r.dot(d1), dg = d1.squaredNorm() + 2 * r.dot(c2);
    if (!(dg > 0)) break;
    const double next = std::clamp(t - g / dg, -3.0, 3.0);
    if (std::abs(next - t) < 1e-12) break;
    t = next;
  }
  const Eigen::Vector3d x(1, t, one_sided ? 0.0 : t * t);
  return (c0 + t * c1 + t * t * c2 - point).norm() / std::sqrt(1 + x.dot(Minv * x));
}

// How far each point of the loop lies off its neighbours' curve: the least
// deviation_from over four windows of neighbours within its stretch (no
// link that is a gap): two each side, the four nearest along the loop, the
// four before and the four after it. A point of the profile fits at least
// one of them — the side of a sharp edge next to a coarsely probed flank,
// the flank at a gap's end — and a stray point none. -1 where fewer than 3
// neighbours are in reach. With `balanced_only`, the two-each-side window
// alone: the least of four is biased low, so the noise is measured on this.
std::vector<double> local_deviations(const std::vector<Vec3>& p, const std::vector<int>& loop,
                                     const std::vector<char>& gap, bool balanced_only = false) {
  const int m = static_cast<int>(loop.size());
  std::vector<double> out(m, -1.0);
  for (int i = 0; i < m; ++i) {
    const auto at = [&](int k) -> const Vec3& { return p[loop[(((i + k) % m) + m) % m]]; };
    const auto link_gap = [&](int k) { return gap[(((i + k) % m) + m) % m] != kNone; };  // link i+k -> i+k+1
    Window left, right;  // up to 4 each way, not across a gap
    for (int k = 1; k <= 4 && k < m && !link_gap(-k); ++k) left.push_back(-k);
    for (int k = 1; k <= 4 && k + static_cast<int>(left.size()) < m && !link_gap(k - 1); ++k) right.push_back(k);
    Window balanced(left.begin(), left.begin() + std::min<long>(2, static_cast<long>(left.size())));
    balanced.insert(balanced.end(), right.begin(), right.begin() + std::min<long>(2, static_cast<long>(right.size())));
    // The four nearest along the loop.
    std::vector<std::pair<double, int>> by_arc;
    double s = 0;
    for (int k : left) by_arc.emplace_back(s += (at(k + 1) - at(k)).norm(), k);
    s = 0;
    for (int k : right) by_arc.emplace_back(s += (at(k) - at(k - 1)).norm(), k);
    std::sort(by_arc.begin(), by_arc.end());
    Window nearest;
    for (size_t r = 0; r < by_arc.size() && r < 4; ++r) nearest.push_back(by_arc[r].second);
    for (const Window* w : {&balanced, &nearest, &left, &right}) {
      if (balanced_only && w != &balanced) break;
      const double d = deviation_from(at(0), *w, at);
      if (d >= 0 && (out[i] < 0 || d < out[i])) out[i] = d;
    }
  }
  return out;
}

void check_options(const SectionOrderOptions& o) {
  if (!(o.max_turn_rad > 0 && o.max_turn_rad < kPi))
    throw ParameterError("options", "max_turn must be in (0, 180) degrees");
  if (!(o.max_step_mm >= 0 && std::isfinite(o.max_step_mm)))
    throw ParameterError("options", "max_step must be >= 0 mm (0: four point spacings)");
  if (!(o.outlier_mm >= 0 && std::isfinite(o.outlier_mm)))
    throw ParameterError("options", "outlier distance must be >= 0 mm (0: from the data)");
  if (!(o.outlier_factor > 0 && std::isfinite(o.outlier_factor)))
    throw ParameterError("options", "outlier_factor must be > 0");
}

}  // namespace

std::vector<Vec3> pick(const std::vector<Vec3>& points, const std::vector<int>& order) {
  std::vector<Vec3> out;
  out.reserve(order.size());
  for (int i : order) {
    if (i < 0 || static_cast<size_t>(i) >= points.size())
      throw ParameterError("order", "index " + std::to_string(i) + " is outside the " +
                                        std::to_string(points.size()) + " points");
    out.push_back(points[i]);
  }
  return out;
}

std::vector<int> thin_section(const std::vector<Vec3>& points, double spacing_mm) {
  if (!(spacing_mm > 0 && std::isfinite(spacing_mm))) throw ParameterError("spacing", "expected a spacing > 0 mm");
  const size_t n = points.size();
  std::vector<int> all(n);
  for (size_t i = 0; i < n; ++i) all[i] = static_cast<int>(i);
  if (n < 8) return all;
  // 1. Cells half the spacing wide, keyed 21 bits per axis.
  const double cell = 0.5 * spacing_mm;
  Vec3 lo = points[0];
  for (const Vec3& p : points) lo = lo.cwiseMin(p);
  auto index_of = [&](const Vec3& p, int a) { return static_cast<long>(std::floor((p[a] - lo[a]) / cell)); };
  auto key_of = [](long x, long y, long z) {
    return (static_cast<std::uint64_t>(x) << 42) | (static_cast<std::uint64_t>(y) << 21) | static_cast<std::uint64_t>(z);
  };
  std::vector<std::pair<std::uint64_t, int>> keyed(n);
  for (size_t i = 0; i < n; ++i) {
    long c[3];
    for (int a = 0; a < 3; ++a) {
      c[a] = index_of(points[i], a);
      if (!(c[a] >= 0 && c[a] < (1L << 21)))
        throw ParameterError("spacing", "the section spans more than 2^21 cells of " + std::to_string(cell) + " mm");
    }
    keyed[i] = {key_of(c[0], c[1], c[2]), static_cast<int>(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  struct Cell {
    std::uint64_t key;
    size_t begin, end;
  };
  std::vector<Cell> cells;
  for (size_t b = 0; b < n;) {
    size_t e = b + 1;
    while (e < n && keyed[e].first == keyed[b].first) ++e;
    cells.push_back({keyed[b].first, b, e});
    b = e;
  }
  std::vector<size_t> counts;
  for (const Cell& c : cells) counts.push_back(c.end - c.begin);
  std::nth_element(counts.begin(), counts.begin() + counts.size() / 2, counts.end());
  const size_t median_count = counts[counts.size() / 2];
  if (median_count < 4) return all;
  auto find = [&](std::uint64_t key) -> const Cell* {
    const auto it = std::lower_bound(cells.begin(), cells.end(), key, [](const Cell& c, std::uint64_t k) { return c.key < k; });
    return it != cells.end() && it->key == key ? &*it : nullptr;
  };
  auto unpack = [](std::uint64_t key, long c[3]) {
    c[0] = static_cast<long>(key >> 42);
    c[1] = static_cast<long>((key >> 21) & ((1u << 21) - 1));
    c[2] = static_cast<long>(key & ((1u << 21) - 1));
  };
  // 2. Each cell's representative, unless its block of 3 x 3 x 3 cells holds
  // fewer points than the median cell: a lone stray.
  std::vector<int> reps;
  std::vector<double> c3[3];
  for (const Cell& cl : cells) {
    long c[3];
    unpack(cl.key, c);
    size_t block = 0;
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz) {
          if (c[0] + dx < 0 || c[1] + dy < 0 || c[2] + dz < 0) continue;
          if (const Cell* o = find(key_of(c[0] + dx, c[1] + dy, c[2] + dz))) block += o->end - o->begin;
        }
    if (block < median_count) continue;
    Vec3 med;
    for (int a = 0; a < 3; ++a) {
      c3[a].clear();
      for (size_t k = cl.begin; k < cl.end; ++k) c3[a].push_back(points[keyed[k].second][a]);
      std::nth_element(c3[a].begin(), c3[a].begin() + c3[a].size() / 2, c3[a].end());
      med[a] = c3[a][c3[a].size() / 2];
    }
    int best = keyed[cl.begin].second;
    for (size_t k = cl.begin; k < cl.end; ++k)
      if ((points[keyed[k].second] - med).squaredNorm() < (points[best] - med).squaredNorm()) best = keyed[k].second;
    reps.push_back(best);
  }
  // 3. No two kept within the spacing: the representatives in cell order,
  // each kept unless one kept already lies within spacing_mm (so the kept
  // points are spacing_mm to about twice that apart along the profile, as
  // evenly as a probe's jittered steps).
  std::vector<int> kept;
  std::unordered_map<std::uint64_t, std::vector<int>> near;
  auto coarse = [&](const Vec3& p, int a) { return static_cast<long>(std::floor((p[a] - lo[a]) / spacing_mm)) + 1; };
  for (const int i : reps) {
    const Vec3& p = points[i];
    const long c[3] = {coarse(p, 0), coarse(p, 1), coarse(p, 2)};
    bool free = true;
    for (long dx = -1; dx <= 1 && free; ++dx)
      for (long dy = -1; dy <= 1 && free; ++dy)
        for (long dz = -1; dz <= 1 && free; ++dz) {
          const auto it = near.find(key_of(c[0] + dx, c[1] + dy, c[2] + dz));
          if (it == near.end()) continue;
          for (const int j : it->second)
            if ((points[j] - p).squaredNorm() < spacing_mm * spacing_mm) {
              free = false;
              break;
            }
        }
    if (!free) continue;
    kept.push_back(i);
    near[key_of(c[0], c[1], c[2])].push_back(i);
  }
  std::sort(kept.begin(), kept.end());
  return kept;
}

OrderedSection order_section(const std::vector<Vec3>& points, const SectionOrderOptions& options) {
  check_options(options);
  const int n = static_cast<int>(points.size());
  if (n < 8) throw ParameterError("points", "a section needs at least 8 points, got " + std::to_string(n));
  Vec3 lo = points[0], hi = points[0];
  for (int i = 0; i < n; ++i) {
    if (!points[i].allFinite()) throw ParameterError("points", "point " + std::to_string(i) + " is not finite");
    lo = lo.cwiseMin(points[i]);
    hi = hi.cwiseMax(points[i]);
  }
  const double diagonal = (hi - lo).norm();
  if (!(diagonal > 0)) throw ParameterError("points", "all points coincide");

  // A loop of n points in a box of this diagonal is ~2.5 diagonal / n apart.
  // The indexes' cells are a few spacings wide: a cell grid is dense over
  // the points' box, and at one spacing a section's box is hundreds of
  // thousands of empty cells to allocate and fill (three indexes per
  // section took more time than the walk); the queries are exact either way.
  constexpr double kCellSpacings = 4;
  const double rough_spacing = 2.5 * diagonal / n;
  const PointIndex rough(points, kCellSpacings * rough_spacing);
  std::vector<double> nearest(n);
  for (int i = 0; i < n; ++i) nearest[i] = nearest_other_distance(rough, i, rough_spacing);
  OrderedSection out;
  out.spacing_mm = median(nearest);
  if (!(out.spacing_mm > 0))
    throw ParameterError("points", "more than half of the points coincide with another point");
  const double h = out.spacing_mm;
  // The longest step from the upper end of the spacings, so a flank probed
  // more coarsely than the rest is still walked.
  std::vector<double> sorted_nearest = nearest;
  std::sort(sorted_nearest.begin(), sorted_nearest.end());
  out.max_step_mm = options.max_step_mm > 0 ? options.max_step_mm
                                            : 2.5 * sorted_nearest[static_cast<size_t>(0.9 * (n - 1))];
  const PointIndex index(points, kCellSpacings * h);

  // First seed: the extreme along the second principal axis (across the
  // chord: the middle of the flattest side) among points that have
  // neighbours, so no stray point starts the walk.
  std::vector<int> all(n);
  for (int i = 0; i < n; ++i) all[i] = i;
  const Vec3 across = principal_axes(points, all).col(1);
  int seed = -1;
  for (int i = 0; i < n; ++i)
    if (nearest[i] <= 2 * h && (seed < 0 || points[i].dot(across) > points[seed].dot(across))) seed = i;

  Walker walker(points, index, out.max_step_mm, options.max_turn_rad, 2 * h);
  std::vector<PointChain> chains;
  std::vector<int> loose;  // points of chains too short to join
  for (int next_seed = 0; seed >= 0;) {
    cancellation_point();
    walker.use(seed);
    const Vec3 d = walker.seed_direction(seed, h);
    std::vector<int> forward{seed}, backward{seed};
    PointChain chain;
    chain.seed = seed;
    chain.closed = walker.walk(forward, d, seed);
    if (!chain.closed) walker.walk(backward, -d, -1);
    chain.points.assign(backward.rbegin(), backward.rend() - 1);
    chain.points.insert(chain.points.end(), forward.begin(), forward.end());
    if (chain.points.size() >= 3)
      chains.push_back(std::move(chain));
    else
      loose.insert(loose.end(), chain.points.begin(), chain.points.end());
    while (next_seed < n && walker.used(next_seed)) ++next_seed;
    seed = next_seed < n ? next_seed : -1;
  }
  if (chains.empty())
    throw ParameterError("points", "no three points follow each other within max_step (" +
                                       std::to_string(out.max_step_mm) + " mm): not a profile");
  out.chains = static_cast<int>(chains.size());
  SectionLoop loop;
  std::vector<char> chain_end;
  loop.at = join_chains(points, chains, chain_end);
  const double cos_turn = std::cos(options.max_turn_rad);
  const auto length = [&](const SectionLoop& l, size_t k) {
    return (points[l.at[(k + 1) % l.at.size()]] - points[l.at[k]]).norm();
  };
  // Gaps: links longer than max_step, and links where a walk stopped because
  // the profile turned back (the ends of a missing edge, on the two flanks).
  const GapRule rule{out.max_step_mm, h, cos_turn};
  loop.gap.assign(loop.at.size(), kNone);
  for (size_t k = 0; k < loop.at.size(); ++k)
    if (chain_end[k]) loop.gap[k] = kTurn;
  mark_gaps(points, loop, rule);

  // The outlier distance follows the noise of the walked points.
  {
    std::vector<double> tested;
    for (double v : local_deviations(points, loop.at, loop.gap, true))
      if (v >= 0) tested.push_back(v);
    out.outlier_mm = options.outlier_mm > 0
                         ? options.outlier_mm
                         : std::max(0.1 * h, tested.empty() ? 0.0 : options.outlier_factor * median(tested));
  }
  // Rejects points off their neighbours' curve, the worst of a neighbourhood
  // first (an outlier also bends its neighbours' fits), until none is left.
  std::vector<int> rejected;
  const auto reject_outliers = [&] {
    for (;;) {
      cancellation_point();
      std::vector<double> deviation = local_deviations(points, loop.at, loop.gap);
      const int m = static_cast<int>(loop.at.size());
      for (double& d : deviation)
        if (d < 0) d = kInf;  // alone between gaps: nothing vouches for it
      std::vector<char> drop(m, 0);
      int dropped = 0;
      for (int i = 0; i < m; ++i) {
        if (!(deviation[i] > out.outlier_mm)) continue;
        bool worst = true;
        for (int k = -2; k <= 2 && worst; ++k)
          if (k != 0 && deviation[((i + k) % m + m) % m] > deviation[i]) worst = false;
        if (worst) drop[i] = 1, ++dropped;
      }
      if (dropped == 0 || m - dropped < 8) return;
      drop_positions(points, loop, drop, rule, rejected);
    }
  };
  reject_outliers();

  // Put back the points the walks passed by, and the short chains, where
  // inserting them lengthens the loop least (on either link of the nearest
  // loop point within max_step), and test them like the rest.
  if (!loose.empty()) {
    const int m = static_cast<int>(loop.at.size());
    const PointIndex on_loop(pick(points, loop.at), kCellSpacings * h);
    std::vector<std::vector<std::pair<double, int>>> onto(m);  // per link: (position along it, point)
    for (int u : loose) {
      const int k = on_loop.nearest(points[u], out.max_step_mm);
      if (k < 0 || !((points[u] - points[loop.at[k]]).norm() > 1e-9 * h)) {  // isolated, or a repeated point
        rejected.push_back(u);
        continue;
      }
      double detour = kInf;
      std::pair<int, double> where{-1, 0.0};
      for (int e : {(k + m - 1) % m, k}) {
        const Vec3 &a = points[loop.at[e]], &b = points[loop.at[(e + 1) % m]];
        const double cost = (points[u] - a).norm() + (b - points[u]).norm() - (b - a).norm();
        const double along = (b - a).squaredNorm() > 0 ? (points[u] - a).dot(b - a) / (b - a).squaredNorm() : 0.0;
        if (cost < detour) detour = cost, where = {e, along};
      }
      onto[where.first].emplace_back(where.second, u);
    }
    SectionLoop merged;
    for (int e = 0; e < m; ++e) {
      merged.at.push_back(loop.at[e]);
      merged.gap.push_back(loop.gap[e]);
      // The pieces of a turn gap stay turn gaps while they still turn back
      // (mark_gaps): the tip points of a coarse edge close it, a stray does not.
      const char pieces = loop.gap[e] == kTurn ? kTurn : kNone;
      std::sort(onto[e].begin(), onto[e].end());
      for (const auto& along : onto[e]) {
        const int u = along.second;
        if (!((points[u] - points[merged.at.back()]).norm() > 1e-9 * h)) {
          rejected.push_back(u);
          continue;
        }
        merged.gap.back() = pieces;
        merged.at.push_back(u);
        merged.gap.push_back(pieces);
      }
    }
    mark_gaps(points, merged, rule);
    loop = std::move(merged);
    reject_outliers();
  }

  // Start at the first seed (if it survived), as the loop was walked from it.
  const auto first = std::find(loop.at.begin(), loop.at.end(), chains[0].seed);
  if (first != loop.at.end()) {
    const auto shift = first - loop.at.begin();
    std::rotate(loop.at.begin(), first, loop.at.end());
    std::rotate(loop.gap.begin(), loop.gap.begin() + shift, loop.gap.end());
  }
  for (size_t k = 0; k < loop.at.size(); ++k)
    if (loop.gap[k]) out.gaps.push_back({static_cast<int>(k), length(loop, k)});
  std::sort(rejected.begin(), rejected.end());
  out.order = std::move(loop.at);
  out.rejected = std::move(rejected);
  return out;
}

std::vector<OrientedSection> orient_sections(const std::vector<std::vector<Vec3>>& loops, const Vec3& axis) {
  if (!axis.allFinite() || !(axis.norm() > 0)) throw ParameterError("axis", "expected a non-zero direction");
  const Vec3 a = axis.normalized();
  std::vector<OrientedSection> out;
  out.reserve(loops.size());
  for (size_t s = 0; s < loops.size(); ++s) {
    const std::vector<Vec3>& loop = loops[s];
    const int n = static_cast<int>(loop.size());
    const std::string which = "loop " + std::to_string(s);
    if (n < 3) throw ParameterError("loops", which + " has fewer than 3 points");
    for (const Vec3& p : loop)
      if (!p.allFinite()) throw ParameterError("loops", which + " has a non-finite point");
    const Vec3 area = vector_area(loop);
    if (!(std::abs(area.dot(a)) >= 0.1 * area.norm() && area.norm() > 0))
      throw ParameterError("loops", which + " is seen edge-on from the axis: its turning sense about it is undefined");
    OrientedSection o;
    o.reversed = area.dot(a) < 0;
    // Input index of position j: reversed loops keep their first point.
    const auto input = [&](int j) { return o.reversed ? (n - j) % n : j; };
    int start = 0;
    if (!out.empty()) {
      const Vec3& previous = out.back().loop.front();
      double best = kInf;
      for (int j = 0; j < n; ++j) {
        const Vec3 d = loop[input(j)] - previous;
        const double across = (d - d.dot(a) * a).norm();
        if (across < best) best = across, start = j;
      }
    }
    o.start = input(start);
    o.loop.reserve(n);
    for (int j = 0; j < n; ++j) o.loop.push_back(loop[input((start + j) % n)]);
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace bliskrun
