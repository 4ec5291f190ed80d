#pragma once
// Nearest point among many (a model sampled densely, a scan): a uniform grid
// of buckets with the given cell size; a query searches the shells of cells
// around the point outwards until no closer point can be left. Near-constant
// time per query when the cell size is about the sample spacing.
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/common/types.h"

namespace bliskrun {

class PointIndex {
 public:
  // Throws ParameterError("cell") unless cell_mm > 0; points must be finite.
  PointIndex(std::vector<Vec3> points, double cell_mm);

  // Index of the nearest point within max_distance_mm, or -1.
  int nearest(const Vec3& q, double max_distance_mm) const;
  const std::vector<Vec3>& points() const { return points_; }

 private:
  std::int64_t key(long i, long j, long k) const;
  std::vector<Vec3> points_;
  double cell_;
  std::unordered_map<std::int64_t, std::vector<int>> buckets_;
};

}  // namespace bliskrun
