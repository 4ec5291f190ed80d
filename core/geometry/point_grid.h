#pragma once
// A rectangular array of points q[i][j] as a CAM user extracts from a CAD
// model: i = 0..rows-1 along u (span), j = 0..cols-1 along v (chord).
#include <vector>

#include "core/common/types.h"

namespace bliskrun {

struct PointGrid {
  int rows = 0;
  int cols = 0;
  std::vector<Vec3> points;  // row-major, size rows * cols

  PointGrid() = default;
  PointGrid(int r, int c) : rows(r), cols(c), points(static_cast<size_t>(r) * c, Vec3::Zero()) {}
  Vec3& at(int i, int j) { return points[static_cast<size_t>(i) * cols + j]; }
  const Vec3& at(int i, int j) const { return points[static_cast<size_t>(i) * cols + j]; }
};

}  // namespace bliskrun
