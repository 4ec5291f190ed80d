// The machine simulation (core/machine/machine_sim.h): the machine's own
// bodies replayed block by block, against closed forms and a dense replay.
#include "core/machine/machine_sim.h"

#include <fcl/fcl.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "core/analysis/part_picture.h"
#include "core/common/error.h"
#include "core/geometry/mesh.h"
#include "core/machine/motion.h"
#include "core/parts/builtin_blisk.h"
#include "core/tools/tool.h"
#include "test_machines.h"
#include "test_support.h"

namespace bliskrun::test {
namespace {

MachineBody box(const std::string& name, const std::string& frame, Vec3 lo, Vec3 hi) {
  MachineBody b;
  b.name = name;
  b.frame = frame;
  b.shape = BodyShape::Box;
  b.min_mm = lo;
  b.max_mm = hi;
  return b;
}

MachineBody cylinder_body(const std::string& name, const std::string& frame, Vec3 from, Vec3 to, double r) {
  MachineBody b;
  b.name = name;
  b.frame = frame;
  b.shape = BodyShape::Cylinder;
  b.from_mm = from;
  b.to_mm = to;
  b.radius_mm = r;
  return b;
}

ProgramMove block(int line, Vec3 xyz, double a_deg, double c_deg, bool tcp = false) {
  ProgramMove m;
  m.line = line;
  m.axes.linear_mm = xyz;
  m.axes.rotary_rad = {deg_to_rad(a_deg), deg_to_rad(c_deg)};
  m.tcp = tcp;
  m.tool = 1;
  return m;
}

const BodyApproach* pair(const MachineSimReport& r, const std::string& a, const std::string& b) {
  for (const BodyApproach& p : r.closest)
    if ((p.a == a && p.b == b) || (p.a == b && p.b == a)) return &p;
  return nullptr;
}

// The test A/C trunnion (A about +X through (0, 0, -80), C through (0, 3, 0))
// with a C table of radius 150 whose face is at z = 0, and a head that is a
// slab from the gauge point up, wider than the table.
MachineDefinition trunnion_with_slab_head() {
  MachineDefinition m = table_table_ac();
  m.bodies = {cylinder_body("table", "C", {0, 3, -30}, {0, 3, 0}, 150),
              box("head", "spindle", {-1000, -1000, 0}, {1000, 1000, 100})};
  return m;
}

constexpr double kToolLength = 100;

TEST(MachineSim, ChainPlacesTheToolTipWhereTheKinematicsDo) {
  std::mt19937 rng(7);
  for (MachineDefinition m : all_machines()) {
    for (double length : {0.0, 120.0}) {
      const Kinematics kin(m, length);
      const MachineChain chain(m, length);
      for (int k = 0; k < 20; ++k) {
        MachineAxes q;
        q.rotary_rad = random_rotary(m, rng);
        q.linear_mm = Vec3::Random() * 200;
        // The tip sits the tool length below the gauge point along the
        // spindle in the spindle link; the part frame is the part link's
        // home coordinates less part_origin.
        const Vec3 tip_world = chain.pose(chain.spindle_link(), q) * Vec3(-length * m.spindle);
        const Vec3 tip_part = chain.pose(chain.part_link(), q).inverse() * tip_world - m.part_origin_mm;
        EXPECT_LT((tip_part - kin.forward(q).tip).norm(), 1e-9) << m.name;
      }
    }
  }
}

TEST(MachineSim, BadBodiesAreNamed) {
  MachineDefinition m = table_table_ac();
  m.bodies = {box("cradle", "W", {0, 0, 0}, {1, 1, 1})};
  try {
    validate(m);
    FAIL() << "expected an error";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies[1].frame: 'W' is no frame of this machine"), std::string::npos) << e.what();
  }
  m.bodies = {cylinder_body("spindle", "spindle", {0, 0, 0}, {0, 0, 0}, 10)};
  EXPECT_THROW(validate(m), ParameterError);
  m.bodies = {box("a", "base", {0, 0, 0}, {1, 1, 1}), box("a", "A", {0, 0, 0}, {1, 1, 1})};
  EXPECT_THROW(validate(m), ParameterError);
}

// The head hangs fixed while A tilts the table 1 deg per block: the table
// face's highest rim point is at z = -80 + 147 sin|A| + 80 cos A (rim
// y = 3 - 150, pivot 80 below the face). The head's face is put where
// that reaches at |A| = 30.5 deg: the first contact is in the block from
// -30 to -31 deg, and no deeper than the rim's rise over that block.
TEST(MachineSim, HeadHitsTheTableAtTheKnownTilt) {
  const MachineDefinition m = trunnion_with_slab_head();
  auto rim = [](double a_deg) {
    const double a = deg_to_rad(std::abs(a_deg));
    return -80 + 147 * std::sin(a) + 80 * std::cos(a);
  };
  const double z_word = rim(30.5) - kToolLength;  // the gauge point (head face) is the tool length above the tip
  std::vector<ProgramMove> blocks;
  for (int k = 0; k <= 40; ++k) blocks.push_back(block(10 * (k + 1), {0, 0, z_word}, -k, 0));
  MachineSimOptions o;
  o.clearance_mm = 0.25;
  o.start = blocks.front().axes;
  const MachineSimReport r = simulate_machine(blocks, m, {SimTool{1, kToolLength, nullptr}}, {}, o);
  ASSERT_TRUE(r.collided);
  EXPECT_FALSE(r.pass());
  EXPECT_EQ(r.first_collision.block, 31);
  EXPECT_EQ(r.first_collision.line, 320);
  EXPECT_EQ(r.first_collision.a, "table");
  EXPECT_EQ(r.first_collision.b, "head");
  EXPECT_LT(r.first_collision.distance_mm, 0);
  EXPECT_LE(-r.first_collision.distance_mm, rim(31) - rim(30.5) + 1e-3);
  EXPECT_EQ(r.colliding_blocks, 10);  // 31..40
  EXPECT_NE(machine_sim_summary(r).find("FAIL: collision table / head at line 320"), std::string::npos)
      << machine_sim_summary(r);
}

// A fixture block on the part passes under the head while A turns 0 -> 20
// deg: its top edge (part y = 20, 130 mm above the A axis) rises to
// -80 + hypot(19, 130) at A = atan(19/130) = 8.3 deg, inside the block. With
// the head 1 mm above that the closest approach is 1 mm, reported within
// the clearance above it.
TEST(MachineSim, FixturePassedAtOneMillimetreReportsOneMillimetre) {
  MachineDefinition m = trunnion_with_slab_head();
  const double top = -80 + std::hypot(19.0, 130.0);
  const double z_word = top + 1 - kToolLength;
  const std::vector<MachineBody> fixture = {box("fixture", "part", {-20, -20, -40}, {20, 20, 10})};
  const std::vector<ProgramMove> blocks = {block(10, {0, 0, z_word}, 0, 0), block(20, {0, 0, z_word}, 20, 0),
                                           block(30, {50, 0, z_word}, 20, 0)};
  for (double c : {0.5, 0.05}) {
    MachineSimOptions o;
    o.clearance_mm = c;
    o.start = blocks.front().axes;
    const MachineSimReport r = simulate_machine(blocks, m, {SimTool{1, kToolLength, nullptr}}, {fixture, {}, {}}, o);
    EXPECT_TRUE(r.pass());
    const BodyApproach* p = pair(r, "fixture", "head");
    ASSERT_NE(p, nullptr);
    EXPECT_GE(p->distance_mm, 1 - 1e-4) << "c " << c;
    EXPECT_LE(p->distance_mm, 1 + c + 1e-4) << "c " << c;
    EXPECT_EQ(p->line, 20);
  }
}

// A pair's closest approach against a dense replay's minimum: within the
// zone never above it by more than the clearance, and never below it (less
// the dense sampling's own slack, 0.3 mm); beyond the zone, the pair truly
// never entered it.
void expect_closest_matches_dense(const BodyApproach& ap, double dense, const MachineSimOptions& o) {
  if (dense > 0) EXPECT_GE(ap.distance_mm, dense - 0.3) << ap.a << " / " << ap.b;
  if (ap.beyond_zone)
    EXPECT_GE(dense, o.near_zone_mm - 0.3) << ap.a << " / " << ap.b;
  else
    EXPECT_LE(ap.distance_mm, dense + o.clearance_mm + 1e-6) << ap.a << " / " << ap.b;
}

// Brute force: the same blocks sampled densely (1000 steps each), the pair
// distances measured with FCL directly. The simulation's closest approach
// of every pair must be within the clearance above the dense minimum and
// not below it (less the dense sampling's own slack), and a contact deeper
// than the clearance must be reported. Under TCP the rotaries linear, or
// (vector) the tool axis on the great circle (vector_turn_bound).
void check_against_dense_replay(bool vector) {
  MachineDefinition m = table_table_ac();
  m.bodies = {cylinder_body("table", "C", {0, 3, -30}, {0, 3, 0}, 150),
              box("cradle cheek", "A", {160, -100, -170}, {220, 100, 30}),
              box("housing", "spindle", {-60, -60, 0}, {60, 60, 300}),
              box("ram", "Z", {-80, 70, 0}, {80, 200, 600})};
  const std::vector<MachineBody> fixture = {box("fixture", "part", {-25, -25, -40}, {25, 25, 20})};
  const double length = 60;
  std::mt19937 rng(vector ? 12 : 11);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<ProgramMove> blocks;
  for (int k = 0; k < 30; ++k) {
    // The tip wanders over the fixture's top with the housing a few mm
    // over it, the table tilting and turning.
    // The second half under TCP (the tip in the part frame, 40 mm below
    // its origin at the table face), the block switching it joint-linear.
    const bool tcp = k >= 15;
    const Vec3 xyz(60 * u(rng), 60 * u(rng), (tcp ? -40.0 : 0.0) + 6 * u(rng));
    // Under vector orientation tilted off the C axis' pole, as a post
    // writes a flank's blocks (through the pole the model switches
    // branches: VectorBlockThroughThePoleIsCountedUnbounded).
    if (vector && tcp)
      blocks.push_back(block(10 * (k + 1), xyz, -25 + 10 * u(rng), 40 * u(rng), tcp));
    else
      blocks.push_back(block(10 * (k + 1), xyz, 12 * u(rng), 90 * u(rng), tcp));
    blocks.back().vector = tcp && vector;
  }
  const Kinematics kin(m, length);
  // The default near-miss zone, and one covering every pair (each closest
  // approach then measured to its allowance).
  for (double zone : {10.0, 1e9}) {
    SCOPED_TRACE("near-miss zone " + std::to_string(zone) + " mm");
    MachineSimOptions o;
    o.clearance_mm = 0.5;
    o.near_zone_mm = zone;
    o.start = blocks.front().axes;
    const MachineSimReport r = simulate_machine(blocks, m, {SimTool{1, length, nullptr}}, {fixture, {}, {}}, o);
    EXPECT_EQ(r.unbounded_blocks, 0);

    // The dense replay, state as the simulation keeps it.
    const MachineChain chain(m, length);
    std::vector<MachineBody> all = m.bodies;
    all.insert(all.end(), fixture.begin(), fixture.end());
    struct Placed {
      std::shared_ptr<fcl::CollisionGeometryd> g;
      Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
      int link = 0;
    };
    std::vector<Placed> placed;
    for (const MachineBody& b : all) {
      Placed p;
      p.link = chain.link_of(b.frame);
      const Vec3 offset = b.frame == "part" ? m.part_origin_mm : Vec3::Zero();
      if (b.shape == BodyShape::Box) {
        const Vec3 s = b.max_mm - b.min_mm;
        p.g = std::make_shared<fcl::Boxd>(s.x(), s.y(), s.z());
        p.local.translation() = 0.5 * (b.min_mm + b.max_mm) + offset;
      } else {
        p.g = std::make_shared<fcl::Cylinderd>(b.radius_mm, (b.to_mm - b.from_mm).norm());
        p.local.linear() = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), (b.to_mm - b.from_mm).normalized()).toRotationMatrix();
        p.local.translation() = 0.5 * (b.from_mm + b.to_mm) + offset;
      }
      placed.push_back(p);
    }
    auto distance = [&](const Placed& a, const Placed& b, const MachineAxes& q) {
      const fcl::Transform3d ta = chain.pose(a.link, q) * a.local, tb = chain.pose(b.link, q) * b.local;
      fcl::DistanceRequestd req;
      req.gjk_solver_type = fcl::GST_LIBCCD;
      fcl::DistanceResultd res;
      fcl::distance(a.g.get(), ta, b.g.get(), tb, req, res);
      if (res.min_distance > 0) return res.min_distance;
      fcl::CollisionRequestd creq(1, true);
      fcl::CollisionResultd cres;
      fcl::collide(a.g.get(), ta, b.g.get(), tb, creq, cres);
      return cres.isCollision() ? -cres.getContact(0).penetration_depth : 0.0;
    };
    int compared = 0, beyond = 0;
    for (const BodyApproach& ap : r.closest) {
      size_t ia = 0, ib = 0;
      for (size_t k = 0; k < all.size(); ++k) {
        if (all[k].name == ap.a) ia = k;
        if (all[k].name == ap.b) ib = k;
      }
      double dense = std::numeric_limits<double>::infinity();
      MachineAxes prev_axes = blocks.front().axes;
      Vec3 prev_tip = kin.forward(prev_axes).tip;
      for (size_t i = 0; i < blocks.size(); ++i) {
        const ProgramMove& b = blocks[i];
        MachineAxes to = b.axes;
        Vec3 tip;
        if (b.tcp) {
          tip = b.axes.linear_mm;
          to.linear_mm = kin.linear_for(tip, to.rotary_rad);
        } else {
          tip = kin.forward(to).tip;
        }
        const bool both_tcp = b.tcp && i > 0 && blocks[i - 1].tcp;
        const ControllerMotion motion = !both_tcp ? ControllerMotion::JointLinear
                                                  : (vector ? ControllerMotion::TcpVector : ControllerMotion::TcpRotaryLinear);
        const int n = i == 0 ? 1 : 1000;
        for (int s = i == 0 ? 1 : 0; s <= n; ++s) {
          const MachineAxes q = i == 0 ? to : controller_axes(kin, motion, prev_axes, to, prev_tip, tip, double(s) / n);
          dense = std::min(dense, distance(placed[ia], placed[ib], q));
        }
        prev_axes = to;
        prev_tip = tip;
      }
      ++compared;
      expect_closest_matches_dense(ap, dense, o);
      if (dense < -o.clearance_mm) EXPECT_TRUE(r.collided) << ap.a << " / " << ap.b;
      beyond += ap.beyond_zone;
    }
    EXPECT_GE(compared, 5);
    if (zone < 1e9) EXPECT_GT(beyond, 0) << "some pair should stay beyond the zone";
    else EXPECT_EQ(beyond, 0);
  }
}

