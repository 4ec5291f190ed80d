#include "core/io/rotor37_reader.h"

#include <cmath>

#include "core/common/error.h"
#include "core/io/data_lines.h"

namespace bliskrun {

namespace {

using io_detail::DataLines;

constexpr double kCmMm = 10.0;

Vec3 at(double z_cm, double r_cm, double theta_rad) {
  const double r = r_cm * kCmMm;
  return {r * std::cos(theta_rad), r * std::sin(theta_rad), z_cm * kCmMm};
}

bool starts_surface(const std::string& line) { return line.find("SURFACE NUMBER") != std::string::npos; }

void expect_header(DataLines& in, const std::string& must_hold, const std::string& expected) {
  const std::string& l = in.take(expected);
  if (l.find(must_hold) == std::string::npos) in.fail("unknown header: expected " + expected + ", got '" + l + "'");
}

std::vector<Vec3> read_surface(DataLines& in, int number) {
  const std::string what = "surface " + std::to_string(number);
  const std::string& title = in.take("the title of " + what);
  const std::vector<std::string> f = DataLines::fields(title);
  if (!starts_surface(title) || f.size() < 3 || f[2] != std::to_string(number))
    in.fail("expected 'SURFACE NUMBER " + std::to_string(number) + " ...', got '" + title + "'");
  const std::string& columns = in.take("the column header of " + what);
  if (DataLines::fields(columns) != std::vector<std::string>{"J", "Z", "R", "THETA", "1", "THETA", "2"})
    in.fail("unknown header: expected 'J Z R THETA 1 THETA 2', got '" + columns + "'");

  std::vector<Vec3> upper, lower;
  for (int j = 1; j <= kRotor37PointsPerSurface; ++j) {
    const std::string expected = std::to_string(kRotor37PointsPerSurface) + " points J Z R THETA1 THETA2 in " + what;
    if (in.at_end() || starts_surface(in.peek())) {
      if (!in.at_end()) in.take(expected);
      in.fail("short block: expected " + expected + ", got " + std::to_string(j - 1));
    }
    const std::vector<double> v = in.numbers(in.take(expected), 5, "J Z R THETA1 THETA2");
    if (v[0] != j) in.fail("expected point J = " + std::to_string(j) + " of " + what);
    upper.push_back(at(v[1], v[2], v[3]));
    lower.push_back(at(v[1], v[2], v[4]));
  }
  // LE -> TE along THETA1, back along THETA2; the shared end points once.
  std::vector<Vec3> loop = upper;
  for (int j = kRotor37PointsPerSurface - 2; j >= 1; --j) loop.push_back(lower[j]);
  return loop;
}

std::vector<double> read_array(DataLines& in, const std::string& label) {
  in.skip_blank();
  const std::string& name = in.take("the array '" + label + "'");
  if (DataLines::fields(name) != std::vector<std::string>{label})
    in.fail("unknown header: expected the array name '" + label + "', got '" + name + "'");
  const std::string& count_line = in.take("'NN points' for " + label);
  const std::vector<std::string> f = DataLines::fields(count_line);
  char* end = nullptr;
  const long count = f.size() == 2 && f[1] == "points" ? std::strtol(f[0].c_str(), &end, 10) : 0;
  if (count < 2 || !end || *end != '\0') in.fail("expected 'NN points' (NN >= 2) for " + label + ", got '" + count_line + "'");
  std::vector<double> values;
  while (static_cast<long>(values.size()) < count) {
    const std::string expected = std::to_string(count) + " values of " + label;
    if (!in.at_end() && !DataLines::fields(in.peek()).empty() &&
        std::isalpha(static_cast<unsigned char>(DataLines::fields(in.peek())[0][0]))) {
      in.take(expected);
      in.fail("short block: expected " + expected + ", got " + std::to_string(values.size()));
    }
    const std::vector<double> row = in.numbers(in.take(expected), -1, label);
    if (row.empty() || row.size() > 8)
      in.fail("expected 1 to 8 values of " + label + " on a line, got " + std::to_string(row.size()));
    values.insert(values.end(), row.begin(), row.end());
  }
  if (static_cast<long>(values.size()) != count)
    in.fail("wrong count: expected " + std::to_string(count) + " values of " + label + ", got " +
            std::to_string(values.size()));
  return values;
}

std::vector<Vec2> meridian(DataLines& in, const std::string& z_label, const std::string& r_label) {
  const std::vector<double> z = read_array(in, z_label);
  const long z_line = in.line();
  const std::vector<double> r = read_array(in, r_label);
  if (r.size() != z.size())
    in.fail("wrong count: expected " + std::to_string(z.size()) + " values of " + r_label + " (as many as " +
            z_label + " up to line " + std::to_string(z_line) + "), got " + std::to_string(r.size()));
  std::vector<Vec2> out;
  for (size_t i = 0; i < z.size(); ++i) {
    if (r[i] <= 0) in.fail("expected positive radii in " + r_label);
    out.emplace_back(z[i] * kCmMm, r[i] * kCmMm);
  }
  return out;
}

}  // namespace

BladeSections parse_rotor37(const std::string& geometry_text, const std::string& geometry_label,
                            const std::string& hub_shroud_text, const std::string& hub_shroud_label) {
  BladeSections out;
  out.source = geometry_label;
  out.blade_count = kRotor37BladeCount;
  {
    DataLines in(geometry_text, geometry_label);
    expect_header(in, "Table IV NASA Rotor 37", "'Table IV NASA Rotor 37 Blade Geometry'");
    expect_header(in, "centimeters", "'Z and R are in centimeters'");
    in.skip_blank();
    while (!in.at_end()) {
      if (static_cast<int>(out.sections.size()) == kRotor37Surfaces) {
        in.take("end of file");
        in.fail("wrong count: expected " + std::to_string(kRotor37Surfaces) + " surfaces, found more");
      }
      out.sections.push_back(read_surface(in, static_cast<int>(out.sections.size()) + 1));
      in.skip_blank();
    }
    if (static_cast<int>(out.sections.size()) != kRotor37Surfaces)
      throw DataError(geometry_label, in.line() + 1,
                      "wrong count: expected " + std::to_string(kRotor37Surfaces) + " surfaces, got " +
                          std::to_string(out.sections.size()));
  }
  {
    DataLines in(hub_shroud_text, hub_shroud_label);
    expect_header(in, "Table V", "'Table V'");
    expect_header(in, "Hub and Shroud Coordinates", "'NASA Rotor 37 Hub and Shroud Coordinates (centimeters)'");
    out.hub_meridian = meridian(in, "Zhub", "Rhub");
    out.casing_meridian = meridian(in, "Zshroud", "Rshroud");
    in.skip_blank();
    if (!in.at_end()) {
      in.take("end of file");
      in.fail("expected the end of file after Rshroud");
    }
  }
  return out;
}

BladeSections read_rotor37(const std::string& geometry_path, const std::string& hub_shroud_path) {
  return parse_rotor37(io_detail::read_text_file(geometry_path), geometry_path,
                       io_detail::read_text_file(hub_shroud_path), hub_shroud_path);
}

}  // namespace bliskrun
