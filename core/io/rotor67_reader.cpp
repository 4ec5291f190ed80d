#include "core/io/rotor67_reader.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/common/error.h"
#include "core/geometry/interpolation.h"

namespace bliskrun {

namespace {

constexpr double kFootMm = 304.8;

struct Lines {
  std::vector<std::string> text;
  std::string file;
  size_t next = 0;  // 0-based index of the next line
  const std::string& take(const std::string& expected) {
    if (next >= text.size()) throw DataError(file, static_cast<long>(next + 1), "unexpected end of file; expected " + expected);
    return text[next++];
  }
  long line() const { return static_cast<long>(next); }  // 1-based number of the last taken line
};

std::vector<double> numbers(const std::string& s, Lines& in, const std::string& what) {
  std::istringstream ss(s);
  std::vector<double> out;
  std::string field;
  while (ss >> field) {
    char* end = nullptr;
    const double v = std::strtod(field.c_str(), &end);
    if (!end || *end != '\0' || !std::isfinite(v))
      throw DataError(in.file, in.line(), "expected numbers (" + what + "), got '" + field + "'");
    out.push_back(v);
  }
  return out;
}

std::vector<double> read_array(Lines& in, const std::string& label, int count) {
  const std::string& l = in.take("the '" + label + "' label");
  if (l.find(label) == std::string::npos)
    throw DataError(in.file, in.line(), "expected the label '" + label + "', got '" + l + "'");
  const std::vector<double> scale = numbers(in.take("a scale factor"), in, "scale factor");
  if (scale.size() != 1) throw DataError(in.file, in.line(), "expected one scale factor");
  std::vector<double> values;
  while (static_cast<int>(values.size()) < count) {
    const std::string& l = in.take(std::to_string(count) + " values of '" + label + "'");
    std::istringstream first(l);
    std::string token;
    if (first >> token && !values.empty() && std::strtod(token.c_str(), nullptr) == 0 &&
        token.find_first_of("0123456789") == std::string::npos)
      throw DataError(in.file, in.line(), "expected " + std::to_string(count) + " values of '" + label + "', got " +
                                              std::to_string(values.size()) + " before this line");
    const std::vector<double> row = numbers(l, in, label);
    if (row.empty() || row.size() > 8)
      throw DataError(in.file, in.line(), "expected 1 to 8 values of '" + label + "' per line, got " + std::to_string(row.size()));
    values.insert(values.end(), row.begin(), row.end());
  }
  if (static_cast<int>(values.size()) != count)
    throw DataError(in.file, in.line(), "expected " + std::to_string(count) + " values of '" + label + "', got " +
                                            std::to_string(values.size()));
  for (double& v : values) v *= scale[0];
  return values;
}

}  // namespace

StreamSurfaceRotor parse_rotor67(const std::string& text, const std::string& file_label) {
  Lines in;
  in.file = file_label;
  std::istringstream ss(text);
  for (std::string l; std::getline(ss, l);) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    in.text.push_back(l);
  }
  // The free-text header ends at the "JM NS NB JLE JTE" line.
  auto is_header = [](const std::string& l) {
    std::istringstream t(l);
    std::string a, b, c, d, e, extra;
    return (t >> a >> b >> c >> d >> e) && !(t >> extra) && a == "JM" && b == "NS" && c == "NB" && d == "JLE" && e == "JTE";
  };
  // The free text describes the format with a sample header of its own; the
  // data's header is the last one.
  size_t header = in.text.size();
  for (size_t i = 0; i < in.text.size(); ++i)
    if (is_header(in.text[i])) header = i;
  in.next = header;
  in.take("the 'JM NS NB JLE JTE' header");
  const std::vector<double> head = numbers(in.take("JM NS NB JLE JTE values"), in, "JM NS NB JLE JTE");
  if (head.size() != 5) throw DataError(in.file, in.line(), "expected 5 values JM NS NB JLE JTE");
  const int jm = static_cast<int>(head[0]), ns = static_cast<int>(head[1]);
  StreamSurfaceRotor r;
  r.source = file_label;
  r.blade_count = static_cast<int>(head[2]);
  r.leading_edge = static_cast<int>(head[3]) - 1;
  r.trailing_edge = static_cast<int>(head[4]) - 1;
  if (jm < 4 || ns < 2 || r.blade_count < 1 || r.leading_edge < 0 || r.trailing_edge >= jm ||
      r.trailing_edge - r.leading_edge < 3)
    throw DataError(in.file, in.line(), "inconsistent JM NS NB JLE JTE");
  for (int k = 0; k < ns; ++k) {
    const std::string& title = in.take("surface " + std::to_string(k + 1));
    if (title.find("Surface number") == std::string::npos)
      throw DataError(in.file, in.line(), "expected 'Surface number " + std::to_string(k + 1) + "', got '" + title + "'");
    const auto x = read_array(in, "Axial Distance", jm);
    const auto rt = read_array(in, "Radius*Theta", jm);
    const auto dt = read_array(in, "Tangential thickness", jm);
    const auto rad = read_array(in, "Radius", jm);
    StreamSurfaceRotor::Surface s;
    for (int j = 0; j < jm; ++j) {
      if (!(rad[j] > 0)) throw DataError(in.file, in.line(), "radius must be > 0 (surface " + std::to_string(k + 1) + ")");
      s.x_mm.push_back(x[j] * kFootMm);
      s.r_mm.push_back(rad[j] * kFootMm);
      s.theta_upper_rad.push_back(rt[j] / rad[j]);
      s.theta_lower_rad.push_back((rt[j] - dt[j]) / rad[j]);
    }
    r.surfaces.push_back(std::move(s));
  }
  for (int j = 0; j < jm; ++j) {
    r.hub_meridian.emplace_back(r.surfaces.front().x_mm[j], r.surfaces.front().r_mm[j]);
    r.casing_meridian.emplace_back(r.surfaces.back().x_mm[j], r.surfaces.back().r_mm[j]);
  }
  return r;
}