TEST(MachineSim, BoundHoldsAgainstDenseReplay) { check_against_dense_replay(false); }

// The same with the TCP blocks under vector orientation: the rotaries'
// turn is the proved bound (vector_turn_bound), no block left unbounded.
TEST(MachineSim, VectorOrientationBoundHoldsAgainstDenseReplay) { check_against_dense_replay(true); }

// A nutating head-table: the B head's axis 45 deg between Y and Z (rotary
// axes at 45 deg, the spindle at 45 deg to B), a C table: the general case
// of vector_turn_bound (neither product term vanishes).
MachineDefinition nutating_head_table() {
  MachineDefinition m = base("test nutating B head / C table");
  m.rotary = {continuous("C", AxisCarrier::Part, Vec3::UnitZ(), {0, 0, 0}),
              rotary("B", AxisCarrier::Tool, Vec3(0, 1, 1).normalized(), {0, 0, 180}, -200, 200)};
  m.part_origin_mm = {0, 0, 15};
  return m;
}

// Brute force for vector_turn_bound: the rotaries as controller_axes moves
// them under vector orientation, sampled densely (4000 steps), turn no
// further than the bound over the block wherever it is bounded (elsewhere
// the modelled controller switched branches near the pole, or the arc ran
// through it: the simulation counts such a block as unbounded — at most
// a fifth of these random blocks). Random blocks turning the tool axis up to
// 40 deg, their rotaries the solution nearest the last as a post writes
// them, on every test machine and a nutating head.
TEST(MachineSim, VectorTurnBoundHoldsAgainstDenseSampling) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "4000-step replays of 750 blocks are slow under the sanitizers; the Release suite runs it";
#endif
  std::vector<MachineDefinition> machines = all_machines();
  machines.push_back(nutating_head_table());
  int checked = 0, skipped = 0;
  for (const MachineDefinition& m : machines) {
    const Kinematics kin(m, 100);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int trial = 0; trial < 150; ++trial) {
      // A block as a post writes it: the next tool axis up to 40 deg
      // away, its rotaries the solution nearest the last (continuity).
      MachineAxes from, to;
      from.rotary_rad = random_rotary(m, rng);
      const Vec3 ka = kin.tool_axis(from.rotary_rad);
      const Vec3 turn_about = ka.cross(Vec3(u(rng), u(rng), u(rng))).normalized();
      const Vec3 kb = Eigen::AngleAxisd(deg_to_rad(40) * std::abs(u(rng)), turn_about) * ka;
      double nearest = std::numeric_limits<double>::infinity();
      for (const RotarySolution& sol : kin.rotary_solutions(kb, from.rotary_rad)) {
        const double d = std::abs(sol.rotary_rad[0] - from.rotary_rad[0]) + std::abs(sol.rotary_rad[1] - from.rotary_rad[1]);
        if (sol.within_limits && d < nearest) {
          nearest = d;
          to.rotary_rad = sol.rotary_rad;
        }
      }
      if (!std::isfinite(nearest)) continue;
      from.linear_mm = kin.linear_for(Vec3::Zero(), from.rotary_rad);
      to.linear_mm = kin.linear_for(Vec3(5, 0, 0), to.rotary_rad);
      const VectorTurnBound bound = vector_turn_bound(kin, from, to, Vec3::Zero(), Vec3(5, 0, 0));
      if (!bound.bounded) {
        ++skipped;
        continue;
      }
      // Dense: 4000 samples.
      std::array<double, 2> dense{0.0, 0.0};
      MachineAxes p = from;
      for (int j = 1; j <= 4000; ++j) {
        const MachineAxes q = controller_axes(kin, ControllerMotion::TcpVector, from, to, Vec3::Zero(), Vec3(5, 0, 0), j / 4000.0);
        for (int r = 0; r < 2; ++r) dense[static_cast<size_t>(r)] += std::abs(q.rotary_rad[static_cast<size_t>(r)] - p.rotary_rad[static_cast<size_t>(r)]);
        p = q;
      }
      ++checked;
      for (int r = 0; r < 2; ++r) {
        EXPECT_LE(dense[static_cast<size_t>(r)], bound.turn_rad[static_cast<size_t>(r)] * (1 + 1e-9) + 1e-12)
            << m.name << " trial " << trial << " axis " << r;
      }
    }
  }
  EXPECT_GE(checked, 500) << "skipped " << skipped;
  EXPECT_LE(skipped, checked / 5);
  // Through the pole of the primary axis: no bound (A -20 deg, C -90 to +90
  // on the A/C trunnion: tool axes 40 deg apart across the C axis).
  const Kinematics kin(table_table_ac(), 100);
  MachineAxes a, b;
  a.rotary_rad = {deg_to_rad(-20), deg_to_rad(-90)};
  b.rotary_rad = {deg_to_rad(-20), deg_to_rad(90)};
  EXPECT_FALSE(vector_turn_bound(kin, a, b, Vec3::Zero(), Vec3::Zero()).bounded);
  b.rotary_rad = {deg_to_rad(-20), deg_to_rad(-60)};
  EXPECT_TRUE(vector_turn_bound(kin, a, b, Vec3::Zero(), Vec3::Zero()).bounded);
}

