#pragma once
// Points as hash keys by their exact coordinates: a mesh's corners shared
// by several triangles (the same doubles), e.g. to make a triangle soup
// one mesh again or to ask a question once per corner.
#include <cstddef>
#include <functional>

#include "core/common/types.h"

namespace bliskrun {

struct ExactPointEqual {
  bool operator()(const Vec3& a, const Vec3& b) const { return a.x() == b.x() && a.y() == b.y() && a.z() == b.z(); }
};
struct ExactPointHash {
  size_t operator()(const Vec3& p) const {
    size_t h = 0;
    for (int k = 0; k < 3; ++k) h = h * 1000003u ^ std::hash<double>()(p[k]);
    return h;
  }
};

}  // namespace bliskrun
