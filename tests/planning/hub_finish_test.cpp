// Hub and blade-root finishing (issue 18 item 2) on the built-in blisk:
// blade 1's root strip and the channel floor between blades 1 and 2 with a
// tapered ball end. The plan is made once and shared; each test checks one
// claim against something the planner did not compute itself — the
// simulation's material left (core/sim) against the scallop closed form,
// the tool's exact signed distance against points of the exact faces and the
// hub, a world with an obstacle the planner must refuse.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "core/common/error.h"
#include "core/geometry/mesh.h"
#include "core/parts/builtin_blisk.h"
#include "core/planning/hub_finish.h"
#include "core/planning/repair_paths.h"

namespace bliskrun {
namespace {

Tool hub_tool() {
  // r 1.5 ball, 2.5 deg taper, 40 mm flute: from the ball to the casing
  // (blades 30 mm tall) with the shank and holder outside it.
  return Tool::tapered_ball_end_mill({1.5, 2.5 * kPi / 180, 40, {8, 30}, {32, 40}});
}

struct HubSetup {
  BuiltinBlisk blisk;
  Tool tool = hub_tool();
  HubFinishRequest rq;
  HubSetup() {
    const int n = blisk.blade_count();
    rq.blade = {blisk.flank_surface(0, FlankSide::kPressure), blisk.flank_surface(0, FlankSide::kSuction)};
    rq.next = {blisk.flank_surface(1, FlankSide::kPressure), blisk.flank_surface(1, FlankSide::kSuction)};
    rq.previous = {blisk.flank_surface(n - 1, FlankSide::kPressure), blisk.flank_surface(n - 1, FlankSide::kSuction)};
    rq.hub = std::make_shared<const SurfaceOfRevolution>(blisk.hub_meridian());
    rq.tool = &tool;
    rq.threads = 2;
  }
};

struct Planned {
  HubSetup s;
  HubFinishResult plan;
  HubFinishSimulation sim;
  Planned() {
    HubFinishSimOptions so;
    so.root_samples_u = 80, so.root_samples_v = 1000, so.floor_samples_v = 200;
#ifdef BLISKRUN_SANITIZED
    // Ten times slower: a 4 mm slice of the channel and two root rows.
    s.rq.z_inlet_mm = -2, s.rq.z_outlet_mm = 2;
    s.rq.root_top_mm = 1.9;
    so.root_samples_v = 500, so.floor_samples_u = 60, so.floor_samples_v = 120;
#endif
    plan = plan_hub_finish(s.rq);
    sim = simulate_hub_finish(plan, s.rq, so);
  }
};

const Planned& planned() {
  static const Planned p;
  return p;
}

TEST(HubFinishParameters, ErrorsNameTheOption) {
  HubSetup s;
  auto expect_key = [&](HubFinishRequest rq, const char* key) {
    try {
      plan_hub_finish(rq);
      ADD_FAILURE() << "no error for " << key;
    } catch (const ParameterError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  HubFinishRequest rq = s.rq;
  rq.hub = nullptr;
  expect_key(rq, "hub");
  rq = s.rq;
  rq.next = {};
  expect_key(rq, "next");
  rq = s.rq;
  rq.scallop_mm = 0;
  expect_key(rq, "scallop");
  rq = s.rq;
  rq.lean_rad = 2 * kPi / 180;  // below the 2.5 deg taper: the cone would run along the blade
  expect_key(rq, "lean");
  rq = s.rq;
  rq.z_inlet_mm = 5, rq.z_outlet_mm = -5;
  expect_key(rq, "z");
  const Tool flat = Tool::flat_end_mill({3, 0.5, 9, {6, 50}, {}});
  rq = s.rq;
  rq.tool = &flat;
  expect_key(rq, "tool");
  rq = s.rq;
  rq.root = rq.channel = false;
  expect_key(rq, "root");
}

TEST(HubFinish, ChannelFloorCuspMatchesTheBallsClosedForm) {
  const Planned& p = planned();
  const HubFinishRequest& rq = p.s.rq;
  // The built-in hub is a cone: no curvature along its meridian, so the
  // step is the flat closed form 2 sqrt(2 r h - h^2).
  const double r = 1.5, h = rq.scallop_mm;
  EXPECT_NEAR(p.plan.channel.step_max_mm, 2 * std::sqrt(2 * r * h - h * h), 1e-9);
  EXPECT_NEAR(ball_step_over(h, r, 0), 2 * std::sqrt(2 * r * h - h * h), 1e-12);
#ifdef BLISKRUN_SANITIZED
  ASSERT_GT(p.plan.channel.rows, 10);
#else
  ASSERT_GT(p.plan.channel.rows, 100);
#endif
  // Between the rows' ends only the rows' own cusps are left: h (the rows
  // are the closed form's step apart along the meridian, straight on a
  // cone); the chord of the centre's arc cuts below, it never leaves more.
  // The samples (0.07 mm along the meridian) read the cusp's top to ~0.4 um.
  const HubFinishRegionStats& m = p.sim.channel_middle;
  ASSERT_GT(m.samples, 500);
  EXPECT_EQ(m.unreached, 0);
  EXPECT_LE(m.left_max_mm, h + 2e-4) << "cusp " << m.left_max_mm * 1000 << " um";
  EXPECT_GE(m.left_max_mm, 0.8 * h) << "rows closer than the closed form asks";
  // The whole floor up to where the ball touches a blade: nothing unreached,
  // nothing beyond the scallop and the chord where the rows' ends meet the
  // fillet (the neighbouring blade's root rows and channels, the plan turned
  // by the pitch, cut there too).
  const HubFinishRegionStats& f = p.sim.channel_floor;
  ASSERT_GT(f.samples, m.samples);
  EXPECT_EQ(f.unreached, 0);
  EXPECT_LE(f.left_max_mm, h + rq.steps.chord_tol_mm + 5e-4) << f.left_max_mm * 1000 << " um";
}

TEST(HubFinish, RootRowsCoverTheStripUpToTheTopHeight) {
  const Planned& p = planned();
  const HubFinishRequest& rq = p.s.rq;
  EXPECT_GE(p.plan.top_height_mm, rq.root_top_mm - 1e-9);
#ifndef BLISKRUN_SANITIZED
  EXPECT_GT(p.plan.root.rows, 5);
#endif
  EXPECT_NEAR(p.plan.root_fillet_mm, 1.5, 1e-6);
  const HubFinishRegionStats& s = p.sim.strip;
  ASSERT_GT(s.samples, 500);
  EXPECT_EQ(s.unreached, 0);
  EXPECT_LE(s.left_max_mm, rq.scallop_mm + rq.steps.chord_tol_mm + 2e-4) << s.left_max_mm * 1000 << " um";
}

TEST(HubFinish, NothingIsCutBelowTheDesignBeyondTheAllowance) {
  const Planned& p = planned();
  const double allowed = p.s.rq.allowed_overcut_mm + 2e-4;  // + what the samples can miss
  EXPECT_GE(p.sim.root.overcut_mm, -allowed);
  EXPECT_GE(p.sim.floor.overcut_mm, -allowed);
  EXPECT_EQ(p.plan.root.refused_connections, 0);
  EXPECT_EQ(p.plan.channel.refused_connections, 0);
}

}  // namespace
}  // namespace bliskrun
namespace bliskrun {
namespace {

// Points of a surface about `spacing` apart (analytic faces, not the
// planner's closed lofts or meshes).
std::vector<Vec3> sample_surface(const Surface& s, int nu, int nv) {
  std::vector<Vec3> out;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) out.push_back(s.point(double(i) / (nu - 1), double(j) / (nv - 1)));
  return out;
}

// Smallest signed distance from a tool part to the points (part frame).
double part_clearance(const Tool& tool, ToolPartId part, const ToolPose& pose, const std::vector<Vec3>& pts) {
  const Eigen::Isometry3d to_tool = tool_to_part(pose).inverse();
  double worst = 1e300;
  for (const Vec3& p : pts) worst = std::min(worst, tool.signed_distance(Vec3(to_tool * p), part));
  return worst;
}

// The hub's clearance from a tool part: the lowest radial offset of points
// on the part's surface (rings of its profile), less nothing (exact hub).
double hub_clearance(const Tool& tool, ToolPartId part, const ToolPose& pose, const SurfaceOfRevolution& hub) {
  const Profile& pr = tool.profile(part);
  const Eigen::Isometry3d T = tool_to_part(pose);
  double worst = 1e300;
  for (int i = 0; i <= 60; ++i) {
    const double z = pr.z_min() + (pr.z_max() - pr.z_min()) * i / 60.0;
    const double rad = pr.radius_at(std::min(z, pr.z_max() - 1e-9));
    for (int k = 0; k < 24; ++k) {
      const double a = 2 * kPi * k / 24;
      worst = std::min(worst, hub.radial_offset(T * Vec3(rad * std::cos(a), rad * std::sin(a), z)));
    }
  }
  return worst;
}

TEST(HubFinish, EveryEmittedPoseIsClearOfTheWorldByBruteForce) {
  const Planned& p = planned();
  const HubFinishRequest& rq = p.s.rq;
  const Tool& tool = p.s.tool;
  const int n = p.s.blisk.blade_count();
  // Faces sampled every ~0.5 mm: between samples a part can come closer by
  // d^2 / (8 R): 21 um for the r 1.5 ball, 8 um for the 8 mm shank.
  auto faces = [&](int b) {
    std::vector<Vec3> pts = sample_surface(*p.s.blisk.flank_surface(b, FlankSide::kPressure), 80, 75);
    const std::vector<Vec3> s = sample_surface(*p.s.blisk.flank_surface(b, FlankSide::kSuction), 80, 75);
    pts.insert(pts.end(), s.begin(), s.end());
    return pts;
  };
  const std::vector<Vec3> prev = faces(n - 1), own = faces(0), next = faces(1);
  const std::vector<DrumFinishMove> moves = hub_finish_moves(p.plan);
#ifdef BLISKRUN_SANITIZED
  const size_t every = 97;  // the 4 mm slice: 46 poses checked
  const int at_least = 40;
#else
  const size_t every = 7;
  const int at_least = 100;
#endif
  int checked = 0;
  for (size_t i = 0; i < moves.size(); ++i) {
    const DrumFinishMove& m = moves[i];
    if (m.kind == DrumFinishMove::Kind::Stop) continue;
    if (m.motion == "cut" && i % every != 0) continue;
    ++checked;
    const ToolPose& pose = m.pose;
    // Blade k - 1: every part at its clearance.
    EXPECT_GE(part_clearance(tool, ToolPartId::Cutter, pose, prev), -0.025) << "move " << i;
    EXPECT_GE(part_clearance(tool, ToolPartId::Shank, pose, prev), rq.clearances.shank_mm - 0.01) << "move " << i;
    EXPECT_GE(part_clearance(tool, ToolPartId::Holder, pose, prev), rq.clearances.holder_mm - 0.01) << "move " << i;
    // Blades k and k + 1: the cutter touches them (within the samples'
    // slack), shank and holder keep their clearance less the meshes' margin.
    for (const std::vector<Vec3>* b : {&own, &next}) {
      EXPECT_GE(part_clearance(tool, ToolPartId::Cutter, pose, *b), -0.025) << "move " << i;
      EXPECT_GE(part_clearance(tool, ToolPartId::Shank, pose, *b), rq.clearances.shank_mm - 0.06) << "move " << i;
      EXPECT_GE(part_clearance(tool, ToolPartId::Holder, pose, *b), rq.clearances.holder_mm - 0.06) << "move " << i;
    }
    // The hub: the cutter on it at most the allowance deep, shank and holder clear.
    EXPECT_GE(hub_clearance(tool, ToolPartId::Cutter, pose, *rq.hub), -rq.allowed_overcut_mm) << "move " << i;
    EXPECT_GE(hub_clearance(tool, ToolPartId::Shank, pose, *rq.hub), rq.clearances.shank_mm) << "move " << i;
    EXPECT_GE(hub_clearance(tool, ToolPartId::Holder, pose, *rq.hub), rq.clearances.holder_mm) << "move " << i;
    if (HasFailure()) break;
  }
  EXPECT_GT(checked, at_least);
}

// A plate standing in the channel (hub to beyond the casing, 2 mm thick in
// z) is refused: the contacts under it get no clear axis and split their
// rows, and no emitted pose touches it.
TEST(HubFinish, APoseBlockedByAnObstacleIsRefusedNotEmitted) {
  HubSetup s;
  HubFinishRequest rq = s.rq;
  rq.root = false;
  rq.z_inlet_mm = -1.5;
  rq.z_outlet_mm = 1.5;
  const double theta = kPi / s.blisk.blade_count();  // mid-channel at z = 0 (blade 1's stacking line at 0)
  const Vec3 e(std::cos(theta), std::sin(theta), 0);
  NamedMesh plate{"plate", {}};
  for (double z : {-0.5, 0.5})
    for (double rad : {55.0, 130.0}) plate.mesh.vertices.push_back(rad * e + Vec3(0, 0, z));
  plate.mesh.triangles = {{0, 1, 3}, {0, 3, 2}};
  const CollisionWorld world = hub_finish_world(rq, {plate});
  rq.world = &world;
  const HubFinishResult plan = plan_hub_finish(rq);
  EXPECT_GT(plan.channel.refusals, 0);
  EXPECT_GT(plan.channel.passes.size(), static_cast<size_t>(plan.channel.rows)) << "refusals split rows";
  std::vector<Vec3> pts;
  for (int i = 0; i <= 150; ++i)
    for (int k = 0; k <= 10; ++k) pts.push_back((55.0 + 75.0 * i / 150) * e + Vec3(0, 0, -0.5 + 0.1 * k));
  for (const DrumFinishMove& m : hub_finish_moves(plan)) {
    if (m.kind == DrumFinishMove::Kind::Stop) continue;
    for (ToolPartId part : {ToolPartId::Cutter, ToolPartId::Shank, ToolPartId::Holder})
      ASSERT_GT(part_clearance(s.tool, part, m.pose, pts), 0) << m.motion << " row " << m.row;
  }
}

}  // namespace
}  // namespace bliskrun
