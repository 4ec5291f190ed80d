// bliskrun.read_points from a recipe: a binary PLY scan of a known surface,
// moved by a known rigid transform, read back and registered with
// register_scan, which must recover the transform; errors at the recipe's
// line naming the data file and where in it.
#include <gtest/gtest.h>

#include <fstream>

#include "test_support.h"

namespace bliskrun::test {
namespace {

// The model: a bicubic patch through a warped, twisted 40 x 40 mm grid (no
// symmetry, so all six degrees of freedom are fixed). The scan: its points
// at 31 x 31 parameters, turned 0.8 degrees about (1, 2, 3) and shifted by
// (0.3, -0.2, 0.15) mm, written as a big-endian double PLY in inches (with a
// face element after the vertices, as a meshed scan has).
const char* const kScanRecipe = R"(
local pts = {}
for i = 0, 8 do for j = 0, 8 do
  local x, y = -20 + 5 * i, -20 + 5 * j
  pts[#pts + 1] = {x, y, (x * x - 2 * y * y) / 80 + x * y * y / 2000 + 0.05 * x}
end end
local model = bliskrun.point_grid{rows = 9, cols = 9, points = pts}:surface()

-- R = rotation by `a` about the unit axis k (Rodrigues), t the shift.
local a = math.rad(0.8)
local kx, ky, kz = 1 / math.sqrt(14), 2 / math.sqrt(14), 3 / math.sqrt(14)
local c, s, C = math.cos(a), math.sin(a), 1 - math.cos(a)
local R = {{c + kx * kx * C, kx * ky * C - kz * s, kx * kz * C + ky * s},
           {ky * kx * C + kz * s, c + ky * ky * C, ky * kz * C - kx * s},
           {kz * kx * C - ky * s, kz * ky * C + kx * s, c + kz * kz * C}}
local t = {0.3, -0.2, 0.15}

local n = 31
local body = {}
for i = 0, n - 1 do for j = 0, n - 1 do
  local p = model:point(0.05 + 0.9 * i / (n - 1), 0.05 + 0.9 * j / (n - 1))
  local q = {}
  for r = 1, 3 do q[r] = (R[r][1] * p.x + R[r][2] * p.y + R[r][3] * p.z + t[r]) / 25.4 end
  body[#body + 1] = string.pack(">ddd", q[1], q[2], q[3])
end end
local header = "ply\nformat binary_big_endian 1.0\ncomment a scan in inches\nelement vertex " .. n * n ..
               "\nproperty double x\nproperty double y\nproperty double z\n" ..
               "element face 0\nproperty list uchar int vertex_indices\nend_header\n"
bliskrun.write_text("scan.ply", header .. table.concat(body))

local scan, info = bliskrun.read_points(bliskrun.out_dir() .. "/scan.ply", {units = "in"})
assert(#scan == n * n and info.count == n * n and info.format == "ply" and info.normals == nil)
local fit = bliskrun.register_scan{scan = scan, surfaces = {model}, samples = 300}
assert(fit.converged, "not converged")

-- scan -> model is x' = R^T (x - t): linear R^T (its columns are R's rows), origin -R^T t.
local worst_axis, worst_origin = 0, 0
for col, key in ipairs({"x", "y", "z"}) do
  for r = 1, 3 do
    worst_axis = math.max(worst_axis, math.abs(fit.transform[key][r] - R[col][r]))
  end
  local o = 0
  for r = 1, 3 do o = o - R[r][col] * t[r] end
  worst_origin = math.max(worst_origin, math.abs(fit.transform.origin[col] - o))
end
bliskrun.log(string.format("registration error: axes %.3g, origin %.3g mm, angle %.6f deg, rms %.3g mm",
                           worst_axis, worst_origin, fit.angle, fit.rms))
-- Point-to-plane ICP on the 300 x 300 model sample lands within ~1 um and
-- ~0.001 degrees of the truth (measured 0.6 um, 0.0004 deg): 500 times below
-- the 0.3 mm, 0.8 degree offset it starts from.
assert(math.abs(fit.angle - 0.8) < 1e-3, "angle " .. fit.angle)
assert(worst_axis < 3e-5, "axes off by " .. worst_axis)
assert(worst_origin < 2e-3, "origin off by " .. worst_origin .. " mm")
)";

TEST(PointCloudLua, PlyScanRegistersToKnownTransform) {
  TempDir dir;
  const RecipeResult r = run_recipe_text(dir, kScanRecipe);
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(PointCloudLua, ReadPointsOptionsFormatsAndErrors) {
  TempDir dir;
  dir.write("pts.csv", "X,Y,Z,NX,NY,NZ\n1,2,3,0,0,1\n4,5,6,0,1,0\n");
  dir.write("bad.xyz", "1 2 3\n4 5 six\n");
  dir.write("cut.stl", std::string(80, ' ') + std::string("\x02\0\0\0", 4) + std::string(60, '\0'));
  const RecipeResult ok = run_recipe_text(dir, R"(
local p, info = bliskrun.read_points("pts.csv", {units = "m"})
assert(#p == 2 and info.format == "csv" and p[2][1] == 4000 and p[2].z == 6000)
assert(info.normals[2][2] == 1 and info.normals[1].z == 1)
-- Forced format: the same file as XYZ is refused at its header line.
local ok, err = pcall(bliskrun.read_points, "pts.csv", {format = "xyz"})
assert(not ok and err:match("pts.csv:1: expected"), err)
)");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_TRUE(fails_at_line_2(dir, {"text", "bliskrun.read_points('bad.xyz')",
                                    "bad.xyz:2: expected a number in column 3 (z), got 'six'"}));
  EXPECT_TRUE(fails_at_line_2(dir, {"binary", "bliskrun.read_points('cut.stl')",
                                    "cut.stl: byte 80: the count says 2 triangles (184 bytes), the file has 144 bytes (truncated)"}));
  EXPECT_TRUE(fails_at_line_2(dir, {"units", "bliskrun.read_points('bad.xyz', {units = 'cm'})", "units"}));
  EXPECT_TRUE(fails_at_line_2(dir, {"key", "bliskrun.read_points('bad.xyz', {unit = 'mm'})", "unit"}));
}

}  // namespace
}  // namespace bliskrun::test
