#include "core/io/hecc_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>

#include "core/common/error.h"
#include "core/io/data_lines.h"

namespace bliskrun {

namespace {

using io_detail::DataLines;

constexpr double kInchMm = 25.4;
// Fewer rows than this cannot be a blade section (the files hold 200-400).
constexpr int kMinSectionRows = 8;

char separator_of(const std::string& header) { return header.find(',') != std::string::npos ? ',' : ' '; }

}  // namespace

std::vector<Vec3> parse_hecc_section(const std::string& text, const std::string& file_label, bool mirror_theta) {
  DataLines in(text, file_label);
  if (in.at_end()) in.take("the header 'X R*THETA R'");
  const char sep = separator_of(in.peek());
  // Design-intent main section 07 ships without its header line; a first line
  // of three numbers is taken as data, anything else must be the header.
  const std::vector<std::string> first = DataLines::fields(in.peek(), sep);
  const bool headerless = first.size() == 3 && std::all_of(first.begin(), first.end(), [](const std::string& f) {
    char* end = nullptr;
    std::strtod(f.c_str(), &end);
    return end != f.c_str() && *end == '\0';
  });
  if (!headerless) {
    const std::string& header = in.take("the header 'X R*THETA R'");
    if (first != std::vector<std::string>{"X", "R*THETA", "R"})
      in.fail("unknown header: expected 'X R*THETA R' (space or comma separated), got '" + header + "'");
  }
  std::vector<Vec3> loop;
  while (!in.at_end()) {
    const std::string& l = in.take("a row X R*THETA R");
    if (DataLines::fields(l, sep).empty()) continue;
    const std::vector<double> v = in.numbers(l, 3, "X R*THETA R", sep);
    if (v[2] <= 0) in.fail("expected a positive radius R, got " + std::to_string(v[2]));
    const double r = v[2] * kInchMm;
    const double theta = (mirror_theta ? -1.0 : 1.0) * v[1] / v[2];
    loop.emplace_back(r * std::cos(theta), r * std::sin(theta), v[0] * kInchMm);
  }
  if (static_cast<int>(loop.size()) < kMinSectionRows)
    throw DataError(file_label, in.line() + 1,
                    "short block: expected at least " + std::to_string(kMinSectionRows) +
                        " rows X R*THETA R in a section loop, got " + std::to_string(loop.size()));
  return loop;
}

std::vector<Vec2> parse_hecc_flowpath(const std::string& text, const std::string& file_label) {
  DataLines in(text, file_label);
  const std::string& header = in.take("the header 'x r'");
  if (DataLines::fields(header) != std::vector<std::string>{"x", "r"})
    in.fail("unknown header: expected 'x r', got '" + header + "'");
  std::vector<Vec2> line;
  while (!in.at_end()) {
    const std::string& l = in.take("a row x r");
    if (DataLines::fields(l).empty()) continue;
    const std::vector<double> v = in.numbers(l, 2, "x r");
    if (v[1] < 0) in.fail("expected a radius r >= 0, got " + std::to_string(v[1]));
    line.emplace_back(v[0] * kInchMm, v[1] * kInchMm);
  }
  if (line.size() < 2)
    throw DataError(file_label, in.line() + 1,
                    "short block: expected at least 2 rows x r, got " + std::to_string(line.size()));
  return line;
}

BladeSections read_hecc_impeller(const std::string& impeller_dir, HeccSet set, HeccBlade blade) {
  const std::string design = impeller_dir + "/design_intent_hot_no_fillets/";
  const bool intent = set == HeccSet::design_intent;
  const int sections = intent ? 11 : 14;
  BladeSections out;
  out.blade_count = blade == HeccBlade::main ? kHeccMainBlades : kHeccSplitterBlades;
  out.rotation_sign = +1;  // Read-Me §6.1: θ positive in the direction of rotation (both sets, after the mirror)
  for (int k = 1; k <= sections; ++k) {
    char name[160];
    if (intent)
      std::snprintf(name, sizeof name, "%sHECCvanedCoordinates_impeller_%s_blade_section_%02d.txt", design.c_str(),
                    blade == HeccBlade::main ? "main" : "splitter", k);
    else
      std::snprintf(name, sizeof name,
                    "%s/as_manufactured_cold_with_fillets/HECCcoordinates_impeller%sBladeColdWithFillets_section%02d.csv",
                    impeller_dir.c_str(), blade == HeccBlade::main ? "Main" : "Splitter", k);
    if (k == 1) out.source = name;
    out.sections.push_back(parse_hecc_section(io_detail::read_text_file(name), name, intent));
  }
  const std::string hub = design + "HECCvanedCoordinates_flowpathCoordinates_hub.txt";
  const std::string shroud = design + "HECCvanedCoordinates_flowpathCoordinates_shroud.txt";
  out.hub_meridian = parse_hecc_flowpath(io_detail::read_text_file(hub), hub);
  out.casing_meridian = parse_hecc_flowpath(io_detail::read_text_file(shroud), shroud);
  return out;
}

}  // namespace bliskrun
