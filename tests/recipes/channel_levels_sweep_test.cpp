// Issue 41 (recipe size, Release only: ~34 s CPU, 2 threads): one channel of the built-in
// blisk roughed in levels (core/planning/channel_levels.h) from a blank
// whose top stands 8 mm over the hub (the lower quarter of the channel, its
// narrowest and most twisted part, where the blades' rounds and the hub
// meet: the casing's 30 mm and 22 channels are the bench's,
// bench/blisk_roughing_bench.cpp), checked independently of the planner's
// own proofs: the stock it leaves on both flanks and the hub by the
// undercut simulation (core/sim: every emitted move swept with the tool's
// exact distance, the true flanks and hub sampled) and every emitted pose
// by a sphere cover of the whole tool against the true surfaces (exact
// projections onto the analytic flanks, the hub's meridian distance) — not
// the FCL world the planner proves against.
#include "core/planning/channel_levels.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/collision/collision_world.h"
#include "core/common/error.h"
#include "core/geometry/mesh.h"
#include "core/geometry/projection.h"
#include "core/geometry/revolution.h"
#include "core/parts/builtin_blisk.h"
#include "core/parts/edge_region.h"
#include "core/planning/trimmed_surface.h"
#include "core/sim/undercut.h"
#include "tests/planning/builtin_channel.h"

namespace bliskrun {
namespace {

using test_channel::Channel;
using test_channel::kStock;

constexpr double kSweepTolerance = 0.05;  // the stock's band (issue 41)
constexpr double kTopOverHub = 8;   // the blank's top, radially over the hub (r 60 -> 66 over z -22 -> 22)


// The distance from x to a bounded face (its nearest point, edges included).
double face_distance(const Surface& s, const Vec3& x, Eigen::Vector2d& seed) {
  ProjectionOptions po;
  po.seed = seed;
  const SurfaceProjection pr = project_to_surface(s, x, po);
  EXPECT_TRUE(pr.ok) << pr.failure;
  seed = Eigen::Vector2d(pr.u, pr.v);
  return pr.distance;
}

// The least distance from a tool part at `pose` to the surfaces `d` of a
// point measures, by spheres covering the part: from height z0 (tool
// frame) up, slab by slab, the sphere on the axis at a slab's middle
// through the farthest point of the slab's profile (sampled), halved until
// clear of `need` or 0.05 mm high (so what it returns at or above `need`
// is a lower bound); below z0 the sphere of radius `ball`
// centred z0 up the axis, when given. Conservative: the spheres hold the
// part (a slab's sphere bulges beyond a cone of half angle beta by about
// rho tan^2(beta) / 2, ~1 um here). d(x, enough): the distance from x,
// exact below `enough`, at least `enough` otherwise.
template <class Distance>
double sweep_part_clearance(const Tool& tool, ToolPartId part, const ToolPose& pose, double need, double ball, double z0,
                      Distance&& d) {
  const Profile& p = tool.profile(part);
  double worst = std::numeric_limits<double>::infinity();
  if (ball > 0) worst = d(pose.tip + z0 * pose.axis, ball + need + 0.5) - ball;
  std::vector<std::pair<double, double>> stack{{std::max(z0, p.z_min()), p.z_max()}};
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    const double c = 0.5 * (a + b), h = b - a;
    double radius = 0;
    for (int k = 0; k <= 16; ++k) {
      const double z = a + h * k / 16.0, rho = p.radius_at(std::clamp(z, p.z_min() + 1e-9, p.z_max() - 1e-9));
      radius = std::max(radius, std::hypot(rho, z - c));
    }
    const double gap = d(pose.tip + c * pose.axis, radius + need + 0.5) - radius;
    if (gap >= need || h <= 0.05) {
      worst = std::min(worst, gap);
      continue;
    }
    stack.push_back({a, c});
    stack.push_back({c, b});
  }
  return worst;
}

TEST(ChannelLevelsSweep, OneBuiltinChannelLeavesAUniformStockCheckedByAnIndependentSweep) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "a whole channel's proofs and sweeps take minutes under the sanitizers";
#endif
  const Channel ch(kTopOverHub);
  const ChannelLevelsPlan plan = plan_channel_levels(ch.request(13));
  ASSERT_TRUE(plan.complete) << plan.stopped;
  ASSERT_TRUE(plan.refusals.empty()) << plan.refusals.front().reason;
  // Levels from the top (8 mm over the hub radially, along its normal)
  // down to the hub's stock, each at most the step-down below the one
  // before; the flanks' and the hub's cusps as measured within the scallop.
  const double top_height = kTopOverHub * std::cos(std::atan(6.0 / 44));
  EXPECT_NEAR(plan.top_height_min_mm, top_height, 0.01);
  EXPECT_NEAR(plan.top_height_max_mm, top_height, 0.01);
  EXPECT_LE(plan.level_step_max_mm, 1.0 + 1e-9);
  EXPECT_GE(plan.levels, static_cast<int>(std::ceil(top_height - kStock)));
  EXPECT_LE(std::max(plan.face_cusp_max_mm[0], plan.face_cusp_max_mm[1]), 0.03);
  EXPECT_LE(plan.hub_cusp_max_mm, 0.03);
  EXPECT_LE(plan.step_over_max_mm, 2.0 + 1e-9);
  EXPECT_GT(plan.axial_engagement_max_mm, plan.level_step_max_mm);
  // The ball's corner with the hub stays under r + hub stock + 1 mm.
  for (double c : plan.corner_mm) EXPECT_LT(c, 3 + kStock + 1.0);