// A vector-orientation block whose arc runs through the primary axis'
// pole is not bounded: counted, named in the summary, swept with its
// sampled turn.
TEST(MachineSim, VectorBlockThroughThePoleIsCountedUnbounded) {
  const MachineDefinition m = trunnion_with_slab_head();
  const Kinematics kin(m, kToolLength);
  // Tool axes (part frame) tilted 20 deg either side of the C axis in the
  // part's XZ plane: A = -20, C = -90 and +90 on the A/C trunnion.
  std::vector<ProgramMove> blocks = {block(10, {0, 0, 50}, -20, -90, true), block(20, {0, 0, 50}, -20, 90, true)};
  for (ProgramMove& b : blocks) b.vector = true;
  const Vec3 a0 = kin.tool_axis(blocks[0].axes.rotary_rad), a1 = kin.tool_axis(blocks[1].axes.rotary_rad);
  ASSERT_NEAR(angle_between(a0, a1), deg_to_rad(40), 1e-9);
  MachineSimOptions o;
  o.start = kin.inverse({blocks[0].axes.linear_mm, a0}, blocks[0].axes);
  o.start.rotary_rad = blocks[0].axes.rotary_rad;
  o.start.linear_mm = kin.linear_for(blocks[0].axes.linear_mm, o.start.rotary_rad);
  const MachineSimReport r = simulate_machine(blocks, m, {SimTool{1, kToolLength, nullptr}}, {}, o);
  EXPECT_EQ(r.unbounded_blocks, 1);
  EXPECT_EQ(r.first_unbounded_line, 20);
  EXPECT_NE(machine_sim_summary(r).find("1 vector-orientation blocks not bounded (first at line 20"), std::string::npos)
      << machine_sim_summary(r);
}

