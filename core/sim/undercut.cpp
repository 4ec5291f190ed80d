#include "core/sim/undercut.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <thread>

#include "core/common/error.h"
#include "core/common/parallel.h"
#include "core/common/progress.h"

namespace bliskrun {

namespace {

constexpr int kFan = 4;     // cells per group side, at every level of a SampleIndex
constexpr int kLevels = 4;  // tiles of 4 x 4 samples, then 16 x 16, 64 x 64, 256 x 256

struct Sample {
  Vec3 p, n;
};

// A group of samples (or of groups) with a bounding sphere.
struct Group {
  Vec3 centre = Vec3::Zero();
  double radius = 0;
  std::vector<int> members;  // sample indices (tiles), or indices of the groups a level below
  // slab_of: the samples' mean normal, their largest distance from the
  // plane through the centre across it, and the cosine and sine of the
  // largest angle between a sample's normal and that mean.
  Vec3 normal = Vec3::Zero();
  double thickness = 0, cone_cos = -1, cone_sin = 0;
};

template <class PointOf>
void bound(Group& g, PointOf point_and_radius) {
  Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
  for (int m : g.members) {
    const auto [c, r] = point_and_radius(m);
    lo = lo.cwiseMin(c - Vec3::Constant(r));
    hi = hi.cwiseMax(c + Vec3::Constant(r));
  }
  g.centre = 0.5 * (lo + hi);
  g.radius = 0;
  for (int m : g.members) {
    const auto [c, r] = point_and_radius(m);
    g.radius = std::max(g.radius, (c - g.centre).norm() + r);
  }
}

// A group's slab (Group::normal ... cone_sin) over the given samples: a
// nearly flat patch of the surface lies within `thickness` of its mean
// plane.
template <class ForEachSample>
void slab_of(Group& g, ForEachSample each) {
  Vec3 n = Vec3::Zero();
  each([&](const Sample& smp) { n += smp.n; });
  if (!(n.norm() > 1e-9)) return;  // normals cancel: no slab (cone_cos -1 never culls)
  g.normal = n.normalized();
  g.thickness = 0;
  g.cone_cos = 1;
  each([&](const Sample& smp) {
    g.thickness = std::max(g.thickness, std::abs(g.normal.dot(smp.p - g.centre)));
    g.cone_cos = std::min(g.cone_cos, g.normal.dot(smp.n));
  });
  g.cone_cos = std::clamp(g.cone_cos, -1.0, 1.0);
  g.cone_sin = std::sqrt(1 - g.cone_cos * g.cone_cos);
}

// The samples bounded by a hierarchy of groups: levels[0] holds tiles of
// kFan x kFan samples, each level above groups kFan x kFan of the one below
// (the last level covers the whole grid in a few groups). Small tiles at the
// bottom: a tool's shell within reach of the samples is thin (0.02-0.1 mm)
// beside tiles of 0.1-0.3 mm, so the finer the last test, the fewer samples
// are traced for nothing.
struct SampleIndex {
  std::vector<Sample> samples;
  std::vector<std::vector<Group>> levels;
};

SampleIndex build_index(const Surface& s, const UndercutOptions& o) {
  SampleIndex idx;
  const int nu = o.samples_u, nv = o.samples_v;
  idx.samples.resize(static_cast<size_t>(nu) * nv);
  // Rows of samples on o.threads workers (each writes its own row).
  Progress quiet;
  run_parallel(static_cast<size_t>(nu), std::max(1, o.threads), quiet, "design samples", [&](size_t row, Progress&) {
    const int i = static_cast<int>(row);
    cancellation_point();
    const double u = o.u0 + (o.u1 - o.u0) * i / (nu - 1);
    for (int j = 0; j < nv; ++j) {
      const double v = o.v0 + (o.v1 - o.v0) * j / (nv - 1);
      const SurfaceDerivs d = s.eval(u, v);
      const Vec3 n = o.flip_normal ? Vec3(d.pv.cross(d.pu)) : Vec3(d.pu.cross(d.pv));
      if (n.norm() < 1e-14)
        throw Error("simulate_undercut: design surface is singular at (u, v) = (" +
                    std::to_string(u) + ", " + std::to_string(v) + ")");
      idx.samples[static_cast<size_t>(i) * nv + j] = {d.p, n.normalized()};
    }
  });
  // Level by level: group kFan x kFan cells of the grid below (samples,
  // then groups) into one, until a few groups cover the grid.
  int cu = nu, cv = nv;  // the grid being grouped, in cells
  for (int level = 0; level < kLevels; ++level) {
    cancellation_point();
    const int gu = (cu + kFan - 1) / kFan, gv = (cv + kFan - 1) / kFan;
    std::vector<Group> groups(static_cast<size_t>(gu) * gv);
    for (int i = 0; i < cu; ++i)
      for (int j = 0; j < cv; ++j) groups[static_cast<size_t>(i / kFan) * gv + j / kFan].members.push_back(i * cv + j);
    const std::vector<Group>* below = level == 0 ? nullptr : &idx.levels.back();
    // Every sample under a group, through the levels below.
    auto each_sample = [&](const Group& g, const auto& f) {
      std::vector<int> cells(g.members);
      for (int l = level - 1; l >= 0; --l) {
        std::vector<int> next;
        for (int c : cells)
          for (int m : idx.levels[l][c].members) next.push_back(m);
        cells.swap(next);
      }
      for (int m : cells) f(idx.samples[m]);
    };
    for (Group& g : groups) {
      if (below)
        bound(g, [&](int m) { return std::pair<Vec3, double>((*below)[m].centre, (*below)[m].radius); });
      else
        bound(g, [&](int m) { return std::pair<Vec3, double>(idx.samples[m].p, 0.0); });
      slab_of(g, [&](const auto& f) { each_sample(g, f); });
    }
    idx.levels.push_back(std::move(groups));
    cu = gu;
    cv = gv;
  }
  return idx;
}

// Every tool position the simulation evaluates, passes swept, with the pass
// and the pose index each belongs to (the pose its motion ends at).
struct Positions {
  std::vector<Eigen::Isometry3d> frames;
  std::vector<std::pair<int, long>> origin;  // (pass, pose)
  std::vector<int> run;                      // which run's cutter
};
void add_positions(Positions& out, const std::vector<ToolPass>& passes, int first_pass, int run, double reach_mm,
                   double step_mm) {
  for (size_t q = 0; q < passes.size(); ++q) {
    const ToolPass& pass = passes[q];
    const size_t p = first_pass + q;
    for (size_t k = 0; k + 1 < pass.size(); ++k) {
      const PoseMotion motion(pass[k], pass[k + 1]);
      const int n = std::max(1, static_cast<int>(std::ceil(motion.max_point_speed(reach_mm) / step_mm)));
      for (int s = 0; s < n; ++s) {
        out.frames.push_back(motion.frame_at(static_cast<double>(s) / n));
        // The motion's start pose ends the motion before it (or is a pass's
        // first pose).
        out.origin.emplace_back(static_cast<int>(p), static_cast<long>(s == 0 ? k : k + 1));
      }
    }
    if (!pass.empty()) {
      out.frames.push_back(tool_to_part(pass.back()));
      out.origin.emplace_back(static_cast<int>(p), static_cast<long>(pass.size() - 1));
    }
  }
  out.run.resize(out.frames.size(), run);
}

// A lower bound of the cutter's signed distance at q (tool frame): the
// distance to its bounding cylinder, or less at the cylinder's rims. Far
// cheaper than the exact one, and as long far from the cutter.
double bounding_cylinder_distance(const Profile& cutter, const Vec3& q) {
  return std::max(std::sqrt(q.x() * q.x() + q.y() * q.y()) - cutter.max_radius(),
                  std::max(cutter.z_min() - q.z(), q.z() - cutter.z_max()));
}

// Lowest s in [-below, limit] where p + s n is inside the cutter, or +inf.
// `limit` is the lower of search_above_mm and the material already left at
// the sample: an entry above it would change nothing, so the trace stops
// there (most positions of a sweep only graze what the one before cut).
double first_entry(const Profile& cutter, const Vec3& p_tool, const Vec3& n_tool,
                   const UndercutOptions& o, double limit) {
  // Stepping by the bounding cylinder's distance is as safe as by the exact
  // one, and far from the cutter nearly as long a step.
  double s = -o.search_below_mm;
  for (int iter = 0; iter < 400; ++iter) {
    const Vec3 q = p_tool + s * n_tool;
    const double bound = bounding_cylinder_distance(cutter, q);
    const double f = bound > 0.02 ? bound : cutter.signed_distance(q);
    if (f <= o.tol_mm) return s;
    s += f;
    if (s > limit) return kInf;
  }
  return kInf;  // grazing line that never entered within the iteration budget
}

// Lowers a to v if v is smaller, from any thread.
void lower_to(std::atomic<double>& a, double v) {
  double current = a.load(std::memory_order_relaxed);
  while (v < current && !a.compare_exchange_weak(current, v, std::memory_order_relaxed)) {
  }
}

// Whether every point p - s n (0 <= s <= range) of a tile's samples lies
// below the cutter's lowest plane z = z_min, where no point of the cutter
// is: what a trace of entries below the surface (s <= 0, a gouge guard)
// can never enter. The bottom of a flat-end mill lies over the flank it
// cuts beside: ~27 000 samples 32 um apart under a 6 mm disc, every one
// within the Lipschitz cull's reach, and this clears their tiles whole.
// With a = the tool axis, z(p - s n) = a.(c - tip) + a.(p - c) - s a.n:
// a.(p - c) <= radius |a x n_t| + thickness (the patch's in-plane spread
// tipped by the axis's angle to its normal, plus its depth), and - s a.n
// <= 0 when every sample normal is within the cone about n_t that keeps
// a.n >= 0.
bool below_the_cutter(const Group& g, const Eigen::Isometry3d& to_tool, double z_min, double tol) {
  if (g.cone_cos < 0) return false;
  const Vec3 a = to_tool.linear().row(2).transpose();  // the tool axis in the part frame
  const double an = a.dot(g.normal);
  const double across = std::sqrt(std::max(0.0, 1 - an * an));
  if (an * g.cone_cos - across * g.cone_sin < 0) return false;  // some normal may point below the axis
  const double top = (to_tool * g.centre).z() + g.radius * across + g.thickness;
  return top < z_min - tol;
}

// Calls f(m) for every sample m whose group the cutter at `to_tool` may
// reach within `range` (the Lipschitz bound prunes each level's groups, top down).
// `only_below`: the caller traces entries below the surface only (s <= 0),
// so tiles wholly below the cutter's lowest plane are pruned too.
template <class F>
void for_each_sample_near(const Profile& cutter, const Eigen::Isometry3d& to_tool, const SampleIndex& idx,
                          double range, double tol, bool only_below, F&& f) {
  // The slab test first: a few products against a signed distance; and the
  // bounding cylinder's distance before the exact one: most groups far
  // enough by it are far enough.
  //
  // Below the surface only, the points traced lie on p - s n (0 <= s <=
  // range) — a slab under the group, not a sphere about it: within
  // radius + range/2 + range |n - n_t| of the centre moved range/2 down its
  // mean normal n_t (|n - n_t|^2 <= 2 - 2 cone_cos), half the shell the
  // sphere's test leaves near a flat bottom or a corner over the surface.
  // A group is skipped there only where every such point is more than tol
  // outside the cutter, so no trace it skips could have entered it: the
  // samples traced are the sphere's less some that find nothing.
  auto skip = [&](const Group& g) {
    if (only_below && below_the_cutter(g, to_tool, cutter.z_min(), tol)) return true;
    if (only_below && g.cone_cos > 0) {
      const Vec3 q = to_tool * Vec3(g.centre - 0.5 * range * g.normal);
      const double reach = g.radius + 0.5 * range + range * std::sqrt(2 - 2 * g.cone_cos) + tol;
      if (bounding_cylinder_distance(cutter, q) > reach || cutter.signed_distance(q) > reach) return true;
    }
    const Vec3 q = to_tool * g.centre;
    const double reach = g.radius + range;
    return bounding_cylinder_distance(cutter, q) > reach || cutter.signed_distance(q) > reach;
  };
  // Depth first from the top level down to the samples.
  auto visit = [&](auto& self, int level, const Group& g) -> void {
    if (skip(g)) return;
    if (level == 0) {
      for (int m : g.members) f(m);
      return;
    }
    for (int c : g.members) self(self, level - 1, idx.levels[level - 1][c]);
  };
  const int top = static_cast<int>(idx.levels.size()) - 1;
  for (const Group& g : idx.levels[top]) visit(visit, top, g);
}

// The cutter's lowest plane in the part frame, for a quick exact answer
// before a trace: the trace visits p + s n for s in [s_lo, s_hi]; where all
// of that lies below the plane by more than tol, every step's bound exceeds
// tol and the trace enters nowhere — its answer, +inf, without the trace (a
// sample under a flat bottom lying on the surface: most of a flat end's
// sweep, and most of what the gouge guard's tiles leave).
struct CutterFloor {
  Vec3 axis;     // the tool axis in the part frame: z (tool frame) = axis . p + z0
  double z0;
  double floor;  // the cutter's lowest z less tol
  CutterFloor(const Profile& cutter, const Eigen::Isometry3d& to_tool, double tol_mm)
      : axis(to_tool.linear().row(2).transpose()), z0(to_tool.translation().z()), floor(cutter.z_min() - tol_mm) {}
  // An empty range (s_hi < s_lo) is the point at s_lo, as the trace has it.
  bool below(const Vec3& p, const Vec3& n, double s_lo, double s_hi) const {
    const double nz = axis.dot(n);
    return axis.dot(p) + z0 + (nz >= 0 ? std::max(s_hi, s_lo) : s_lo) * nz < floor;
  }
};

void cut_with(const Profile& cutter, const Eigen::Isometry3d& to_part, const SampleIndex& idx,
              const UndercutOptions& o, std::vector<std::atomic<double>>& residual, long& evaluations) {
  const Eigen::Isometry3d to_tool = to_part.inverse();
  const CutterFloor under(cutter, to_tool, o.tol_mm);
  for_each_sample_near(cutter, to_tool, idx, std::max(o.search_above_mm, o.search_below_mm), o.tol_mm, false, [&](int m) {
    const double left = residual[m].load(std::memory_order_relaxed);
    if (left <= o.settled_mm) return;
    const Sample& smp = idx.samples[m];
    ++evaluations;
    const double limit = std::min(o.search_above_mm, left);
    if (under.below(smp.p, smp.n, -o.search_below_mm, limit)) return;  // +inf: the residual unchanged
    const double s = first_entry(cutter, to_tool * smp.p, to_tool.linear() * smp.n, o, limit);
    if (s < kInf) lower_to(residual[m], s);
  });
}

}  // namespace

void summarise_residual(UndercutResult& r, const UndercutOptions& o) {
  r.untouched = 0;
  r.undercut_max_mm = r.undercut_mean_mm = r.undercut_median_mm = r.undercut_std_mm = 0;
  r.overcut_mm = 0;
  r.overcut_sample = -1;
  std::vector<double> under;
  under.reserve(r.residual_mm.size());
  for (size_t i = 0; i < r.residual_mm.size(); ++i) {
    const double res = r.residual_mm[i];
    if (std::isnan(res)) continue;  // outside the region measured (a mask)
    const double u = o.u0 + (o.u1 - o.u0) * static_cast<double>(i / o.samples_v) / (o.samples_u - 1);
    const bool machined = u >= o.machined_u0 && u <= o.machined_u1;
    if (!std::isfinite(res)) {
      if (machined) ++r.untouched;
      continue;
    }
    if (res < r.overcut_mm) {
      r.overcut_mm = res;
      r.overcut_sample = static_cast<long>(i);
    }
    if (machined) under.push_back(std::max(res, 0.0));
  }
  if (!under.empty()) {
    double sum = 0;
    for (double x : under) sum += x;
    r.undercut_mean_mm = sum / under.size();
    double var = 0;
    for (double x : under) var += (x - r.undercut_mean_mm) * (x - r.undercut_mean_mm);
    r.undercut_std_mm = std::sqrt(var / under.size());
    cancellation_point();
    std::sort(under.begin(), under.end());
    r.undercut_max_mm = under.back();
    const size_t n = under.size();
    r.undercut_median_mm = n % 2 ? under[n / 2] : 0.5 * (under[n / 2 - 1] + under[n / 2]);
  }
}

UndercutResult simulate_undercut(const Surface& design, const Tool& tool,
                                 const std::vector<ToolPass>& passes,
                                 const UndercutOptions& o, Progress& progress) {
  return simulate_undercut(design, std::vector<ToolRun>{ToolRun{&tool, &passes}}, o, progress);
}

UndercutResult simulate_undercut(const Surface& design, const std::vector<ToolRun>& runs,
                                 const UndercutOptions& o, Progress& progress) {
  if (o.samples_u < 2 || o.samples_v < 2)
    throw ParameterError("samples", "need at least 2 x 2 samples");
  if (!(o.search_above_mm > 0) || !(o.search_below_mm > 0))
    throw ParameterError("search", "search_above_mm and search_below_mm must be > 0");
  if (!(o.sweep_step_mm > 0)) throw ParameterError("sweep_step", "must be > 0");
  if (!(o.sweep_reach_mm >= 0)) throw ParameterError("sweep_reach", "must be >= 0 (0: the cutter's reach)");
  if (o.threads < 1) throw ParameterError("threads", "must be >= 1");

  const SampleIndex idx = build_index(design, o);
  std::vector<const Profile*> cutters;
  Positions swept;
  int first_pass = 0;
  for (const ToolRun& run : runs) {
    if (!run.tool || !run.passes) throw ParameterError("runs", "a run without its tool or passes");
    cutters.push_back(&run.tool->cutter());
    add_positions(swept, *run.passes, first_pass, static_cast<int>(cutters.size()) - 1,
                  o.sweep_reach_mm > 0 ? std::min(o.sweep_reach_mm, cutters.back()->reach()) : cutters.back()->reach(),
                  o.sweep_step_mm);
    first_pass += static_cast<int>(run.passes->size());
  }
  const std::vector<Eigen::Isometry3d>& positions = swept.frames;

  // The workers share one residual array (atomic minimum) and take chunks
  // of consecutive positions in turn, so each sees what the others have
  // already cut. The result does not depend on the thread count or the
  // order: a trace returns the same value whenever it returns one, and it
  // stops early only above a residual that is already at least the final
  // minimum.
  const int workers = std::min<int>(o.threads, std::max<size_t>(1, positions.size()));
  std::vector<std::atomic<double>> residual(idx.samples.size());
  for (auto& x : residual) x.store(kInf, std::memory_order_relaxed);
  cancellation_point();
  std::vector<long> evaluations(workers, 0);
  constexpr size_t kChunk = 32;
  std::atomic<size_t> next{0};
  progress.begin("undercut simulation", static_cast<long>(positions.size()));
  auto work = [&](int w) {
    // Counted locally: the workers' counters side by side in one cache
    // line, incremented per sample, made every evaluation a line transfer.
    long count = 0;
    for (;;) {
      const size_t begin = next.fetch_add(kChunk);
      if (begin >= positions.size()) break;
      if (w == 0) progress.step(static_cast<long>(begin));
      else progress.check();
      const size_t end = std::min(positions.size(), begin + kChunk);
      for (size_t k = begin; k < end; ++k) cut_with(*cutters[swept.run[k]], positions[k], idx, o, residual, count);
    }
    evaluations[w] = count;
  };
  if (workers == 1) {
    work(0);
  } else {
    std::vector<std::thread> threads;
    std::exception_ptr failure;
    std::mutex failure_mutex;
    for (int w = 0; w < workers; ++w)
      threads.emplace_back([&, w] {
        try {
          work(w);
        } catch (...) {
          std::lock_guard<std::mutex> lock(failure_mutex);
          if (!failure) failure = std::current_exception();
        }
      });
    for (auto& t : threads) t.join();
    if (failure) std::rethrow_exception(failure);
  }
  progress.end();

  UndercutResult r;
  r.samples_u = o.samples_u;
  r.samples_v = o.samples_v;
  r.tool_positions = static_cast<long>(positions.size());
  r.residual_mm.resize(idx.samples.size());
  for (size_t i = 0; i < idx.samples.size(); ++i) r.residual_mm[i] = residual[i].load(std::memory_order_relaxed);
  for (int w = 0; w < workers; ++w) r.line_evaluations += evaluations[w];
  summarise_residual(r, o);
  if (r.overcut_sample >= 0) {
    // Which motion cut it: the first position (in program order) whose
    // trace reaches the final residual there.
    const Sample& smp = idx.samples[r.overcut_sample];
    for (size_t k = 0; k < positions.size(); ++k) {
      if ((k & 1023) == 0) cancellation_point();
      const Eigen::Isometry3d to_tool = positions[k].inverse();
      const double s =
          first_entry(*cutters[swept.run[k]], to_tool * smp.p, to_tool.linear() * smp.n, o, r.overcut_mm + 1e-9);
      if (s <= r.overcut_mm + 1e-9) {
        r.overcut_pass = swept.origin[k].first;
        r.overcut_pose = swept.origin[k].second;
        break;
      }
    }
  }
  return r;
}

struct GougeGuard::Index {
  SampleIndex samples;
  double spacing_mm = 0;
  long id = 0;  // unique among the guards of the process (GuardQueryMemo)
};

namespace {

// The last queries of deepest_cut on this thread, by guard and motion: a
// planner asks the same one again — whether a motion cuts, then how deep
// to lift it, then with both ends lifted, each starting from the motion as
// it was (a fifth of the built-in TE edge finish's guard queries were
// repeats). The answer depends on nothing else, so a repeat is answered
// from here, bit for bit. Direct-mapped by a hash of the query; a guard is
// known by its id, never by its address (a later guard may reuse it).
struct GuardQuery {
  long guard = -1;
  ToolPose from, to;
  double allowed = 0, step = 0;
  bool include_from = false, include_to = false;
  const Profile* cutter = nullptr;
  bool operator==(const GuardQuery& o) const {
    return guard == o.guard && cutter == o.cutter && from.tip == o.from.tip && from.axis == o.from.axis &&
           to.tip == o.to.tip && to.axis == o.to.axis && allowed == o.allowed && step == o.step &&
           include_from == o.include_from && include_to == o.include_to;
  }
};
struct GuardQueryMemo {
  static constexpr size_t kSlots = 1024;
  struct Slot {
    GuardQuery query;
    GougeGuard::Cut cut;
  };
  std::vector<Slot> slots = std::vector<Slot>(kSlots);
  static size_t slot_of(const GuardQuery& q) {
    size_t h = static_cast<size_t>(q.guard) * 0x9E3779B97F4A7C15ull;
    auto mix = [&](double x) {
      std::uint64_t b;
      std::memcpy(&b, &x, sizeof b);
      h = (h ^ b) * 0x100000001B3ull;
    };
    for (int k = 0; k < 3; ++k) {
      mix(q.from.tip[k]);
      mix(q.from.axis[k]);
      mix(q.to.tip[k]);
      mix(q.to.axis[k]);
    }
    mix(q.allowed);
    h ^= (q.include_from ? 1u : 0u) | (q.include_to ? 2u : 0u);
    return (h ^ (h >> 29)) % kSlots;
  }
};
std::atomic<long> next_guard_id{1};

}  // namespace

GougeGuard::GougeGuard(const Surface& design, const UndercutOptions& o)
    : index_(std::make_unique<Index>()), options_(o) {
  if (o.samples_u < 2 || o.samples_v < 2) throw ParameterError("samples", "need at least 2 x 2 samples");
  if (!(o.search_below_mm > 0)) throw ParameterError("search_below_mm", "must be > 0");
  if (!(o.sweep_step_mm > 0)) throw ParameterError("sweep_step", "must be > 0");
  index_->samples = build_index(design, o);
  index_->id = next_guard_id.fetch_add(1);
  const auto& smp = index_->samples.samples;
  for (int i = 0; i < o.samples_u; ++i)
    for (int j = 0; j < o.samples_v; ++j) {
      const size_t m = static_cast<size_t>(i) * o.samples_v + j;
      if (i + 1 < o.samples_u)
        index_->spacing_mm = std::max(index_->spacing_mm, (smp[m + o.samples_v].p - smp[m].p).norm());
      if (j + 1 < o.samples_v) index_->spacing_mm = std::max(index_->spacing_mm, (smp[m + 1].p - smp[m].p).norm());
    }
}

GougeGuard::~GougeGuard() = default;

double GougeGuard::spacing_mm() const { return index_->spacing_mm; }

double GougeGuard::between_samples_mm(double r_mm) const {
  if (!(r_mm > 0)) throw ParameterError("r_mm", "must be > 0");
  return index_->spacing_mm * index_->spacing_mm / (8 * r_mm);
}

GougeGuard::Cut GougeGuard::deepest_cut(const Tool& tool, const ToolPose& from, const ToolPose& to,
                                        double allowed_mm, bool include_from, bool include_to, double step_mm) const {
  if (!(allowed_mm >= 0)) throw ParameterError("allowed_mm", "must be >= 0");
  const Profile& cutter = tool.cutter();
  thread_local GuardQueryMemo memo;
  const GuardQuery query{index_->id, from, to, allowed_mm, step_mm, include_from, include_to, &cutter};
  GuardQueryMemo::Slot& slot = memo.slots[GuardQueryMemo::slot_of(query)];
  if (slot.query == query) return slot.cut;
  const PoseMotion motion(from, to);
  const double step = step_mm > 0 ? step_mm : options_.sweep_step_mm;
  const int n = std::max(1, static_cast<int>(std::ceil(motion.max_point_speed(cutter.reach()) / step)));
  const SampleIndex& idx = index_->samples;
  const double range = options_.search_below_mm;
  Cut cut;
  Eigen::Isometry3d previous;  // the frame of the position before (a pose asked alone is one position twice)
  for (int s = include_from ? 0 : 1; s <= (include_to ? n : n - 1); ++s) {
    const double t = static_cast<double>(s) / n;
    const Eigen::Isometry3d to_tool = motion.frame_at(t).inverse();
    // The same frame again finds nothing deeper, and keeps the first.
    if (s > (include_from ? 0 : 1) && to_tool.matrix() == previous.matrix()) continue;
    previous = to_tool;
    const CutterFloor under(cutter, to_tool, options_.tol_mm);
    for_each_sample_near(cutter, to_tool, idx, range, options_.tol_mm, true, [&](int m) {
      const Sample& smp = idx.samples[m];
      // Only entries below -allowed matter: the trace stops there.
      const double limit = std::min(-allowed_mm, cut.depth_mm);
      if (under.below(smp.p, smp.n, -range, limit)) return;  // enters nowhere: +inf
      const double e = first_entry(cutter, to_tool * smp.p, to_tool.linear() * smp.n, options_, limit);
      if (e < cut.depth_mm && e < -allowed_mm) {
        cut.depth_mm = e;
        cut.t = t;
        cut.point = smp.p;
      }
    });
  }
  slot = {query, cut};
  return cut;
}

UndercutOptions guard_sampling(const Surface& s, double spacing_mm, double u0, double u1, double v0, double v1) {
  if (!(spacing_mm > 0)) throw ParameterError("guard_spacing", "expected a positive length in mm");
  double len_u = 0, len_v = 0;
  for (int i = 0; i <= 8; ++i) {
    double lu = 0, lv = 0;
    const double a = static_cast<double>(i) / 8;
    for (int k = 0; k < 64; ++k) {
      const double t0 = static_cast<double>(k) / 64, t1 = static_cast<double>(k + 1) / 64;
      lu += (s.point(u0 + (u1 - u0) * t1, v0 + (v1 - v0) * a) - s.point(u0 + (u1 - u0) * t0, v0 + (v1 - v0) * a)).norm();
      lv += (s.point(u0 + (u1 - u0) * a, v0 + (v1 - v0) * t1) - s.point(u0 + (u1 - u0) * a, v0 + (v1 - v0) * t0)).norm();
    }
    len_u = std::max(len_u, lu);
    len_v = std::max(len_v, lv);
  }
  UndercutOptions o;
  o.u0 = u0;
  o.u1 = u1;
  o.v0 = v0;
  o.v1 = v1;
  o.samples_u = std::clamp(static_cast<int>(std::ceil(len_u / spacing_mm)) + 1, 8, 8000);
  o.samples_v = std::clamp(static_cast<int>(std::ceil(len_v / spacing_mm)) + 1, 8, 8000);
  return o;
}

UndercutOptions link_guard_sampling(const Surface& s, double spacing_mm, bool flip_normal) {
  UndercutOptions o = guard_sampling(s, spacing_mm);
  o.flip_normal = flip_normal;
  o.search_below_mm = 0.02;
  o.sweep_step_mm = 0.02;
  o.threads = 1;
  return o;
}

}  // namespace bliskrun
