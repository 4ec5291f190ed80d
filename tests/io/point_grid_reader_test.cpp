#include "core/io/point_grid_reader.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <random>
#include <string>

#include "core/common/error.h"

namespace bliskrun {
namespace {

// Runs the parser and returns the DataError's message ("" if none).
std::string grid_error_of(const std::string& text, const PointGridReadOptions& o = {}) {
  try {
    parse_point_grid(text, "blade.txt", o);
  } catch (const DataError& e) {
    return e.what();
  }
  return "";
}

TEST(PointGridReader, ReadsRowMajorWithHeaderCommentsAndCommas) {
  const std::string text =
      "# exported from CAD\n"
      "# grid 2 3\n"
      "0 0 0\n1,0,0   # trailing comment\n"
      "\n"
      "2 0 0\n0 1 0\n1 1 0.5\n2 1 1e-3\n";
  const PointGrid g = parse_point_grid(text, "blade.txt");
  ASSERT_EQ(g.rows, 2);
  ASSERT_EQ(g.cols, 3);
  EXPECT_EQ(g.at(0, 1), Vec3(1, 0, 0));
  EXPECT_EQ(g.at(1, 1), Vec3(1, 1, 0.5));
  EXPECT_EQ(g.at(1, 2), Vec3(2, 1, 1e-3));
}

TEST(PointGridReader, ColumnMajorFromHeaderOrOptions) {
  // Column order: all of column 0 (along u) first.
  const std::string body = "0 0 0\n0 1 0\n1 0 0\n1 1 0\n2 0 0\n2 1 0\n";
  const PointGrid a = parse_point_grid("# grid 2 3 order=column\n" + body, "f");
  PointGridReadOptions o;
  o.rows = 2;
  o.cols = 3;
  o.order = GridOrder::kColumnMajor;
  const PointGrid b = parse_point_grid(body, "f", o);
  for (const PointGrid* g : {&a, &b}) {
    EXPECT_EQ(g->at(0, 2), Vec3(2, 0, 0));
    EXPECT_EQ(g->at(1, 0), Vec3(0, 1, 0));
  }
}

TEST(PointGridReader, ErrorsNameFileLineAndExpectation) {
  const std::string h = "# grid 2 2\n";
  EXPECT_EQ(grid_error_of(h + "0 0 0\n1 0 abc\n0 1 0\n1 1 0\n"),
            "blade.txt:3: expected a number in column 3 (z), got 'abc'");
  EXPECT_EQ(grid_error_of(h + "0 0 0\n1 0\n"), "blade.txt:3: expected 3 fields (x y z), got 2");
  EXPECT_EQ(grid_error_of(h + "0,0,0,0\n"), "blade.txt:2: expected 3 fields (x y z), got 4");
  EXPECT_EQ(grid_error_of(h + "0 nan 0\n"),
            "blade.txt:2: expected a finite number in column 2 (y), got 'nan'");
  EXPECT_EQ(grid_error_of(h + "inf 0 0\n"),
            "blade.txt:2: expected a finite number in column 1 (x), got 'inf'");
  EXPECT_EQ(grid_error_of(h + "0 0 0\n1 0 0\n0 1 0\n"),
            "blade.txt:4: expected 2 x 2 = 4 points, got 3");
  EXPECT_EQ(grid_error_of(h + "0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 2 2\n"),
            "blade.txt:6: expected 2 x 2 = 4 points, got 5");
  EXPECT_EQ(grid_error_of("0 0 0\n"),
            "blade.txt:0: expected a '# grid ROWS COLS [order=row|column]' header or rows and "
            "cols options");
  EXPECT_EQ(grid_error_of("# grid 1 4\n0 0 0\n1 0 0\n2 0 0\n3 0 0\n"),
            "blade.txt:1: expected at least 2 rows and 2 columns, got 1 x 4");
  EXPECT_EQ(grid_error_of("# grid two 4\n"),
            "blade.txt:1: expected '# grid ROWS COLS [order=row|column]' with integer ROWS and "
            "COLS");
  EXPECT_EQ(grid_error_of("# grid 2 2 order=diagonal\n"),
            "blade.txt:1: expected '# grid ROWS COLS [order=row|column]', got 'order=diagonal'");
  PointGridReadOptions o;
  o.rows = 3;
  EXPECT_EQ(grid_error_of(h + "0 0 0\n", o), "blade.txt:1: header says 2 rows, options say 3");
}

TEST(PointGridReader, DegenerateGridNamesBothLines) {
  // Repeat along a row: point (0,1) on line 3 repeats line 2.
  EXPECT_EQ(grid_error_of("# grid 2 2\n0 0 0\n0 0 0\n0 1 0\n1 1 0\n"),
            "blade.txt:3: expected distinct consecutive points along row 0, point (0, 1) repeats "
            "line 2");
  // Repeat along a column, column-major: u-neighbours are consecutive lines.
  EXPECT_EQ(grid_error_of("# grid 2 2 order=column\n0 0 0\n0 0 0\n1 0 0\n2 1 0\n"),
            "blade.txt:3: expected distinct consecutive points along column 0, point (1, 0) "
            "repeats line 2");
  EXPECT_EQ(grid_error_of("# grid 2 2\n0 0 0\n1 0 0\n0 0 0\n1 1 0\n"),
            "blade.txt:4: expected distinct consecutive points along column 0, point (1, 0) "
            "repeats line 2");
  // A row collapsed to one point (zero-length row).
  EXPECT_NE(grid_error_of("# grid 2 3\n0 0 0\n0 0 0\n0 0 0\n0 1 0\n1 1 0\n2 1 0\n")
                .find("along row 0"),
            std::string::npos);
}

TEST(PointGridReader, UnreadableFile) {
  try {
    read_point_grid("/nonexistent/dir/grid.txt");
    FAIL();
  } catch (const DataError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/dir/grid.txt");
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
  }
}

TEST(PointGridReader, WriterRoundTripIsExact) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-150, 150);
  PointGrid g(7, 11);
  for (Vec3& p : g.points) p = Vec3(d(rng), d(rng), d(rng) * 1e-7);
  const std::string path =
      (std::filesystem::temp_directory_path() / "bliskrun_grid_roundtrip.txt").string();
  write_point_grid(g, path);
  const PointGrid back = read_point_grid(path);
  std::remove(path.c_str());
  ASSERT_EQ(back.rows, 7);
  ASSERT_EQ(back.cols, 11);
  for (size_t k = 0; k < g.points.size(); ++k) EXPECT_EQ(back.points[k], g.points[k]) << k;
}

}  // namespace
}  // namespace bliskrun
