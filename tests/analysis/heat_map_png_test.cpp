#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/analysis/heat_map.h"
#include "core/common/error.h"
#include "core/common/raster.h"
#include "test_support.h"

namespace bliskrun {
namespace {

// 4 rows (u) x 5 columns (v); the scale is +-2 (largest |value|).
HeatMap small_map() {
  HeatMap m;
  m.rows = 4;
  m.cols = 5;
  m.values.assign(20, 0.5);
  m.values[0] = -2;                                        // (0, 0): hub, v = 0
  m.values[3 * 5 + 4] = 2;                                 // (3, 4): tip, v = 1
  m.values[1 * 5 + 2] = std::numeric_limits<double>::quiet_NaN();  // never reached
  return m;
}

// Centre pixel of cell (i, j): u = 0 is the bottom row of the plot.
Rgb cell_pixel(const RgbImage& im, const HeatMapRasterLayout& L, const HeatMapOptions& o, const HeatMap& m,
               int i, int j) {
  const int x = L.plot_x + static_cast<int>((j + 0.5) * o.plot_width_px / m.cols);
  const int y = L.plot_y + o.plot_height_px - 1 - static_cast<int>((i + 0.5) * o.plot_height_px / m.rows);
  return im.at(x, y);
}

TEST(HeatMapPng, DecodesToTheLayoutSizeWithTheScaleColoursAtKnownCells) {
  const HeatMap m = small_map();
  HeatMapOptions o;
  o.title = "Test map";
  o.value_label = "mm";
  o.plot_width_px = 500;
  o.plot_height_px = 200;
  o.levels = 2;  // two colours: half way to each end of the scale
  const RgbImage im = decode_png(encode_png(heat_map_raster(m, o)));
  const HeatMapRasterLayout L = heat_map_raster_layout(o);
  ASSERT_EQ(im.width, L.width);
  ASSERT_EQ(im.height, L.height);
  EXPECT_EQ(im.height, 40 + 200 + 62);
  // Closed form of the two-level scale: level centres at s = -+0.5 of the way
  // from white (255) to the end colours blue (33, 102, 172) and red (178, 24, 43).
  const Rgb blue{144, 179, 214}, red{217, 140, 149}, grey{187, 187, 187};
  EXPECT_EQ(cell_pixel(im, L, o, m, 0, 0), blue);
  EXPECT_EQ(cell_pixel(im, L, o, m, 3, 4), red);
  EXPECT_EQ(cell_pixel(im, L, o, m, 0, 1), red);  // 0.5 >= 0: upper level
  EXPECT_EQ(cell_pixel(im, L, o, m, 1, 2), grey);
  EXPECT_EQ(heat_map_colour(-2, 2, 2), blue);
  EXPECT_EQ(heat_map_colour(std::numeric_limits<double>::infinity(), 2, 2), grey);
  // Colour bar: -m at the bottom, +m at the top.
  EXPECT_EQ(im.at(L.bar_x + 5, L.plot_y + 200 - 3), blue);
  EXPECT_EQ(im.at(L.bar_x + 5, L.plot_y + 2), red);
  // Labels are drawn: black pixels in the title band and under the plot.
  int title_ink = 0, axis_ink = 0;
  for (int y = 0; y < L.plot_y - 14; ++y)
    for (int x = L.plot_x; x < L.plot_x + 200; ++x) title_ink += im.at(x, y) == Rgb{0, 0, 0};
  for (int y = L.plot_y + 200 + 6; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) axis_ink += im.at(x, y) == Rgb{0, 0, 0};
  EXPECT_GT(title_ink, 50);
  EXPECT_GT(axis_ink, 100);
}

TEST(HeatMapPng, FontDrawsTheGlyphItKnowsAndQuestionMarkOtherwise) {
  RgbImage a(20, 10, {255, 255, 255}), b(20, 10, {255, 255, 255}), c(20, 10, {255, 255, 255});
  a.text(0, 0, "e", {0, 0, 0});
  b.text(0, 0, "E", {0, 0, 0});
  c.text(0, 0, "\x01", {0, 0, 0});
  EXPECT_EQ(a.pixels, b.pixels);  // lower case drawn as capitals
  // 'E': full top and bottom rows, left column, middle bar: 18 inked pixels in all.
  int ink = 0;
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 5; ++x) ink += b.at(x, y) == Rgb{0, 0, 0};
  EXPECT_EQ(ink, 18);
  RgbImage q(20, 10, {255, 255, 255});
  q.text(0, 0, "?", {0, 0, 0});
  EXPECT_EQ(c.pixels, q.pixels);
  EXPECT_EQ(text_width("abc"), 17);
}

TEST(HeatMapPng, NoisyFlankSizedMapStaysWellUnderAMegabyte) {
  // The undercut map of one flank: 200 x 1000 samples, noisy along the chord.
  HeatMap m;
  m.rows = 200;
  m.cols = 1000;
  m.values.resize(200000);
  unsigned state = 12345;
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) {
      state = state * 1664525u + 1013904223u;
      const double noise = (static_cast<double>(state >> 8) / (1u << 24) - 0.5) * 0.004;
      m.values[static_cast<size_t>(i) * m.cols + j] = 0.01 * std::sin(j * 0.3) * std::cos(i * 0.05) + noise;
    }
  HeatMapOptions o;
  o.title = "Undercut (mm)";
  const std::string png = encode_png(heat_map_raster(m, o));
  const std::string svg = heat_map_svg(m, o);
  RecordProperty("png_bytes", static_cast<int>(png.size()));
  RecordProperty("svg_bytes", static_cast<int>(svg.size()));
  // Pure per-cell noise is the worst case for compression (~310 kB at 800 x 320).
  EXPECT_LT(png.size(), 512u * 1024u);
  EXPECT_LT(png.size() * 5, svg.size());
  const RgbImage im = decode_png(png);
  EXPECT_EQ(im.width, heat_map_raster_layout(o).width);
}

TEST(HeatMapPng, WritesAtomicallyAndRejectsBadInput) {
  test::TempDir dir;
  const std::string path = dir.path() + "/map.png";
  HeatMapOptions o;
  write_heat_map_png(small_map(), path, o);
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  EXPECT_EQ(decode_png(bytes.str()).height, heat_map_raster_layout(o).height);
  EXPECT_THROW(decode_png("not a png at all", "x.png"), DataError);
  HeatMap bad = small_map();
  bad.values.pop_back();
  EXPECT_THROW(heat_map_raster(bad, o), ParameterError);
  o.plot_width_px = 10;
  EXPECT_THROW(heat_map_raster(small_map(), o), ParameterError);
}

}  // namespace
}  // namespace bliskrun