// The part as a mesh (a 40 x 40 mm plate, 20 mm over the part frame's
// origin, its margin 0.05 mm): the shank and the head are measured against
// it, the cutter is not (it crosses the plate from the first block); the
// shank meets it when the tip goes down 4 mm more than its flute.
TEST(MachineSim, PartMeshAgainstTheShankAndHeadNotTheCutter) {
  const MachineDefinition m = trunnion_with_slab_head();
  auto plate = std::make_shared<TriangleMesh>();
  plate->vertices = {{20, -20, 20}, {60, -20, 20}, {60, 20, 20}, {20, 20, 20}};
  plate->triangles = {{0, 1, 2}, {0, 2, 3}};
  MachineBody part;
  part.name = "plate";
  part.frame = "part";
  part.shape = BodyShape::Mesh;
  part.meshes = {plate};
  part.margin_mm = 0.05;
  // Flat-end mill r 3, flutes 9 mm, shank d 6 x 30, holder d 12 x 20.
  const auto tool = std::make_shared<const Tool>(Tool::flat_end_mill({3, 0.5, 9, {6, 30}, {12, 20}}));
  // The tip at part (40, 0, z), tool vertical: the cutter spans z..z+9,
  // the shank z+9..z+39.
  std::vector<ProgramMove> blocks = {block(10, {40, 0, 15}, 0, 0, true), block(20, {40, 0, 12}, 0, 0, true)};
  for (ProgramMove& b : blocks) b.tool = 1;
  MachineSimOptions o;
  o.clearance_mm = 0.1;
  const Kinematics kin(m, kToolLength);
  o.start.rotary_rad = {0, 0};
  o.start.linear_mm = kin.linear_for(blocks[0].axes.linear_mm, o.start.rotary_rad);
  MachineSimReport r = simulate_machine(blocks, m, {SimTool{1, kToolLength, tool}}, {{}, {}, {part}}, o);
  EXPECT_TRUE(r.pass()) << machine_sim_summary(r);
  EXPECT_EQ(pair(r, "plate", "T1 cutter"), nullptr);
  // Reported at most the allowance above the truth (machine_sim.h): the
  // shank's end face over the plate, the head's face.
  const BodyApproach* shank = pair(r, "plate", "T1 shank");
  ASSERT_NE(shank, nullptr);
  const double shank_mm = 12 + 9 - 20 - 0.05, head_mm = 12 + kToolLength - 20 - 0.05;
  EXPECT_GE(shank->distance_mm, shank_mm - 1e-9);
  EXPECT_LE(shank->distance_mm, shank_mm + std::max(o.clearance_mm, 0.1 * shank->distance_mm) + 1e-9);
  EXPECT_EQ(shank->line, 20);
  const BodyApproach* head = pair(r, "plate", "head");
  ASSERT_NE(head, nullptr);
  EXPECT_GE(head->distance_mm, head_mm - 1e-9);
  EXPECT_LE(head->distance_mm, head_mm + 0.1 * head->distance_mm + 1e-9);
  // Down to z = 8: the shank's end 3 mm through the plate.
  blocks.push_back(block(30, {40, 0, 8}, 0, 0, true));
  blocks.back().tool = 1;
  r = simulate_machine(blocks, m, {SimTool{1, kToolLength, tool}}, {{}, {}, {part}}, o);
  ASSERT_TRUE(r.collided);
  EXPECT_EQ(r.first_collision.a, "plate");
  EXPECT_EQ(r.first_collision.b, "T1 shank");
  EXPECT_EQ(r.first_collision.line, 30);
  // The shank's end meets the plate less its margin (20.05) at t = 0.2375
  // of the block (4 mm down): found within the clearance past that.
  EXPECT_LE(-r.first_collision.distance_mm, o.clearance_mm + 1e-6);
  EXPECT_GE(r.first_collision.t, 0.2375 - 1e-9);
  EXPECT_LE(r.first_collision.t, 0.2375 + o.clearance_mm / 4 + 1e-9);
}

