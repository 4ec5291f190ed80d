#include "core/io/rotor67_reader.h"

#include <cmath>
#include <cstdlib>

#include "core/common/error.h"
#include "core/io/data_lines.h"

namespace bliskrun {

namespace {

using io_detail::DataLines;

constexpr double kFootMm = 304.8;

// Any whitespace-separated finite numbers; the message keeps this format's
// wording ("expected numbers (<what>)").
std::vector<double> numbers(const std::string& s, const DataLines& in, const std::string& what) {
  std::vector<double> out;
  for (const std::string& field : DataLines::fields(s)) {
    char* end = nullptr;
    const double v = std::strtod(field.c_str(), &end);
    if (end == field.c_str() || *end != '\0' || !std::isfinite(v))
      in.fail("expected numbers (" + what + "), got '" + field + "'");
    out.push_back(v);
  }
  return out;
}

std::vector<double> read_array(DataLines& in, const std::string& label, int count) {
  const std::string& l = in.take("the '" + label + "' label");
  if (l.find(label) == std::string::npos) in.fail("expected the label '" + label + "', got '" + l + "'");
  const std::vector<double> scale = numbers(in.take("a scale factor"), in, "scale factor");
  if (scale.size() != 1) in.fail("expected one scale factor");
  std::vector<double> values;
  while (static_cast<int>(values.size()) < count) {
    const std::string& l = in.take(std::to_string(count) + " values of '" + label + "'");
    const std::vector<std::string> f = DataLines::fields(l);
    if (!f.empty() && !values.empty() && f[0].find_first_of("0123456789") == std::string::npos)
      in.fail("expected " + std::to_string(count) + " values of '" + label + "', got " +
              std::to_string(values.size()) + " before this line");
    const std::vector<double> row = numbers(l, in, label);
    if (row.empty() || row.size() > 8)
      in.fail("expected 1 to 8 values of '" + label + "' per line, got " + std::to_string(row.size()));
    values.insert(values.end(), row.begin(), row.end());
  }
  if (static_cast<int>(values.size()) != count)
    in.fail("expected " + std::to_string(count) + " values of '" + label + "', got " + std::to_string(values.size()));
  for (double& v : values) v *= scale[0];
  return values;
}

bool is_header(const std::string& l) {
  return DataLines::fields(l) == std::vector<std::string>{"JM", "NS", "NB", "JLE", "JTE"};
}

}  // namespace

StreamSurfaceRotor parse_rotor67(const std::string& text, const std::string& file_label) {
  // The free text describes the format with a sample header of its own; the
  // data's header is the last 'JM NS NB JLE JTE' line.
  size_t header = 0, count = 0;
  for (DataLines scan(text, file_label); !scan.at_end(); ++count)
    if (is_header(scan.take("a line"))) header = count;
  DataLines in(text, file_label);
  if (header == 0 && !(count && is_header(in.peek())))
    header = count;  // none: read to the end, so the message says so
  for (size_t i = 0; i < header; ++i) in.take("a line");
  in.take("the 'JM NS NB JLE JTE' header");
  const std::vector<double> head = numbers(in.take("JM NS NB JLE JTE values"), in, "JM NS NB JLE JTE");
  if (head.size() != 5) in.fail("expected 5 values JM NS NB JLE JTE");
  const int jm = static_cast<int>(head[0]), ns = static_cast<int>(head[1]);
  StreamSurfaceRotor r;
  r.source = file_label;
  r.blade_count = static_cast<int>(head[2]);
  r.leading_edge = static_cast<int>(head[3]) - 1;
  r.trailing_edge = static_cast<int>(head[4]) - 1;
  if (jm < 4 || ns < 2 || r.blade_count < 1 || r.leading_edge < 0 || r.trailing_edge >= jm ||
      r.trailing_edge - r.leading_edge < 3)
    in.fail("inconsistent JM NS NB JLE JTE");
  for (int k = 0; k < ns; ++k) {
    const std::string& title = in.take("surface " + std::to_string(k + 1));
    if (title.find("Surface number") == std::string::npos)
      in.fail("expected 'Surface number " + std::to_string(k + 1) + "', got '" + title + "'");
    const auto x = read_array(in, "Axial Distance", jm);
    const auto rt = read_array(in, "Radius*Theta", jm);
    const auto dt = read_array(in, "Tangential thickness", jm);
    const auto rad = read_array(in, "Radius", jm);
    StreamSurfaceRotor::Surface s;
    for (int j = 0; j < jm; ++j) {
      if (!(rad[j] > 0)) in.fail("radius must be > 0 (surface " + std::to_string(k + 1) + ")");
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
  return parse_rotor67(io_detail::read_text_file(path), path);
}

BladeSections blade_sections(const StreamSurfaceRotor& rotor) {
  BladeSections b;
  b.source = rotor.source;
  b.blade_count = rotor.blade_count;
  b.hub_meridian = rotor.hub_meridian;
  b.casing_meridian = rotor.casing_meridian;
  for (const auto& s : rotor.surfaces) {
    auto at = [&](int j, double th) { return Vec3(s.r_mm[j] * std::cos(th), s.r_mm[j] * std::sin(th), s.x_mm[j]); };
    std::vector<Vec3> loop;
    for (int j = rotor.leading_edge; j <= rotor.trailing_edge; ++j) loop.push_back(at(j, s.theta_upper_rad[j]));
    for (int j = rotor.trailing_edge - 1; j > rotor.leading_edge; --j) loop.push_back(at(j, s.theta_lower_rad[j]));
    b.sections.push_back(std::move(loop));
  }
  return b;
}

}  // namespace bliskrun
