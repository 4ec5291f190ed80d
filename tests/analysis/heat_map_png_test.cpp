#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
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
  m.values[1 * 5 + 2] = std::numeric_limits<double>::infinity();   // never reached
  m.values[2 * 5 + 0] = std::numeric_limits<double>::quiet_NaN();  // not part of this map
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
  EXPECT_EQ(im.height, 40 + 200 + 70);
  // Closed form of the two-level scale: level centres at s = -+0.5 of the way
  // from white (255) to the end colours blue (33, 102, 172) and red (178, 24, 43).
  const Rgb blue{144, 179, 214}, red{217, 140, 149}, grey{187, 187, 187};
  EXPECT_EQ(cell_pixel(im, L, o, m, 0, 0), blue);
  EXPECT_EQ(cell_pixel(im, L, o, m, 3, 4), red);
  EXPECT_EQ(cell_pixel(im, L, o, m, 0, 1), red);  // 0.5 >= 0: upper level
  EXPECT_EQ(cell_pixel(im, L, o, m, 1, 2), grey);
  EXPECT_EQ(heat_map_colour(std::numeric_limits<double>::quiet_NaN(), 2, 2), (Rgb{255, 255, 255}));
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

// Every pixel of cell (i, j)'s block (its centre third, clear of rounding
// at the block's edges): how many are each colour.
std::map<Rgb, int> cell_colours(const RgbImage& im, const HeatMapRasterLayout& L, const HeatMapOptions& o,
                                const HeatMap& m, int i, int j) {
  const int w = o.plot_width_px / m.cols, h = o.plot_height_px / m.rows;
  const int x0 = L.plot_x + j * w, y0 = L.plot_y + o.plot_height_px - (i + 1) * h;
  std::map<Rgb, int> n;
  for (int y = y0 + h / 3; y < y0 + 2 * h / 3; ++y)
    for (int x = x0 + w / 3; x < x0 + 2 * w / 3; ++x) ++n[im.at(x, y)];
  return n;
}

// "Never reached" (+inf) is plain grey; "not part of this map" (NaN) is
// white hatched with grey diagonals: no pixel of the one is grey 187, and
// each kind has its legend swatch drawn the same way.
TEST(HeatMapPng, NotPartOfTheMapIsHatchedAndNeverReachedIsGreyEachWithALegendEntry) {
  const HeatMap m = small_map();
  HeatMapOptions o;
  o.plot_width_px = 500;
  o.plot_height_px = 200;
  const RgbImage im = decode_png(encode_png(heat_map_raster(m, o)));
  const HeatMapRasterLayout L = heat_map_raster_layout(o);
  const Rgb grey{187, 187, 187}, white{255, 255, 255}, hatch{150, 150, 150};
  const std::map<Rgb, int> never = cell_colours(im, L, o, m, 1, 2), outside = cell_colours(im, L, o, m, 2, 0);
  ASSERT_EQ(never.size(), 1u);
  EXPECT_EQ(never.begin()->first, grey);
  EXPECT_EQ(outside.count(grey), 0u);
  ASSERT_EQ(outside.size(), 2u);
  // One diagonal every 6 pixels: a sixth of the pixels of any block.
  const int all = outside.at(white) + outside.at(hatch);
  EXPECT_NEAR(static_cast<double>(outside.at(hatch)) / all, 1.0 / 6, 0.02);
  // Legend: the grey swatch first, then the hatched one, on the legend line.
  std::map<Rgb, int> legend;
  for (int y = L.legend_y; y < L.legend_y + 10; ++y)
    for (int x = L.plot_x; x < L.plot_x + 400; ++x) ++legend[im.at(x, y)];
  EXPECT_GE(legend[grey], 14 * 10);
  EXPECT_GT(legend[hatch], 14 * 10 / 6 - 3);
  // A map with neither has no legend: the line stays white.
  HeatMap full = m;
  for (double& x : full.values)
    if (!std::isfinite(x)) x = 0;
  const RgbImage plain = heat_map_raster(full, o);
  for (int y = L.legend_y; y < L.legend_y + 10; ++y)
    for (int x = 0; x < plain.width; ++x) ASSERT_EQ(plain.at(x, y), white) << x << " " << y;
  // The SVG the same: the hatch pattern for NaN, grey for +inf, both in its legend.
  const std::string svg = heat_map_svg(m, o);
  EXPECT_NE(svg.find("fill=\"url(#not-in-map)\""), std::string::npos);
  EXPECT_NE(svg.find("fill=\"#bbbbbb\""), std::string::npos);
  EXPECT_NE(svg.find(">never reached</text>"), std::string::npos);
  EXPECT_NE(svg.find(">not part of this map</text>"), std::string::npos);
  EXPECT_EQ(heat_map_svg(full, o).find(">never reached</text>"), std::string::npos);
}