// The test A/C table-table with a spindle housing, a ram and a nose over
// the table (the blade tests' head).
MachineDefinition head_and_ram_over_the_table() {
  MachineDefinition m = table_table_ac();
  m.bodies = {box("housing", "spindle", {-60, -60, 0}, {60, 60, 300}), box("ram", "Z", {-80, 70, 0}, {80, 200, 600}),
              cylinder_body("nose", "spindle", {0, 0, 0}, {0, 0, 40}, 25)};
  return m;
}

// A mesh body on the part frame with the blades' 0.05 mm tessellation as
// margin; its meshes left to the caller.
MachineBody part_mesh_body(const std::string& name) {
  MachineBody b;
  b.name = name;
  b.frame = "part";
  b.shape = BodyShape::Mesh;
  b.margin_mm = 0.05;
  return b;
}

// 20 blocks over blade 1 of the built-in blisk (radius 58..96 along +X in
// the part frame, z up to 22), the nose's face 2 to 26 mm above its top,
// tilting, under TCP; `o` gets the 0.5 mm clearance and starts at the first.
std::vector<ProgramMove> tilting_over_blade_1(const MachineDefinition& m, double length, MachineSimOptions& o) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<ProgramMove> blocks;
  for (int k = 0; k < 20; ++k) {
    const Vec3 tip(80 + 15 * u(rng), 12 * u(rng), 38 + 12 * u(rng) - length);
    blocks.push_back(block(10 * (k + 1), tip, 5 * u(rng), 20 * u(rng), true));
  }
  o.clearance_mm = 0.5;
  const Kinematics kin(m, length);
  o.start.rotary_rad = blocks.front().axes.rotary_rad;
  o.start.linear_mm = kin.linear_for(blocks.front().axes.linear_mm, o.start.rotary_rad);
  return blocks;
}

