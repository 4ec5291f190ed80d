// A blisk from CAD (core/parts/cad_blisk.h): the built-in blisk's blade 1,
// hub and casing written to STEP by OCCT, read back and rebuilt with the
// blade count reproduce the built-in blisk's other blades, hub, casing and
// narrowest passage; two flank faces in any parametrisation are told apart
// and oriented; bad input is refused naming what is wrong.
#include "core/parts/cad_blisk.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "core/cad/cad.h"
#include "core/common/error.h"
#include "core/geometry/interpolation.h"
#include "core/geometry/projection.h"
#include "core/geometry/reparametrised.h"
#include "core/parts/builtin_blisk.h"
#include "test_support.h"

namespace bliskrun {
namespace {

// A meridian line (z, r) as the CAD curve a file holds: the line (r, 0, z)
// in the plane y = 0 (bliskrun's frame: axis Z, radius hypot(x, y)).
NurbsCurve meridian_curve(const std::vector<Vec2>& zr) {
  return NurbsCurve(1, {0, 0, 1, 1}, {Vec3(zr.front().y(), 0, zr.front().x()), Vec3(zr.back().y(), 0, zr.back().x())},
                    {1, 1});
}

struct CadBliskFixture {
  BuiltinBlisk blisk;
  CadModel step;  // blade 1's flanks (pressure, suction), hub and casing, read back
  explicit CadBliskFixture(const std::string& dir) : blisk(params()) {
    // The fixture of CadStep.BuiltinBliskFlankRoundTripWithin10nm (tests/cad):
    // each flank the kernel's B-spline through its grid.
    const NurbsSurface pressure(interpolate_grid(blisk.flank_grid(0, FlankSide::kPressure)));
    const NurbsSurface suction(interpolate_grid(blisk.flank_grid(0, FlankSide::kSuction)));
    const NurbsCurve hub = meridian_curve(blisk.hub_meridian()), casing = meridian_curve(blisk.casing_meridian());
    write_step(dir + "/blisk_blade1.step", {&pressure, &suction}, {&hub, &casing});
    step = read_cad(dir + "/blisk_blade1.step");
  }
  static BliskParams params() {
    BliskParams p;
    p.grid_rows = 30;
    p.grid_cols = 80;
    return p;
  }
  std::shared_ptr<const SurfaceOfRevolution> revolution(int curve) const {
    return std::make_shared<SurfaceOfRevolution>(revolution_from_curve(*step.curves.at(curve).curve, {}));
  }
  CadBlisk rebuild(int blade_count) const {
    return CadBlisk(step.faces.at(0).surface, step.faces.at(1).surface, revolution(0), revolution(1), blade_count);
  }
};

TEST(CadBlisk, BuiltinBliskFromStepBlade1ReproducesEveryBladeWithin10nm) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "3000 projections and two passage searches: the Release suite runs it; the other CadBlisk tests "
                  "run the same code under the sanitizers";
#endif
  const test::TempDir dir;
  const CadBliskFixture f(dir.path());
  ASSERT_EQ(f.step.faces.size(), 2u);
  ASSERT_EQ(f.step.curves.size(), 2u);
  const CadBlisk cad = f.rebuild(f.blisk.blade_count());
  ASSERT_EQ(cad.blade_count(), 22);
  // Blade k of the built-in blisk (its grid points, the data the STEP
  // surfaces interpolate for blade 1) on blade k of the rebuilt blisk: the
  // rebuilt blade k is blade 1 turned by the pitch.
  double worst = 0;
  for (int k = 0; k < 22; ++k)
    for (FlankSide side : {FlankSide::kPressure, FlankSide::kSuction}) {
      const PointGrid grid = f.blisk.flank_grid(k, side);
      const auto s = cad.flank_surface(k, side);
      for (int i = 0; i < grid.rows; i += 7)
        for (int j = 0; j < grid.cols; j += 13) {
          ProjectionOptions o;
          o.seed = Eigen::Vector2d(double(i) / (grid.rows - 1), double(j) / (grid.cols - 1));
          const SurfaceProjection p = project_to_surface(*s, grid.at(i, j), o);
          ASSERT_TRUE(p.ok) << p.failure;
          worst = std::max(worst, p.distance);
        }
    }
  EXPECT_LT(worst, 1e-5) << "mm";
  // A blade turned the wrong way, or the wrong neighbour, is millimetres off:
  // blade 2 of the built-in blisk is not on blade 1 of the rebuilt one.
  const SurfaceProjection off =
      project_to_surface(*cad.flank_surface(0, FlankSide::kPressure), f.blisk.flank_grid(1, FlankSide::kPressure).at(15, 40));
  EXPECT_GT(off.distance, 1.0);
  // Hub and casing: the built-in cones.
  for (double z : {-22.0, -10.0, 0.0, 13.0, 22.0}) {
    EXPECT_NEAR(cad.hub_radius_at(z), f.blisk.hub_radius_at(z), 1e-9) << z;
    EXPECT_NEAR(cad.casing_radius_at(z), f.blisk.casing_radius_at(z), 1e-9) << z;
  }
  const std::vector<Vec2> hub = cad.hub_meridian();
  EXPECT_NEAR(hub.front().x(), -22, 1e-9);
  EXPECT_NEAR(hub.back().y(), 66, 1e-9);
  // The narrowest passage, between blade 1's suction and blade 2's pressure
  // flank, as the built-in blisk measures it on its analytic flanks.
  EXPECT_NEAR(cad.narrowest_passage_mm(), f.blisk.narrowest_passage_mm(), 1e-4);
}

TEST(CadBlisk, TwoFlankFacesInAnyParametrisationAreToldApartAndOriented) {
  const test::TempDir dir;
  const CadBliskFixture f(dir.path());
  const auto p = f.step.faces.at(0).surface, s = f.step.faces.at(1).surface;
  // Swapped, reversed, in either order: the same pressure and suction
  // flanks, u hub -> tip, normals out of the material.
  const auto p2 = std::make_shared<ReorientedSurface>(p, true, true, false);
  const auto s2 = std::make_shared<ReorientedSurface>(s, false, true, true);
  for (const auto& [a, b] : {std::pair<std::shared_ptr<const Surface>, std::shared_ptr<const Surface>>{p2, s2},
                             {s2, p2}, {p, s}}) {
    const CadBlade blade = cad_blade_from_flanks(a, b);
    for (double u : {0.0, 0.4, 1.0})
      for (double v : {0.0, 0.3, 1.0}) {
        EXPECT_LT((blade.pressure->point(u, v) - p->point(u, v)).norm(), 1e-12);
        EXPECT_LT((blade.suction->point(u, v) - s->point(u, v)).norm(), 1e-12);
        const SurfaceDerivs dp = blade.pressure->eval(u, v), dq = p->eval(u, v);
        EXPECT_GT(dp.pu.cross(dp.pv).normalized().dot(dq.pu.cross(dq.pv).normalized()), 1 - 1e-12);
      }
  }
}

void expect_refused(const std::function<void()>& build, const std::string& name, const std::string& what) {
  try {
    build();
    ADD_FAILURE() << name << ": built without error";
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.name(), name) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(CadBlisk, BadInputIsRefusedNamingWhatIsWrong) {
  const test::TempDir dir;
  const CadBliskFixture f(dir.path());
  const auto p = f.step.faces.at(0).surface, s = f.step.faces.at(1).surface;
  const auto hub = f.revolution(0), casing = f.revolution(1);
  expect_refused([&] { CadBlisk(p, s, hub, casing, 1); }, "blade_count", "[2, 400], got 1");
  expect_refused([&] { CadBlisk(p, s, nullptr, casing, 22); }, "hub", "got none");
  expect_refused([&] { CadBlisk(p, s, hub, nullptr, 22); }, "casing", "got none");
  // The flanks given the wrong way round.
  expect_refused([&] { CadBlisk(s, p, hub, casing, 22); }, "pressure", "expected v to run leading -> trailing edge");
  // A hub 15 mm below the blade's root (the flank starts above it): does not meet it.
  const auto low = std::make_shared<SurfaceOfRevolution>(std::vector<Vec2>{{-22, 45}, {22, 51}});
  expect_refused([&] { CadBlisk(p, s, low, casing, 22); }, "hub", "does not meet the blade");
  // A hub too short for the blade's axial extent.
  const auto short_hub = std::make_shared<SurfaceOfRevolution>(std::vector<Vec2>{{-5, 62}, {5, 63}});
  expect_refused([&] { CadBlisk(p, s, short_hub, casing, 22); }, "hub", "does not reach the blade");
  // Two faces that are not one blade's flanks: blade 1's pressure flank and
  // blade 1's pressure flank turned half a turn.
  expect_refused([&] { cad_blade_from_flanks(p, std::make_shared<RotatedSurface>(p, kPi)); }, "faces",
                 "not the flanks of one blade");
}

}  // namespace
}  // namespace bliskrun