// The colour bar reads the scale given, not the data's: two maps with
// different data under one scale_max have the same bar, and its labels are
// the scale at 3 significant digits (no exponent).
TEST(HeatMapPng, AFixedScaleGivesTheSameColourBarWhateverTheData) {
  HeatMap a = small_map(), b = small_map();
  for (double& x : b.values)
    if (std::isfinite(x)) x *= 0.01;  // a hundredth of a's values
  HeatMapOptions o;
  o.plot_width_px = 300;
  o.plot_height_px = 100;
  o.scale_max = 14;
  const RgbImage ia = heat_map_raster(a, o), ib = heat_map_raster(b, o);
  const HeatMapRasterLayout L = heat_map_raster_layout(o);
  for (int y = L.plot_y - 14; y < L.plot_y + o.plot_height_px + 4; ++y)
    for (int x = L.bar_x - 1; x < L.width; ++x) ASSERT_EQ(ia.at(x, y), ib.at(x, y)) << x << " " << y;
  // The same value is the same colour on both: b's 0.5 * 0.01 near white, a's 0.5 not.
  EXPECT_EQ(heat_map_colour(0.5, 14, o.levels), cell_pixel(ia, L, o, a, 0, 1));
  const std::string svg = heat_map_svg(b, o);
  for (const char* label : {">-14.0</text>", ">-7.00</text>", ">0</text>", ">7.00</text>", ">14.0</text>"})
    EXPECT_NE(svg.find(label), std::string::npos) << label;
  EXPECT_EQ(svg.find("e-0"), std::string::npos);
  EXPECT_EQ(svg.find("e+0"), std::string::npos);
}

// Labels over the plot (a mosaic's tiles) and the ticks switched off.
TEST(HeatMapPng, LabelsAreDrawnOnWhiteBoxesAndTicksCanBeOff) {
  const HeatMap m = small_map();
  HeatMapOptions o;
  o.plot_width_px = 500;
  o.plot_height_px = 200;
  o.labels = {HeatMapLabel{0.0, 1.0, "pressure flank"}, HeatMapLabel{0.6, 0.5, "trailing edge"}};
  o.fraction_ticks = false;
  const std::string svg = heat_map_svg(m, o);
  EXPECT_NE(svg.find("class=\"tile-label\" x=\"85.0\" y=\"54.0\">pressure flank</text>"), std::string::npos) << svg;
  EXPECT_NE(svg.find(">trailing edge</text>"), std::string::npos);
  EXPECT_EQ(svg.find(">0.25</text>"), std::string::npos);
  o.fraction_ticks = true;
  EXPECT_NE(heat_map_svg(m, o).find(">0.25</text>"), std::string::npos);
  // Raster: the label's box is white with black ink inside, over the top-left cell (red there).
  o.fraction_ticks = false;
  const RgbImage im = heat_map_raster(m, o);
  const HeatMapRasterLayout L = heat_map_raster_layout(o);
  int ink = 0;
  for (int y = L.plot_y + 3; y < L.plot_y + 10; ++y)
    for (int x = L.plot_x + 3; x < L.plot_x + 3 + text_width("pressure flank"); ++x) ink += im.at(x, y) == Rgb{0, 0, 0};
  EXPECT_GT(ink, 100);
  EXPECT_EQ(im.at(L.plot_x + 2, L.plot_y + 2), (Rgb{255, 255, 255}));
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
  // µ (UTF-8 C2 B5) is one glyph of its own, not two '?'.
  EXPECT_EQ(text_width("\xC2\xB5m"), 11);
  RgbImage mu(20, 10, {255, 255, 255}), qq(20, 10, {255, 255, 255});
  mu.text(0, 0, "\xC2\xB5", {0, 0, 0});
  qq.text(0, 0, "??", {0, 0, 0});
  EXPECT_NE(mu.pixels, q.pixels);
  EXPECT_NE(mu.pixels, qq.pixels);
  EXPECT_EQ(mu.at(0, 6), (Rgb{0, 0, 0}));  // the descender on the left
  // "µm": the m after µ is lower case (no ink in its top two rows), "M" elsewhere.
  RgbImage um(20, 10, {255, 255, 255});
  um.text(0, 0, "\xC2\xB5m", {0, 0, 0});
  int top_ink = 0;
  for (int y = 0; y < 2; ++y)
    for (int x = 6; x < 11; ++x) top_ink += um.at(x, y) == Rgb{0, 0, 0};
  EXPECT_EQ(top_ink, 0);
  RgbImage lone(20, 10, {255, 255, 255}), capital(20, 10, {255, 255, 255});
  lone.text(0, 0, "m", {0, 0, 0});
  capital.text(0, 0, "M", {0, 0, 0});
  EXPECT_EQ(lone.pixels, capital.pixels);
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
