#include "core/geometry/point_index.h"

#include <algorithm>
#include <cmath>

#include "core/common/error.h"

namespace bliskrun {

PointIndex::PointIndex(std::vector<Vec3> points, double cell_mm) : points_(std::move(points)), cell_(cell_mm) {
  if (!(cell_ > 0) || !std::isfinite(cell_)) throw ParameterError("cell", "expected a cell size > 0 in mm");
  Vec3 hi = Vec3::Zero();
  for (size_t n = 0; n < points_.size(); ++n) {
    const Vec3& p = points_[n];
    if (!p.allFinite()) throw ParameterError("points", "point " + std::to_string(n) + " is not finite");
    lo_ = n == 0 ? p : lo_.cwiseMin(p);
    hi = n == 0 ? p : hi.cwiseMax(p);
  }
  const Vec3 extent = hi - lo_;
  const auto cells = [&](double c) {
    return (std::floor(extent.x() / c) + 1) * (std::floor(extent.y() / c) + 1) * (std::floor(extent.z() / c) + 1);
  };
  while (cells(cell_) > 4e6) cell_ *= 2;
  for (int a = 0; a < 3; ++a) count_[a] = static_cast<long>(std::floor(extent[a] / cell_)) + 1;
  // Counting sort of the points by cell.
  std::vector<size_t> of(points_.size());
  start_.assign(static_cast<size_t>(count_[0] * count_[1] * count_[2]) + 1, 0);
  for (size_t n = 0; n < points_.size(); ++n) {
    const Vec3& p = points_[n];
    of[n] = cell(std::min(count_[0] - 1, cell_along(p.x(), 0)), std::min(count_[1] - 1, cell_along(p.y(), 1)),
                 std::min(count_[2] - 1, cell_along(p.z(), 2)));
    ++start_[of[n] + 1];
  }
  for (size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
  order_.resize(points_.size());
  std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
  for (size_t n = 0; n < points_.size(); ++n) order_[fill[of[n]]++] = static_cast<std::uint32_t>(n);
}

long PointIndex::cell_along(double x, int axis) const {
  return static_cast<long>(std::floor((x - lo_[axis]) / cell_));
}

int PointIndex::nearest(const Vec3& q, double max_distance_mm) const {
  const long c[3] = {cell_along(q.x(), 0), cell_along(q.y(), 1), cell_along(q.z(), 2)};
  int best = -1;
  double best_d2 = max_distance_mm * max_distance_mm;
  const long reach = static_cast<long>(std::ceil(max_distance_mm / cell_));
  for (long r = 0; r <= reach; ++r) {
    // Every point in shell r is at least (r - 1) cells away.
    if (r >= 2 && best >= 0 && (r - 1) * cell_ * (r - 1) * cell_ > best_d2) break;
    for (long i = std::max(0L, c[0] - r); i <= std::min(count_[0] - 1, c[0] + r); ++i)
      for (long j = std::max(0L, c[1] - r); j <= std::min(count_[1] - 1, c[1] + r); ++j)
        for (long k = std::max(0L, c[2] - r); k <= std::min(count_[2] - 1, c[2] + r); ++k) {
          if (std::max({std::labs(i - c[0]), std::labs(j - c[1]), std::labs(k - c[2])}) != r) continue;  // shell only
          const size_t cc = cell(i, j, k);
          for (std::uint32_t n = start_[cc]; n < start_[cc + 1]; ++n) {
            const double d2 = (points_[order_[n]] - q).squaredNorm();
            if (d2 < best_d2) {
              best_d2 = d2;
              best = static_cast<int>(order_[n]);
            }
          }
        }
  }
  return best;
}

}  // namespace bliskrun
