#include "core/geometry/point_index.h"

#include <cmath>

#include "core/common/error.h"

namespace bliskrun {

std::int64_t PointIndex::key(long i, long j, long k) const {
  // 21 bits per axis: +-1M cells, far beyond any part at micrometre cells.
  const auto m = [](long v) { return static_cast<std::int64_t>(v & 0x1FFFFF); };
  return (m(i) << 42) | (m(j) << 21) | m(k);
}

PointIndex::PointIndex(std::vector<Vec3> points, double cell_mm) : points_(std::move(points)), cell_(cell_mm) {
  if (!(cell_ > 0) || !std::isfinite(cell_)) throw ParameterError("cell", "expected a cell size > 0 in mm");
  buckets_.reserve(points_.size());
  for (size_t n = 0; n < points_.size(); ++n) {
    const Vec3& p = points_[n];
    if (!p.allFinite()) throw ParameterError("points", "point " + std::to_string(n) + " is not finite");
    buckets_[key(std::lround(std::floor(p.x() / cell_)), std::lround(std::floor(p.y() / cell_)),
                 std::lround(std::floor(p.z() / cell_)))]
        .push_back(static_cast<int>(n));
  }
}

int PointIndex::nearest(const Vec3& q, double max_distance_mm) const {
  const long ci = std::lround(std::floor(q.x() / cell_)), cj = std::lround(std::floor(q.y() / cell_)),
             ck = std::lround(std::floor(q.z() / cell_));
  int best = -1;
  double best_d2 = max_distance_mm * max_distance_mm;
  const long reach = static_cast<long>(std::ceil(max_distance_mm / cell_));
  for (long r = 0; r <= reach; ++r) {
    // Every point in shell r is at least (r - 1) cells away.
    if (r >= 2 && best >= 0 && (r - 1) * cell_ * (r - 1) * cell_ > best_d2) break;
    for (long i = ci - r; i <= ci + r; ++i)
      for (long j = cj - r; j <= cj + r; ++j)
        for (long k = ck - r; k <= ck + r; ++k) {
          if (std::max({std::labs(i - ci), std::labs(j - cj), std::labs(k - ck)}) != r) continue;  // shell only
          const auto it = buckets_.find(key(i, j, k));
          if (it == buckets_.end()) continue;
          for (int n : it->second) {
            const double d2 = (points_[n] - q).squaredNorm();
            if (d2 < best_d2) {
              best_d2 = d2;
              best = n;
            }
          }
        }
  }
  return best;
}

}  // namespace bliskrun
