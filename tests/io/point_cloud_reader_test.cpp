#include "core/io/point_cloud_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "core/common/error.h"
#include "test_support.h"

namespace bliskrun {
namespace {

// Known points with full-precision doubles, and normals of unit length.
std::vector<Vec3> known_points(int n, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-300, 300);
  std::vector<Vec3> p;
  for (int i = 0; i < n; ++i) p.emplace_back(d(rng), d(rng), d(rng));
  return p;
}

std::vector<Vec3> unit_normals(int n) {
  std::vector<Vec3> out;
  for (const Vec3& p : known_points(n, 11)) out.push_back(p.normalized());
  return out;
}

// Float-representable points (PLY float, STL): the double of the float.
std::vector<Vec3> as_floats(const std::vector<Vec3>& p) {
  std::vector<Vec3> out;
  for (const Vec3& q : p)
    out.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()));
  return out;
}

std::string g17(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// Appends `v` as sizeof(T) bytes in little- or big-endian order.
template <typename T>
void put(std::string* out, T v, bool big = false) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  for (size_t i = 0; i < sizeof(T); ++i) out->push_back(static_cast<char>(b[big ? sizeof(T) - 1 - i : i]));
}

std::string cloud_error_of(const std::string& bytes, const std::string& name, PointCloudFormat f = PointCloudFormat::kAuto) {
  try {
    PointCloudReadOptions o;
    o.format = f;
    parse_point_cloud(bytes, name, o);
  } catch (const DataError& e) {
    return e.what();
  }
  return "";
}

// ---- XYZ / CSV ----------------------------------------------------------------

TEST(PointCloudReader, XyzRoundTripsExactlyWithNormalsCommentsAndBlankLines) {
  const std::vector<Vec3> p = known_points(50), n = unit_normals(50);
  std::string text = "# scanner export\n\n";
  for (size_t i = 0; i < p.size(); ++i)
    text += g17(p[i].x()) + " " + g17(p[i].y()) + "\t" + g17(p[i].z()) + "  " + g17(n[i].x()) + " " +
            g17(n[i].y()) + " " + g17(n[i].z()) + (i % 7 == 0 ? "  # note\r\n" : "\n");
  test::TempDir dir;
  const PointCloud c = read_point_cloud(dir.write("scan.xyz", text));
  EXPECT_EQ(c.format, PointCloudFormat::kXyz);
  ASSERT_EQ(c.points.size(), p.size());
  ASSERT_EQ(c.normals.size(), p.size());
  for (size_t i = 0; i < p.size(); ++i) {
    EXPECT_EQ(c.points[i], p[i]) << i;
    EXPECT_EQ(c.normals[i], n[i]) << i;
  }
}

TEST(PointCloudReader, CsvWithNamedHeaderColumnsInAnyOrderAndInches) {
  const std::vector<Vec3> p = known_points(20);
  std::string text = "Point,Z,\"X\",Y,deviation\n";
  for (size_t i = 0; i < p.size(); ++i)
    text += "P" + std::to_string(i) + ", " + g17(p[i].z()) + "," + g17(p[i].x()) + "," + g17(p[i].y()) + ",0.01\n";
  test::TempDir dir;
  PointCloudReadOptions o;
  o.mm_per_unit = 25.4;
  const PointCloud c = read_point_cloud(dir.write("cmm.csv", text), o);
  EXPECT_EQ(c.format, PointCloudFormat::kCsv);
  ASSERT_EQ(c.points.size(), p.size());
  EXPECT_TRUE(c.normals.empty());
  for (size_t i = 0; i < p.size(); ++i) EXPECT_EQ(c.points[i], p[i] * 25.4) << i;
}

TEST(PointCloudReader, CsvHeaderThatNamesNothingIsSkippedAndColumnsArePositional) {
  const PointCloud c = parse_point_cloud("a,b,c\n1,2,3\n4,5,6\n", "pts.csv");
  ASSERT_EQ(c.points.size(), 2u);
  EXPECT_EQ(c.points[1], Vec3(4, 5, 6));
  // ... and in an XYZ file a header is an error at its line.
  EXPECT_EQ(cloud_error_of("x y z\n1 2 3\n", "pts.xyz"), "pts.xyz:1: expected a number in column 1 (x), got 'x'");
}

