#include "core/analysis/heat_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <tuple>
#include <utility>

#include "core/common/atomic_file.h"
#include "core/common/error.h"
#include "core/common/fixed_text.h"
#include "core/common/xml_escape.h"

namespace bliskrun {

namespace {

// Diverging blue - white - red; s in [-1, 1].
void colour(double s, int* r, int* g, int* b) {
  s = std::clamp(s, -1.0, 1.0);
  const double t = std::abs(s);
  // From white to a saturated end colour.
  const double er = s < 0 ? 33 : 178, eg = s < 0 ? 102 : 24, eb = s < 0 ? 172 : 43;
  *r = static_cast<int>(std::lround(255 + (er - 255) * t));
  *g = static_cast<int>(std::lround(255 + (eg - 255) * t));
  *b = static_cast<int>(std::lround(255 + (eb - 255) * t));
}

std::string fmt(const char* f, double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, x);
  return buf;
}

void check(const HeatMap& map, const HeatMapOptions& o) {
  if (map.rows < 1 || map.cols < 1 ||
      map.values.size() != static_cast<size_t>(map.rows) * static_cast<size_t>(map.cols))
    throw ParameterError("map", "expected rows x cols values");
  if (o.levels < 2 || o.levels > 1024) throw ParameterError("levels", "expected 2 to 1024");
  if (o.plot_width_px < 50 || o.plot_height_px < 50 || o.plot_width_px > 10000 || o.plot_height_px > 10000)
    throw ParameterError("plot_width_px", "expected a plot of 50 x 50 to 10000 x 10000 px");
  if (!(o.scale_max >= 0)) throw ParameterError("scale_max", "expected >= 0");
}

// Level -2 is "not part of this map" (NaN), -1 "never reached" (+-inf);
// [-m, m] maps onto levels 0..levels-1.
constexpr int kHeatNotInMap = -2, kHeatNeverReached = -1;
int level_of(double x, double m, int levels) {
  if (std::isnan(x)) return kHeatNotInMap;
  if (!std::isfinite(x)) return kHeatNeverReached;
  const int l = static_cast<int>(std::floor((x / m + 1) / 2 * levels));
  return std::clamp(l, 0, levels - 1);
}

Rgb level_rgb(int l, int levels) {
  if (l == kHeatNotInMap) return {255, 255, 255};
  if (l < 0) return {187, 187, 187};
  int r, g, b;
  colour(((l + 0.5) / levels) * 2 - 1, &r, &g, &b);
  return {static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g), static_cast<std::uint8_t>(b)};
}

// The colour bar's labels at fractions 0, 1/4, .. 1 of its height (-m at the bottom).
std::vector<std::pair<double, std::string>> heat_bar_labels(double m) {
  std::vector<std::pair<double, std::string>> out;
  for (int k = 0; k <= 4; ++k) out.emplace_back(k / 4.0, significant_text(m * (k / 2.0 - 1)));
  return out;
}

// Which kinds of "no value" the map holds (each gets a legend entry).
struct HeatMapGaps {
  bool never_reached = false, not_in_map = false;
};
HeatMapGaps heat_gaps_of(const HeatMap& map) {
  HeatMapGaps g;
  for (double x : map.values) {
    if (std::isnan(x)) g.not_in_map = true;
    else if (!std::isfinite(x)) g.never_reached = true;
  }
  return g;
}

}  // namespace

Rgb heat_map_hatch(int x, int y) {
  return (x + y) % 6 == 0 ? Rgb{150, 150, 150} : Rgb{255, 255, 255};
}

double heat_map_scale(const HeatMap& map, const HeatMapOptions& o) {
  double m = o.scale_max;
  if (!(m > 0)) {
    for (double x : map.values)
      if (std::isfinite(x)) m = std::max(m, std::abs(x));
  }
  return m > 0 ? m : 1;  // all zero: everything white
}

Rgb heat_map_colour(double value, double m, int levels) { return level_rgb(level_of(value, m, levels), levels); }

