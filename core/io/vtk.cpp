#include "core/io/vtk.h"

#include <cmath>
#include <cstdio>

#include "core/common/atomic_file.h"
#include "core/common/error.h"
#include "core/common/xml_escape.h"

namespace bliskrun {

namespace {

void append_number(std::string& out, double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  out += buf;
}

// Comments may not contain "--".
std::string comment_safe(std::string s) {
  for (size_t p = s.find("--"); p != std::string::npos; p = s.find("--")) s.replace(p, 2, "- ");
  return s;
}

void append_ints(std::string& out, const char* name, const std::vector<long long>& v) {
  out += "        <DataArray type=\"Int64\" Name=\"";
  out += name;
  out += "\" format=\"ascii\">\n         ";
  for (long long x : v) out += " " + std::to_string(x);
  out += "\n        </DataArray>\n";
}

}  // namespace

std::string vtp_xml(const VtkPolyData& d) {
  const size_t n = d.points.size();
  for (const Vec3& p : d.points)
    if (!p.allFinite()) throw ParameterError("points", "expected finite coordinates");
  for (const VtkPointArray& a : d.point_data) {
    if (a.components < 1 || a.components > 9) throw ParameterError(a.name, "expected 1 to 9 components");
    if (a.values.size() != n * static_cast<size_t>(a.components))
      throw ParameterError(a.name, "expected " + std::to_string(n * a.components) + " values (points x " +
                                       std::to_string(a.components) + "), got " + std::to_string(a.values.size()));
  }
  auto check_index = [&](int i, const char* what) {
    if (i < 0 || static_cast<size_t>(i) >= n)
      throw ParameterError(what, "point index " + std::to_string(i) + " outside 0.." + std::to_string(n) + "-1");
  };
  for (const auto& line : d.lines) {
    if (line.size() < 2) throw ParameterError("lines", "expected at least 2 points per polyline");
    for (int i : line) check_index(i, "lines");
  }
  for (const auto& t : d.triangles)
    for (int i : t) check_index(i, "triangles");

  std::string out;
  out.reserve(n * 64 + d.triangles.size() * 24);
  out += "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  if (!d.code_names.empty()) {
    out += "<!-- codes:";
    for (size_t i = 0; i < d.code_names.size(); ++i)
      out += " " + std::to_string(i) + " = " + comment_safe(d.code_names[i]) + ";";
    out += " -->\n";
  }
  out += "  <PolyData>\n";
  out += "    <Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfVerts=\"" +
         std::to_string(d.vertices ? n : 0) + "\" NumberOfLines=\"" + std::to_string(d.lines.size()) +
         "\" NumberOfStrips=\"0\" NumberOfPolys=\"" + std::to_string(d.triangles.size()) + "\">\n";
  out += "      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const Vec3& p : d.points) {
    out += "         ";
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_number(out, p[k]);
    }
    out += '\n';
  }
  out += "        </DataArray>\n      </Points>\n";
  if (!d.point_data.empty()) {
    out += "      <PointData>\n";
    for (const VtkPointArray& a : d.point_data) {
      out += "        <DataArray type=\"Float64\" Name=\"" + xml_escape(a.name) + "\" NumberOfComponents=\"" +
             std::to_string(a.components) + "\" format=\"ascii\">\n         ";
      for (double x : a.values) {
        out += ' ';
        // ParaView reads "nan"; keep non-finite samples visible as NaN.
        if (std::isfinite(x))
          append_number(out, x);
        else
          out += "nan";
      }
      out += "\n        </DataArray>\n";
    }
    out += "      </PointData>\n";
  }
  // Cells: connectivity and running end offsets, per section.
  auto section = [&](const char* tag, const std::vector<std::vector<long long>>& cells) {
    std::vector<long long> conn, offsets;
    for (const auto& c : cells) {
      conn.insert(conn.end(), c.begin(), c.end());
      offsets.push_back(static_cast<long long>(conn.size()));
    }
    out += "      <";
    out += tag;
    out += ">\n";
    append_ints(out, "connectivity", conn);
    append_ints(out, "offsets", offsets);
    out += "      </";
    out += tag;
    out += ">\n";
  };
  if (d.vertices) {
    std::vector<std::vector<long long>> v(n);
    for (size_t i = 0; i < n; ++i) v[i] = {static_cast<long long>(i)};
    section("Verts", v);
  }
  if (!d.lines.empty()) {
    std::vector<std::vector<long long>> v;
    for (const auto& l : d.lines) v.emplace_back(l.begin(), l.end());
    section("Lines", v);
  }
  if (!d.triangles.empty()) {
    std::vector<std::vector<long long>> v;
    for (const auto& t : d.triangles) v.push_back({t[0], t[1], t[2]});
    section("Polys", v);
  }
  out += "    </Piece>\n  </PolyData>\n</VTKFile>\n";
  return out;
}

void write_vtp(const VtkPolyData& data, const std::string& path) { write_file_atomic(path, vtp_xml(data)); }

void write_pvd(const std::vector<std::pair<std::string, std::string>>& blocks, const std::string& path) {
  std::string out = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n  <Collection>\n";
  for (size_t i = 0; i < blocks.size(); ++i)
    out += "    <DataSet timestep=\"0\" part=\"" + std::to_string(i) + "\" name=\"" + xml_escape(blocks[i].first) +
           "\" file=\"" + xml_escape(blocks[i].second) + "\"/>\n";
  out += "  </Collection>\n</VTKFile>\n";
  write_file_atomic(path, out);
}

}  // namespace bliskrun