// A blade of the built-in blisk as the part's mesh (both flanks, 0.05 mm,
// that margin), the head and ram passing over it: every reported closest
// approach of a machine body to the blade is within the clearance above a
// dense replay's (300 samples a block, FCL against the mesh less its
// margin) and not below it — the box bound and the seeded mesh queries
// (machine_sim.h, "The bound") lose nothing.
TEST(MachineSim, PartMeshBoundHoldsAgainstDenseReplay) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "FCL against meshes over dense replays is slow under the sanitizers; the Release suite runs it";
#endif
  const MachineDefinition m = head_and_ram_over_the_table();
  const BuiltinBlisk blisk;
  MachineBody blade = part_mesh_body("blade 1");
  for (FlankSide side : {FlankSide::kPressure, FlankSide::kSuction})
    blade.meshes.push_back(std::make_shared<TriangleMesh>(tessellate(*blisk.flank_surface(1, side), 0.05)));
  const double length = 40;
  MachineSimOptions o;
  const std::vector<ProgramMove> blocks = tilting_over_blade_1(m, length, o);
  const Kinematics kin(m, length);
  const MachineSimReport r = simulate_machine(blocks, m, {SimTool{1, length, nullptr}}, {{}, {}, {blade}}, o);

  // Dense: FCL between the blade's BVH and each machine body.
  const MachineChain chain(m, length);
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  model->beginModel();
  for (const auto& mesh : blade.meshes) {
    std::vector<fcl::Vector3d> v(mesh->vertices.begin(), mesh->vertices.end());
    std::vector<fcl::Triangle> t;
    for (const Eigen::Vector3i& x : mesh->triangles) t.emplace_back(x[0], x[1], x[2]);
    model->addSubModel(v, t);
  }
  model->endModel();
  int compared = 0;
  for (const MachineBody& body : m.bodies) {
    const BodyApproach* ap = pair(r, "blade 1", body.name);
    ASSERT_NE(ap, nullptr) << body.name;
    std::shared_ptr<fcl::CollisionGeometryd> g;
    Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
    if (body.shape == BodyShape::Box) {
      const Vec3 s = body.max_mm - body.min_mm;
      g = std::make_shared<fcl::Boxd>(s.x(), s.y(), s.z());
      local.translation() = 0.5 * (body.min_mm + body.max_mm);
    } else {
      g = std::make_shared<fcl::Cylinderd>(body.radius_mm, (body.to_mm - body.from_mm).norm());
      local.translation() = 0.5 * (body.from_mm + body.to_mm);
    }
    const int link = chain.link_of(body.frame);
    double dense = std::numeric_limits<double>::infinity();
    MachineAxes prev = o.start;
    Vec3 prev_tip = kin.forward(prev).tip;
    for (size_t i = 0; i < blocks.size(); ++i) {
      MachineAxes to = blocks[i].axes;
      const Vec3 tip = to.linear_mm;
      to.linear_mm = kin.linear_for(tip, to.rotary_rad);
      const int n = i == 0 ? 1 : 300;
      for (int s = i == 0 ? 1 : 0; s <= n; ++s) {
        const MachineAxes q =
            i == 0 ? to : controller_axes(kin, ControllerMotion::TcpRotaryLinear, prev, to, prev_tip, tip, double(s) / n);
        const fcl::Transform3d tb = chain.pose(link, q) * local;
        const fcl::Transform3d tm = chain.pose(chain.part_link(), q) * Eigen::Translation3d(m.part_origin_mm);
        fcl::DistanceRequestd req;
        req.gjk_solver_type = fcl::GST_LIBCCD;
        fcl::DistanceResultd res;
        fcl::distance(model.get(), tm, g.get(), tb, req, res);
        dense = std::min(dense, res.min_distance - blade.margin_mm);
      }
      prev = to;
      prev_tip = tip;
    }
    ++compared;
    ASSERT_GT(dense, 0) << body.name << ": the program should pass the blade, not hit it";
    expect_closest_matches_dense(*ap, dense, o);
  }
  EXPECT_TRUE(r.pass());
  EXPECT_EQ(compared, 3);
  const BodyApproach* nose = pair(r, "blade 1", "nose");
  EXPECT_LT(nose->distance_mm, 20) << "the program should pass the nose near the blade";
}