std::string heat_map_svg(const HeatMap& map, const HeatMapOptions& o) {
  check(map, o);
  const int nu = map.rows, nv = map.cols;
  const double m = heat_map_scale(map, o);

  const double left = 80, top = 40, W = o.plot_width_px, H = o.plot_height_px;
  const double bar_x = left + W + 30, bar_w = 18;
  const double total_w = bar_x + bar_w + 90, total_h = top + H + 78;
  const double cw = W / nv, ch = H / nu;
  auto level = [&](double x) { return level_of(x, m, o.levels); };
  auto level_colour = [&](int l) {
    if (l == kHeatNotInMap) return std::string("url(#not-in-map)");
    const Rgb c = level_rgb(l, o.levels);
    char buf[16];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c[0], c[1], c[2]);
    return std::string(buf);
  };
  std::string out;
  out.reserve(static_cast<size_t>(nu) * 2000);
  out += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fmt("%.0f", total_w) +
         "\" height=\"" + fmt("%.0f", total_h) + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  out += "<defs><pattern id=\"not-in-map\" width=\"6\" height=\"6\" patternUnits=\"userSpaceOnUse\" "
         "patternTransform=\"rotate(45)\"><rect width=\"6\" height=\"6\" fill=\"white\"/><line x1=\"0\" y1=\"0\" "
         "x2=\"0\" y2=\"6\" stroke=\"#969696\"/></pattern></defs>\n";
  out += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  out += "<text x=\"" + fmt("%.1f", left) + "\" y=\"24\" font-size=\"15\">" + xml_escape(o.title) +
         "</text>\n";
  out += "<g shape-rendering=\"crispEdges\">\n";
  // Row i (u) from the bottom; runs of equal colour along v merged.
  for (int i = 0; i < nu; ++i) {
    const double y = top + H - (i + 1) * ch;
    int j = 0;
    while (j < nv) {
      const int l = level(map.at(i, j));
      int k = j + 1;
      while (k < nv && level(map.at(i, k)) == l) ++k;
      out += "<rect x=\"" + fmt("%.2f", left + j * cw) + "\" y=\"" + fmt("%.2f", y) +
             "\" width=\"" + fmt("%.2f", (k - j) * cw + 0.01) + "\" height=\"" +
             fmt("%.2f", ch + 0.01) + "\" fill=\"" + level_colour(l) + "\"/>\n";
      j = k;
    }
  }
  out += "</g>\n";
  out += "<rect x=\"" + fmt("%.1f", left) + "\" y=\"" + fmt("%.1f", top) + "\" width=\"" +
         fmt("%.1f", W) + "\" height=\"" + fmt("%.1f", H) +
         "\" fill=\"none\" stroke=\"black\"/>\n";
  for (const HeatMapLabel& label : o.labels) {
    const double x = left + label.v * W + 2, y = top + (1 - label.u) * H + 2;
    out += "<rect x=\"" + fmt("%.1f", x) + "\" y=\"" + fmt("%.1f", y) + "\" width=\"" +
           fmt("%.1f", 7.0 * static_cast<double>(label.text.size()) + 6) +
           "\" height=\"16\" fill=\"white\" stroke=\"black\" stroke-width=\"0.5\"/>\n";
    out += "<text class=\"tile-label\" x=\"" + fmt("%.1f", x + 3) + "\" y=\"" + fmt("%.1f", y + 12) + "\">" +
           xml_escape(label.text) + "</text>\n";
  }
  // Axes: v across, u up.
  for (int t = 0; o.fraction_ticks && t <= 4; ++t) {
    const double f = t / 4.0;
    out += "<text x=\"" + fmt("%.1f", left + f * W) + "\" y=\"" + fmt("%.1f", top + H + 16) +
           "\" text-anchor=\"middle\">" + fmt("%.2f", f) + "</text>\n";
    out += "<text x=\"" + fmt("%.1f", left - 6) + "\" y=\"" + fmt("%.1f", top + H - f * H + 4) +
           "\" text-anchor=\"end\">" + fmt("%.2f", f) + "</text>\n";
  }
  out += "<text x=\"" + fmt("%.1f", left + W / 2) + "\" y=\"" + fmt("%.1f", top + H + 36) +
         "\" text-anchor=\"middle\">" + xml_escape(o.v_label) + "</text>\n";
  out += "<text x=\"20\" y=\"" + fmt("%.1f", top + H / 2) +
         "\" text-anchor=\"middle\" transform=\"rotate(-90 20 " + fmt("%.1f", top + H / 2) +
         ")\">" + xml_escape(o.u_label) + "</text>\n";
  // Colour bar, K from -m (bottom) to m (top).
  const double lh = H / o.levels;
  for (int l = 0; l < o.levels; ++l)
    out += "<rect x=\"" + fmt("%.1f", bar_x) + "\" y=\"" + fmt("%.2f", top + H - (l + 1) * lh) +
           "\" width=\"" + fmt("%.1f", bar_w) + "\" height=\"" + fmt("%.2f", lh + 0.01) +
           "\" fill=\"" + level_colour(l) + "\"/>\n";
  out += "<rect x=\"" + fmt("%.1f", bar_x) + "\" y=\"" + fmt("%.1f", top) + "\" width=\"" +
         fmt("%.1f", bar_w) + "\" height=\"" + fmt("%.1f", H) +
         "\" fill=\"none\" stroke=\"black\"/>\n";
  for (const auto& [f, text] : heat_bar_labels(m))
    out += "<text x=\"" + fmt("%.1f", bar_x + bar_w + 4) + "\" y=\"" + fmt("%.1f", top + H - f * H + 4) + "\">" +
           text + "</text>\n";
  out += "<text x=\"" + fmt("%.1f", bar_x) + "\" y=\"" + fmt("%.1f", top - 8) + "\">" +
         xml_escape(o.value_label) + "</text>\n";
  if (!o.footer.empty())
    out += "<text x=\"" + fmt("%.1f", left) + "\" y=\"" + fmt("%.1f", top + H + 54) + "\">" +
           xml_escape(o.footer) + "</text>\n";
  const HeatMapGaps gaps = heat_gaps_of(map);
  double legend_x = left;
  for (const auto& [present, fill, text] :
       {std::tuple{gaps.never_reached, std::string("#bbbbbb"), "never reached"},
        std::tuple{gaps.not_in_map, std::string("url(#not-in-map)"), "not part of this map"}}) {
    if (!present) continue;
    out += "<rect class=\"legend\" x=\"" + fmt("%.1f", legend_x) + "\" y=\"" + fmt("%.1f", top + H + 62) +
           "\" width=\"14\" height=\"10\" fill=\"" + fill + "\" stroke=\"black\"/>\n";
    out += "<text x=\"" + fmt("%.1f", legend_x + 18) + "\" y=\"" + fmt("%.1f", top + H + 71) + "\">" + text +
           "</text>\n";
    legend_x += 40 + 7.0 * std::strlen(text);
  }
  out += "</svg>\n";
  return out;
}

