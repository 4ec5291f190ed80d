// The independent simulation (core/sim simulate_undercut) of the hub
// finish: every move of the plan, the neighbours' copies included, over
// blade k's root strip and fillet and over the channel floor, and the
// material left there by region.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/common/error.h"
#include "core/planning/hub_finish/internal.h"

namespace bliskrun {
namespace hub_detail {
namespace {

HubFinishRegionStats region_stats(const UndercutResult& u, const std::vector<char>& in_region) {
  HubFinishRegionStats s;
  double sum = 0;
  int reached = 0;
  for (size_t i = 0; i < u.residual_mm.size(); ++i) {
    const double x = u.residual_mm[i];
    if (std::isfinite(x)) s.overcut_mm = std::min(s.overcut_mm, x);
    if (!in_region[i]) continue;
    ++s.samples;
    if (!std::isfinite(x)) {
      ++s.unreached;
      continue;
    }
    ++reached;
    if (x > s.left_max_mm || s.left_max_sample < 0) s.left_max_mm = std::max(s.left_max_mm, x), s.left_max_sample = static_cast<long>(i);
    sum += std::max(0.0, x);
  }
  s.left_mean_mm = reached ? sum / reached : 0;
  return s;
}

double interp(const std::vector<double>& x, const std::vector<double>& y, double at) {
  const auto it = std::lower_bound(x.begin(), x.end(), at);
  if (it == x.begin()) return y.front();
  if (it == x.end()) return y.back();
  const size_t k = static_cast<size_t>(it - x.begin());
  const double f = (at - x[k - 1]) / std::max(1e-15, x[k] - x[k - 1]);
  return y[k - 1] + f * (y[k] - y[k - 1]);
}

// The root strip and the fillet on blade k's closed surface: u from below
// the lowest root point to above the top row's highest.
void root_region(const HubFinishResult& result, const HubFinishRequest& rq, const HubFinishSimOptions& options,
                 const UndercutOptions& base, HubFinishRegions& regions) {
  const SurfaceOfRevolution& hub = *rq.hub;
  const Surface& bs = *result.blade_closed;
  // u window: from below the lowest root point to above the top row's highest.
  double ulo = 1, uhi = 0;
  for (size_t i = 0; i < result.fillet_u.size(); i += 8) {
    const double v = result.fillet_v[i];
    auto g = [&](double u) { return hub.radial_offset(bs.point(u, v)); };
    const double du = 1.0 / std::max(1e-9, bs.eval(result.fillet_u[i], v).pu.norm());
    ulo = std::min(ulo, result.fillet_u[i] - (g(result.fillet_u[i]) + 0.3) * du);
    uhi = std::max(uhi, result.fillet_u[i] + (result.top_height_mm + 0.5 - g(result.fillet_u[i])) * du);
  }
  UndercutOptions& o = regions.root;
  o = base;
  o.u0 = std::max(0.0, ulo);
  o.u1 = std::min(1.0, uhi);
  o.samples_u = options.root_samples_u;
  o.samples_v = options.root_samples_v;
  regions.blade = result.blade_closed;
  std::vector<char>& strip = regions.strip;
  std::vector<char>& fillet = regions.fillet;
  strip.assign(static_cast<size_t>(o.samples_u) * o.samples_v, 0);
  fillet.assign(strip.size(), 0);
  for (int i = 0; i < o.samples_u; ++i) {
    const double u = o.u0 + (o.u1 - o.u0) * i / (o.samples_u - 1);
    for (int j = 0; j < o.samples_v; ++j) {
      const double v = o.v0 + (o.v1 - o.v0) * j / (o.samples_v - 1);
      const double h = hub.radial_offset(bs.point(u, v));
      if (h < 0 || h > result.top_height_mm) continue;
      const size_t k = static_cast<size_t>(i) * o.samples_v + j;
      (u >= interp(result.fillet_v, result.fillet_u, v) ? strip : fillet)[k] = 1;
    }
  }
}

// The channel floor on the hub sector: between the inlet and outlet planes,
// the rows' ends at each z and the cell's mid-lines.
void floor_region(const HubFinishResult& result, const HubFinishRequest& rq, const HubFinishSimOptions& options,
                  const UndercutOptions& base, HubFinishRegions& regions) {
  const SurfaceOfRevolution& hub = *rq.hub;
  UndercutOptions& o = regions.floor;
  o = base;
  o.flip_normal = result.hub_sector_flip;
  o.samples_u = options.floor_samples_u;
  o.samples_v = options.floor_samples_v;
  // The meridian u of the inlet and outlet planes.
  auto u_at_z = [&](double z) {
    double lo = 0, hi = 1;
    const bool rising = hub.point(1, 0).z() > hub.point(0, 0).z();
    for (int i = 0; i < 60; ++i) {
      const double m = 0.5 * (lo + hi);
      if ((hub.point(m, 0).z() < z) == rising) lo = m; else hi = m;
    }
    return 0.5 * (lo + hi);
  };
  const double ua = u_at_z(result.z_inlet_mm), ub = u_at_z(result.z_outlet_mm);
  o.u0 = std::min(ua, ub);
  o.u1 = std::max(ua, ub);
  // Floor: between the rows' ends at the sample's z (the row ends are ball
  // centres; the contact below is at the same angle, z moved by the
  // normal's tilt, which the row interpolation in z absorbs).
  regions.hub = result.hub_sector;
  std::vector<char>& floor = regions.channel_floor;
  std::vector<char>& middle = regions.channel_middle;
  floor.assign(static_cast<size_t>(o.samples_u) * o.samples_v, 0);
  middle.assign(floor.size(), 0);
  const double zmin = result.floor_z.front(), zmax = result.floor_z.back();
  constexpr double kExactMm = 0.6;
  const double r = ball_radius(*rq.tool);
  std::vector<Vec3> seeds;
  for (size_t k = 0; k < result.fillet_u.size(); ++k)
    seeds.push_back(result.blade_closed->point(result.fillet_u[k], result.fillet_v[k]));
  std::vector<Vec3> seeds_next;
  for (size_t k = 0; k < result.fillet_u.size(); ++k)
    seeds_next.push_back(result.next_closed->point(result.fillet_u[k], result.fillet_v[k]));
  auto fits = [&](const Vec3& c) {
    const struct {
      const Surface* s;
      const std::vector<Vec3>* pts;
    } blades[] = {{result.blade_closed.get(), &seeds}, {result.next_closed.get(), &seeds_next}};
    for (const auto& b : blades) {
      double near = 1e300;
      for (const Vec3& q : *b.pts) near = std::min(near, (q - c).squaredNorm());
      if (near > (3 * r + 2) * (3 * r + 2)) continue;
      if (blade_signed_distance(*b.s, result.fillet_u, result.fillet_v, *b.pts, 0, c) < r - 1e-4) return false;
    }
    return true;
  };
  for (int i = 0; i < o.samples_u; ++i) {
    const double u = o.u0 + (o.u1 - o.u0) * i / (o.samples_u - 1);
    for (int j = 0; j < o.samples_v; ++j) {
      const double v = o.v0 + (o.v1 - o.v0) * j / (o.samples_v - 1);
      const SurfaceDerivs d = result.hub_sector->eval(u, v);
      const Vec3& p = d.p;
      // The ball resting on the hub here: its centre (the rows' z is the centre's).
      const Vec3 c = p + r * unit_normal(d, result.hub_sector_flip);
      const double zc = c.z();
      if (zc < zmin || zc > zmax) continue;
      const double t0 = interp(result.floor_z, result.floor_theta0, zc);
      const double t1 = interp(result.floor_z, result.floor_theta1, zc);
      const double th = wrap_near(angle_of(p), t0);
      const double radius = std::hypot(p.x(), p.y());
      if (th < t0 - kExactMm / radius || th > t1 + kExactMm / radius) continue;
      // The cell's own: beyond its mid-lines the next channel's rows cut.
      if (th < interp(result.floor_z, result.floor_cell0, zc) || th > interp(result.floor_z, result.floor_cell1, zc))
        continue;
      bool in = th >= t0 && th <= t1;
      // Near the rows' ends (a round's end moves fast from row to row):
      // whether the ball resting on the hub here fits, measured.
      if (std::min(std::abs(th - t0), std::abs(th - t1)) * radius < kExactMm) in = fits(c);
      if (in) floor[static_cast<size_t>(i) * o.samples_v + j] = 1;
      if (th > t0 + 1.0 / radius && th < t1 - 1.0 / radius) middle[static_cast<size_t>(i) * o.samples_v + j] = 1;
    }
  }
}

}  // namespace
}  // namespace hub_detail

using hub_detail::Program;
using hub_detail::program_of;
using hub_detail::region_stats;

HubFinishRegions hub_finish_regions(const HubFinishResult& result, const HubFinishRequest& rq,
                                    const HubFinishSimOptions& options) {
  if (!rq.tool || !rq.hub) throw ParameterError("tool", "the request's tool and hub are required");
  if (options.root_samples_u < 2 || options.root_samples_v < 2 || options.floor_samples_u < 2 ||
      options.floor_samples_v < 2)
    throw ParameterError("samples", "expected at least 2 samples each way");
  HubFinishRegions regions;
  UndercutOptions base;
  base.sweep_step_mm = options.sweep_step_mm;
  base.threads = options.threads;
  base.search_above_mm = 0.1;
  base.search_below_mm = 0.1;
  if (rq.root && result.blade_closed && !result.fillet_v.empty()) hub_detail::root_region(result, rq, options, base, regions);
  if (rq.channel && result.hub_sector && !result.floor_z.empty())
    hub_detail::floor_region(result, rq, options, base, regions);
  return regions;
}

HubFinishSimulation simulate_hub_finish(const HubFinishResult& result, const HubFinishRequest& rq,
                                        const HubFinishSimOptions& options, Progress& progress) {
  if (!(options.sweep_step_mm > 0)) throw ParameterError("sweep_step", "expected > 0");
  const HubFinishRegions regions = hub_finish_regions(result, rq, options);
  const auto t0 = SteadyClock::now();
  HubFinishSimulation sim;
  // Every move of the plan, root and channel: either can cut the other's region.
  // The plan is blade k's and channel k's; the blisk is periodic and a job
  // turns the plan onto every blade, so the neighbours' copies cut here too:
  // channel k - 1 reaches blade k's pressure-side fillet, blade k + 1's root
  // rows and channel k + 1 the floor's far side.
  auto turned = [&](const std::vector<ToolPass>& in, double angle) {
    const Eigen::AngleAxisd rot(angle, Vec3::UnitZ());
    std::vector<ToolPass> out = in;
    for (ToolPass& pass : out)
      for (ToolPose& p : pass) p = ToolPose{rot * p.tip, rot * p.axis};
    return out;
  };
  auto join = [](std::vector<ToolPass> a, const std::vector<ToolPass>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  };
  // Only what can reach a window's samples: the stretches of each pass
  // whose poses come within the tool's reach of the window's box, with the
  // pose before and after (the motion from or to a far pose can still cut).
  auto near_window = [&](const std::vector<ToolPass>& in, const Surface& s, const UndercutOptions& o) {
    Eigen::AlignedBox3d box;
    for (int i = 0; i <= 16; ++i)
      for (int j = 0; j <= 64; ++j) box.extend(s.point(o.u0 + (o.u1 - o.u0) * i / 16, o.v0 + (o.v1 - o.v0) * j / 64));
    const double reach = rq.tool->cutter().reach() + 1;
    std::vector<ToolPass> out;
    for (const ToolPass& pass : in) {
      std::vector<char> near(pass.size());
      for (size_t k = 0; k < pass.size(); ++k) near[k] = box.exteriorDistance(pass[k].tip) < reach;
      ToolPass cur;
      for (size_t k = 0; k < pass.size(); ++k) {
        const bool keep = near[k] || (k > 0 && near[k - 1]) || (k + 1 < pass.size() && near[k + 1]);
        if (keep) {
          cur.push_back(pass[k]);
        } else if (!cur.empty()) {
          out.push_back(std::move(cur));
          cur.clear();
        }
      }
      if (!cur.empty()) out.push_back(std::move(cur));
    }
    return out;
  };
  // The join as one pass from the root's last pose to the channel's first.
  const Program program = program_of(result);
  Toolpath join_moves;
  if (result.join.clear && !program.root.empty() && !program.channel.empty()) {
    join_moves.push_back(program.root.back());
    join_moves.insert(join_moves.end(), program.join.begin(), program.join.end());
    join_moves.push_back(program.channel.front());
  }
  const std::vector<ToolPass> root = toolpath_passes(program.root).passes;
  const std::vector<ToolPass> channel = toolpath_passes(program.channel).passes;
  const std::vector<ToolPass> link = toolpath_passes(join_moves).passes;
  const double pitch = result.pitch_rad;
  // Blade k - 1's join runs through channel k - 1, beside blade k's pressure
  // flank; blade k + 1's starts on its root, beside the floor.
  const std::vector<ToolPass> root_passes =
      join(join(join(join(root, link), channel), turned(channel, -pitch)), turned(link, -pitch));
  const std::vector<ToolPass> floor_passes = join(
      join(join(join(join(join(channel, root), link), turned(root, pitch)), turned(link, pitch)), turned(channel, -pitch)),
      turned(channel, pitch));
  if (regions.blade) {
    const Surface& bs = *regions.blade;
    sim.root = simulate_undercut(bs, *rq.tool, near_window(root_passes, bs, regions.root), regions.root, progress);
    sim.strip = region_stats(sim.root, regions.strip);
    sim.fillet = region_stats(sim.root, regions.fillet);
  }
  if (regions.hub) {
    sim.floor = simulate_undercut(*regions.hub, *rq.tool, near_window(floor_passes, *regions.hub, regions.floor),
                                  regions.floor, progress);
    sim.channel_floor = region_stats(sim.floor, regions.channel_floor);
    sim.channel_middle = region_stats(sim.floor, regions.channel_middle);
  }
  sim.seconds = seconds_since(t0);
  return sim;
}

}  // namespace bliskrun