TEST(PointCloudReader, TextErrorsNameFileAndLine) {
  EXPECT_EQ(cloud_error_of("1 2 3\n4 5\n", "s.xyz"), "s.xyz:2: expected 3 fields as at line 1, got 2");
  EXPECT_EQ(cloud_error_of("1 2\n", "s.xyz"), "s.xyz:1: expected 3 fields (x y z) or 6 (x y z nx ny nz), got 2");
  EXPECT_EQ(cloud_error_of("# c\n1 2 nan\n", "s.xyz"), "s.xyz:2: expected a finite number in column 3 (z), got 'nan'");
  EXPECT_EQ(cloud_error_of("1,,3\n", "s.csv"), "s.csv:1: expected a number in column 2 (y), got ''");
  EXPECT_EQ(cloud_error_of("1 2 3 0 0 1e999\n", "s.xyz"), "s.xyz:1: expected a number in column 6 (nz), got '1e999'");
  EXPECT_EQ(cloud_error_of("# only a comment\n\n", "s.xyz"), "s.xyz:2: expected at least one point, the file has none");
  EXPECT_EQ(cloud_error_of("x,y\n1,2\n", "s.csv"), "s.csv:1: expected the header to name columns x, y and z, 'z' is missing");
  EXPECT_EQ(cloud_error_of("x,y,z,nx\n1,2,3,4\n", "s.csv"), "s.csv:1: expected the header to name all of nx, ny, nz or none");
  EXPECT_EQ(cloud_error_of("z,x,y\n1,2\n", "s.csv"), "s.csv:2: expected at least 3 fields (the header's columns), got 2");
}

// ---- PLY ----------------------------------------------------------------------

TEST(PointCloudReader, AsciiPlyWithNormalsOtherPropertiesAndFacesFirst) {
  const std::vector<Vec3> p = known_points(10), n = unit_normals(10);
  std::string text =
      "ply\nformat ascii 1.0\ncomment from a scanner\nelement face 2\nproperty list uchar int vertex_indices\n"
      "element vertex 10\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\n"
      "property float nx\nproperty float ny\nproperty float nz\nend_header\n3 0 1 2\n4 0 1 2 3\n";
  const std::vector<Vec3> nf = as_floats(n);
  for (size_t i = 0; i < p.size(); ++i)
    text += g17(p[i].x()) + " " + g17(p[i].y()) + " " + g17(p[i].z()) + " 200 " + g17(nf[i].x()) + " " +
            g17(nf[i].y()) + " " + g17(nf[i].z()) + "\n";
  test::TempDir dir;
  const PointCloud c = read_point_cloud(dir.write("scan.ply", text));
  EXPECT_EQ(c.format, PointCloudFormat::kPly);
  ASSERT_EQ(c.points.size(), p.size());
  ASSERT_EQ(c.normals.size(), p.size());
  for (size_t i = 0; i < p.size(); ++i) {
    EXPECT_EQ(c.points[i], p[i]);
    EXPECT_EQ(c.normals[i], nf[i]);
  }
}

