#include "core/machine/wheel_clearance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>

#include "core/common/error.h"

namespace bliskrun {
namespace {

// A face from a point function on [0,1]^2 (the body needs points only).
class Patch : public Surface {
 public:
  explicit Patch(std::function<Vec3(double, double)> f) : f_(std::move(f)) {}
  SurfaceDerivs eval(double u, double v) const override {
    SurfaceDerivs d;
    d.p = f_(u, v);
    return d;
  }

 private:
  std::function<Vec3(double, double)> f_;
};

using Faces = std::vector<std::pair<std::string, std::shared_ptr<const Surface>>>;

std::shared_ptr<const Surface> patch(std::function<Vec3(double, double)> f) {
  return std::make_shared<Patch>(std::move(f));
}

// The plane z = 0 of the blade frame over x in [x0, x1], y in [y0, y1];
// its normal +z points out of the material, towards the wheel.
std::shared_ptr<const Surface> floor_face(double x0, double x1, double y0, double y1) {
  return patch([=](double u, double v) { return Vec3(x0 + (x1 - x0) * u, y0 + (y1 - y0) * v, 0); });
}

BeltStation belt_wheel(double r, double w, double compliance) {
  BeltStation s;
  s.name = "test";
  s.wheel_radius_mm = r;
  s.wheel_width_mm = w;
  s.compliance_mm = compliance;
  return s;
}

// The blade in the station frame that puts blade point p (normal +z, path
// along +x) on the wheel, `offset` mm off it along the normal: blade x to
// the wheel axis, blade z into the wheel (-z of the station).
Frame contact_at(const Vec3& p, double offset = 0) {
  Frame f = Frame::Identity();
  f.linear() = Vec3(1, -1, -1).asDiagonal();
  f.translation() = Vec3(0, 0, offset) - f.linear() * p;
  return f;
}

TEST(BladeBody, SamplesEveryFaceAtMostTheSpacingApart) {
  const BladeBody body = BladeBody::sample({{"floor", floor_face(-30, 30, -10, 10)}}, 0.5);
  // 60 x 20 mm at <= 0.5 mm: at least 121 x 41 samples, each with a neighbour <= 0.5 mm away.
  EXPECT_GE(body.points.size(), 121u * 41u);
  EXPECT_LT(body.points.size(), 125u * 44u);
  EXPECT_EQ(body.face_names, std::vector<std::string>{"floor"});
  EXPECT_THROW(BladeBody::sample({{"floor", floor_face(0, 1, 0, 1)}}, 0), ParameterError);
  EXPECT_THROW(BladeBody::sample({}, 1), ParameterError);
}

TEST(WheelClearance, AFlatFaceTouchesTheWheelOnlyAtTheContactLine) {
  const BladeBody body = BladeBody::sample({{"flank", floor_face(-40, 40, -40, 40)}}, 0.5);
  const WheelClearance check(body, belt_wheel(25, 12, 0.5));
  WheelContactReport r;
  check.check_pose(contact_at(Vec3(3, 2, 0)), r);
  EXPECT_EQ(r.poses, 1);
  EXPECT_EQ(r.collisions, 0) << r.first_collision;
  // The wheel's straight contact line lies on the plane: no point inside it
  // deeper than the rounding of the samples.
  EXPECT_LT(r.max_conformity_mm, 1e-9);
}

TEST(WheelClearance, AFaceConcaveAlongThePathDigsInByTheSagittaOfHalfTheWidth) {
  // z = R - sqrt(R^2 - x^2): concave towards the wheel along the path (x).
  // The rigid wheel's straight contact line of width w has its ends
  // R - sqrt(R^2 - (w/2)^2) inside the face: 0.313 mm for R = 40, w = 10.
  const double R = 40, w = 10;
  const auto face = patch([=](double u, double v) {
    const double x = -8 + 16 * u;
    return Vec3(x, -4 + 8 * v, R - std::sqrt(R * R - x * x));
  });
  const BladeBody body = BladeBody::sample({{"pressure", face}}, 0.05);
  const double sagitta = R - std::sqrt(R * R - w * w / 4);
  {
    const WheelClearance check(body, belt_wheel(20, w, 0.5));
    WheelContactReport r;
    check.check_pose(contact_at(Vec3::Zero()), r);
    EXPECT_EQ(r.collisions, 0) << r.first_collision;
    // Samples 0.05 mm apart on a slope of w / 2R: within 0.05 * 0.125.
    EXPECT_NEAR(r.max_conformity_mm, sagitta, 0.0065);
  }
  {
    // A harder wheel that gives only 0.2 mm: the ends of the wheel collide.
    const WheelClearance check(body, belt_wheel(20, w, 0.2));
    WheelContactReport r;
    check.check_pose(contact_at(Vec3::Zero()), r);
    EXPECT_EQ(r.collisions, 1);
    EXPECT_NE(r.first_collision.find("pressure face point"), std::string::npos) << r.first_collision;
    EXPECT_NE(r.first_collision.find("inside the wheel"), std::string::npos) << r.first_collision;
  }
}

TEST(WheelClearance, AWallBesideThePathMeetsTheWheelAsTheCircleSays) {
  // The flank z = 0 up to a wall y = 0 standing 20 mm towards the wheel (a
  // root platform, or another face). Contact d mm from the wall: the wheel's
  // circle (radius r about (0, -d, r)) reaches the wall's top edge by
  // r - sqrt(d^2 + (r - 20)^2) when that is > 0.
  const double r = 25;
  const auto wall = patch([](double u, double v) { return Vec3(-30 + 60 * u, 0, 20 * v); });
  const BladeBody body = BladeBody::sample({{"flank", floor_face(-30, 30, -60, 0)}, {"wall", wall}}, 0.25);
  const WheelClearance check(body, belt_wheel(r, 12, 0.5));
  for (double d : {22.0, 24.0}) {
    WheelContactReport rep;
    check.check_pose(contact_at(Vec3(0, -d, 0)), rep);
    ASSERT_EQ(rep.collisions, 1) << d;
    EXPECT_NEAR(rep.max_collision_depth_mm, r - std::sqrt(d * d + (r - 20) * (r - 20)), 1e-9) << d;
    EXPECT_NE(rep.first_collision.find("wall face point"), std::string::npos) << rep.first_collision;
  }
  WheelContactReport clear;
  check.check_pose(contact_at(Vec3(0, -25.5, 0)), clear);
  EXPECT_EQ(clear.collisions, 0) << clear.first_collision;
}

TEST(WheelClearance, ThePartOfTheBladeBehindTheWheelMeetsTheBelt) {
  // A patch 60 mm behind the wheel's centre, within the wheel's width and
  // diameter: in the belt's run back to its pulleys.
  const double r = 25;
  const auto behind = patch([=](double u, double v) { return Vec3(-3 + 6 * u, -5 + 10 * v, r + r + 60); });
  const BladeBody body = BladeBody::sample({{"flank", floor_face(-20, 20, -20, 20)}, {"shroud", behind}}, 0.5);
  WheelContactReport rep;
  WheelClearance(body, belt_wheel(r, 12, 0.5)).check_pose(contact_at(Vec3::Zero()), rep);
  ASSERT_EQ(rep.collisions, 1);
  EXPECT_NE(rep.first_collision.find("belt"), std::string::npos) << rep.first_collision;
  // Depth = the distance to the slab's side: 6 - |x| at the sample nearest x = 0.
  EXPECT_NEAR(rep.max_collision_depth_mm, 6, 0.25);
  BeltStation no_belt = belt_wheel(r, 12, 0.5);
  no_belt.belt_run_mm = 50;  // ends before the patch
  WheelContactReport short_run;
  WheelClearance(body, no_belt).check_pose(contact_at(Vec3::Zero()), short_run);
  EXPECT_EQ(short_run.collisions, 0) << short_run.first_collision;
}

TEST(WheelClearance, TheMotionBetweenTwoClearPosesIsSweptTheWayTheControllerMoves) {
  // A plate 8 mm high across the face at x = 0; the wheel 5 mm off the face
  // passes over it from x = -40 to x = 40: both ends clear, the middle not.
  const double r = 25;
  const auto plate = patch([](double u, double v) { return Vec3(0, -5 + 10 * u, 8 * v); });
  const BladeBody body = BladeBody::sample({{"flank", floor_face(-60, 60, -20, 20)}, {"plate", plate}}, 0.25);
  const WheelClearance check(body, belt_wheel(r, 12, 0.5));
  const Frame a = contact_at(Vec3(-40, 0, 0), 5), b = contact_at(Vec3(40, 0, 0), 5);
  WheelContactReport ends;
  check.check_pose(a, ends);
  check.check_pose(b, ends);
  EXPECT_EQ(ends.collisions, 0) << ends.first_collision;
  WheelContactReport swept;
  check.check_motion(a, b, swept);
  EXPECT_EQ(swept.poses, 80);  // 1 mm steps
  EXPECT_GT(swept.collisions, 0);
  // Over the plate the wheel's lowest line is 3 mm below its top edge.
  EXPECT_NEAR(swept.max_collision_depth_mm, 3, 1e-3);  // the samples across miss y = 0 by < 0.2 mm
  // 10 mm off the face it passes.
  WheelContactReport high;
  check.check_motion(contact_at(Vec3(-40, 0, 0), 10), contact_at(Vec3(40, 0, 0), 10), high);
  EXPECT_EQ(high.collisions, 0) << high.first_collision;
}

TEST(WheelClearance, RejectsAnImpossibleWheel) {
  const BladeBody body = BladeBody::sample({{"flank", floor_face(-1, 1, -1, 1)}}, 0.5);
  EXPECT_THROW(WheelClearance(body, belt_wheel(25, 12, 30)), ParameterError);  // gives more than its radius
  EXPECT_THROW(WheelClearance(body, belt_wheel(0, 12, 0.5)), ParameterError);
}

}  // namespace
}  // namespace bliskrun