StreamSurfaceRotor read_rotor67(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw DataError(path, 0, "cannot read the file");
  std::ostringstream s;
  s << f.rdbuf();
  return parse_rotor67(s.str(), path);
}

RotorFlanks rotor_flank_grids(const StreamSurfaceRotor& rotor, int cols, double margin) {
  if (cols < 4) throw ParameterError("cols", "need at least 4 columns");
  if (!(margin >= 0 && margin < 0.5)) throw ParameterError("edge_margin", "must be in [0, 0.5)");
  const int rows = static_cast<int>(rotor.surfaces.size());
  RotorFlanks out{PointGrid(rows, cols), PointGrid(rows, cols)};
  for (int i = 0; i < rows; ++i) {
    const auto& s = rotor.surfaces[i];
    const double x0 = s.x_mm[rotor.leading_edge], x1 = s.x_mm[rotor.trailing_edge];
    for (int side = 0; side < 2; ++side) {
      std::vector<Vec3> pts;
      for (int j = rotor.leading_edge; j <= rotor.trailing_edge; ++j) {
        const double th = side == 0 ? s.theta_lower_rad[j] : s.theta_upper_rad[j];
        const Vec3 p(s.r_mm[j] * std::cos(th), s.r_mm[j] * std::sin(th), s.x_mm[j]);
        if (!pts.empty() && (p - pts.back()).norm() < 1e-9) continue;  // repeated edge points
        pts.push_back(p);
      }
      const BSplineCurve c = interpolate_cubic(pts);
      // Resample where the axial fraction hits each target (z grows LE -> TE
      // along a side beyond the edge circle, which the margin excludes).
      for (int j = 0; j < cols; ++j) {
        const double f = margin + (1 - 2 * margin) * j / (cols - 1.0);
        const double z = x0 + f * (x1 - x0);
        double lo = 0, hi = 1;
        for (int it = 0; it < 80; ++it) {
          const double mid = 0.5 * (lo + hi);
          (c.point(mid).z() < z ? lo : hi) = mid;
        }
        const Vec3 p = c.point(0.5 * (lo + hi));
        if (side == 0) out.pressure.at(i, j) = p;
        else out.suction.at(i, cols - 1 - j) = p;  // TE -> LE
      }
    }
  }
  return out;
}

}  // namespace bliskrun
