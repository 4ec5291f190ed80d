#include "core/stock/stock.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/common/error.h"
#include "core/common/memory_budget.h"

namespace bliskrun {

namespace {

// Spans across a ray along X (or Y) at lateral offset `w` from the axis,
// from the meridian's r spans at the ray's height: |x| in
// [sqrt(r0² - w²), sqrt(r1² - w²)], merged where they meet at x = 0.
std::vector<std::pair<double, double>> stock_spans_across(const std::vector<std::pair<double, double>>& r_spans, double w) {
  std::vector<std::pair<double, double>> out;
  for (const auto& [r0, r1] : r_spans) {
    if (r1 <= std::abs(w)) continue;
    const double x1 = std::sqrt(r1 * r1 - w * w);
    if (r0 <= std::abs(w)) {
      out.emplace_back(-x1, x1);
    } else {
      const double x0 = std::sqrt(r0 * r0 - w * w);
      out.emplace_back(-x1, -x0);
      out.emplace_back(x0, x1);
    }
  }
  std::sort(out.begin(), out.end());
  std::vector<std::pair<double, double>> merged;
  for (const auto& s : out) {
    if (!merged.empty() && s.first <= merged.back().second) {
      merged.back().second = std::max(merged.back().second, s.second);
    } else {
      merged.push_back(s);
    }
  }
  return merged;
}

}  // namespace

Stock::Stock(const BlankProfile& blank, const StockOptions& options) : spacing_(options.resolution_mm) {
  const double h = spacing_;
  const double height = blank.z_max() - blank.z_min(), radius = blank.r_max();
  if (!(h >= 0.01) || !(h <= 0.25 * height) || !(h <= 0.25 * radius)) {
    throw ParameterError("resolution_mm", "expected 0.01 mm up to a quarter of the blank's height (" +
                                              std::to_string(height) + " mm) and radius (" + std::to_string(radius) +
                                              " mm), got " + std::to_string(h));
  }
  // Cells over the blank's box: x and y over [-r_max, r_max], z over its height.
  const int nxy = static_cast<int>(std::ceil(2 * radius / h));
  const int nz = static_cast<int>(std::ceil(height / h));
  const double xy0 = -0.5 * nxy * h, z0 = 0.5 * (blank.z_min() + blank.z_max()) - 0.5 * nz * h;
  const std::array<int, 3> count{nxy, nxy, nz};
  const std::array<double, 3> corner{xy0, xy0, z0};
  const double rays = 1.0 * nxy * nxy + 2.0 * nxy * nz;
  // 2·10^8 rays are 3.2 GB before any span: beyond any blank this is for.
  if (!(rays <= 2e8)) {
    throw ParameterError("resolution_mm", std::to_string(h) + " mm over a blank of radius " + std::to_string(radius) +
                                              " mm and height " + std::to_string(height) + " mm needs " +
                                              std::to_string(rays) + " rays, more than 2e8: coarser, please");
  }
  check_allocation_estimate(rays * sizeof(DexelRay), "the stock's rays (" + std::to_string(static_cast<long>(rays)) +
                                                         " at " + std::to_string(h) + " mm)");
  for (int k = 0; k < 3; ++k) {
    DexelGrid& g = grids_[static_cast<size_t>(k)];
    g.axis = k;
    g.spacing = h;
    g.nu = count[static_cast<size_t>(g.u_axis())];
    g.nv = count[static_cast<size_t>(g.v_axis())];
    g.u0 = corner[static_cast<size_t>(g.u_axis())];
    g.v0 = corner[static_cast<size_t>(g.v_axis())];
    g.rays.resize(static_cast<size_t>(g.nu) * g.nv);
  }
  // Z rays: the meridian's z spans at the ray's radius.
  DexelGrid& gz = grids_[2];
  for (int j = 0; j < gz.nv; ++j) {
    cancellation_point();
    for (int i = 0; i < gz.nu; ++i) {
      const double r = std::hypot(gz.u_of(i), gz.v_of(j));
      if (r >= radius) continue;
      for (const auto& [a, b] : blank.z_spans_at_radius(r)) gz.ray(i, j).push_back(a, b);
    }
  }
  // X rays on (y, z) and Y rays on (z, x): the meridian's r spans at the
  // ray's height, across at its lateral offset.
  DexelGrid& gx = grids_[0];
  for (int j = 0; j < gx.nv; ++j) {  // v = z
    cancellation_point();
    const auto r_spans = blank.r_spans_at_height(gx.v_of(j));
    for (int i = 0; i < gx.nu; ++i) {  // u = y
      for (const auto& [a, b] : stock_spans_across(r_spans, gx.u_of(i))) gx.ray(i, j).push_back(a, b);
    }
  }
  DexelGrid& gy = grids_[1];
  for (int i = 0; i < gy.nu; ++i) {  // u = z
    cancellation_point();
    const auto r_spans = blank.r_spans_at_height(gy.u_of(i));
    for (int j = 0; j < gy.nv; ++j) {  // v = x
      for (const auto& [a, b] : stock_spans_across(r_spans, gy.v_of(j))) gy.ray(i, j).push_back(a, b);
    }
  }
  for (int k = 0; k < 3; ++k) material_mm_[static_cast<size_t>(k)] = grids_[static_cast<size_t>(k)].material_length();
  blank_volume_ = volume();
  blank_exact_volume_ = blank.volume();
}

double Stock::volume_of_grid(int axis) const {
  if (axis < 0 || axis > 2) throw ParameterError("axis", "expected 0, 1 or 2");
  return material_mm_[static_cast<size_t>(axis)] * spacing_ * spacing_;
}

double Stock::volume() const {
  return (material_mm_[0] + material_mm_[1] + material_mm_[2]) * spacing_ * spacing_ / 3;
}

double Stock::material_above(const Vec3& point, const Vec3& normal, double max_mm) const {
  const double len = normal.norm();
  if (!(len > 0) || !std::isfinite(len)) throw ParameterError("normal", "expected a non-zero finite vector");
  if (!(max_mm > 0)) throw ParameterError("max_mm", "expected a positive search depth, mm");
  const Vec3 n = normal / len;
  int k = 0;
  for (int a = 1; a < 3; ++a) {
    if (std::abs(n[a]) > std::abs(n[k])) k = a;
  }
  const DexelGrid& g = grids_[static_cast<size_t>(k)];
  const double sign = n[k] > 0 ? 1 : -1, cosine = std::abs(n[k]);
  const double c = point[k];
  // Along the ray, outwards (sign), the search reaches max_mm / cosine.
  const double reach = max_mm / cosine;
  const double fu = (point[g.u_axis()] - g.u0) / g.spacing - 0.5, fv = (point[g.v_axis()] - g.v0) / g.spacing - 0.5;
  const int i0 = static_cast<int>(std::floor(fu)), j0 = static_cast<int>(std::floor(fv));
  const double tu = fu - i0, tv = fv - j0;
  double weight = 0, sum = 0;
  for (int dj = 0; dj < 2; ++dj) {
    for (int di = 0; di < 2; ++di) {
      const int i = i0 + di, j = j0 + dj;
      if (i < 0 || j < 0 || i >= g.nu || j >= g.nv) continue;
      const double w = (di ? tu : 1 - tu) * (dj ? tv : 1 - tv);
      if (w <= 0) continue;
      // The top of the material under c (outwards = +sign): the far end of
      // the span holding c, else of the nearest span below it.
      double top = std::nan("");
      for (const DexelRay::Span& s : g.ray(i, j)) {
        const double lo = sign > 0 ? s.start : -static_cast<double>(s.end);
        const double hi = sign > 0 ? s.end : -static_cast<double>(s.start);
        const double at = sign * c;
        if (lo > at) {
          if (sign < 0) continue;  // spans in decreasing outward order: keep looking
          break;
        }
        if (hi >= at - reach) top = std::isnan(top) ? hi : std::max(top, hi);
      }
      if (std::isnan(top)) continue;
      const double depth = std::min(top - sign * c, reach);
      sum += w * depth;
      weight += w;
    }
  }
  if (weight <= 0) return std::nan("");
  return sum / weight * cosine;
}

long Stock::ray_count() const {
  long n = 0;
  for (const DexelGrid& g : grids_) n += static_cast<long>(g.rays.size());
  return n;
}

long Stock::span_count() const {
  long n = 0;
  for (const DexelGrid& g : grids_) {
    for (const DexelRay& r : g.rays) n += r.size();
  }
  return n;
}

std::size_t Stock::memory_bytes() const {
  std::size_t bytes = sizeof(*this);
  for (const DexelGrid& g : grids_) {
    bytes += g.rays.capacity() * sizeof(DexelRay);
    for (const DexelRay& r : g.rays) bytes += r.heap_bytes();
  }
  return bytes;
}

}  // namespace bliskrun
