#include "core/io/camber_data.h"

#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

#include "core/common/atomic_file.h"
#include "core/common/error.h"
#include "core/io/data_lines.h"

namespace bliskrun {

namespace {

using io_detail::DataLines;

bool is_comment_or_blank(const std::string& line) {
  const size_t i = line.find_first_not_of(" \t");
  return i == std::string::npos || line[i] == '#';
}

void skip_comments(DataLines& in) {
  while (!in.at_end() && is_comment_or_blank(in.peek())) in.take("");
}

// Reads `count` point lines after a list header at `header_line`.
std::vector<CamberPoint> read_list(DataLines& in, long header_line, const std::string& name,
                                   long long count) {
  if (count < 4)
    throw DataError(in.file(), header_line,
                    name + ": expected at least 4 camber points, got " + std::to_string(count));
  std::vector<CamberPoint> pts;
  for (long long i = 0; i < count; ++i) {
    skip_comments(in);
    const std::string& line = in.take(name + " point " + std::to_string(i + 1) + " of " +
                                      std::to_string(count) + " (x y z h)");
    const std::vector<double> v = in.numbers(line, 4, "x y z h of " + name);
    CamberPoint c{Vec3(v[0], v[1], v[2]), v[3]};
    if (!(c.half_thickness_mm > 0))
      in.fail(name + ": expected a half thickness h > 0, got " + std::to_string(c.half_thickness_mm));
    if (!pts.empty()) {
      const Vec3 chord = c.p - pts.back().p;
      if (chord.norm() <= 1e-9) in.fail(name + ": point repeats the previous point");
      if (pts.size() >= 2 && chord.dot(pts.back().p - pts[pts.size() - 2].p) <= 0)
        in.fail(name + ": points must advance along the curve (leading edge -> trailing edge); "
                       "this one turns back by 90 degrees or more");
    }
    pts.push_back(c);
  }
  return pts;
}

}  // namespace

ImpellerDefinition parse_camber_data(const std::string& text, const std::string& label) {
  DataLines in(text, label);
  ImpellerDefinition d;
  bool have_blades = false;
  std::map<std::string, std::vector<CamberPoint>> lists;
  std::map<std::string, long> header_line;  // each list's header, for the pairing error
  while (true) {
    skip_comments(in);
    if (in.at_end()) break;
    const std::string& line = in.take("a keyword");
    const std::vector<std::string> f = DataLines::fields(line);
    const std::string& key = f[0];
    if (key == "blades" || key == "splitter_offset") {
      if (f.size() != 2) in.fail("expected '" + key + " <number>'");
      const double v = in.numbers(f[1], 1, key)[0];
      if (key == "blades") {
        if (v != std::floor(v) || v < 2 || v > 200) in.fail("expected a blade count in [2, 200]");
        d.blade_count = static_cast<int>(v);
        have_blades = true;
      } else {
        if (!(v > 0 && v < 1)) in.fail("expected a splitter offset in (0, 1) pitches");
        d.splitter_offset_pitch = v;
      }
    } else if ((key == "main" || key == "splitter") && f.size() == 3 &&
               (f[1] == "shroud" || f[1] == "hub")) {
      const std::string name = key + " " + f[1];
      if (lists.count(name)) in.fail("the list '" + name + "' appears twice");
      const double n = in.numbers(f[2], 1, "point count")[0];
      if (n != std::floor(n)) in.fail("expected an integer point count");
      header_line[name] = in.line();
      lists[name] = read_list(in, in.line(), name, static_cast<long long>(n));
    } else {
      in.fail("expected 'blades N', 'splitter_offset F' or a list header "
              "'main|splitter shroud|hub <count>', got '" + line + "'");
    }
  }
  const long end = in.line();
  if (!have_blades) throw DataError(label, end, "expected a 'blades N' line");
  for (const char* name : {"main shroud", "main hub"})
    if (!lists.count(name)) throw DataError(label, end, std::string("expected a '") + name + "' list");
  if (lists.count("splitter shroud") != lists.count("splitter hub"))
    throw DataError(label, end, "expected both 'splitter shroud' and 'splitter hub' lists, or neither");
  // Point i of a blade's shroud list and point i of its hub list lie on one
  // ruling (core/parts/impeller.h): lists of different lengths state no
  // pairing, so they are refused here, at the later list's header.
  for (const char* blade : {"main", "splitter"}) {
    const std::string shroud = std::string(blade) + " shroud", hub = std::string(blade) + " hub";
    if (!lists.count(shroud) || lists[shroud].size() == lists[hub].size()) continue;
    const bool hub_later = header_line[hub] > header_line[shroud];
    throw DataError(label, std::max(header_line[hub], header_line[shroud]),
                    "expected as many points in '" + (hub_later ? hub : shroud) + "' as in '" +
                        (hub_later ? shroud : hub) + "' (" + std::to_string(lists[hub_later ? shroud : hub].size()) +
                        ": point i of each lies on one ruling), got " +
                        std::to_string(lists[hub_later ? hub : shroud].size()));
  }
  d.main.shroud = lists["main shroud"];
  d.main.hub = lists["main hub"];
  if (lists.count("splitter hub")) d.splitter = BladeCamber{lists["splitter shroud"], lists["splitter hub"]};
  return d;
}

ImpellerDefinition read_camber_data(const std::string& path) {
  return parse_camber_data(io_detail::read_text_file(path), path);
}

std::string format_camber_data(const ImpellerDefinition& d) {
  std::ostringstream s;
  s << std::setprecision(17);
  s << "# bliskrun impeller camber data (impeller paper §2): x y z h in mm, h = half thickness,\n"
       "# each list leading edge -> trailing edge; Z is the impeller axis\n";
  s << "blades " << d.blade_count << "\n";
  auto list = [&](const std::string& name, const std::vector<CamberPoint>& pts) {
    s << name << " " << pts.size() << "\n";
    for (const CamberPoint& c : pts)
      s << c.p.x() << " " << c.p.y() << " " << c.p.z() << " " << c.half_thickness_mm << "\n";
  };
  list("main shroud", d.main.shroud);
  list("main hub", d.main.hub);
  if (d.splitter) {
    list("splitter shroud", d.splitter->shroud);
    list("splitter hub", d.splitter->hub);
    s << "splitter_offset " << d.splitter_offset_pitch << "\n";
  }
  return s.str();
}

void write_camber_data(const ImpellerDefinition& d, const std::string& path) {
  write_file_atomic(path, format_camber_data(d));
}

}  // namespace bliskrun
