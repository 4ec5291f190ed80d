#pragma once
// Order statistics of measured values (noise levels, point spacings).
#include <algorithm>
#include <vector>

namespace bliskrun {

// The median (the upper one of an even count); 0 for no values.
inline double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace bliskrun