void write_heat_map_svg(const HeatMap& map, const std::string& path, const HeatMapOptions& opts) {
  write_file_atomic(path, heat_map_svg(map, opts));
}

HeatMapRasterLayout heat_map_raster_layout(const HeatMapOptions& o) {
  HeatMapRasterLayout l;
  l.plot_x = 80;
  l.plot_y = 40;
  l.bar_x = l.plot_x + o.plot_width_px + 30;
  l.bar_width = 18;
  l.width = l.bar_x + l.bar_width + 80;
  l.legend_y = l.plot_y + o.plot_height_px + 54;
  l.height = l.legend_y + 16;
  // A long title or footer widens the picture rather than being cut.
  l.width = std::max({l.width, l.plot_x + text_width(o.title, 2) + 10, l.plot_x + text_width(o.footer) + 10});
  return l;
}

RgbImage heat_map_raster(const HeatMap& map, const HeatMapOptions& o) {
  check(map, o);
  const double m = heat_map_scale(map, o);
  const HeatMapRasterLayout L = heat_map_raster_layout(o);
  const int W = o.plot_width_px, H = o.plot_height_px;
  const Rgb white{255, 255, 255}, black{0, 0, 0};
  RgbImage im(L.width, L.height, white);
  // Plot: pixel (x, y) shows the cell whose centre is nearest its centre;
  // rows counted from the bottom so u = 0 (hub) is at the bottom.
  std::vector<Rgb> palette(static_cast<size_t>(o.levels) + 2);
  for (int l = kHeatNotInMap; l < o.levels; ++l) palette[static_cast<size_t>(l + 2)] = level_rgb(l, o.levels);
  for (int y = 0; y < H; ++y) {
    const int i = std::min(map.rows - 1, static_cast<int>((H - 1 - y + 0.5) / H * map.rows));
    for (int x = 0; x < W; ++x) {
      const int j = std::min(map.cols - 1, static_cast<int>((x + 0.5) / W * map.cols));
      const int l = level_of(map.at(i, j), m, o.levels);
      const int px = L.plot_x + x, py = L.plot_y + y;
      im.set(px, py, l == kHeatNotInMap ? heat_map_hatch(px, py) : palette[static_cast<size_t>(l + 2)]);
    }
  }
  im.frame(L.plot_x - 1, L.plot_y - 1, L.plot_x + W + 1, L.plot_y + H + 1, black);
  im.text(L.plot_x, 12, o.title, black, 2);
  for (const HeatMapLabel& label : o.labels) {
    const int x = L.plot_x + static_cast<int>(std::lround(label.v * (W - 1))) + 3;
    const int y = L.plot_y + static_cast<int>(std::lround((1 - label.u) * (H - 1))) + 3;
    im.fill(x - 2, y - 2, x + text_width(label.text) + 2, y + 9, white);
    im.frame(x - 3, y - 3, x + text_width(label.text) + 3, y + 10, black);
    im.text(x, y, label.text, black);
  }
  // Axes: ticks and fractions along v (across) and u (up).
  for (int t = 0; o.fraction_ticks && t <= 4; ++t) {
    const std::string label = fmt("%.2f", t / 4.0);
    const int x = L.plot_x + static_cast<int>(std::lround(t / 4.0 * (W - 1)));
    const int y = L.plot_y + H - 1 - static_cast<int>(std::lround(t / 4.0 * (H - 1)));
    im.fill(x, L.plot_y + H + 1, x + 1, L.plot_y + H + 5, black);
    im.text(x - text_width(label) / 2, L.plot_y + H + 8, label, black);
    im.fill(L.plot_x - 5, y, L.plot_x - 1, y + 1, black);
    im.text(L.plot_x - 8 - text_width(label), y - 3, label, black);
  }
  const std::string& v_label = o.v_label;
  const std::string& u_label = o.u_label;
  im.text(L.plot_x + W / 2 - text_width(v_label) / 2, L.plot_y + H + 22, v_label, black);
  im.text(14, L.plot_y + H / 2 + text_width(u_label) / 2, u_label, black, 1, true);
  // Colour bar: level l's band of rows, -m at the bottom.
  for (int y = 0; y < H; ++y) {
    const int l = std::min(o.levels - 1, static_cast<int>((H - 1 - y + 0.5) / H * o.levels));
    im.fill(L.bar_x, L.plot_y + y, L.bar_x + L.bar_width, L.plot_y + y + 1, level_rgb(l, o.levels));
  }
  im.frame(L.bar_x - 1, L.plot_y - 1, L.bar_x + L.bar_width + 1, L.plot_y + H + 1, black);
  for (const auto& [f, text] : heat_bar_labels(m)) {
    const int y = L.plot_y + H - 1 - static_cast<int>(f * (H - 1));
    im.fill(L.bar_x + L.bar_width + 1, y, L.bar_x + L.bar_width + 4, y + 1, black);
    im.text(L.bar_x + L.bar_width + 6, y - 3, text, black);
  }
  im.text(L.bar_x, L.plot_y - 12, o.value_label, black);
  if (!o.footer.empty()) im.text(L.plot_x, L.plot_y + H + 40, o.footer, black);
  const HeatMapGaps gaps = heat_gaps_of(map);
  int legend_x = L.plot_x;
  for (const auto& [present, hatched, text] :
       {std::tuple{gaps.never_reached, false, "never reached"}, std::tuple{gaps.not_in_map, true, "not part of this map"}}) {
    if (!present) continue;
    for (int y = L.legend_y; y < L.legend_y + 10; ++y)
      for (int x = legend_x; x < legend_x + 14; ++x) im.set(x, y, hatched ? heat_map_hatch(x, y) : level_rgb(kHeatNeverReached, o.levels));
    im.frame(legend_x - 1, L.legend_y - 1, legend_x + 15, L.legend_y + 11, black);
    im.text(legend_x + 20, L.legend_y + 2, text, black);
    legend_x += 20 + text_width(text) + 24;
  }
  return im;
}

void write_heat_map_png(const HeatMap& map, const std::string& path, const HeatMapOptions& opts) {
  write_file_atomic(path, encode_png(heat_map_raster(map, opts)));
}

}  // namespace bliskrun
