#pragma once
// Points bucketed in a uniform grid over their bounding box (a model sampled
// densely, a scan, a blade's surface samples): the nearest point to a query
// — the shells of cells around it searched outwards until no closer point
// can be left — and every point in a box. Near-constant time per query when
// the cell size is about the sample spacing. The buckets are one array of
// point indices with a start per cell (no per-cell allocation); where the
// box would need more than 4 million cells the cell size is doubled.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/common/types.h"

namespace bliskrun {

class PointIndex {
 public:
  // Throws ParameterError("cell") unless cell_mm > 0, ("points") unless
  // every point is finite.
  PointIndex(std::vector<Vec3> points, double cell_mm);

  // Index of the nearest point within max_distance_mm, or -1.
  int nearest(const Vec3& q, double max_distance_mm) const;

  // Calls f(index) for every point in the cells that meet the box [lo, hi]:
  // a superset of the points in the box, for the caller to filter exactly.
  template <class F>
  void for_each_in_box(const Vec3& lo, const Vec3& hi, F&& f) const {
    long first[3], last[3];
    for (int a = 0; a < 3; ++a) {
      first[a] = std::max(0L, cell_along(lo[a], a));
      last[a] = std::min(count_[a] - 1, cell_along(hi[a], a));
      if (first[a] > last[a]) return;
    }
    for (long i = first[0]; i <= last[0]; ++i)
      for (long j = first[1]; j <= last[1]; ++j)
        for (long k = first[2]; k <= last[2]; ++k) {
          const size_t c = cell(i, j, k);
          for (std::uint32_t n = start_[c]; n < start_[c + 1]; ++n) f(static_cast<int>(order_[n]));
        }
  }

  const std::vector<Vec3>& points() const { return points_; }
  double cell_mm() const { return cell_; }

 private:
  long cell_along(double x, int axis) const;  // unclamped
  size_t cell(long i, long j, long k) const {
    return (static_cast<size_t>(i) * static_cast<size_t>(count_[1]) + static_cast<size_t>(j)) *
               static_cast<size_t>(count_[2]) +
           static_cast<size_t>(k);
  }

  std::vector<Vec3> points_;
  double cell_;
  Vec3 lo_ = Vec3::Zero();
  long count_[3] = {1, 1, 1};
  std::vector<std::uint32_t> start_;  // cells + 1
  std::vector<std::uint32_t> order_;  // point indices, cell by cell
};

}  // namespace bliskrun