  const Toolpath moves = channel_moves(plan);
  ToolPass all;
  for (const Move& m : moves) all.push_back(m.pose);
  const std::vector<ToolPass> passes{all};

  // Stock left, by the simulation: the flanks from 1 mm over the ball's
  // corner (r + hub stock over the hub) to the top, the hub r + stock +
  // 0.5 mm clear of both flanks between the hub level's ends. Above the top
  // is no blank: only the least stock counts there.
  const double corner = 3 + kStock + 1.0;
  const auto over_hub = [&](const Vec3& p) {
    const SurfaceProjection pr = project_to_surface(ch.hub, p);
    return pr.ok ? pr.distance * (ch.hub.radial_offset(p) >= 0 ? 1 : -1) : 0.0;
  };
  // The part's own surface points: over the hub, under the casing (the
  // flanks' grids reach past both).
  const auto on_part = [&](const Vec3& p) { return ch.hub.radial_offset(p) >= 0 && ch.casing.radial_offset(p) <= 0; };
  const auto check = [&](const char* name, const Surface& s, const UndercutOptions& o, const auto& reached) {
    const UndercutResult r = simulate_undercut(s, ch.tool, passes, o);
    int kept = 0, off = 0;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo, least = lo;
    for (int i = 0; i < r.samples_u; ++i)
      for (int j = 0; j < r.samples_v; ++j) {
        const double u = o.u0 + (o.u1 - o.u0) * i / (r.samples_u - 1), v = o.v0 + (o.v1 - o.v0) * j / (r.samples_v - 1);
        const double left = r.residual_mm[static_cast<size_t>(i) * r.samples_v + j];
        const Vec3 p = s.point(u, v);
        if (on_part(p)) least = std::min(least, left);  // nothing on the part closer than stock - tolerance
        if (!reached(p)) continue;
        ++kept;
        lo = std::min(lo, left);
        hi = std::max(hi, left);
        if (!(std::abs(left - kStock) <= kSweepTolerance)) ++off;
      }
    EXPECT_GT(kept, 500) << name;
    EXPECT_EQ(off, 0) << name << ": stock left " << lo << " .. " << hi << " mm";
    EXPECT_GE(least, kStock - kSweepTolerance) << name;
    return std::make_pair(lo, hi);
  };
  const auto on_flank = [&](const Vec3& p) { return over_hub(p) >= corner && ch.top.radial_offset(p) <= 0; };
  UndercutOptions fo;
  // The flanks up to r 74 (their grids span 39 mm radially, r 58.5 .. 97.5:
  // the top stands 8 mm over the hub, r 61 .. 65), ~0.45 mm along the span: the
  // cusps between levels (~0.8 mm apart) show.
  fo.u1 = 0.4;
  fo.samples_u = 36;
  fo.samples_v = 160;
  fo.search_above_mm = 1.5;
  fo.threads = 2;
  const auto l = check("blade 0 suction", *ch.left, fo, on_flank);
  const auto r = check("blade 1 pressure", *ch.right, fo, on_flank);
  // The hub between the hub level's ends, round the channel: its samples
  // in the channel, r + stock + 0.5 mm off both flanks, their feet inside
  // the flanks' chords.
  UndercutOptions ho = fo;
  ho.u0 = plan.hub_u_in;
  ho.u1 = plan.hub_u_out;
  ho.v0 = -0.06;
  ho.v1 = 0.12;
  ho.samples_u = 60;  // ~0.7 mm along the hub's meridian
  ho.samples_v = 160;
  ho.flip_normal = true;  // the hub's pu x pv points at the axis
  const Surface* faces[2] = {ch.left.get(), ch.right.get()};
  const auto in_channel = [&](const Vec3& p) {
    for (const Surface* f : faces) {
      const SurfaceProjection pr = project_to_surface(*f, p);
      if (!pr.ok || pr.on_boundary) return false;
      const SurfaceDerivs d = f->eval(pr.u, pr.v);
      if ((p - pr.point).dot(d.pu.cross(d.pv).normalized()) < 3 + kStock + 0.5) return false;
    }
    return true;
  };
  const auto h = check("hub", ch.hub, ho, in_channel);
  RecordProperty("stock_left_mm", std::to_string(std::min({l.first, r.first, h.first})) + " .. " +
                                      std::to_string(std::max({l.second, r.second, h.second})));

