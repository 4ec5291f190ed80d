#pragma once
// An RGB raster picture, drawn with filled rectangles and a small built-in
// 5 x 7 bitmap font, and its PNG encoding through libpng (Debian libpng-dev).
// The font is ours (drawn in raster.cpp); it covers digits, letters (lower
// case is drawn as upper case), space and the punctuation labels use
// (. , : ; - + = % / ( ) [ ] ^ ' _ < > * # ?) and the micro sign µ (UTF-8);
// anything else draws as '?'.
// Big enough for axis labels and titles, not a typesetting engine.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace bliskrun {

using Rgb = std::array<std::uint8_t, 3>;

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // row-major, top row first, 3 bytes per pixel

  RgbImage() = default;
  RgbImage(int w, int h, Rgb fill);
  Rgb at(int x, int y) const;
  void set(int x, int y, Rgb c);  // ignores pixels outside the picture
  // Fills [x0, x1) x [y0, y1), clipped to the picture.
  void fill(int x0, int y0, int x1, int y1, Rgb c);
  // One-pixel outline of [x0, x1) x [y0, y1).
  void frame(int x0, int y0, int x1, int y1, Rgb c);
  // Text with its top-left corner at (x, y), each font pixel `scale` x `scale`.
  // vertical: reads bottom to top (rotated 90 degrees anticlockwise), (x, y)
  // is then the bottom-left corner.
  void text(int x, int y, const std::string& s, Rgb c, int scale = 1, bool vertical = false);
};

// Width in pixels of `s` drawn at `scale` (6 columns a character, the last
// one blank); height is 7 * scale.
int text_width(const std::string& s, int scale = 1);

// PNG bytes (8-bit RGB, default zlib compression). Throws ParameterError for
// an empty or mis-sized image.
std::string encode_png(const RgbImage& image);
// Decodes any PNG libpng reads to 8-bit RGB (for tests and read-backs).
// Throws DataError naming `what` when the bytes are not a PNG.
RgbImage decode_png(const std::string& bytes, const std::string& what = "png");

}  // namespace bliskrun
