#include "core/io/vtk.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "core/common/error.h"
#include "test_support.h"

namespace bliskrun {
namespace {

// A minimal .vtp reader: the Piece's declared counts and every DataArray's
// numbers by name (Points as "Points"; cell arrays as "<Section>/<name>").
struct ReadBack {
  std::map<std::string, long long> declared;
  std::map<std::string, std::vector<double>> arrays;
  std::map<std::string, int> components;
};

ReadBack read_vtp(const std::string& xml) {
  ReadBack r;
  const std::regex piece("<Piece ([^>]*)>"), attr("(\\w+)=\"(\\d+)\"");
  std::smatch m;
  EXPECT_TRUE(std::regex_search(xml, m, piece));
  const std::string attrs = m[1];
  for (std::sregex_iterator it(attrs.begin(), attrs.end(), attr), end; it != end; ++it)
    r.declared[(*it)[1]] = std::stoll((*it)[2]);
  // Walk the sections in order, so cell arrays get their section's name.
  const std::regex tag("<(Points|PointData|Verts|Lines|Polys)>|<DataArray ([^>]*)>([^<]*)</DataArray>");
  std::string section;
  for (std::sregex_iterator it(xml.begin(), xml.end(), tag), end; it != end; ++it) {
    if ((*it)[1].matched) {
      section = (*it)[1];
      continue;
    }
    const std::string a = (*it)[2];
    std::smatch nm;
    std::string name = "Points";
    if (std::regex_search(a, nm, std::regex("Name=\"([^\"]*)\""))) name = nm[1];
    if (section == "Verts" || section == "Lines" || section == "Polys") name = section + "/" + name;
    int comps = 1;
    if (std::regex_search(a, nm, std::regex("NumberOfComponents=\"(\\d+)\""))) comps = std::stoi(nm[1]);
    std::istringstream in((*it)[3].str());
    std::vector<double> values;
    std::string word;
    while (in >> word) values.push_back(word == "nan" ? std::nan("") : std::stod(word));
    r.arrays[name] = values;
    r.components[name] = comps;
  }
  return r;
}

VtkPolyData toolpath() {
  VtkPolyData d;
  for (int i = 0; i < 7; ++i) d.points.push_back(Vec3(0.1 * i, std::sqrt(2.0) * i, -1.0 / 3 * i));
  d.lines = {{0, 1, 2, 3}, {3, 4, 5, 6}};
  VtkPointArray axis{"tool_axis", 3, {}}, feed{"feed", 1, {}};
  for (int i = 0; i < 7; ++i) {
    const Vec3 a = Vec3(0, std::sin(0.1 * i), std::cos(0.1 * i));
    axis.values.insert(axis.values.end(), {a.x(), a.y(), a.z()});
    feed.values.push_back(i == 3 ? 0 : 1);
  }
  d.point_data = {axis, feed};
  return d;
}

TEST(Vtk, DeclaredCountsMatchTheDataAndCoordinatesRoundTrip) {
  const VtkPolyData d = toolpath();
  const ReadBack r = read_vtp(vtp_xml(d));
  EXPECT_EQ(r.declared.at("NumberOfPoints"), 7);
  EXPECT_EQ(r.declared.at("NumberOfLines"), 2);
  EXPECT_EQ(r.declared.at("NumberOfPolys"), 0);
  ASSERT_EQ(r.arrays.at("Points").size(), 3u * 7);
  for (int i = 0; i < 7; ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(r.arrays.at("Points")[3 * i + k], d.points[i][k]);  // exact: %.17g
  EXPECT_EQ(r.components.at("tool_axis"), 3);
  EXPECT_EQ(r.arrays.at("tool_axis").size(), 21u);
  EXPECT_EQ(r.arrays.at("tool_axis"), d.point_data[0].values);
  EXPECT_EQ(r.arrays.at("feed").size(), 7u);
  EXPECT_EQ(r.arrays.at("Lines/connectivity"), (std::vector<double>{0, 1, 2, 3, 3, 4, 5, 6}));
  EXPECT_EQ(r.arrays.at("Lines/offsets"), (std::vector<double>{4, 8}));
}

TEST(Vtk, TrianglesAndPointSetsAndTheCollection) {
  test::TempDir dir;
  VtkPolyData mesh;
  mesh.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
  mesh.triangles = {{0, 1, 2}, {1, 3, 2}};
  mesh.point_data = {{"undercut", 1, {0.0, 0.001, std::nan(""), -0.002}}};
  write_vtp(mesh, dir.path() + "/flank.vtp");
  std::ifstream in(dir.path() + "/flank.vtp");
  std::stringstream s;
  s << in.rdbuf();
  const ReadBack r = read_vtp(s.str());
  EXPECT_EQ(r.declared.at("NumberOfPolys"), 2);
  EXPECT_EQ(r.arrays.at("Polys/offsets"), (std::vector<double>{3, 6}));
  EXPECT_TRUE(std::isnan(r.arrays.at("undercut")[2]));
  EXPECT_EQ(r.arrays.at("undercut")[3], -0.002);

  VtkPolyData refused;
  refused.points = {Vec3(1, 2, 3), Vec3(4, 5, 6)};
  refused.vertices = true;
  refused.point_data = {{"reason", 1, {0, 1}}};
  refused.code_names = {"collision -- holder", "undercut"};
  const std::string xml = vtp_xml(refused);
  const ReadBack p = read_vtp(xml);
  EXPECT_EQ(p.declared.at("NumberOfVerts"), 2);
  EXPECT_EQ(p.arrays.at("Verts/connectivity"), (std::vector<double>{0, 1}));
  EXPECT_NE(xml.find("0 = collision -  holder; 1 = undercut;"), std::string::npos);

  write_pvd({{"flank", "flank.vtp"}, {"refused <poses>", "refused.vtp"}}, dir.path() + "/run.pvd");
  std::ifstream pin(dir.path() + "/run.pvd");
  std::stringstream ps;
  ps << pin.rdbuf();
  EXPECT_NE(ps.str().find("part=\"1\" name=\"refused &lt;poses&gt;\" file=\"refused.vtp\""), std::string::npos);
}

TEST(Vtk, RefusesDataThatDoesNotFitThePoints) {
  VtkPolyData d = toolpath();
  d.point_data[1].values.pop_back();
  EXPECT_THROW(vtp_xml(d), ParameterError);
  d = toolpath();
  d.lines.push_back({6, 7});
  EXPECT_THROW(vtp_xml(d), ParameterError);
  d = toolpath();
  d.points[2].x() = std::nan("");
  EXPECT_THROW(vtp_xml(d), ParameterError);
}

}  // namespace
}  // namespace bliskrun
