// Stock::cut: the tool's solid, placed at sampled poses along each move,
// taken out of every ray it crosses. The three grids never meet: each runs
// the whole list of placements on its own (on up to three threads), and the
// figures of a placement are summed over the grids in grid order, so the
// result does not depend on the thread count.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/common/error.h"
#include "core/stock/revolved_solid.h"
#include "core/stock/stock.h"

namespace bliskrun {

namespace {

// The span of u on the row v = const of the points within `radius` of the
// 2-D segment p0-p1 (a stadium: the capsule around the tool's axis seen
// along the rays). False when the row misses it.
bool stock_stadium_row(const Vec2& p0, const Vec2& p1, double radius, double v, double& lo, double& hi) {
  lo = kInf;
  hi = -kInf;
  for (const Vec2* p : {&p0, &p1}) {
    const double dv = v - p->y();
    if (std::abs(dv) <= radius) {
      const double w = std::sqrt(radius * radius - dv * dv);
      lo = std::min(lo, p->x() - w);
      hi = std::max(hi, p->x() + w);
    }
  }
  const Vec2 d = p1 - p0;
  const double length = d.norm();
  if (length > 1e-12) {
    const Vec2 t = d / length, n(-t.y(), t.x());
    // Both constraints are linear in u along the row: c0 + c1·u in [min, max].
    double band_lo = -kInf, band_hi = kInf;
    const auto limit = [&](double c1, double c0, double min, double max) {
      if (std::abs(c1) < 1e-12) {
        if (c0 < min || c0 > max) band_lo = kInf;
        return;
      }
      double a = (min - c0) / c1, b = (max - c0) / c1;
      if (a > b) std::swap(a, b);
      band_lo = std::max(band_lo, a);
      band_hi = std::min(band_hi, b);
    };
    limit(t.x(), t.y() * (v - p0.y()) - t.x() * p0.x(), 0, length);
    limit(n.x(), n.y() * (v - p0.y()) - n.x() * p0.x(), -radius, radius);
    if (band_lo <= band_hi) {
      lo = std::min(lo, band_lo);
      hi = std::max(hi, band_hi);
    }
  }
  return lo <= hi;
}

// One sample of the motion: the cutter's solid (or a plunge step's exact
// sweep) placed at (tip, axis), and the whole tool's pose for the shank and
// holder.
struct StockPlacement {
  const RevolvedSolid* solid = nullptr;
  Vec3 tip, axis;
  std::optional<Vec3> side;  // across the feed, perpendicular to the axis (radial engagement)
  ToolPose body;             // where the shank and holder are
  int body_grid = 2;         // the one grid they are measured on (rays closest to their axis)
};

// Calls visit(ray, origin, lo, hi) for every ray of `g` with material that
// the placed solid crosses, with the span [lo, hi] it occupies there.
template <class Visit>
void stock_for_each_crossing(DexelGrid& g, const RevolvedSolid& solid, const Vec3& tip, const Vec3& axis, Visit&& visit) {
  const Vec3 p0 = tip + solid.z_min() * axis, p1 = tip + solid.z_max() * axis;
  const double radius = solid.max_radius();
  const int ua = g.u_axis(), va = g.v_axis(), k = g.axis;
  const Vec2 q0(p0[ua], p0[va]), q1(p1[ua], p1[va]);
  // Along the rays the capsule spans [along_lo, along_hi].
  const double along_lo = std::min(p0[k], p1[k]) - radius, along_hi = std::max(p0[k], p1[k]) + radius;
  const double h = g.spacing;
  const int j_lo = std::max(0, static_cast<int>(std::ceil((std::min(q0.y(), q1.y()) - radius - g.v0) / h - 0.5)));
  const int j_hi = std::min(g.nv - 1, static_cast<int>(std::floor((std::max(q0.y(), q1.y()) + radius - g.v0) / h - 0.5)));
  const Vec3 dir = g.direction();
  for (int j = j_lo; j <= j_hi; ++j) {
    double u_lo, u_hi;
    if (!stock_stadium_row(q0, q1, radius, g.v_of(j), u_lo, u_hi)) continue;
    const int i_lo = std::max(0, static_cast<int>(std::ceil((u_lo - g.u0) / h - 0.5)));
    const int i_hi = std::min(g.nu - 1, static_cast<int>(std::floor((u_hi - g.u0) / h - 0.5)));
    for (int i = i_lo; i <= i_hi; ++i) {
      DexelRay& ray = g.ray(i, j);
      if (ray.empty() || ray[ray.size() - 1].end <= along_lo || ray[0].start >= along_hi) continue;
      const Vec3 origin = g.origin(i, j);
      const FrameRay fr = FrameRay::make(origin, dir, tip, axis);
      // Only a ray with material within the tool's bounding cylinder is
      // intersected exactly: in a channel most rays the tool's box holds
      // pass through air already cut.
      double lo, hi;
      if (!solid.bound(fr, lo, hi) || !ray.overlaps(lo, hi) || !solid.intersect(fr, lo, hi, lo, hi)) continue;
      visit(ray, origin, lo, hi);
    }
  }
}

// What one placement did on one grid: material removed along its rays (mm)
// and the extents of the removed pieces in the placement's frame; the
// material inside the shank and holder (mm, along rays).
struct StockGridStep {
  double removed_mm = 0;
  double z_lo = kInf, z_hi = -kInf, w_lo = kInf, w_hi = -kInf;
  double body_mm = 0;
};

// Pieces shorter than this along a ray do not count in the engagement's
// extents: they are the cutter's surface grazing a ray, not a cut.
constexpr double kStockEngagedPieceMm = 1e-3;

StockGridStep stock_apply(DexelGrid& g, const StockPlacement& at, const std::vector<RevolvedSolid>& body) {
  StockGridStep out;
  const Vec3 dir = g.direction();
  stock_for_each_crossing(g, *at.solid, at.tip, at.axis, [&](DexelRay& ray, const Vec3& origin, double lo, double hi) {
    out.removed_mm += ray.subtract(lo, hi, [&](double s, double e) {
      if (e - s < kStockEngagedPieceMm) return;
      for (double x : {s, e}) {
        const Vec3 p = origin + x * dir - at.tip;
        const double z = p.dot(at.axis);
        out.z_lo = std::min(out.z_lo, z);
        out.z_hi = std::max(out.z_hi, z);
        if (at.side) {
          const double w = p.dot(*at.side);
          out.w_lo = std::min(out.w_lo, w);
          out.w_hi = std::max(out.w_hi, w);
        }
      }
    });
  });
  // A contact is a finding, not a volume to account: one grid suffices, the
  // one whose rays run closest to the axis, on which the long shank's
  // shadow is smallest (a 96 mm shank across the rays covers ~40x more).
  if (g.axis != at.body_grid) return out;
  for (const RevolvedSolid& part : body) {
    double inside = 0;
    stock_for_each_crossing(g, part, at.body.tip, at.body.axis, [&](DexelRay& ray, const Vec3&, double lo, double hi) {
      for (const DexelRay::Span& s : ray) {
        if (s.start >= hi) break;
        inside += std::max(0.0, std::min<double>(s.end, hi) - std::max<double>(s.start, lo));
      }
    });
    out.body_mm = std::max(out.body_mm, inside);
  }
  return out;
}

// The grid whose rays run closest to `axis`.
int stock_axis_grid(const Vec3& axis) {
  int k = 0;
  for (int a = 1; a < 3; ++a) {
    if (std::abs(axis[a]) > std::abs(axis[k])) k = a;
  }
  return k;
}

// Moves are sampled and applied in chunks of about this many placements,
// bounding the per-grid figures held at once.
constexpr size_t kStockChunkPlacements = 1 << 15;

}  // namespace

CutResult Stock::cut(const Toolpath& moves, const Tool& tool, const CutOptions& o, const ToolPose* from,
                     Progress& progress) {
  if (!(o.step_mm >= 0) || !std::isfinite(o.step_mm)) throw ParameterError("step_mm", "expected >= 0 mm (0: the resolution)");
  if (!(o.air_mm2 >= 0) || !std::isfinite(o.air_mm2)) throw ParameterError("air_mm2", "expected >= 0 mm²");
  if (o.threads < 1) throw ParameterError("threads", "expected at least 1");
  const double step = o.step_mm > 0 ? o.step_mm : spacing_;
  if (step < 1e-3) throw ParameterError("step_mm", "expected at least 0.001 mm");
  const RevolvedSolid cutter(tool.cutter(), o.torus_tol_mm);
  std::vector<RevolvedSolid> body;
  if (o.check_body) {
    for (ToolPartId part : {ToolPartId::Shank, ToolPartId::Holder}) {
      if (tool.has(part)) body.emplace_back(tool.profile(part), o.torus_tol_mm);
    }
  }
  const double reach = tool.cutter().reach();
  const double cell_mm2 = spacing_ * spacing_ / 3;  // a ray's share of a volume (mean of three grids)
  // Less than this (mm³) in a rapid or in the shank and holder is rounding.
  const double contact_mm3 = std::max(o.air_mm2, 1e-4) * spacing_;

  CutResult result;
  result.moves.resize(moves.size());
  std::optional<ToolPose> last;
  if (from) last = ToolPose{from->tip, unit_axis(from->axis, "from.axis")};
  progress.begin("stock", static_cast<long>(moves.size()));

  std::vector<StockPlacement> placements;
  std::vector<size_t> move_of;     // per placement
  std::vector<double> sub_length;  // per placement: its stretch of tip path (0 for a placed tool)
  std::deque<RevolvedSolid> sweeps;  // a chunk's plunge steps
  std::array<std::vector<StockGridStep>, 3> steps;
  size_t m = 0;
  while (m < moves.size()) {
    placements.clear();
    move_of.clear();
    sub_length.clear();
    sweeps.clear();
    const size_t chunk_first = m;
    // Sample a chunk of moves.
    for (; m < moves.size() && placements.size() < kStockChunkPlacements; ++m) {
      const Move& move = moves[m];
      MoveCut& mc = result.moves[m];
      if (move.kind == Move::Kind::Stop) {
        last.reset();
        continue;
      }
      const std::string name = "moves[" + std::to_string(m + 1) + "].axis";
      const ToolPose to{move.pose.tip, unit_axis(move.pose.axis, name.c_str())};
      if (!to.tip.allFinite()) throw ParameterError("moves", "move " + std::to_string(m + 1) + ": the tip is not finite");
      if (!last) {
        // Placed, not moved there: the tool's own volume at the pose.
        placements.push_back({&cutter, to.tip, to.axis, std::nullopt, to, stock_axis_grid(to.axis)});
        move_of.push_back(m);
        sub_length.push_back(0);
        last = to;
        continue;
      }
      if (last->axis.dot(to.axis) < -1 + 1e-12) {
        throw ParameterError("moves", "move " + std::to_string(m + 1) + " turns the tool axis by 180°: no motion");
      }
      const PoseMotion motion(*last, to);
      const Vec3 delta = to.tip - last->tip;
      mc.length_mm = delta.norm();
      const double samples = std::ceil(motion.max_point_speed(reach) / step);
      // 10^7 samples of one move: a move kilometres long at a µm step.
      if (!(samples <= 1e7)) {
        throw ParameterError("moves", "move " + std::to_string(m + 1) + " needs " + std::to_string(samples) +
                                          " samples at a step of " + std::to_string(step) + " mm (at most 1e7)");
      }
      const int n = std::max(1, static_cast<int>(samples));
      // Along the tool's own axis the sweep is exact, one solid per step.
      const double along = delta.dot(to.axis);
      const bool axial = motion.angle_rad() < 1e-12 && (delta - along * to.axis).norm() <= 1e-9 * (1 + mc.length_mm);
      const RevolvedSolid* swept = nullptr;
      if (axial) {
        sweeps.push_back(cutter.swept_along_axis(along / n));
        swept = &sweeps.back();
      }
      for (int k = 1; k <= n; ++k) {
        const double t = static_cast<double>(k) / n;
        StockPlacement at;
        if (axial) {
          at = {swept, last->tip + (static_cast<double>(k - 1) / n) * delta, to.axis, std::nullopt,
                {last->tip + t * delta, to.axis}};
        } else {
          const ToolPose p = motion.pose_at(t);
          at = {&cutter, p.tip, p.axis, std::nullopt, p};
          const Vec3 across = delta - delta.dot(p.axis) * p.axis;
          if (across.norm() > 1e-9) at.side = p.axis.cross(across).normalized();
        }
        at.body_grid = stock_axis_grid(at.body.axis);
        placements.push_back(at);
        move_of.push_back(m);
        sub_length.push_back(mc.length_mm / n);
      }
      last = to;
    }
    // Each grid through the chunk's placements, the grids side by side.
    for (auto& s : steps) s.assign(placements.size(), StockGridStep{});
    std::atomic<int> next{0};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    const auto work = [&] {
      for (int k; (k = next.fetch_add(1)) < 3;) {
        try {
          DexelGrid& g = grids_[static_cast<size_t>(k)];
          std::vector<StockGridStep>& out = steps[static_cast<size_t>(k)];
          for (size_t p = 0; p < placements.size(); ++p) {
            if (p % 512 == 0) progress.check();
            out[p] = stock_apply(g, placements[p], body);
            material_mm_[static_cast<size_t>(k)] -= out[p].removed_mm;
          }
        } catch (...) {
          std::lock_guard<std::mutex> lock(failure_mutex);
          if (!failure) failure = std::current_exception();
          next.store(3);
        }
      }
    };
    const int workers = placements.size() < 64 ? 1 : std::min(3, o.threads);
    if (workers == 1) {
      work();
    } else {
      std::vector<std::thread> pool;
      for (int w = 1; w < workers; ++w) pool.emplace_back(work);
      work();
      for (std::thread& t : pool) t.join();
    }
    if (failure) std::rethrow_exception(failure);
    // The placements' figures, grid by grid in order, into their moves.
    for (size_t p = 0; p < placements.size(); ++p) {
      MoveCut& mc = result.moves[move_of[p]];
      double removed = 0, body_mm = 0, z_lo = kInf, z_hi = -kInf, w_lo = kInf, w_hi = -kInf;
      for (const auto& s : steps) {
        const StockGridStep& g = s[p];
        removed += g.removed_mm;
        body_mm += g.body_mm;
        z_lo = std::min(z_lo, g.z_lo);
        z_hi = std::max(z_hi, g.z_hi);
        w_lo = std::min(w_lo, g.w_lo);
        w_hi = std::max(w_hi, g.w_hi);
      }
      removed *= cell_mm2;
      mc.removed_mm3 += removed;
      if (z_hi > z_lo) mc.axial_mm = std::max(mc.axial_mm, z_hi - z_lo);
      if (w_hi > w_lo) mc.radial_mm = std::max(mc.radial_mm, w_hi - w_lo);
      // Float rounding where a shank as wide as the cutter follows it is
      // not a contact.
      const double body_mm3 = body_mm * spacing_ * spacing_;  // one grid's
      if (body_mm3 >= contact_mm3) mc.body_mm3 = std::max(mc.body_mm3, body_mm3);
      if (sub_length[p] > 0) {
        const double rate = removed / sub_length[p];
        mc.rate_max_mm2 = std::max(mc.rate_max_mm2, rate);
        if (moves[move_of[p]].kind == Move::Kind::Feed && rate < o.air_mm2) mc.air_mm += sub_length[p];
      }
    }
    result.samples += static_cast<long>(placements.size());
    for (size_t q = chunk_first; q < m; ++q) {
      const MoveCut& mc = result.moves[q];
      if (moves[q].kind == Move::Kind::Stop) continue;
      result.removed_mm3 += mc.removed_mm3;
      if (moves[q].kind == Move::Kind::Feed) {
        result.cut_mm += mc.length_mm;
        result.air_cut_mm += mc.air_mm;
      } else {
        result.rapid_mm += mc.length_mm;
        if (mc.removed_mm3 >= contact_mm3) {
          result.rapid_removed_mm3 += mc.removed_mm3;
          ++result.rapid_cut_moves;
        }
      }
      if (mc.body_mm3 > 0) {
        ++result.body_contact_moves;
        result.body_contact_max_mm3 = std::max(result.body_contact_max_mm3, mc.body_mm3);
      }
      result.rate_max_mm2 = std::max(result.rate_max_mm2, mc.rate_max_mm2);
      result.axial_max_mm = std::max(result.axial_max_mm, mc.axial_mm);
      result.radial_max_mm = std::max(result.radial_max_mm, mc.radial_mm);
    }
    progress.step(static_cast<long>(m));
  }
  progress.end();
  return result;
}

}  // namespace bliskrun
