#include "core/analysis/heat_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/common/atomic_file.h"
#include "core/common/error.h"

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

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

std::string heat_map_svg(const HeatMap& map, const HeatMapOptions& o) {
  if (map.rows < 1 || map.cols < 1 ||
      map.values.size() != static_cast<size_t>(map.rows) * static_cast<size_t>(map.cols))
    throw ParameterError("map", "expected rows x cols values");
  if (o.levels < 2 || o.levels > 1024) throw ParameterError("levels", "expected 2 to 1024");
  if (o.plot_width_px < 50 || o.plot_height_px < 50)
    throw ParameterError("plot_width_px", "expected a plot of at least 50 x 50 px");
  if (!(o.scale_max >= 0)) throw ParameterError("scale_max", "expected >= 0");

  const int nu = map.rows, nv = map.cols;
  double m = o.scale_max;
  if (!(m > 0)) {
    for (double x : map.values)
      if (std::isfinite(x)) m = std::max(m, std::abs(x));
  }
  if (!(m > 0)) m = 1;  // all zero: everything white

  const double left = 80, top = 40, W = o.plot_width_px, H = o.plot_height_px;
  const double bar_x = left + W + 30, bar_w = 18;
  const double total_w = bar_x + bar_w + 90, total_h = top + H + 60;
  const double cw = W / nv, ch = H / nu;
  // Level -1 is "no value" (grey).
  auto level_of = [&](double x) {
    if (!std::isfinite(x)) return -1;
    // Map [-m, m] onto levels 0..levels-1.
    const int l = static_cast<int>(std::floor((x / m + 1) / 2 * o.levels));
    return std::clamp(l, 0, o.levels - 1);
  };
  auto level_colour = [&](int l) {
    if (l < 0) return std::string("#bbbbbb");
    const double s = ((l + 0.5) / o.levels) * 2 - 1;
    int r, g, b;
    colour(s, &r, &g, &b);
    char buf[16];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", r, g, b);
    return std::string(buf);
  };
  std::string out;
  out.reserve(static_cast<size_t>(nu) * 2000);
  out += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fmt("%.0f", total_w) +
         "\" height=\"" + fmt("%.0f", total_h) + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  out += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  out += "<text x=\"" + fmt("%.1f", left) + "\" y=\"24\" font-size=\"15\">" + escape(o.title) +
         "</text>\n";
  out += "<g shape-rendering=\"crispEdges\">\n";
  // Row i (u) from the bottom; runs of equal colour along v merged.
  for (int i = 0; i < nu; ++i) {
    const double y = top + H - (i + 1) * ch;
    int j = 0;
    while (j < nv) {
      const int l = level_of(map.at(i, j));
      int k = j + 1;
      while (k < nv && level_of(map.at(i, k)) == l) ++k;
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
  // Axes: v across, u up.
  for (int t = 0; t <= 4; ++t) {
    const double f = t / 4.0;
    out += "<text x=\"" + fmt("%.1f", left + f * W) + "\" y=\"" + fmt("%.1f", top + H + 16) +
           "\" text-anchor=\"middle\">" + fmt("%.2f", f) + "</text>\n";
    out += "<text x=\"" + fmt("%.1f", left - 6) + "\" y=\"" + fmt("%.1f", top + H - f * H + 4) +
           "\" text-anchor=\"end\">" + fmt("%.2f", f) + "</text>\n";
  }
  out += "<text x=\"" + fmt("%.1f", left + W / 2) + "\" y=\"" + fmt("%.1f", top + H + 36) +
         "\" text-anchor=\"middle\">v (chord)</text>\n";
  out += "<text x=\"20\" y=\"" + fmt("%.1f", top + H / 2) +
         "\" text-anchor=\"middle\" transform=\"rotate(-90 20 " + fmt("%.1f", top + H / 2) +
         ")\">u (span, hub to tip)</text>\n";
  // Colour bar, K from -m (bottom) to m (top).
  const double lh = H / o.levels;
  for (int l = 0; l < o.levels; ++l)
    out += "<rect x=\"" + fmt("%.1f", bar_x) + "\" y=\"" + fmt("%.2f", top + H - (l + 1) * lh) +
           "\" width=\"" + fmt("%.1f", bar_w) + "\" height=\"" + fmt("%.2f", lh + 0.01) +
           "\" fill=\"" + level_colour(l) + "\"/>\n";
  out += "<rect x=\"" + fmt("%.1f", bar_x) + "\" y=\"" + fmt("%.1f", top) + "\" width=\"" +
         fmt("%.1f", bar_w) + "\" height=\"" + fmt("%.1f", H) +
         "\" fill=\"none\" stroke=\"black\"/>\n";
  for (const auto& [f, value] : {std::pair{0.0, -m}, std::pair{0.5, 0.0}, std::pair{1.0, m}})
    out += "<text x=\"" + fmt("%.1f", bar_x + bar_w + 4) + "\" y=\"" +
           fmt("%.1f", top + H - f * H + 4) + "\">" + fmt("%.3e", value) + "</text>\n";
  out += "<text x=\"" + fmt("%.1f", bar_x) + "\" y=\"" + fmt("%.1f", top - 8) + "\">" +
         escape(o.value_label) + "</text>\n";
  if (!o.footer.empty())
    out += "<text x=\"" + fmt("%.1f", left) + "\" y=\"" + fmt("%.1f", top + H + 54) + "\">" +
           escape(o.footer) + "</text>\n";
  out += "</svg>\n";
  return out;
}

void write_heat_map_svg(const HeatMap& map, const std::string& path, const HeatMapOptions& opts) {
  write_file_atomic(path, heat_map_svg(map, opts));
}

}  // namespace bliskrun
