// bliskrun.read_cad from a recipe: a STEP file the test writes (a rational
// quarter cylinder) read back in Lua, its surface used as any Surface
// (curvature, projection, tessellation), and errors at the recipe's line.
#include <gtest/gtest.h>

#include <cmath>

#include "core/cad/cad.h"
#include "core/geometry/interpolation.h"
#include "core/parts/impeller.h"
#include "test_support.h"

namespace bliskrun::test {
namespace {

// Quarter cylinder of radius 25 about Z, z in [0, 40]: rational quadratic
// around (v), linear along Z (u).
void write_quarter_cylinder(const std::string& path) {
  const double r = 25, s = std::sqrt(0.5);
  std::vector<Vec3> ctrl;
  std::vector<double> w;
  for (double z : {0.0, 40.0})
    for (const auto& [p, wt] : {std::pair{Vec3(r, 0, 0), 1.0}, {Vec3(r, r, 0), s}, {Vec3(0, r, 0), 1.0}}) {
      ctrl.push_back(p + Vec3(0, 0, z));
      w.push_back(wt);
    }
  const NurbsSurface cyl(1, 2, {0, 0, 1, 1}, {0, 0, 0, 1, 1, 1}, 2, 3, ctrl, w);
  const NurbsCurve arc(2, {0, 0, 0, 1, 1, 1}, {{r, 0, 50}, {r, r, 50}, {0, r, 50}}, {1, s, 1});
  write_step(path, {&cyl}, {&arc});
}

TEST(CadLua, ReadCadGivesSurfacesUsableAsAnySurface) {
  TempDir dir;
  write_quarter_cylinder(dir.path() + "/cyl.step");
  const RecipeResult r = run_recipe_text(dir, R"(
local cad = bliskrun.read_cad("cyl.step")
assert(cad.units == "mm" and cad.file_units == "millimetre" and cad.format == "STEP")
assert(#cad.faces == 1 and #cad.curves == 1)
local f = cad.faces[1]
assert(f.name == "face_1" and f.entity:match("^STEP #%d+"), f.name .. " " .. f.entity)
assert(f.bounds.u[1] == 0 and f.bounds.u[2] == 1 and f.bounds.v[1] == 0 and f.bounds.v[2] == 1)
assert(#f.boundary > 4 and #f.boundary == #f.boundary_uv)
for k = 0, 20 do
  local p = f.surface:point(k / 20, (k % 7) / 6)
  assert(math.abs(math.sqrt(p.x^2 + p.y^2) - 25) < 1e-9, "off the cylinder")
end
local c = f.surface:curvature(0.5, 0.5)
assert(math.abs(math.abs(c.k1) + math.abs(c.k2) - 1 / 25) < 1e-9, "curvature 1/R around, 0 along")
local foot = assert(f.surface:project({30, 30, 20}))
assert(math.abs(foot.distance - (math.sqrt(1800) - 25)) < 1e-8)
local mesh = f.surface:tessellate(0.01)
local arc = cad.curves[1].curve
local q = arc:eval(0.5).point
assert(math.abs(math.sqrt(q.x^2 + q.y^2) - 25) < 1e-9 and q.z == 50)
)");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(CadLua, ErrorsNameTheRecipeLineAndTheFile) {
  TempDir dir;
  dir.write("broken.step", "ISO-10303-21;\nHEADER;\n");
  dir.write("part.dxf", "0\nSECTION\n");
  for (const auto& [call, expected] :
       {std::pair{"bliskrun.read_cad('broken.step')", "broken.step:0: not a readable STEP file"},
        {"bliskrun.read_cad('part.dxf')", "unknown CAD format '.dxf'"},
        {"bliskrun.read_cad('nothing.igs')", "cannot find 'nothing.igs'"},
        {"bliskrun.read_cad()", "path"}}) {
    EXPECT_TRUE(fails_at_line_2(dir, {"", call, expected}));
  }
}

// Impeller faces from CAD (issue 36 item 3): the built-in impeller's blade 1
// and splitter 1 faces, each the kernel's B-spline through 20 x 80 of its
// points (two of them written transposed or reversed, as a CAD system may
// parametrise them), and its hub meridian, written to STEP by OCCT and read
// back; cad_part.impeller orients them and makes the part the impeller
// operations take. Its blade k (main and splitter, both faces) carries the
// built-in impeller's blade k points; the faces are ruled (their fit's error
// at round-off), the hub is the built-in one.
TEST(CadLua, ImpellerFromStepFacesReproducesTheBuiltinImpeller) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "1300 projections and four ruled fits in Lua: the Release suite runs it";
#endif
  TempDir dir;
  const Impeller imp(builtin_impeller_definition());
  const int rows = 20, cols = 80;
  std::vector<NurbsSurface> faces;
  for (BladeKind kind : {BladeKind::kMain, BladeKind::kSplitter})
    for (CamberSide side : {CamberSide::kPlus, CamberSide::kMinus}) {
      const auto f = imp.face(kind, 0, side);
      const bool transposed = kind == BladeKind::kMain && side == CamberSide::kMinus;
      const bool reversed = kind == BladeKind::kSplitter && side == CamberSide::kPlus;
      PointGrid g(transposed ? cols : rows, transposed ? rows : cols);
      for (int i = 0; i < rows; ++i)
        for (int j = 0; j < cols; ++j) {
          const Vec3 p = f->point(double(i) / (rows - 1), double(j) / (cols - 1));
          if (transposed) g.at(j, i) = p;
          else g.at(reversed ? rows - 1 - i : i, reversed ? cols - 1 - j : j) = p;
        }
      faces.emplace_back(interpolate_grid(g));
    }
  std::vector<Vec3> hub_pts;
  for (const Vec2& zr : imp.hub_meridian()) hub_pts.emplace_back(zr.y(), 0, zr.x());
  const BSplineCurve hub_b = interpolate_cubic(hub_pts);
  const NurbsCurve hub(hub_b.degree(), hub_b.knots(), hub_b.control_points(),
                       std::vector<double>(hub_b.control_points().size(), 1.0));
  // Splitter first, main second, in the file: the order does not matter.
  write_step(dir.path() + "/impeller_blade1.step", {&faces[2], &faces[3], &faces[1], &faces[0]}, {&hub});
  const RecipeResult r = run_recipe_text(dir, R"(
local cad_part = require("cad_part")
local m = bliskrun.read_cad("impeller_blade1.step")
assert(#m.faces == 4 and #m.curves == 1)
local part = cad_part.impeller{blade = {m.faces[3], m.faces[4]}, splitter = {m.faces[1], m.faces[2]},
                               hub = m.curves[1].curve, blade_count = 17, name = "impeller_blade1.step"}
local imp = bliskrun.impeller{}
assert(part:blade_count() == 17 and part:has_splitter())
local worst, ruled = 0, 0
for _, k in ipairs{1, 2, 9, 17} do
  for _, kind in ipairs{"main", "splitter"} do
    for _, side in ipairs{"plus", "minus"} do
      local design, face, ref = part:design_face(k, side, kind), part:face(k, side, kind), imp:face(k, side, kind)
      for i = 0, 19, 3 do
        for j = 0, 79, 7 do
          local p = ref:point(i / 19, j / 79)
          worst = math.max(worst, assert(design:project(p)).distance)
          ruled = math.max(ruled, assert(face:project(p)).distance)
        end
      end
      -- Same orientation: the same point at the same corner parameters.
      local a, b = design:point(0, 0), ref:point(0, 0)
      assert(math.abs(a.x - b.x) + math.abs(a.y - b.y) + math.abs(a.z - b.z) < 1e-8, kind .. " " .. side .. " corner")
    end
  end
end
assert(worst < 1e-5, "design faces off the built-in impeller's by " .. worst .. " mm")
for _, kind in ipairs{"main", "splitter"} do
  for _, side in ipairs{"plus", "minus"} do
    assert(part:ruled_fit(kind, side).max < 1e-6, "ruled fit " .. part:ruled_fit(kind, side).max)
  end
end
assert(ruled < 1e-5, "ruled faces off by " .. ruled .. " mm")
for _, t in ipairs{0.1, 0.3, 0.5, 0.7, 0.9} do
  local h = assert(part:hub():project(imp:hub():point(t, 0.1)))
  assert(h.distance < 1e-4, "hub " .. h.distance)
end
assert(math.abs(part:outer_radius() - imp:outer_radius()) < 0.05)
bliskrun.log(string.format("design %.3g mm, ruled %.3g mm", worst, ruled))
-- One face twice is not a blade.
local ok, msg = pcall(cad_part.impeller, {blade = {m.faces[3], m.faces[3]}, hub = m.curves[1].curve, blade_count = 17})
assert(not ok and msg:find("not the two faces of one blade", 1, true), msg)
local ok2, msg2 = pcall(cad_part.impeller, {blade = {m.faces[3], m.faces[4]}, hub = m.curves[1].curve, blade_count = 1})
assert(not ok2 and msg2:find("blade_count", 1, true), msg2)
)", false);
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

}  // namespace
}  // namespace bliskrun::test
