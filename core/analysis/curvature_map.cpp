#include "core/analysis/curvature_map.h"

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

std::string curvature_map_svg(const CurvatureStats& st, const CurvatureMapOptions& o) {
  if (st.map.empty() ||
      st.map.size() != static_cast<size_t>(st.samples_u) * static_cast<size_t>(st.samples_v))
    throw ParameterError("stats", "expected curvature statistics with a map (keep_map = true)");
  if (o.levels < 2 || o.levels > 1024) throw ParameterError("levels", "expected 2 to 1024");
  if (o.plot_width_px < 50 || o.plot_height_px < 50)
    throw ParameterError("plot_width_px", "expected a plot of at least 50 x 50 px");

  const int nu = st.samples_u, nv = st.samples_v;
  double m = 0;
  for (const CurvatureSample& s : st.map) m = std::max(m, std::abs(s.K));
  if (!(m > 0)) m = 1;  // a flat surface: everything white

  const double left = 80, top = 40, W = o.plot_width_px, H = o.plot_height_px;
  const double bar_x = left + W + 30, bar_w = 18;
  const double total_w = bar_x + bar_w + 90, total_h = top + H + 60;
  const double cw = W / nv, ch = H / nu;
  auto level_of = [&](double K) {
    // Map [-m, m] onto levels 0..levels-1.
    const int l = static_cast<int>(std::floor((K / m + 1) / 2 * o.levels));
    return std::clamp(l, 0, o.levels - 1);
  };
  auto level_colour = [&](int l) {
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
      const int l = level_of(st.at(i, j).K);
      int k = j + 1;
      while (k < nv && level_of(st.at(i, k).K) == l) ++k;
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
  out += "<text x=\"" + fmt("%.1f", bar_x) + "\" y=\"" + fmt("%.1f", top - 8) +
         "\">K (mm^-2)</text>\n";
  out += "<text x=\"" + fmt("%.1f", left) + "\" y=\"" + fmt("%.1f", top + H + 54) + "\">" +
         "K &lt; 0 on " + fmt("%.1f", 100 * st.negative_K_fraction) + "% of " +
         std::to_string(nu) + " x " + std::to_string(nv) + " samples; K in [" +
         fmt("%.3e", st.K_min) + ", " + fmt("%.3e", st.K_max) + "]</text>\n";
  out += "</svg>\n";
  return out;
}

void write_curvature_map_svg(const CurvatureStats& stats, const std::string& path,
                             const CurvatureMapOptions& opts) {
  write_file_atomic(path, curvature_map_svg(stats, opts));
}

}  // namespace bliskrun