// A binary PLY of `p` (x y z as `T`, an extra uchar, optional float normals)
// followed by a face element.
template <typename T>
std::string binary_ply(const std::vector<Vec3>& p, const std::vector<Vec3>& n, bool big) {
  const char* type = sizeof(T) == 8 ? "double" : "float";
  std::string s = std::string("ply\r\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\r\nelement vertex " + std::to_string(p.size()) + "\r\nproperty " + type + " x\r\nproperty " +
                  type + " y\r\nproperty " + type + " z\r\nproperty uchar quality\r\n";
  if (!n.empty()) s += "property float nx\r\nproperty float ny\r\nproperty float nz\r\n";
  s += "element face 1\r\nproperty list uchar uint vertex_indices\r\nend_header\r\n";
  for (size_t i = 0; i < p.size(); ++i) {
    for (int a = 0; a < 3; ++a) put<T>(&s, static_cast<T>(p[i][a]), big);
    put<uint8_t>(&s, 7, big);
    if (!n.empty())
      for (int a = 0; a < 3; ++a) put<float>(&s, static_cast<float>(n[i][a]), big);
  }
  put<uint8_t>(&s, 3);
  for (uint32_t k = 0; k < 3; ++k) put<uint32_t>(&s, k, big);
  return s;
}

TEST(PointCloudReader, BinaryPlyBothEndiannessesFloatAndDouble) {
  const std::vector<Vec3> p = known_points(40), n = unit_normals(40);
  test::TempDir dir;
  for (bool big : {false, true}) {
    const PointCloud d = read_point_cloud(dir.write("d.ply", binary_ply<double>(p, n, big)));
    ASSERT_EQ(d.points.size(), p.size());
    ASSERT_EQ(d.normals.size(), p.size());
    for (size_t i = 0; i < p.size(); ++i) {
      EXPECT_EQ(d.points[i], p[i]) << big << " " << i;
      EXPECT_EQ(d.normals[i], as_floats(n)[i]) << big << " " << i;
    }
    PointCloudReadOptions in;
    in.mm_per_unit = 25.4;
    const PointCloud f = read_point_cloud(dir.write("f.ply", binary_ply<float>(p, {}, big)), in);
    ASSERT_EQ(f.points.size(), p.size());
    EXPECT_TRUE(f.normals.empty());
    for (size_t i = 0; i < p.size(); ++i) EXPECT_EQ(f.points[i], as_floats(p)[i] * 25.4) << big << " " << i;
  }
}

TEST(PointCloudReader, PlyErrorsNameHeaderLineOrByteOffset) {
  const std::vector<Vec3> p = known_points(3);
  const std::string good = binary_ply<float>(p, {}, false);
  const size_t body = good.find("end_header\r\n") + 12;  // 12 bytes of x y z + 1 of quality per vertex
  // Truncated inside the vertices: the element does not fit, said where it starts.
  EXPECT_EQ(cloud_error_of(good.substr(0, body + 20), "t.ply"),
            "t.ply: byte " + std::to_string(body) + ": truncated: element 'vertex' has 3 × 13 bytes, 20 remain (header line 3)");
  // Cut inside the faces after the vertices: the faces are not read, the points are whole.
  EXPECT_EQ(parse_point_cloud(good.substr(0, good.size() - 2), "t.ply").points.size(), 3u);
  // A list before the vertices is walked, and a cut in it found.
  const std::string faces_first =
      "ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
      "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n\x03";
  EXPECT_EQ(cloud_error_of(faces_first + std::string(8, '\0'), "t.ply"),
            "t.ply: byte " + std::to_string(faces_first.size()) +
                ": truncated: expected property 'vertex_indices' of face 0, 8 bytes remain");
  // NaN at vertex 1's y.
  std::string nan = good;
  const float q = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&nan[body + 13 + 4], &q, 4);
  EXPECT_EQ(cloud_error_of(nan, "t.ply"),
            "t.ply: byte " + std::to_string(body + 17) + ": expected a finite y of vertex 1, got nan");
  // Header errors at their line.
  EXPECT_EQ(cloud_error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty int x\nproperty float y\nproperty float z\nend_header\n1 2 3\n", "t.ply"),
            "t.ply:3: expected vertex property 'x' of type float or double");
  EXPECT_EQ(cloud_error_of("ply\nformat ascii 1.0\nelement vertex -2\n", "t.ply"),
            "t.ply:3: expected a count of 0 or more for element 'vertex', got '-2'");
  EXPECT_EQ(cloud_error_of("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n", "t.ply"),
            "t.ply:3: expected at least one vertex, the element has 0");
  EXPECT_EQ(cloud_error_of("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n", "t.ply"),
            "t.ply:4: unexpected end of file; expected 'end_header'");
  EXPECT_EQ(cloud_error_of("ply\nformat binary 1.0\n", "t.ply"),
            "t.ply:2: expected format ascii, binary_little_endian or binary_big_endian, got 'binary'");
  EXPECT_EQ(cloud_error_of("plx\n", "t.ply"), "t.ply:1: expected 'ply' on the first line of a PLY file");
  // ASCII body errors at the body's line.
  const std::string ascii = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  EXPECT_EQ(cloud_error_of(ascii + "1 2 3\n4 5 inf\n", "t.ply"), "t.ply:9: expected a finite number in column 3 (z), got 'inf'");
  EXPECT_EQ(cloud_error_of(ascii + "1 2 3\n4 5\n", "t.ply"), "t.ply:9: expected a value for property 'z', the line has 2 fields");
  EXPECT_EQ(cloud_error_of(ascii + "1 2 3\n", "t.ply"), "t.ply:9: unexpected end of file; element 'vertex' has 2 lines, 1 remain");
}

// ---- STL ----------------------------------------------------------------------

// Two triangles of a unit square sharing an edge: 4 distinct vertices of 6.
const float kSquare[2][3][3] = {{{0, 0, 0}, {10.5f, 0, 0}, {10.5f, 10.25f, 0}},
                                {{0, 0, 0}, {10.5f, 10.25f, 0}, {0, 10.25f, -0.0f}}};

std::string binary_stl(const char* header) {
  std::string s(80, '\0');
  std::memcpy(&s[0], header, std::strlen(header));
  put<uint32_t>(&s, 2);
  for (const auto& t : kSquare) {
    for (int a = 0; a < 3; ++a) put<float>(&s, a == 2 ? 1.0f : 0.0f);
    for (const auto& v : t)
      for (float c : v) put<float>(&s, c);
    put<uint16_t>(&s, 0);
  }
  return s;
}

void expect_square(const PointCloud& c, double scale = 1.0) {
  EXPECT_EQ(c.format, PointCloudFormat::kStl);
  ASSERT_EQ(c.points.size(), 4u);  // shared vertices (and -0 == 0) once
  EXPECT_EQ(c.points[0], Vec3(0, 0, 0));
  EXPECT_EQ(c.points[1], Vec3(10.5, 0, 0) * scale);
  EXPECT_EQ(c.points[2], Vec3(10.5, 10.25, 0) * scale);
  EXPECT_EQ(c.points[3], Vec3(0, 10.25, 0) * scale);
  EXPECT_TRUE(c.normals.empty());
}

