// bliskrun.read_cad from a recipe: a STEP file the test writes (a rational
// quarter cylinder) read back in Lua, its surface used as any Surface
// (curvature, projection, tessellation), and errors at the recipe's line.
#include <gtest/gtest.h>

#include <cmath>

#include "core/cad/cad.h"
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

}  // namespace
}  // namespace bliskrun::test
