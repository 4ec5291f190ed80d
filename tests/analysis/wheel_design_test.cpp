#include "core/analysis/wheel_design.h"

#include <gtest/gtest.h>

#include "core/common/error.h"

namespace bliskrun {
namespace {

// Table 2 of the blisk paper from Table 1's curvatures and d_min = 10.5 mm.
TEST(WheelDesign, ReproducesPaperTable2) {
  const WheelDesign w = design_drum_wheel({0.0435, 0.0195, 10.5});
  EXPECT_NEAR(w.traditional.radius_limit_mm, 23.0, 0.05);  // 1/k1max = 22.99
  EXPECT_DOUBLE_EQ(w.traditional.drum_radius_mm, 20.0);
  EXPECT_DOUBLE_EQ(w.traditional.diameter_mm, 8.0);
  EXPECT_NEAR(w.extended.radius_limit_mm, 51.3, 0.05);  // 1/kemax = 51.28
  EXPECT_DOUBLE_EQ(w.extended.drum_radius_mm, 50.0);
  EXPECT_DOUBLE_EQ(w.extended.diameter_mm, 8.0);
  // The passage, not eq. 12 (2/k1 = 46 mm), bounds D_t here.
  EXPECT_DOUBLE_EQ(w.extended.diameter_limit_mm, 8.5);
}

TEST(WheelDesign, BoundsAreStrict) {
  EXPECT_DOUBLE_EQ(largest_multiple_below(50.0, 10.0), 40.0);
  EXPECT_DOUBLE_EQ(largest_multiple_below(50.0 + 1e-12, 10.0), 40.0);
  EXPECT_DOUBLE_EQ(largest_multiple_below(50.001, 10.0), 50.0);
  EXPECT_DOUBLE_EQ(largest_multiple_below(9.99, 10.0), 0.0);
  // 1/k1 exactly 25 -> R_c must be below 25 -> 20; clearance making the
  // diameter limit exactly 8 -> D_t 7.
  WheelDesignOptions opts;
  opts.passage_clearance_mm = 2.5;
  const WheelDesign w = design_drum_wheel({0.04, 0.02, 10.5}, opts);
  EXPECT_DOUBLE_EQ(w.traditional.drum_radius_mm, 20.0);
  EXPECT_DOUBLE_EQ(w.traditional.diameter_mm, 7.0);
  EXPECT_DOUBLE_EQ(w.extended.drum_radius_mm, 40.0);  // below 1/0.02 = 50
}

TEST(WheelDesign, CurvatureBoundsTheDiameterWhenPassageIsWide) {
  // 2/k1 = 10 mm < d_min - clearance = 18 -> D_t < 10 -> 9.
  WheelDesignOptions o;
  o.drum_radius_step_mm = 1.0;
  const WheelDesign w = design_drum_wheel({0.2, 0.05, 20.0}, o);
  EXPECT_DOUBLE_EQ(w.traditional.drum_radius_mm, 4.0);  // below 1/0.2 = 5
  EXPECT_DOUBLE_EQ(w.extended.drum_radius_mm, 19.0);    // below 1/0.05 = 20
  EXPECT_DOUBLE_EQ(w.traditional.diameter_limit_mm, 10.0);
  EXPECT_DOUBLE_EQ(w.traditional.diameter_mm, 9.0);
}

TEST(WheelDesign, RejectsBadInputNamingIt) {
  auto name_of = [](WheelDesignInput in, WheelDesignOptions o = {}) -> std::string {
    try {
      design_drum_wheel(in, o);
    } catch (const ParameterError& e) {
      return e.name();
    }
    return "";
  };
  EXPECT_EQ(name_of({0, 0.02, 10}), "k1_max");
  EXPECT_EQ(name_of({0.04, -1, 10}), "ke_max");
  EXPECT_EQ(name_of({0.04, 0.05, 10}), "ke_max");  // k_e cannot exceed k1
  EXPECT_EQ(name_of({0.04, 0.02, 0}), "d_min");
  WheelDesignOptions o;
  o.passage_clearance_mm = 10;
  EXPECT_EQ(name_of({0.04, 0.02, 10.5}, o), "passage_clearance");
  o = {};
  o.drum_radius_step_mm = 0;
  EXPECT_EQ(name_of({0.04, 0.02, 10.5}, o), "drum_radius_step");
  // 1/k1 = 5 mm: no multiple of 10 mm fits.
  EXPECT_EQ(name_of({0.2, 0.05, 10.5}), "k1_max");
}

}  // namespace
}  // namespace bliskrun