  // Every emitted pose against the true surfaces: the cutter at least the
  // stock less the tolerance off both blades (flanks to the casing, edge
  // rounds) and the hub, the shank and holder at least the stock.
  std::vector<const Surface*> surfaces;
  for (const auto& b : ch.part)
    for (const auto& s : b) surfaces.push_back(s.get());
  // Each surface's 8 x 8 patches in boxes (of 6 x 6 samples each, grown by
  // the samples' largest half diagonal) give a lower bound; the exact
  // projection only where that bound does not already clear what is asked.
  struct Box {
    Vec3 lo, hi;
  };
  std::vector<std::vector<Box>> boxes(surfaces.size());
  for (size_t k = 0; k < surfaces.size(); ++k) {
    constexpr int n = 40, patch = 5;
    std::vector<Vec3> pts;
    for (int a = 0; a <= n; ++a)
      for (int b = 0; b <= n; ++b) pts.push_back(surfaces[k]->point(a / double(n), b / double(n)));
    double slack = 0;
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
        slack = std::max({slack, 0.5 * (pts[a * (n + 1) + b] - pts[(a + 1) * (n + 1) + b + 1]).norm(),
                          0.5 * (pts[(a + 1) * (n + 1) + b] - pts[a * (n + 1) + b + 1]).norm()});
    for (int a = 0; a < n; a += patch)
      for (int b = 0; b < n; b += patch) {
        Box box{Vec3::Constant(1e9), Vec3::Constant(-1e9)};
        for (int i = a; i <= a + patch; ++i)
          for (int j = b; j <= b + patch; ++j) {
            box.lo = box.lo.cwiseMin(pts[i * (n + 1) + j]);
            box.hi = box.hi.cwiseMax(pts[i * (n + 1) + j]);
          }
        box.lo.array() -= slack;
        box.hi.array() += slack;
        boxes[k].push_back(box);
      }
  }
  std::vector<Eigen::Vector2d> seeds(surfaces.size(), Eigen::Vector2d(0.5, 0.5));
  const auto distance = [&](const Vec3& x, double enough) {
    double d = std::abs(ch.hub.radial_offset(x));
    for (size_t k = 0; k < surfaces.size(); ++k) {
      double bound = std::numeric_limits<double>::infinity();
      for (const Box& b : boxes[k]) bound = std::min(bound, (x.cwiseMax(b.lo).cwiseMin(b.hi) - x).norm());
      d = std::min(d, bound >= std::min(enough, d) ? bound : face_distance(*surfaces[k], x, seeds[k]));
    }
    return d;
  };

  // The cutter: up to its ball's centre a sphere there of radius r / cos
  // beta (the ball, and the cone from where it meets the ball, r (1 - sin
  // beta) up, to the centre's height, which is r / cos beta wide), then its
  // cone.
  const double ball_r = 3 / std::cos(deg_to_rad(1.5)), ball_top = 3;
  double cutter_min = std::numeric_limits<double>::infinity(), body_min = cutter_min;
  for (const Move& m : moves) {
    const double c = sweep_part_clearance(ch.tool, ToolPartId::Cutter, m.pose, kStock, ball_r, ball_top, distance);
    if (c < kStock - kSweepTolerance) {
      const Vec3 b = m.pose.tip + 3 * m.pose.axis;
      std::string near;
      double best = 1e9;
      for (size_t k = 0; k < surfaces.size(); ++k) {
        Eigen::Vector2d sd(0.5, 0.5);
        const double d = face_distance(*surfaces[k], b, sd);
        if (d < best) { best = d; near = std::to_string(k); }
      }
      ADD_FAILURE() << "move " << (&m - &moves[0]) << " " << m.motion << " row " << m.row << " cutter " << c
                    << " ball centre " << b.transpose() << " nearest surface " << near << " at " << best
                    << " hub " << ch.hub.radial_offset(b);
    }
    cutter_min = std::min(cutter_min, c);
    for (ToolPartId part : {ToolPartId::Shank, ToolPartId::Holder})
      body_min = std::min(body_min, sweep_part_clearance(ch.tool, part, m.pose, kStock, 0, 0, distance));
  }
  EXPECT_GE(cutter_min, kStock - kSweepTolerance);
  EXPECT_GE(body_min, kStock);
}

}  // namespace
}  // namespace bliskrun
