#pragma once
// One of the stock's three grids of parallel rays (dexels): rays along the
// part axis `axis`, one through the centre of every square cell of side
// `spacing` in the plane of the other two axes (u = axis + 1, v = axis + 2,
// cyclic: rays along X sit on a (y, z) grid, along Y on (z, x), along Z on
// (x, y)). Each ray stands for the cell's area: the grid's volume is the
// sum of its rays' material lengths times spacing².
#include <cmath>
#include <vector>

#include "core/common/types.h"
#include "core/stock/dexel_ray.h"

namespace bliskrun {

struct DexelGrid {
  int axis = 2;
  double u0 = 0, v0 = 0, spacing = 1;  // the grid's corner: ray (i, j) at u0 + (i + 0.5)·spacing, ...
  int nu = 0, nv = 0;
  std::vector<DexelRay> rays;  // ray (i, j) at j·nu + i

  int u_axis() const { return (axis + 1) % 3; }
  int v_axis() const { return (axis + 2) % 3; }
  double u_of(int i) const { return u0 + (i + 0.5) * spacing; }
  double v_of(int j) const { return v0 + (j + 0.5) * spacing; }
  DexelRay& ray(int i, int j) { return rays[static_cast<size_t>(j) * nu + i]; }
  const DexelRay& ray(int i, int j) const { return rays[static_cast<size_t>(j) * nu + i]; }
  // The point of ray (i, j) at coordinate 0 along it.
  Vec3 origin(int i, int j) const {
    Vec3 p = Vec3::Zero();
    p[u_axis()] = u_of(i);
    p[v_axis()] = v_of(j);
    return p;
  }
  Vec3 direction() const { return Vec3::Unit(axis); }
  // Sum of the rays' material lengths, mm.
  double material_length() const {
    double total = 0;
    for (const DexelRay& r : rays) total += r.length();
    return total;
  }
};

}  // namespace bliskrun
