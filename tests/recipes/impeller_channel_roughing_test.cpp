// scripts/recipes/impeller_channel_roughing.lua on one channel at a coarse
// setting: it runs, reports the notch levels, the widening paths and the
// measured scallop, and every move it writes — cuts, steps, links, leads —
// passes an independent check against a finer tessellation of the model
// (zero clearance, the whole tool), and every cutting pose leaves the stock
// on the hub.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/collision/collision_world.h"
#include "core/geometry/mesh.h"
#include "core/geometry/projection.h"
#include "core/parts/impeller.h"
#include "test_support.h"

namespace bliskrun::test {
namespace {

TEST(ImpellerChannelRoughingRecipe, OneChannelRunsAndEveryMoveIsClearInAnIndependentCheck) {
#ifdef BLISKRUN_SANITIZED
  // ~3 minutes under ASan+UBSan; the planner, its links and moves run there
  // in tests/planning/channel_roughing_test.cpp.
  GTEST_SKIP() << "impeller channel recipe skipped under the sanitizers (runs in the Release suite)";
#endif
  TempDir dir;
  const double stock = 0.5, tip = 3;
  const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/impeller_channel_roughing.lua",
                                       "--out", dir.path(), "--quiet", "--set", "channels=left", "--set", "stations=11",
                                       "--set", "scallop=0.05", "--set", "depth_step=10", "--set", "mesh_tol=0.1"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has_run_report(dir.path(), "impeller_channel_roughing.pvd"));
  std::ifstream json_file(dir.path() + "/impeller_channel_roughing.json");
  ASSERT_TRUE(json_file.good());
  const nlohmann::json j = nlohmann::json::parse(json_file);
  const nlohmann::json& c = j["channels"]["left"];
  // Eq. 12 exact: f = 2 sqrt(2 r h - h^2); eq. 13 per side at the outlet.
  const double f = 2 * std::sqrt(2 * tip * 0.05 - 0.05 * 0.05);
  EXPECT_NEAR(c["step_over"].get<double>(), f, 1e-12);
  EXPECT_EQ(c["widen_left"].get<int>(), static_cast<int>(std::ceil(c["outlet_width_left"].get<double>() / f)));
  EXPECT_EQ(c["widen_right"].get<int>(), static_cast<int>(std::ceil(c["outlet_width_right"].get<double>() / f)));
  EXPECT_LE(c["scallop_max"].get<double>(), 0.05 + 1e-9);
  EXPECT_GT(c["scallop_outlet"].get<double>(), 0.5 * 0.05);  // N is the fewest: the outlet's cusps are near h
  EXPECT_LE(c["deepest_step"].get<double>(), 10.0);
  EXPECT_GE(c["notch_levels"].get<int>(), 2);
  EXPECT_EQ(c["refusals"].size(), 0u);

  // The independent check: the model rebuilt here, the channel's two faces,
  // the other faces of main 1 and the splitter, and the hub tessellated at
  // 0.05 mm (2x finer than the recipe's), every APT move — the pose and the
  // straight motion from the previous one — with zero clearance for every
  // tool part.
  const Impeller imp(builtin_impeller_definition());
  TaperedBallEndMillSpec spec;
  spec.tip_radius_mm = tip;
  spec.half_angle_rad = deg_to_rad(2);
  spec.flute_length_mm = 90;
  spec.shank = {16, 60};
  spec.holder = {50, 60};
  const ToolBody body(Tool::tapered_ball_end_mill(spec));
  CollisionWorld world;
  for (CamberSide side : {CamberSide::kPlus, CamberSide::kMinus}) {
    world.add(std::string("main 1 ") + (side == CamberSide::kPlus ? "plus" : "minus"),
              tessellate(*imp.face(BladeKind::kMain, 0, side), 0.05));
    world.add(std::string("splitter 1 ") + (side == CamberSide::kPlus ? "plus" : "minus"),
              tessellate(*imp.face(BladeKind::kSplitter, 0, side), 0.05));
  }
  world.add("hub", tessellate(imp.hub(), 0.05));
  const std::vector<AptMove> moves = read_apt_moves(dir.path() + "/impeller_channel_left.apt");
  ASSERT_GT(moves.size(), 200u);
  int rapids = 0;
  for (size_t i = 0; i < moves.size(); ++i) {
    const ToolPose pose{moves[i].tip, moves[i].axis};
    const PoseCheck pc = world.check(body, pose, Clearances{}, 0.0);
    EXPECT_TRUE(pc.clear) << "move " << i << ": " << describe(pc, world);
    if (i > 0) {
      const MotionCheck mc = world.check_motion(body, {moves[i - 1].tip, moves[i - 1].axis}, pose, Clearances{}, 0.01);
      EXPECT_TRUE(mc.clear) << "motion into move " << i << ": " << describe(mc.at, world);
    }
    rapids += moves[i].rapid;
    // The stock on the hub: every ball centre at least r + stock from it
    // (to the APT's 6 decimals).
    const Vec3 centre = pose.tip + tip * pose.axis;
    const SurfaceProjection pr = project_to_surface(imp.hub(), centre);
    ASSERT_TRUE(pr.ok);
    EXPECT_GE(pr.distance, tip + stock - 1e-5) << "move " << i;
  }
  EXPECT_GE(rapids, 2);  // at least the lead-in and lead-out
}

}  // namespace
}  // namespace bliskrun::test