TEST(PointCloudReader, BinaryStlGivesDistinctVerticesEvenWithASolidHeader) {
  test::TempDir dir;
  expect_square(read_point_cloud(dir.write("part.stl", binary_stl("binary export"))));
  expect_square(read_point_cloud(dir.write("part2.stl", binary_stl("solid written by a careless exporter"))));
  // Without an extension: found by the size.
  expect_square(parse_point_cloud(binary_stl("x"), "scan"));
}

TEST(PointCloudReader, AsciiStlGivesDistinctVerticesInInches) {
  std::string text = "solid square\n";
  for (const auto& t : kSquare) {
    text += "  facet normal 0 0 1\n    outer loop\n";
    for (const auto& v : t) text += "      vertex " + g17(v[0]) + " " + g17(v[1]) + " " + g17(v[2]) + "\n";
    text += "    endloop\n  endfacet\n";
  }
  text += "endsolid square\n";
  test::TempDir dir;
  PointCloudReadOptions o;
  o.mm_per_unit = 25.4;
  expect_square(read_point_cloud(dir.write("part.stl", text), o), 25.4);
  EXPECT_EQ(cloud_error_of("solid a\nfacet normal 0 0 1\nouter loop\nvertex 1 2 3\nvertex 1 2\n", "a.stl"),
            "a.stl:5: expected 'vertex x y z', got 2 numbers");
  EXPECT_EQ(cloud_error_of("solid a\nfacet normal 0 0 1\nouter loop\nvertex 1 2 3\nendloop\n", "a.stl"),
            "a.stl:5: expected 3 vertices in the loop of line 3, got 1");
  EXPECT_EQ(cloud_error_of("solid a\nfacet normal 0 0 1\nouter loop\nvertex 1 nan 3\n", "a.stl"),
            "a.stl:4: expected a finite number in column 3 (y), got 'nan'");
  EXPECT_EQ(cloud_error_of("solid a\nendsolid a\n", "a.stl"), "a.stl:2: expected at least one vertex, the file has none");
}

TEST(PointCloudReader, BinaryStlErrorsNameTheByteOffset) {
  const std::string good = binary_stl("b");
  EXPECT_EQ(cloud_error_of(good.substr(0, 60), "b.stl"),
            "b.stl: byte 60: truncated: a binary STL has an 84-byte header, the file has 60 bytes");
  EXPECT_EQ(cloud_error_of(good.substr(0, good.size() - 1), "b.stl"),
            "b.stl: byte 80: the count says 2 triangles (184 bytes), the file has 183 bytes (truncated)");
  EXPECT_EQ(cloud_error_of(good + "x", "b.stl"), "b.stl: byte 80: the count says 2 triangles (184 bytes), the file has 185 bytes");
  std::string zero = good.substr(0, 84);
  zero[80] = 0;
  EXPECT_EQ(cloud_error_of(zero, "b.stl"), "b.stl: byte 80: expected at least one triangle, the count is 0");
  std::string nan = good;
  const float inf = std::numeric_limits<float>::infinity();
  std::memcpy(&nan[84 + 50 + 12 + 12 * 2 + 8], &inf, 4);  // triangle 1, vertex 3, z
  EXPECT_EQ(cloud_error_of(nan, "b.stl"), "b.stl: byte 178: expected a finite z of triangle 1 vertex 3");
  try {
    parse_point_cloud(nan, "b.stl");
    FAIL();
  } catch (const BinaryDataError& e) {
    EXPECT_EQ(e.offset(), 178);
    EXPECT_EQ(e.file(), "b.stl");
  }
}

TEST(PointCloudReader, FormatFromContentWithoutExtensionAndForced) {
  EXPECT_EQ(parse_point_cloud("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                              "property float z\nend_header\n1 2 3\n", "scan").format,
            PointCloudFormat::kPly);
  EXPECT_EQ(parse_point_cloud("1,2,3\n", "scan").format, PointCloudFormat::kCsv);
  EXPECT_EQ(parse_point_cloud("1 2 3\n", "scan").format, PointCloudFormat::kXyz);
  PointCloudReadOptions o;
  o.format = PointCloudFormat::kCsv;
  EXPECT_EQ(parse_point_cloud("x,y,z\n1,2,3\n", "scan.txt", o).points.at(0), Vec3(1, 2, 3));
  EXPECT_EQ(cloud_error_of("", "none.xyz"), "none.xyz:0: expected at least one point, the file has none");
  test::TempDir dir;
  EXPECT_THROW(read_point_cloud(dir.path() + "/missing.ply"), DataError);
}

}  // namespace
}  // namespace bliskrun
