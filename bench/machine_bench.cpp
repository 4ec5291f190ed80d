// Machine kinematics, posting and read-back. Issue 5's target: IK + post +
// verify of 100,000 moves in <= 2 s, the Lua post included.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "core/geometry/mesh.h"
#include "core/machine/machine_sim.h"
#include "core/machine/robot.h"
#include "core/parts/builtin_blisk.h"
#include "core/tools/tool.h"
#include "core/machine/verify.h"
#include "core/machine/wheel_clearance.h"
#include "lua_api/machine_host.h"

namespace bliskrun {
namespace {

const std::string kScripts = std::string(BLISKRUN_SOURCE_DIR) + "/scripts";

MachineDefinition dmg_like_trunnion(lua_State* L) {
  lua_api::load_machine_file(L, kScripts + "/machines/dmg_like_ac_trunnion.lua", 0, kScripts + "/machines");
  MachineDefinition m = lua_api::test_machine(L, -1)->definition;
  lua_pop(L, 1);
  return m;
}

// A finishing-like path: rows along a 40 mm radius arc, 0.2 mm steps, the
// tool leaning 20-35 deg and turning with the row.
std::vector<PlannedMove> finishing_path(long moves) {
  std::vector<PlannedMove> path;
  path.reserve(static_cast<size_t>(moves));
  const long per_row = 500;
  for (long i = 0; i < moves; ++i) {
    const long row = i / per_row, k = i % per_row;
    const double phi = 0.2 * k / 40.0 + 0.01 * row;
    const double tilt = (20 + 15 * double(k) / per_row) * kPi / 180;
    PlannedMove m;
    m.kind = k == 0 ? MoveKind::Rapid : MoveKind::Feed;
    m.feed_mm_per_min = 1200;
    m.row = row;
    m.pose.tip = Vec3(40 * std::cos(phi), 40 * std::sin(phi), 5 + 0.1 * row);
    m.pose.axis = Vec3(std::sin(tilt) * std::cos(phi), std::sin(tilt) * std::sin(phi), std::cos(tilt));
    path.push_back(m);
  }
  return path;
}

void BM_InverseKinematics(benchmark::State& state) {
  lua_State* L = luaL_newstate();
  luaL_openlibs(L);
  const Kinematics kin(dmg_like_trunnion(L), 80.0);
  lua_close(L);
  const std::vector<PlannedMove> path = finishing_path(1000);
  MachineAxes q;
  size_t i = 0;
  for (auto _ : state) {
    q = kin.inverse(path[i].pose, q);
    benchmark::DoNotOptimize(q);
    if (++i == path.size()) i = 0;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_InverseKinematics);

// IK with splitting, the Lua post, read-back and replay: the whole of
// post.write but the file write. Arg 0: moves; arg 1: 1 = TCP (G43.4).
void BM_PostAndVerify(benchmark::State& state) {
  lua_State* L = luaL_newstate();
  luaL_openlibs(L);
  const Kinematics kin(dmg_like_trunnion(L), 80.0);
  const std::vector<PlannedMove> path = finishing_path(state.range(0));
  lua_api::load_post_file(L, kScripts + "/posts/fanuc.lua", kScripts + "/posts");
  lua_pushboolean(L, state.range(1) != 0);
  lua_setfield(L, -2, "tcp");
  lua_api::PostJob job;
  job.name = "bench";
  job.tools.push_back({1, 80, 0});
  MotionOptions motion;
  motion.tcp = state.range(1) != 0;
  motion.chord_tol_mm = 0.005;
  motion.start.rotary_rad = {-0.3, 0};
  long blocks = 0;
  for (auto _ : state) {
    const MachineProgram plan = plan_machine_motion(kin, path, motion);
    const std::string text = lua_api::run_post(L, -1, kin, plan, job);
    const VerifyReport report = verify_program(text, kin, plan, VerifyOptions{});
    blocks = report.moves;
    benchmark::DoNotOptimize(report);
  }
  lua_close(L);
  state.counters["blocks"] = static_cast<double>(blocks);
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_PostAndVerify)->Args({10000, 0})->Args({10000, 1})->Args({100000, 0})->Args({100000, 1})
    ->Unit(benchmark::kMillisecond);


// The machine simulation (issue 42) with the part: the DMG-like trunnion's
// bodies, the blisk job's fixture and disc, all 22 blades of the built-in
// blisk as meshes (both flanks, 0.05 mm, as blisk_world.part_bodies), the
// edge finish's flat-end mill on a 100 mm stick-out, replaying blocks that
// run the tip along blade 1's pressure flank 3.3 mm off it (the shank a
// few tenths from the blade), the tool leaning 10-30 deg towards the
// passage, 20 rows by 150 blocks: joint-linear blocks as the Fanuc post
// writes them. items_per_second: blocks per CPU second (the blisk job's
// Fanuc programs are ~160 000 blocks with 2 blades, ~1.4 million with 22).
void BM_MachineSimBladesPerBlock(benchmark::State& state) {
  lua_State* L = luaL_newstate();
  luaL_openlibs(L);
  const MachineDefinition machine = dmg_like_trunnion(L);
  lua_close(L);
  const BuiltinBlisk blisk;
  MachineSetupBodies setup;
  // Arg 0: a body per blade; 1: all blades one body of named meshes, as
  // the jobs give them (MachineBody::mesh_names).
  const bool one_body = state.range(0) == 1;
  MachineBody mesh_body;
  mesh_body.frame = "part";
  mesh_body.shape = BodyShape::Mesh;
  mesh_body.margin_mm = 0.05;
  MachineBody blades = mesh_body;
  blades.name = "blades";
  for (int b = 0; b < blisk.blade_count(); ++b) {
    MachineBody body = mesh_body;
    body.name = "blade " + std::to_string(b + 1);
    for (FlankSide side : {FlankSide::kPressure, FlankSide::kSuction}) {
      const auto mesh = std::make_shared<TriangleMesh>(tessellate(*blisk.flank_surface(b, side), 0.05));
      body.meshes.push_back(mesh);
      blades.meshes.push_back(mesh);
      blades.mesh_names.push_back(body.name);
    }
    if (!one_body) setup.part.push_back(body);
  }
  if (one_body) setup.part.push_back(blades);
  auto cylinder = [](const std::string& name, double z0, double z1, double r) {
    MachineBody b;
    b.name = name;
    b.frame = "part";
    b.shape = BodyShape::Cylinder;
    b.from_mm = Vec3(0, 0, z0);
    b.to_mm = Vec3(0, 0, z1);
    b.radius_mm = r;
    return b;
  };
  setup.fixture = {cylinder("fixture", -120, -23, 50)};
  setup.stock = {cylinder("disc", -23, 23, 66.5)};
  const double length = 100;
  const auto mill = std::make_shared<const Tool>(Tool::flat_end_mill({3, 0.5, 9, {6, 50}, {12, 40}}));
  const Kinematics kin(machine, length);
  const std::shared_ptr<const Surface> flank = blisk.flank_surface(0, FlankSide::kPressure);
  std::vector<ProgramMove> blocks;
  MachineAxes q;
  q.rotary_rad = {-0.5, 0};
  const int rows = 20, cols = 150;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const double u = 0.3 + 0.6 * i / (rows - 1), v = 0.1 + 0.8 * (i % 2 ? cols - 1 - j : j) / (cols - 1);
      const SurfaceDerivs d = flank->eval(u, v);
      const Vec3 n = d.pu.cross(d.pv).normalized(), up = d.pu.normalized();
      const double lean = deg_to_rad(10 + 20 * v);
      ToolPose pose;
      pose.tip = d.p + 3.3 * n;
      pose.axis = (std::cos(lean) * up + std::sin(lean) * n).normalized();
      q = kin.inverse(pose, q);
      ProgramMove m;
      m.line = static_cast<int>(blocks.size()) + 1;
      m.axes = q;
      m.tool = 7;
      blocks.push_back(m);
    }
  MachineSimOptions o;
  o.start = blocks.front().axes;
  MachineSimReport r;
  for (auto _ : state) {
    r = simulate_machine(blocks, machine, {SimTool{7, length, mill}}, setup, o);
    benchmark::DoNotOptimize(r);
  }
  state.counters["blocks"] = static_cast<double>(blocks.size());
  state.counters["pairs"] = static_cast<double>(r.pairs);
  state.counters["queries"] = static_cast<double>(r.queries);
  state.counters["closest_mm"] = r.closest.empty() ? -1 : r.closest.front().distance_mm;
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(blocks.size()));  // blocks per second
}
BENCHMARK(BM_MachineSimBladesPerBlock)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// Six-axis arm (issue 15 item 8: IK <= 5 us per pose, all branches): every
// solution of a pose on a KUKA KR 120-class arm, poses from random joints.
void BM_RobotInverseAllBranches(benchmark::State& state) {
  RobotArm arm;
  arm.geometry = {.a1_mm = 350, .a2_mm = -41, .b_mm = 0, .c1_mm = 675, .c2_mm = 1150, .c3_mm = 1200, .c4_mm = 215};
  std::mt19937 rng(3);
  std::vector<Frame> poses;
  for (int n = 0; n < 1024; ++n) {
    JointAngles q;
    for (double& v : q) v = std::uniform_real_distribution<double>(-2.0, 2.0)(rng);
    poses.push_back(robot_forward(arm, q));
  }
  size_t k = 0, solutions = 0;
  for (auto _ : state) {
    const auto s = robot_inverse(arm, poses[k++ % poses.size()]);
    solutions += s.size();
    benchmark::DoNotOptimize(s);
  }
  state.counters["solutions_per_pose"] = static_cast<double>(solutions) / state.iterations();
}
BENCHMARK(BM_RobotInverseAllBranches)->Unit(benchmark::kMicrosecond);

// The wheel against the whole blade (issue 15 item 3): one pose of a
// 25 mm wheel on a twisted 100 x 150 mm flank pair sampled every `spacing`
// mm (0.5 mm: 120 000 points), the wheel swept across the face.
class TwistedFlank : public Surface {
 public:
  explicit TwistedFlank(double thickness) : t_(thickness) {}
  SurfaceDerivs eval(double u, double v) const override {
    SurfaceDerivs d;
    const double x = 100 * v - 50, y = 150 * u;
    d.p = Vec3(x, y, t_ + 0.002 * x * y * 0.1 - 0.004 * x * x);
    return d;
  }

 private:
  double t_;
};

void BM_WheelClearancePose(benchmark::State& state) {
  const double spacing = state.range(0) / 10.0;
  const BladeBody body = BladeBody::sample(
      {{"pressure", std::make_shared<TwistedFlank>(0)}, {"suction", std::make_shared<TwistedFlank>(-3)}}, spacing);
  BeltStation st;
  st.wheel_radius_mm = 25;
  st.wheel_width_mm = 8;
  const WheelClearance check(body, st);
  WheelContactReport report;
  int k = 0;
  for (auto _ : state) {
    // The contact on the face at (x, y), normal +z, path along x, 0.1 mm off.
    const double x = -40 + (k % 80), y = 5 + (k / 80) % 140;
    ++k;
    Frame f = Frame::Identity();
    f.linear() = Vec3(1, -1, -1).asDiagonal();
    f.translation() = Vec3(0, 0, 0.1) - f.linear() * Vec3(x, y, 0.0002 * x * y - 0.004 * x * x);
    check.check_pose(f, report);
  }
  state.counters["points"] = static_cast<double>(body.points.size());
  benchmark::DoNotOptimize(report);
}
BENCHMARK(BM_WheelClearancePose)->Arg(10)->Arg(5)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace bliskrun