// The part's blades as one body of named meshes (MachineBody::mesh_names,
// how the jobs give their blades: one pair per machine body, not one per
// blade) against the same blades as a body each, the head passing over
// blade 1 of the built-in blisk with blade 2 beside it: each machine body's
// closest approach is named after the blade it lies on and stands within
// the allowance (machine_sim.h, "The bound") of the nearer of the two
// bodies' approaches; the pairs fall from 6 to 3. Names of the wrong
// count are refused where they are given.
TEST(MachineSim, PartOfNamedMeshesNamesTheNearestBlade) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "FCL against two blades' meshes over 20 tilting blocks is slow under the sanitizers";
#endif
  const MachineDefinition m = head_and_ram_over_the_table();
  const BuiltinBlisk blisk;
  std::vector<MachineBody> separate;
  MachineBody blades = part_mesh_body("blades");
  for (int k : {1, 2}) {
    MachineBody b = part_mesh_body("blade " + std::to_string(k));
    for (FlankSide side : {FlankSide::kPressure, FlankSide::kSuction}) {
      b.meshes.push_back(std::make_shared<TriangleMesh>(tessellate(*blisk.flank_surface(k, side), 0.05)));
      blades.meshes.push_back(b.meshes.back());
      blades.mesh_names.push_back(b.name);
    }
    separate.push_back(b);
  }
  const double length = 40;
  MachineSimOptions o;
  const std::vector<ProgramMove> blocks = tilting_over_blade_1(m, length, o);
  const std::vector<SimTool> tools = {SimTool{1, length, nullptr}};
  const MachineSimReport each = simulate_machine(blocks, m, tools, {{}, {}, separate}, o);
  const MachineSimReport one = simulate_machine(blocks, m, tools, {{}, {}, {blades}}, o);
  EXPECT_EQ(each.pairs, 6);
  EXPECT_EQ(one.pairs, 3);
  for (const MachineBody& body : m.bodies) {
    const BodyApproach *b1 = pair(each, "blade 1", body.name), *b2 = pair(each, "blade 2", body.name);
    ASSERT_NE(b1, nullptr);
    ASSERT_NE(b2, nullptr);
    const BodyApproach* nearer = b1->distance_mm <= b2->distance_mm ? b1 : b2;
    const std::string blade = nearer == b1 ? "blade 1" : "blade 2";
    const BodyApproach* merged = pair(one, blade, body.name);
    ASSERT_NE(merged, nullptr) << body.name << ": expected its approach named " << blade << "\n"
                               << machine_sim_summary(one);
    const double allowance = std::max(o.clearance_mm, 0.1 * nearer->distance_mm);
    EXPECT_NEAR(merged->distance_mm, nearer->distance_mm, allowance) << body.name;
  }
  EXPECT_EQ(pair(one, "blades", "nose"), nullptr) << "the body's own name where a mesh's is known";
  // The machine's picture at an approach named after a mesh finds its body.
  const BodyApproach* nose = pair(one, "blade 1", "nose");
  ASSERT_NE(nose, nullptr);
  const MachineScene scene = machine_scene(m, tools, {{}, {}, {blades}}, *nose);
  // The nearest points stand the distance plus the margin apart (and the
  // nose's hull's gap, within 0.01 mm: machine_sim.cpp, kHullGap).
  EXPECT_NEAR((scene.nearest_a - scene.nearest_b).norm(), nose->distance_mm + blades.margin_mm, 0.011);

  MachineBody wrong = blades;
  wrong.mesh_names.pop_back();
  try {
    simulate_machine(blocks, m, tools, {{}, {}, {wrong}}, o);
    FAIL() << "expected an error";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("part[1].mesh_names: expected one name per mesh (4), got 3"), std::string::npos)
        << e.what();
  }
}

// The broad phase: a head 200 mm over the table creeping 0.1 mm a block
// is measured once, then cleared block after block by the summed motion
// bounds (0.1 mm each) until they could have used up the 20 mm its
// closest approach may be reported above the truth (a tenth of it).
TEST(MachineSim, FarPairsAreClearedByTheBroadPhase) {
  const MachineDefinition m = trunnion_with_slab_head();
  std::vector<ProgramMove> blocks;
  for (int k = 0; k <= 100; ++k) blocks.push_back(block(k + 1, {0.1 * k, 0, 200 - kToolLength}, 0, 0));
  MachineSimOptions o;
  o.start = blocks.front().axes;
  const MachineSimReport r = simulate_machine(blocks, m, {SimTool{1, kToolLength, nullptr}}, {}, o);
  EXPECT_TRUE(r.pass());
  EXPECT_EQ(r.queries, 1);  // the first block; 100 x 0.1 mm < 20 mm
  EXPECT_EQ(r.skipped, 100);
  ASSERT_EQ(r.closest.size(), 1u);
  EXPECT_NEAR(r.closest.front().distance_mm, 200, 1e-6);
}

