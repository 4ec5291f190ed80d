// Tilt until clear: axis from λ and w, tool placement on the contact, the
// paper's C-axis limit, a wall cleared at the closed-form lead, and refusals.
#include <gtest/gtest.h>

#include <cmath>

#include "collision/test_meshes.h"
#include "core/collision/tilt.h"
#include "core/common/error.h"
#include "test_support.h"

namespace bliskrun {
namespace {

using test::grid_mesh;

// Contact at the origin on the plane z = 0, path along +x: Y_SL = +y.
const ContactFrame kFlat{Vec3::Zero(), Vec3::UnitX(), Vec3::UnitZ()};

TEST(Tilt, AxisFromLeadAndTiltFollowsThePaperFrame) {
  EXPECT_NEAR((axis_from_lead_tilt(kFlat, 0, 0) - Vec3::UnitY()).norm(), 0, 1e-15);
  const double l = deg_to_rad(20), w = deg_to_rad(15);
  const Vec3 a = axis_from_lead_tilt(kFlat, l, w);
  EXPECT_NEAR(std::asin(a.z()), l, 1e-12);                 // λ: angle to the tangent plane
  EXPECT_NEAR(std::atan2(-a.x(), a.y()), w, 1e-12);        // w: turn about the normal
  EXPECT_NEAR(a.norm(), 1, 1e-15);
  // The tangent need not be perpendicular to the normal; it is projected.
  const ContactFrame skew{Vec3::Zero(), Vec3(1, 0, 0.3), Vec3::UnitZ()};
  EXPECT_NEAR((axis_from_lead_tilt(skew, 0, 0) - Vec3::UnitY()).norm(), 0, 1e-15);
  EXPECT_THROW(axis_from_lead_tilt(ContactFrame{Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitZ()}, 0, 0),
               ParameterError);
}

TEST(Tilt, RotaryLimitMeasuresTheAxisTurnedIntoTheWorkingPlane) {
  const RotaryAxisLimit c;  // the paper's: C about Z from Y, ±30°
  const auto about_z = [](double deg, double rise) {
    const double a = deg_to_rad(deg);
    return Vec3(-std::sin(a), std::cos(a), rise).normalized();
  };
  EXPECT_NEAR(rad_to_deg(c.angle_rad(about_z(25, 0))), 25, 1e-12);
  EXPECT_NEAR(rad_to_deg(c.angle_rad(about_z(-40, 0.7))), -40, 1e-12);  // rising out of the plane: same C
  EXPECT_TRUE(c.violation(about_z(29.9, 0.3)).empty());
  EXPECT_NE(c.violation(about_z(-30.5, 0)).find("C = -30.5 deg outside"), std::string::npos);
  EXPECT_TRUE(std::isnan(c.angle_rad(Vec3::UnitZ())));
  EXPECT_TRUE(c.violation(Vec3::UnitZ()).empty());  // along the C axis: any C reaches it
  RotaryAxisLimit bad;
  bad.reference = Vec3(0, 1, 1);
  EXPECT_THROW(make_axis_limit(bad), ParameterError);
}

TEST(Tilt, PlacedToolTouchesTheTangentPlaneAtTheContact) {
  const Tool tool = test::paper_drum_wheel();
  const ContactFrame f{Vec3(3, -1, 2), Vec3(1, 1, 0), Vec3(0, 0, 1)};
  for (double lead_deg : {0.0, 1.0, 2.0, 5.0, 30.0}) {
    const Vec3 axis = axis_from_lead_tilt(f, deg_to_rad(lead_deg), deg_to_rad(7));
    const ToolPose pose = place_tool(tool, f, axis);
    const Eigen::Isometry3d to_tool = tool_to_part(pose).inverse();
    EXPECT_NEAR(tool.signed_distance(to_tool * f.point), 0, 1e-9) << lead_deg;
    EXPECT_LT(tool.signed_distance(to_tool * (f.point + 1e-3 * f.normal)), 0) << lead_deg;
    // Nothing of the tool below the tangent plane.
    for (double dx = -6; dx <= 6; dx += 0.25) {
      for (double dy = -6; dy <= 6; dy += 0.25) {
        EXPECT_GE(tool.signed_distance(to_tool * (f.point + Vec3(dx, dy, 0))), -1e-9) << lead_deg;
      }
    }
  }
}

// The tool pose the loop must produce on kFlat, in closed form: the barrel
// (centre (-46, 2), R_c 50) touches with its point at angle -λ while
// λ <= asin(2/50), the bottom corner beyond.
ToolPose closed_form_pose(double lead) {
  const Vec3 a(0, std::cos(lead), std::sin(lead));
  const Vec3 e_r(0, std::sin(lead), -std::cos(lead));  // radial direction towards the plane
  const double alpha0 = std::asin(2.0 / 50);
  double r, z;
  if (lead <= alpha0) {
    r = -46 + 50 * std::cos(lead);
    z = 2 - 50 * std::sin(lead);
  } else {
    r = -46 + std::sqrt(2500.0 - 4);
    z = 0;
  }
  return ToolPose{-(z * a + r * e_r), a};
}

// Distance from the shank (radius 3, axis from 4 to 100 mm) to the top edge
// of a plate at y = 60 reaching up to z = top, negative while the axis runs
// through the plate; the edge runs along x, across the axis plane, so the
// 3-D distance is the 2-D one in the y-z plane.
double shank_to_edge(double lead, double top) {
  const ToolPose p = closed_form_pose(lead);
  const Vec2 dir(std::cos(lead), std::sin(lead));
  const Vec2 e(60 - p.tip.y(), top - p.tip.z());
  const double along = e.dot(dir);
  EXPECT_GT(along, 4);
  EXPECT_LT(along, 100);
  return e.x() * dir.y() - e.y() * dir.x() - 3;
}

CollisionWorld plate_world(double top, double x0 = -100, double x1 = 100) {
  CollisionWorld world;
  world.add("blade k+1", grid_mesh(Vec3(x0, 60, -5), Vec3(x1 - x0, 0, 0), Vec3(0, 0, top + 5), 2, 2));
  return world;
}

TEST(Tilt, ClearsAWallAtTheClosedFormLead) {
  const ToolBody body(test::paper_drum_wheel());
  TiltSettings s;
  s.lead_step_rad = deg_to_rad(0.5);
  s.clearances = Clearances{0.5, 0.5, 0};
  for (double top : {5.0, 9.0, 20.0}) {
    const CollisionWorld world = plate_world(top);
    // λ*: the smallest lead with the shank 0.5 mm clear of the edge (bisection).
    double lo = 0, hi = deg_to_rad(40);
    ASSERT_LT(shank_to_edge(lo, top), 0.5);
    for (int i = 0; i < 80; ++i) {
      const double mid = (lo + hi) / 2;
      (shank_to_edge(mid, top) >= 0.5 ? hi : lo) = mid;
    }
    const TiltOutcome o = tilt_until_clear(world, body, kFlat, 0, s);
    ASSERT_TRUE(o.accepted) << o.refusal.reason;
    // FCL's shank encloses the true one within its overestimate (< 2 µm),
    // which can only delay clearance by far less than a step.
    EXPECT_GE(o.pose.lead_rad, hi - 1e-7) << "top " << top;
    EXPECT_LT(o.pose.lead_rad, hi + s.lead_step_rad) << "top " << top;
    EXPECT_NEAR((o.pose.pose.tip - closed_form_pose(o.pose.lead_rad).tip).norm(), 0, 1e-9);
    // The loop resolves distances only up to the clearance; ask again fully.
    const PoseCheck full = world.check(body, o.pose.pose, s.clearances);
    EXPECT_LE(full.parts[1].distance_mm, shank_to_edge(o.pose.lead_rad, top) + 1e-9);
    EXPECT_GE(full.parts[1].distance_mm, shank_to_edge(o.pose.lead_rad, top) - body.overestimate_mm() - 1e-9);
    EXPECT_EQ(o.pose.tries, static_cast<int>(std::round(o.pose.lead_rad / s.lead_step_rad)) + 1);
  }
}

TEST(Tilt, RefusesWhatTheAxisLimitForbidsAndSaysWhy) {
  const ToolBody body(test::paper_drum_wheel());
  const CollisionWorld world = plate_world(30);  // needs about 28° of lead
  TiltSettings s;
  s.clearances = Clearances{0.5, 0.5, 0};
  RotaryAxisLimit a;  // an A axis about X, from Y: measures λ here
  a.name = "A";
  a.rotary_axis = Vec3::UnitX();
  a.min_rad = deg_to_rad(-10);
  a.max_rad = deg_to_rad(10);
  s.axis_limit = make_axis_limit(a);
  const ContactFrame contact{Vec3(1, 2, 0), Vec3::UnitX(), Vec3::UnitZ()};
  const TiltOutcome o = tilt_until_clear(world, body, contact, 17, s);
  ASSERT_FALSE(o.accepted);
  EXPECT_EQ(o.refusal.index, 17);
  EXPECT_EQ(o.refusal.contact, contact.point);
  EXPECT_NE(o.refusal.reason.find("first beyond the limit at lead 10.5 deg, tilt 0 deg: axis limit: A = 10.5 deg outside"),
            std::string::npos) << o.refusal.reason;
  EXPECT_NE(o.refusal.reason.find("last interference at lead 10 deg, tilt 0 deg: shank"), std::string::npos)
      << o.refusal.reason;
  EXPECT_NE(o.refusal.reason.find("70 beyond the axis limit, 21 interfere at the pose"), std::string::npos)
      << o.refusal.reason;

  // Without the limit but with a 20° ceiling on the lead: refused for the shank.
  s.axis_limit = nullptr;
  s.lead_max_rad = deg_to_rad(20);
  const TiltOutcome capped = tilt_until_clear(world, body, contact, 3, s);
  ASSERT_FALSE(capped.accepted);
  EXPECT_NE(capped.refusal.reason.find("last interference at lead 20 deg, tilt 0 deg: shank"), std::string::npos)
      << capped.refusal.reason;
  EXPECT_NE(capped.refusal.reason.find("'blade k+1', needs 0.5 mm"), std::string::npos) << capped.refusal.reason;

  // Tilting w as well cannot help a wall across the whole path either.
  s.allow_tilt = true;
  s.tilt_range_rad = deg_to_rad(3);
  EXPECT_FALSE(tilt_until_clear(world, body, contact, 3, s).accepted);
}

// A bottom-cutting tool starts with its axis near the normal (λ near 90°)
// and leans away from it (lead_step < 0) under a plate over the contact; the
// loop takes the first lead, stepping down, whose pose the world finds
// clear (brute force over the same leads), and a pose filter (the
// operation's own test) refuses the leads it names before the world is asked.
TEST(Tilt, LeansABottomCuttingToolDownFromTheNormalPastAFilter) {
  const ToolBody body(Tool::flat_end_mill({3, 0.5, 9, {6, 50}, {12, 40}}));
  CollisionWorld world;
  world.add("plate", grid_mesh(Vec3(-100, -20, 40), Vec3(200, 0, 0), Vec3(0, 120, 0), 2, 2));
  TiltSettings s;
  s.clearances = Clearances{0, 0.1, 0.5};
  s.lead0_rad = deg_to_rad(85);
  s.lead_step_rad = -deg_to_rad(5);
  s.lead_max_rad = deg_to_rad(10);
  s.tilt0_rad = kPi;  // leaning towards -y, out from under the plate
  double expected = -1;
  for (double lead = s.lead0_rad; lead >= s.lead_max_rad - 1e-9; lead += s.lead_step_rad) {
    const ToolPose pose = place_tool(body.tool(), kFlat, axis_from_lead_tilt(kFlat, lead, s.tilt0_rad));
    if (world.check(body, pose, s.clearances, 0).clear) {
      expected = lead;
      break;
    }
  }
  ASSERT_GT(expected, deg_to_rad(20)) << "the plate must be clearable above the filter's ceiling";
  ASSERT_LT(expected, deg_to_rad(80)) << "the plate must force some leaning";
  const TiltOutcome o = tilt_until_clear(world, body, kFlat, 0, s);
  ASSERT_TRUE(o.accepted) << o.refusal.reason;
  EXPECT_NEAR(o.pose.lead_rad, expected, 1e-9);
  // The operation allows nothing steeper than 20° from the tangent plane.
  s.pose_filter = [](const ToolPose& pose) {
    return pose.axis.z() > std::sin(deg_to_rad(20)) + 1e-9 ? std::string("too steep") : std::string();
  };
  const TiltOutcome f = tilt_until_clear(world, body, kFlat, 0, s);
  ASSERT_TRUE(f.accepted) << f.refusal.reason;
  EXPECT_NEAR(f.pose.lead_rad, deg_to_rad(20), 1e-9);
  s.lead_max_rad = deg_to_rad(25);
  const TiltOutcome none = tilt_until_clear(world, body, kFlat, 0, s);
  ASSERT_FALSE(none.accepted);
  EXPECT_NE(none.refusal.reason.find("13 refused by the operation"), std::string::npos) << none.refusal.reason;
  EXPECT_NE(none.refusal.reason.find("too steep"), std::string::npos) << none.refusal.reason;
  // A step away from lead_max is an error.
  s.lead_step_rad = deg_to_rad(5);
  EXPECT_THROW(tilt_until_clear(world, body, kFlat, 0, s), ParameterError);
}

TEST(Tilt, PathRefusesPosesAndMotionsItCannotClear) {
  // A high, narrow plate at x in [-5, 5]: the middle contact cannot lift its
  // shank over it within A ±10°, and the motion from the first accepted pose
  // to the last would cut through it (paper Fig. 9) — both refused.
  const ToolBody body(test::paper_drum_wheel());
  const CollisionWorld world = plate_world(30, -5, 5);
  TiltSettings s;
  s.clearances = Clearances{0.5, 0.5, 0};
  RotaryAxisLimit a;
  a.name = "A";
  a.rotary_axis = Vec3::UnitX();
  a.min_rad = deg_to_rad(-10);
  a.max_rad = deg_to_rad(10);
  s.axis_limit = make_axis_limit(a);
  std::vector<ContactFrame> path;
  for (double x : {-20.0, 0.0, 20.0}) path.push_back(ContactFrame{Vec3(x, 0, 0), Vec3::UnitX(), Vec3::UnitZ()});
  const TiltRun run = tilt_path(world, body, path, s);
  ASSERT_EQ(run.poses.size(), 1u);
  EXPECT_EQ(run.poses[0].index, 0);
  EXPECT_EQ(run.poses[0].lead_rad, 0);
  ASSERT_EQ(run.refusals.size(), 2u);
  EXPECT_EQ(run.refusals[0].index, 1);
  EXPECT_EQ(run.refusals[1].index, 2);
  EXPECT_NE(run.refusals[1].reason.find("motion from the previous pose interferes"), std::string::npos)
      << run.refusals[1].reason;

  // Alone, the last contact is clear at λ = 0: only the motion refused it.
  EXPECT_TRUE(tilt_until_clear(world, body, path[2], 2, s).accepted);
}

}  // namespace
}  // namespace bliskrun
