#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "test_support.h"

namespace bliskrun {
namespace {

namespace fs = std::filesystem;

std::string slurp_vtk(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

long long declared(const std::string& xml, const std::string& what) {
  std::smatch m;
  EXPECT_TRUE(std::regex_search(xml, m, std::regex(what + "=\"(\\d+)\""))) << what;
  return m.empty() ? -1 : std::stoll(m[1]);
}

// Numbers inside the DataArray called `name` (first match).
size_t count_values(const std::string& xml, const std::string& name) {
  const auto at = xml.find("Name=\"" + name + "\"");
  if (at == std::string::npos) return 0;
  const auto start = xml.find('>', at) + 1, end = xml.find("</DataArray>", start);
  std::istringstream in(xml.substr(start, end - start));
  size_t n = 0;
  std::string w;
  while (in >> w) ++n;
  return n;
}

TEST(WriteVtk, WritesOneVtpPerBlockAndTheCollection) {
  test::TempDir dir;
  const auto r = test::run_recipe_text(dir, R"(
local flank = bliskrun.blisk{}:flank_grid(1, "pressure"):surface()
local moves = {}
for i = 1, 9 do
  moves[i] = {tip = {i, 2 * i, 0.5}, axis = {0, 0, 1}, kind = (i == 1 or i == 9) and "rapid" or "feed", row = 1}
end
local pvd = bliskrun.write_vtk{path = "run.pvd", blocks = {
  {name = "Pressure flank", surface = flank, samples_u = 5, samples_v = 7},
  {name = "toolpath", moves = moves},
  {name = "refused", points = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}}, reason = {"holder", "shank", "holder"}},
}}
assert(pvd:match("run%.pvd$"))
)");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path out = fs::path(dir.path()) / "out";
  const std::string pvd = slurp_vtk(out / "run.pvd");
  for (const char* f : {"run_1_pressure_flank.vtp", "run_2_toolpath.vtp", "run_3_refused.vtp"}) {
    EXPECT_NE(pvd.find(std::string("file=\"") + f + "\""), std::string::npos) << f;
    ASSERT_TRUE(fs::exists(out / f)) << f;
  }
  const std::string flank = slurp_vtk(out / "run_1_pressure_flank.vtp");
  EXPECT_EQ(declared(flank, "NumberOfPoints"), 35);
  EXPECT_EQ(declared(flank, "NumberOfPolys"), 2 * 4 * 6);
  EXPECT_EQ(count_values(flank, "connectivity"), 3u * 48);
  const std::string path = slurp_vtk(out / "run_2_toolpath.vtp");
  EXPECT_EQ(declared(path, "NumberOfPoints"), 9);
  EXPECT_EQ(declared(path, "NumberOfLines"), 1);
  EXPECT_EQ(count_values(path, "tool_axis"), 27u);
  EXPECT_EQ(count_values(path, "feed"), 9u);
  EXPECT_NE(path.find("\n          9 18 0.5\n"), std::string::npos);  // last tip, exactly
  const std::string refused = slurp_vtk(out / "run_3_refused.vtp");
  EXPECT_EQ(declared(refused, "NumberOfVerts"), 3);
  EXPECT_EQ(count_values(refused, "reason"), 3u);
  EXPECT_NE(refused.find("0 = holder; 1 = shank;"), std::string::npos);
}

class WriteVtkErrors : public ::testing::TestWithParam<test::RecipeErrorCase> {};

TEST_P(WriteVtkErrors, NameTheLineAndTheKey) {
  test::TempDir dir;
  EXPECT_TRUE(test::fails_at_line_2(dir, GetParam()));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, WriteVtkErrors,
    ::testing::Values(
        test::RecipeErrorCase{"NotPvd", "bliskrun.write_vtk{path = 'run.vtp', blocks = {}}", "expected a .pvd"},
        test::RecipeErrorCase{"NoKind", "bliskrun.write_vtk{path = 'a.pvd', blocks = {{name = 'x'}}}",
                              "blocks[1]: expected exactly one of surface, mesh, moves, points"},
        test::RecipeErrorCase{"UnknownKey", "bliskrun.write_vtk{path = 'a.pvd', blocks = {{name = 'x', colour = 1}}}",
                              "colour"},
        test::RecipeErrorCase{"ReasonCount",
                              "bliskrun.write_vtk{path = 'a.pvd', blocks = {{name = 'x', points = {{1, 2, 3}}, "
                              "reason = {'a', 'b'}}}}",
                              "expected one reason per point"},
        test::RecipeErrorCase{"BadMove",
                              "bliskrun.write_vtk{path = 'a.pvd', blocks = {{name = 'x', moves = {{tip = {0, 0, 0}, "
                              "axis = {0, 0, 1}, kind = 'walk'}, {}}}}}",
                              "blocks[1].moves[1].kind"}),
    test::error_case_name);

}  // namespace
}  // namespace bliskrun