// Every shipped machine file with bodies: nothing touches standing at
// program zero with a 150 mm tool, nor at the top of Z with the rotaries
// at their travel ends (a tilt at the safe height), X and Y in the middle
// or at the corners of their travel.
TEST(MachineSim, ShippedMachinesBodiesDoNotTouchAtHome) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, R"lua(
local checked = 0
for _, name in ipairs{"dmg_like_ac_trunnion", "bc_trunnion_hermle_like", "monoblock_like_head_table", "gantry_head_head",
                      "table_table_ac", "table_table_bc", "head_table_bc", "head_head"} do
  local m = bliskrun.machine.load(name)
  local names, travel = m:axes(), m:travel()
  local function ends(axis)
    local t = travel[axis]
    if not t then return {0, 90, 180} end
    return {t[1], 0 >= t[1] and 0 <= t[2] and 0 or t[1], t[2]}
  end
  local poses = {{X = 0, Y = 0, Z = 0, [names[4]] = 0, [names[5]] = 0}}
  for _, a in ipairs(ends(names[4])) do
    for _, b in ipairs(ends(names[5])) do
      for _, xy in ipairs{{0, 0}, {travel.X[1], travel.Y[1]}, {travel.X[2], travel.Y[2]}, {travel.X[1], travel.Y[2]},
                          {travel.X[2], travel.Y[1]}} do
        poses[#poses + 1] = {X = xy[1], Y = xy[2], Z = travel.Z[2], [names[4]] = a, [names[5]] = b}
      end
    end
  end
  for _, q in ipairs(poses) do
    local c = m:body_clearance(q, {tool_length = 150})
    assert(c, name .. " has no bodies")
    checked = checked + 1
    if c.distance <= 0 then
      error(string.format("TOUCH %s: %s / %s %.3f mm at %s %g %s %g Z %g", name, c.a, c.b, c.distance,
                          names[4], q[names[4]], names[5], q[names[5]], q.Z))
    end
  end
end
assert(checked == 8 * (1 + 9 * 5), "checked " .. checked)
)lua");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// post.write runs the simulation by default: a program that puts the
// spindle nose into the table is refused at the line of the contact and
// not written; machine_check = false writes it, with the warning in the
// report.
TEST(MachineSim, PostWriteRefusesACollisionAndSkipsOnlyWhenAsked) {
  TempDir dir;
  const std::string post = R"lua(
local m = bliskrun.machine.load("dmg_like_ac_trunnion")
-- The part frame's origin stands 120 mm over the table face: a tip 125 mm
-- below it with a 1 mm tool puts the spindle nose 4 mm into the table.
local path = {{kind = "rapid", tip = {40, 0, 30}, axis = {0, 0, 1}},
              {kind = "feed", tip = {40, 0, -125}, axis = {0, 0, 1}, feed = 800}}
local function write(check)
  return bliskrun.post.write{machine = m, post = "fanuc", path = path, file = "x.nc", tool = {number = 1, length = 1},
                             machine_check = check}
end
)lua";
  RecipeResult r = run_recipe_text(dir, post + "write(nil)\n");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("machine simulation: FAIL: collision C table / spindle nose at line"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("nothing written"), std::string::npos) << r.output;
  r = run_recipe_text(dir, post + "local w = write(false)\nassert(w.machine_check.verdict == 'SKIPPED')\n"
                                  "assert(w.machine_check.warning:find('NOT checked'))\n");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// post.write's `part`: the blisk's blade 1 as a mesh body. A vertical tool
// 10 mm long with its tip 5 mm over the part frame's origin at x = 80
// puts the spindle nose (radius 60, from the gauge point up) into the blade
// (radius 58..96 along +X, z up to 22): refused at that line, naming the
// pair, the collision drawn in the machine picture where POV-Ray runs. The
// same program with the part clocked 180 deg (setup.clocking_deg: the
// part's bodies are turned with it) passes, the blade now on the far side.
TEST(MachineSim, PostWriteChecksThePartsBladesPlacedBySetup) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "FCL against meshes over dense replays is slow under the sanitizers; the Release suite runs it";
#endif
  TempDir dir;
  const std::string post = R"lua(
local m = bliskrun.machine.load("dmg_like_ac_trunnion")
local blisk = bliskrun.blisk{}
local part = {{name = "blade 1", margin = 0.05,
               meshes = {blisk:flank(1, "pressure"):tessellate(0.05), blisk:flank(1, "suction"):tessellate(0.05)}}}
local path = {{kind = "rapid", tip = {80, 0, 60}, axis = {0, 0, 1}},
              {kind = "feed", tip = {80, 0, 5}, axis = {0, 0, 1}, feed = 800}}
local function write(setup)
  return bliskrun.post.write{machine = m, post = "fanuc", path = path, file = "x.nc", tool = {number = 1, length = 10},
                             part = part, setup = setup, machine_picture = "x_machine.png"}
end
)lua";
  RecipeResult r = run_recipe_text(dir, post + "write(nil)\n");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("machine simulation: FAIL: collision spindle nose / blade 1 at line"), std::string::npos)
      << r.output;
  if (part_renderer_available()) {
    EXPECT_NE(r.output.find("the collision drawn in x_machine.png"), std::string::npos) << r.output;
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(dir.path()) / "out" / "x_machine.png"));
  }
  r = run_recipe_text(dir, post + R"lua(
local w = write({name = "clocked", clocking_deg = 180})
assert(w.machine_check.verdict == "PASS", w.machine_check.summary)
local near
for _, c in ipairs(w.machine_check.closest) do
  if c.a == "blade 1" or c.b == "blade 1" then near = near or c end
end
assert(near and near.distance > 50, "blade 1 should stand on the far side")
)lua");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = run_recipe_text(dir, post + R"lua(
bliskrun.post.write{machine = m, post = "fanuc", path = path, file = "y.nc", tool = {number = 1, length = 10},
                    part = {{name = "blade 1", mesh = 3}}}
)lua");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("part[1].mesh: expected a bliskrun.Mesh"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace bliskrun::test
