// scripts/recipes/impeller_flank_finish.lua on small samples: it runs, the
// report states the residual and the proofs, and every emitted pose passes an
// independent collision check against a finer tessellation of the model.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/collision/collision_world.h"
#include "core/geometry/mesh.h"
#include "core/parts/impeller.h"
#include "test_support.h"

namespace bliskrun::test {
namespace {

std::vector<ToolPose> apt_poses(const std::string& path) {
  std::vector<ToolPose> poses;
  for (const AptMove& m : read_apt_moves(path)) poses.push_back({m.tip, m.axis});
  return poses;
}

TEST(ImpellerFlankFinishRecipe, RunsAndEveryEmittedPoseIsClearInAnIndependentCheck) {
  TempDir dir;
  const RecipeResult r = run_bliskrun({std::string(BLISKRUN_SOURCE_DIR) + "/scripts/recipes/impeller_flank_finish.lua",
                                       "--out", dir.path(), "--quiet", "--set", "chord_tol=0.05", "--set",
                                       "mesh_tol=0.2", "--set", "residual_points=8", "--set", "apt_blades=2"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has_run_report(dir.path(), "impeller_flank_finish.pvd"));
  std::ifstream in(dir.path() + "/impeller_flank_finish.json");
  ASSERT_TRUE(in.good());
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["blades"].get<int>(), 17);
  EXPECT_NEAR(j["outer_diameter"].get<double>(), 410.0, 3.0);
  for (const char* face : {"impeller_main_plus", "impeller_main_minus", "impeller_splitter_plus",
                           "impeller_splitter_minus"}) {
    const nlohmann::json& f = j["faces"][face];
    EXPECT_EQ(f["poses"].get<int>() + f["refused"].get<int>(), f["stations"].get<int>()) << face;
    EXPECT_GT(f["poses"].get<int>(), 20) << face;
    // Residual of flank milling a twisted ruled face with a tapered ball end,
    // with the paper's axes: 0.07–0.14 mm undercut (near the hub fillet) and
    // 0.02–0.17 mm overcut (mid-ruling, the paper's concave overcut); with
    // the balanced axes (default) the band is centred: bounds with margin.
    EXPECT_LT(f["residual"]["max_abs"].get<double>(), 0.5) << face;
    EXPECT_LT(f["residual_unbalanced"]["min"].get<double>(), 0.0) << face;
    EXPECT_LE(f["residual"]["max_abs"].get<double>(), f["residual_unbalanced"]["max_abs"].get<double>() + 1e-9) << face;
    EXPECT_EQ(f["per_pose"].size(), f["poses"].get<size_t>());
    // The root corner apart from the residual: a ball of 3 mm riding the hub
    // leaves r / sin(theta / 2) - r, 1.24 mm at a right angle, more where the
    // blade leans over the channel (3.09 mm measured on both minus faces
    // near 62 % of the main blade's chord, theta about 59 degrees; 1.27 mm
    // on the plus faces), far beyond the residual.
    EXPECT_GT(f["root_corner"]["max"].get<double>(), 1.0) << face;
    EXPECT_LT(f["root_corner"]["max"].get<double>(), 3.5) << face;
    EXPECT_GT(f["root_corner"]["max"].get<double>(), 5 * f["residual"]["max_abs"].get<double>()) << face;
    // The clearance reported includes the leads.
    EXPECT_LE(f["min_margin"].get<double>(), f["pose_min_margin"].get<double>()) << face;
    EXPECT_LE(f["min_margin"].get<double>(), f["lead_min_margin"].get<double>()) << face;
  }

  // Independent check: the model rebuilt here, tessellated 4x finer than the
  // recipe's check meshes, blade 1's main "plus" face poses (from the APT,
  // both blade 1 and blade 2 as turned by the recipe) against the
  // neighbouring main blades and splitters with every tool part.
  const Impeller imp(builtin_impeller_definition());
  TaperedBallEndMillSpec spec;
  spec.tip_radius_mm = 3;
  spec.half_angle_rad = deg_to_rad(2);
  spec.flute_length_mm = 90;
  spec.shank = {16, 60};
  spec.holder = {50, 60};
  const ToolBody body(Tool::tapered_ball_end_mill(spec));
  const int n = imp.blade_count();
  const std::vector<ToolPose> poses = apt_poses(dir.path() + "/impeller_main_plus.apt");
  ASSERT_GT(poses.size(), 40u);
  for (int blade : {0, 1}) {
    CollisionWorld world;
    for (auto [kind, k] : {std::pair{BladeKind::kMain, (blade + 1) % n}, std::pair{BladeKind::kMain, (blade + n - 1) % n},
                           std::pair{BladeKind::kSplitter, blade}, std::pair{BladeKind::kSplitter, (blade + n - 1) % n}})
      for (CamberSide side : {CamberSide::kPlus, CamberSide::kMinus})
        world.add(std::to_string(int(kind)) + "/" + std::to_string(k) + "/" + std::to_string(int(side)),
                  tessellate(*imp.face(kind, k, side), 0.05));
    const size_t half = poses.size() / 2;  // the APT holds blade 1's poses, then blade 2's
    for (size_t i = blade * half; i < (blade + 1) * half; ++i) {
      const PoseCheck c = world.check(body, poses[i], Clearances{}, 0.0);
      EXPECT_TRUE(c.clear) << "blade " << blade + 1 << " pose " << i << " margin " << c.min_margin_mm;
    }
  }
}

}  // namespace
}  // namespace bliskrun::test
