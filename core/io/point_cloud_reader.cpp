#include "core/io/point_cloud_reader.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "core/common/progress.h"

namespace bliskrun {

namespace {

// ---- text helpers ------------------------------------------------------------

std::string cloud_lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string cloud_strip(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r\n\v\f");
  if (b == std::string::npos) return {};
  const size_t e = s.find_last_not_of(" \t\r\n\v\f");
  return s.substr(b, e - b + 1);
}

// The text's lines (LF, a trailing CR dropped, a leading UTF-8 BOM dropped).
std::vector<std::string> cloud_lines(const std::string& text) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < text.size()) {
    if ((lines.size() & 4095) == 0) cancellation_point();
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string l = text.substr(start, end - start);
    if (!l.empty() && l.back() == '\r') l.pop_back();
    lines.push_back(std::move(l));
    start = end + 1;
  }
  if (!lines.empty() && lines[0].compare(0, 3, "\xEF\xBB\xBF") == 0) lines[0].erase(0, 3);
  return lines;
}

// The whitespace-separated words of `line` into `out` (cleared first).
void cloud_words(const std::string& line, std::vector<std::string>* out) {
  out->clear();
  size_t i = 0;
  const size_t n = line.size();
  while (i < n) {
    while (i < n && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const size_t start = i;
    while (i < n && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) out->emplace_back(line, start, i - start);
  }
}

// Fields split on commas when the line has any (each trimmed; an empty one
// kept, so "1,,3" is caught), else on whitespace.
std::vector<std::string> cloud_fields(const std::string& line) {
  std::vector<std::string> fields;
  if (line.find(',') != std::string::npos) {
    size_t start = 0;
    for (;;) {
      const size_t comma = line.find(',', start);
      fields.push_back(cloud_strip(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  } else {
    cloud_words(line, &fields);
  }
  return fields;
}

bool cloud_number(const std::string& s, double* out) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0' || errno == ERANGE) return false;
  *out = v;
  return true;
}

// A finite number, or a DataError at file:line naming the column and what it is.
double cloud_finite(const std::string& s, const std::string& file, long line, int column, const char* what) {
  double v = 0;
  if (!cloud_number(s, &v))
    throw DataError(file, line, "expected a number in column " + std::to_string(column) + " (" + what +
                                    "), got '" + s + "'");
  if (!std::isfinite(v))
    throw DataError(file, line, "expected a finite number in column " + std::to_string(column) + " (" + what +
                                    "), got '" + s + "'");
  return v;
}

const char* const kCloudAxis[6] = {"x", "y", "z", "nx", "ny", "nz"};

// ---- XYZ and CSV -------------------------------------------------------------

PointCloud parse_xyz_text(const std::string& text, const std::string& file, bool csv, double scale) {
  PointCloud cloud;
  cloud.format = csv ? PointCloudFormat::kCsv : PointCloudFormat::kXyz;
  const std::vector<std::string> lines = cloud_lines(text);
  // Columns of x y z [nx ny nz]: from a CSV header naming them, else 0..5.
  int column[6] = {0, 1, 2, 3, 4, 5};
  bool named = false, with_normals = false;
  size_t first_fields = 0;  // field count of the first point line (positional columns)
  long first_line = 0;
  for (size_t k = 0; k < lines.size(); ++k) {
    const long line_no = static_cast<long>(k + 1);
    if ((k & 4095) == 0) cancellation_point();
    std::string line = lines[k];
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    if (cloud_strip(line).empty()) continue;
    const std::vector<std::string> f = cloud_fields(line);
    if (first_line == 0) {
      double unused = 0;
      if (csv && !cloud_number(f[0], &unused)) {
        // The header: names the columns when it has x, y and z.
        int found[6] = {-1, -1, -1, -1, -1, -1};
        for (size_t c = 0; c < f.size(); ++c) {
          std::string name = cloud_lower(f[c]);
          if (name.size() >= 2 && name.front() == '"' && name.back() == '"') name = name.substr(1, name.size() - 2);
          for (int a = 0; a < 6; ++a)
            if (name == kCloudAxis[a]) {
              if (found[a] >= 0)
                throw DataError(file, line_no, std::string("expected one column named '") + kCloudAxis[a] +
                                                   "' in the header, got two");
              found[a] = static_cast<int>(c);
            }
        }
        if (found[0] >= 0 || found[1] >= 0 || found[2] >= 0) {
          for (int a = 0; a < 3; ++a)
            if (found[a] < 0)
              throw DataError(file, line_no, std::string("expected the header to name columns x, y and z, '") +
                                                 kCloudAxis[a] + "' is missing");
          const int normals = (found[3] >= 0) + (found[4] >= 0) + (found[5] >= 0);
          if (normals != 0 && normals != 3)
            throw DataError(file, line_no, "expected the header to name all of nx, ny, nz or none");
          named = true;
          with_normals = normals == 3;
          for (int a = 0; a < 6; ++a) column[a] = found[a];
        }
        first_line = -1;  // header seen; the next line is the first point
        continue;
      }
      first_line = line_no;
    } else if (first_line < 0) {
      first_line = line_no;
    }
    if (!named) {
      if (first_fields == 0) {
        if (f.size() != 3 && f.size() != 6)
          throw DataError(file, line_no, "expected 3 fields (x y z) or 6 (x y z nx ny nz), got " +
                                             std::to_string(f.size()));
        first_fields = f.size();
        with_normals = first_fields == 6;
      } else if (f.size() != first_fields) {
        throw DataError(file, line_no, "expected " + std::to_string(first_fields) + " fields as at line " +
                                           std::to_string(first_line) + ", got " + std::to_string(f.size()));
      }
    } else {
      const int need = *std::max_element(column, column + (with_normals ? 6 : 3)) + 1;
      if (static_cast<int>(f.size()) < need)
        throw DataError(file, line_no, "expected at least " + std::to_string(need) +
                                           " fields (the header's columns), got " + std::to_string(f.size()));
    }
    double v[6];
    for (int a = 0; a < (with_normals ? 6 : 3); ++a)
      v[a] = cloud_finite(f[static_cast<size_t>(column[a])], file, line_no, column[a] + 1, kCloudAxis[a]);
    cloud.points.emplace_back(v[0] * scale, v[1] * scale, v[2] * scale);
    if (with_normals) cloud.normals.emplace_back(v[3], v[4], v[5]);
  }
  if (cloud.points.empty())
    throw DataError(file, static_cast<long>(lines.size()), "expected at least one point, the file has none");
  return cloud;
}

// ---- PLY ---------------------------------------------------------------------

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

bool ply_type(const std::string& name, PlyType* t) {
  static const std::pair<const char*, PlyType> kNames[] = {
      {"char", PlyType::kInt8},     {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
      {"uint8", PlyType::kUint8},   {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16}, {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},   {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32}, {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  for (const auto& [n, type] : kNames)
    if (name == n) {
      *t = type;
      return true;
    }
  return false;
}

size_t ply_size(PlyType t) {
  switch (t) {
    case PlyType::kInt8: case PlyType::kUint8: return 1;
    case PlyType::kInt16: case PlyType::kUint16: return 2;
    case PlyType::kInt32: case PlyType::kUint32: case PlyType::kFloat32: return 4;
    case PlyType::kFloat64: return 8;
  }
  return 1;
}

bool ply_is_float(PlyType t) { return t == PlyType::kFloat32 || t == PlyType::kFloat64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;
  bool list = false;
  PlyType count_type = PlyType::kUint8;
};

struct PlyElement {
  std::string name;
  long long count = 0;
  long line = 0;  // header line of its "element"
  std::vector<PlyProperty> properties;
};

// A binary value at p, in the file's byte order.
double ply_value(const unsigned char* p, PlyType t, bool big_endian) {
  unsigned char b[8];
  const size_t n = ply_size(t);
  for (size_t i = 0; i < n; ++i) b[i] = big_endian ? p[n - 1 - i] : p[i];  // host is little-endian (x86, arm64)
  switch (t) {
    case PlyType::kInt8: { int8_t v; std::memcpy(&v, b, 1); return v; }
    case PlyType::kUint8: return b[0];
    case PlyType::kInt16: { int16_t v; std::memcpy(&v, b, 2); return v; }
    case PlyType::kUint16: { uint16_t v; std::memcpy(&v, b, 2); return v; }
    case PlyType::kInt32: { int32_t v; std::memcpy(&v, b, 4); return v; }
    case PlyType::kUint32: { uint32_t v; std::memcpy(&v, b, 4); return v; }
    case PlyType::kFloat32: { float v; std::memcpy(&v, b, 4); return v; }
    case PlyType::kFloat64: { double v; std::memcpy(&v, b, 8); return v; }
  }
  return 0;
}

PointCloud parse_ply(const std::string& bytes, const std::string& file, double scale) {
  // The header is text up to "end_header" and its newline.
  enum class PlyFormat { kAscii, kLittle, kBig } format = PlyFormat::kAscii;
  bool have_format = false;
  std::vector<PlyElement> elements;
  size_t pos = 0;
  long line_no = 0;
  bool ended = false;
  while (pos < bytes.size() && !ended) {
    size_t nl = bytes.find('\n', pos);
    if (nl == std::string::npos) nl = bytes.size();
    std::string line = bytes.substr(pos, nl - pos);
    pos = std::min(nl + 1, bytes.size());
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::vector<std::string> w;
    cloud_words(line, &w);
    if (line_no == 1) {
      if (w.size() != 1 || w[0] != "ply") throw DataError(file, 1, "expected 'ply' on the first line of a PLY file");
      continue;
    }
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      if (w.size() != 3 || w[2] != "1.0")
        throw DataError(file, line_no, "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      if (w[1] == "ascii") format = PlyFormat::kAscii;
      else if (w[1] == "binary_little_endian") format = PlyFormat::kLittle;
      else if (w[1] == "binary_big_endian") format = PlyFormat::kBig;
      else throw DataError(file, line_no, "expected format ascii, binary_little_endian or binary_big_endian, got '" + w[1] + "'");
      have_format = true;
    } else if (w[0] == "element") {
      PlyElement e;
      e.line = line_no;
      char* end = nullptr;
      errno = 0;
      if (w.size() != 3) throw DataError(file, line_no, "expected 'element NAME COUNT'");
      e.name = w[1];
      e.count = std::strtoll(w[2].c_str(), &end, 10);
      if (*end != '\0' || end == w[2].c_str() || errno == ERANGE || e.count < 0)
        throw DataError(file, line_no, "expected a count of 0 or more for element '" + e.name + "', got '" + w[2] + "'");
      elements.push_back(std::move(e));
    } else if (w[0] == "property") {
      if (elements.empty()) throw DataError(file, line_no, "expected an 'element' line before its properties");
      PlyProperty p;
      if (w.size() == 5 && w[1] == "list") {
        p.list = true;
        if (!ply_type(w[2], &p.count_type) || ply_is_float(p.count_type))
          throw DataError(file, line_no, "expected an integer type for the list's count, got '" + w[2] + "'");
        if (!ply_type(w[3], &p.type)) throw DataError(file, line_no, "expected a PLY type, got '" + w[3] + "'");
        p.name = w[4];
      } else if (w.size() == 3) {
        if (!ply_type(w[1], &p.type)) throw DataError(file, line_no, "expected a PLY type, got '" + w[1] + "'");
        p.name = w[2];
      } else {
        throw DataError(file, line_no, "expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME'");
      }
      elements.back().properties.push_back(std::move(p));
    } else if (w[0] == "end_header") {
      ended = true;
    } else {
      throw DataError(file, line_no, "expected a PLY header line (format, element, property, comment, end_header), got '" + w[0] + "'");
    }
  }
  if (!ended) throw DataError(file, line_no, "unexpected end of file; expected 'end_header'");
  if (!have_format) throw DataError(file, line_no, "expected a 'format' line in the header");

  // The vertex element and where its x y z (nx ny nz) are.
  size_t vertex = elements.size();
  for (size_t k = 0; k < elements.size(); ++k)
    if (elements[k].name == "vertex") {
      vertex = k;
      break;
    }
  if (vertex == elements.size()) throw DataError(file, line_no, "expected a 'vertex' element in the header");
  const PlyElement& ve = elements[vertex];
  int slot[6] = {-1, -1, -1, -1, -1, -1};
  for (size_t i = 0; i < ve.properties.size(); ++i)
    for (int a = 0; a < 6; ++a)
      if (ve.properties[i].name == kCloudAxis[a]) {
        if (ve.properties[i].list || !ply_is_float(ve.properties[i].type))
          throw DataError(file, ve.line, std::string("expected vertex property '") + kCloudAxis[a] +
                                             "' of type float or double");
        slot[a] = static_cast<int>(i);
      }
  for (int a = 0; a < 3; ++a)
    if (slot[a] < 0)
      throw DataError(file, ve.line, std::string("expected a vertex property '") + kCloudAxis[a] + "'");
  const bool with_normals = slot[3] >= 0 && slot[4] >= 0 && slot[5] >= 0;
  if (ve.count == 0) throw DataError(file, ve.line, "expected at least one vertex, the element has 0");

  PointCloud cloud;
  cloud.format = PointCloudFormat::kPly;
  const long long body = static_cast<long long>(pos);
  if (format == PlyFormat::kAscii) {
    // One line per element instance; blank lines and comments are not PLY.
    const std::vector<std::string> lines = cloud_lines(bytes.substr(pos));
    size_t next = 0;
    for (size_t k = 0; k <= vertex; ++k) {
      const PlyElement& e = elements[k];
      if (static_cast<unsigned long long>(e.count) > lines.size() - next)
        throw DataError(file, line_no + static_cast<long>(lines.size()) + 1,
                        "unexpected end of file; element '" + e.name + "' has " + std::to_string(e.count) +
                            " lines, " + std::to_string(lines.size() - next) + " remain");
      if (k < vertex) {
        next += static_cast<size_t>(e.count);
        continue;
      }
      cloud.points.reserve(static_cast<size_t>(e.count));
      std::vector<std::string> w;
      for (long long i = 0; i < e.count; ++i, ++next) {
        if ((i & 4095) == 0) cancellation_point();
        const long at = line_no + static_cast<long>(next) + 1;
        cloud_words(lines[next], &w);
        size_t t = 0;
        double v[6] = {0, 0, 0, 0, 0, 0};
        for (size_t pi = 0; pi < e.properties.size(); ++pi) {
          const PlyProperty& p = e.properties[pi];
          long long n = 1;
          if (p.list) {
            double c = 0;
            if (t >= w.size() || !cloud_number(w[t], &c) || c < 0 || c != std::floor(c) || c > 1e9)
              throw DataError(file, at, "expected the count of list '" + p.name + "'");
            ++t;
            n = static_cast<long long>(c);
          }
          if (static_cast<unsigned long long>(n) > w.size() - std::min(t, w.size()))
            throw DataError(file, at, "expected a value for property '" + p.name + "', the line has " +
                                          std::to_string(w.size()) + " fields");
          for (int a = 0; a < 6; ++a)
            if (slot[a] == static_cast<int>(pi)) v[a] = cloud_finite(w[t], file, at, static_cast<int>(t) + 1, kCloudAxis[a]);
          t += static_cast<size_t>(n);
        }
        if (t != w.size())
          throw DataError(file, at, "expected " + std::to_string(t) + " values for a vertex, got " + std::to_string(w.size()));
        cloud.points.emplace_back(v[0] * scale, v[1] * scale, v[2] * scale);
        if (with_normals) cloud.normals.emplace_back(v[3], v[4], v[5]);
      }
    }
    return cloud;
  }

  const bool big = format == PlyFormat::kBig;
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const long long size = static_cast<long long>(bytes.size());
  long long at = body;
  for (size_t k = 0; k <= vertex; ++k) {
    const PlyElement& e = elements[k];
    // Fixed-size instances: the count must fit in what is left.
    bool fixed = true;
    long long stride = 0;
    for (const PlyProperty& p : e.properties) {
      if (p.list) fixed = false;
      else stride += static_cast<long long>(ply_size(p.type));
    }
    if (fixed && stride > 0 && e.count > (size - at) / stride)
      throw BinaryDataError(file, at, "truncated: element '" + e.name + "' has " + std::to_string(e.count) + " × " +
                                          std::to_string(stride) + " bytes, " + std::to_string(size - at) +
                                          " remain (header line " + std::to_string(e.line) + ")");
    if (e.properties.empty()) continue;  // nothing to read, however many
    if (k == vertex) cloud.points.reserve(static_cast<size_t>(std::min(e.count, size - at)));
    for (long long i = 0; i < e.count; ++i) {
      if ((i & 4095) == 0) cancellation_point();
      double v[6] = {0, 0, 0, 0, 0, 0};
      for (size_t pi = 0; pi < e.properties.size(); ++pi) {
        const PlyProperty& p = e.properties[pi];
        long long n = 1;
        if (p.list) {
          if (at + static_cast<long long>(ply_size(p.count_type)) > size)
            throw BinaryDataError(file, at, "truncated: expected the count of list '" + p.name + "' of " + e.name +
                                                " " + std::to_string(i));
          const double c = ply_value(data + at, p.count_type, big);
          if (c < 0) throw BinaryDataError(file, at, "expected a list count of 0 or more, got " + std::to_string(c));
          n = static_cast<long long>(c);
          at += static_cast<long long>(ply_size(p.count_type));
        }
        const long long need = n * static_cast<long long>(ply_size(p.type));
        if (need > size - at)
          throw BinaryDataError(file, at, "truncated: expected property '" + p.name + "' of " + e.name + " " +
                                              std::to_string(i) + ", " + std::to_string(size - at) + " bytes remain");
        if (k == vertex)
          for (int a = 0; a < 6; ++a)
            if (slot[a] == static_cast<int>(pi)) {
              v[a] = ply_value(data + at, p.type, big);
              if (!std::isfinite(v[a]))
                throw BinaryDataError(file, at, std::string("expected a finite ") + kCloudAxis[a] + " of vertex " +
                                                    std::to_string(i) + ", got " + std::to_string(v[a]));
            }
        at += need;
      }
      if (k == vertex) {
        cloud.points.emplace_back(v[0] * scale, v[1] * scale, v[2] * scale);
        if (with_normals) cloud.normals.emplace_back(v[3], v[4], v[5]);
      }
    }
  }
  return cloud;
}

// ---- STL ---------------------------------------------------------------------

// Distinct vertices in order of first appearance, compared exactly.
struct StlVertexKey {
  double x, y, z;
  bool operator==(const StlVertexKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct StlVertexHash {
  // splitmix64's finaliser over the three bit patterns: a float widened to a
  // double has 29 zero low bits, which an identity hash would hand to the table.
  static uint64_t mix(uint64_t h) {
    h ^= h >> 30;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 27;
    h *= 0x94D049BB133111EBull;
    return h ^ (h >> 31);
  }
  size_t operator()(const StlVertexKey& k) const {
    uint64_t h = 0;
    for (double d : {k.x, k.y, k.z}) {
      uint64_t b;
      std::memcpy(&b, &d, 8);  // -0 was made +0 by the caller
      h = mix(h ^ b);
    }
    return static_cast<size_t>(h);
  }
};

class StlVertices {
 public:
  // Room for `n` distinct vertices without rehashing (a mesh has about half
  // as many as its triangles' corners, a triangle soup all of them).
  void reserve(size_t n) {
    index_.reserve(n);
    points_.reserve(n);
  }
  void add(double x, double y, double z) {
    const StlVertexKey k{x + 0.0, y + 0.0, z + 0.0};
    if (index_.emplace(k, points_.size()).second) points_.emplace_back(x + 0.0, y + 0.0, z + 0.0);
  }
  std::vector<Vec3>& points() { return points_; }

 private:
  std::unordered_map<StlVertexKey, size_t, StlVertexHash> index_;
  std::vector<Vec3> points_;
};

void scale_points(std::vector<Vec3>* points, double scale) {
  if (scale != 1.0)
    for (Vec3& p : *points) p *= scale;
}

PointCloud parse_binary_stl(const std::string& bytes, const std::string& file, double scale) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const long long size = static_cast<long long>(bytes.size());
  if (size < 84)
    throw BinaryDataError(file, size, "truncated: a binary STL has an 84-byte header, the file has " +
                                          std::to_string(size) + " bytes");
  const long long count = static_cast<long long>(ply_value(data + 80, PlyType::kUint32, false));
  if (count == 0) throw BinaryDataError(file, 80, "expected at least one triangle, the count is 0");
  if (84 + 50 * count != size)
    throw BinaryDataError(file, 80, "the count says " + std::to_string(count) + " triangles (" +
                                        std::to_string(84 + 50 * count) + " bytes), the file has " +
                                        std::to_string(size) + " bytes" +
                                        (84 + 50 * count > size ? " (truncated)" : ""));
  StlVertices vertices;
  vertices.reserve(static_cast<size_t>(count) / 2 + 3);
  for (long long t = 0; t < count; ++t) {
    if ((t & 4095) == 0) cancellation_point();
    const long long base = 84 + 50 * t + 12;  // after the facet normal
    for (int v = 0; v < 3; ++v) {
      double c[3];
      for (int a = 0; a < 3; ++a) {
        const long long at = base + 12 * v + 4 * a;
        c[a] = ply_value(data + at, PlyType::kFloat32, false);
        if (!std::isfinite(c[a]))
          throw BinaryDataError(file, at, std::string("expected a finite ") + kCloudAxis[a] + " of triangle " +
                                              std::to_string(t) + " vertex " + std::to_string(v + 1));
      }
      vertices.add(c[0], c[1], c[2]);
    }
  }
  PointCloud cloud;
  cloud.format = PointCloudFormat::kStl;
  cloud.points = std::move(vertices.points());
  scale_points(&cloud.points, scale);
  return cloud;
}

PointCloud parse_ascii_stl(const std::string& text, const std::string& file, double scale) {
  const std::vector<std::string> lines = cloud_lines(text);
  StlVertices vertices;
  int in_loop = -1;  // vertices seen in the open loop, -1 outside one
  long loop_line = 0;
  bool solid = false;
  std::vector<std::string> w;
  for (size_t k = 0; k < lines.size(); ++k) {
    const long line_no = static_cast<long>(k + 1);
    if ((k & 4095) == 0) cancellation_point();
    cloud_words(lines[k], &w);
    if (w.empty()) continue;
    const std::string key = cloud_lower(w[0]);
    if (!solid) {
      if (key != "solid") throw DataError(file, line_no, "expected 'solid' at the start of an ASCII STL");
      solid = true;
    } else if (key == "vertex") {
      if (in_loop < 0) throw DataError(file, line_no, "expected 'vertex' inside 'outer loop' ... 'endloop'");
      if (w.size() != 4) throw DataError(file, line_no, "expected 'vertex x y z', got " + std::to_string(w.size() - 1) + " numbers");
      double c[3];
      for (int a = 0; a < 3; ++a) c[a] = cloud_finite(w[static_cast<size_t>(a) + 1], file, line_no, a + 2, kCloudAxis[a]);
      vertices.add(c[0], c[1], c[2]);
      ++in_loop;
    } else if (key == "outer") {
      if (in_loop >= 0) throw DataError(file, line_no, "expected 'endloop' before another 'outer loop'");
      in_loop = 0;
      loop_line = line_no;
    } else if (key == "endloop") {
      if (in_loop != 3)
        throw DataError(file, line_no, "expected 3 vertices in the loop of line " + std::to_string(loop_line) +
                                           ", got " + std::to_string(std::max(in_loop, 0)));
      in_loop = -1;
    } else if (key == "facet" || key == "endfacet") {
      if (in_loop >= 0) throw DataError(file, line_no, "expected 'endloop' before '" + w[0] + "'");
    } else if (key == "endsolid") {
      solid = false;  // a file may hold several solids
    } else {
      throw DataError(file, line_no, "expected an STL keyword (facet, outer loop, vertex, endloop, endfacet, endsolid), got '" + w[0] + "'");
    }
  }
  if (in_loop >= 0) throw DataError(file, static_cast<long>(lines.size()), "unexpected end of file inside the loop of line " + std::to_string(loop_line));
  if (vertices.points().empty())
    throw DataError(file, static_cast<long>(lines.size()), "expected at least one vertex, the file has none");
  PointCloud cloud;
  cloud.format = PointCloudFormat::kStl;
  cloud.points = std::move(vertices.points());
  scale_points(&cloud.points, scale);
  return cloud;
}

bool stl_binary_size(const std::string& bytes) {
  if (bytes.size() < 84) return false;
  const auto count = static_cast<unsigned long long>(
      ply_value(reinterpret_cast<const unsigned char*>(bytes.data()) + 80, PlyType::kUint32, false));
  return 84 + 50 * count == bytes.size();
}

bool starts_with_solid(const std::string& bytes) {
  const size_t b = bytes.find_first_not_of(" \t\r\n");
  return b != std::string::npos && cloud_lower(bytes.substr(b, 5)) == "solid";
}

PointCloud parse_stl(const std::string& bytes, const std::string& file, double scale) {
  // Some exporters start a binary STL's header with "solid": the size, or a
  // NUL byte no text has, decides first.
  if (stl_binary_size(bytes) || !starts_with_solid(bytes) || bytes.find('\0') != std::string::npos)
    return parse_binary_stl(bytes, file, scale);
  return parse_ascii_stl(bytes, file, scale);
}

PointCloudFormat detect_format(const std::string& bytes, const std::string& file) {
  const size_t dot = file.find_last_of('.');
  const size_t slash = file.find_last_of('/');
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) {
    const std::string ext = cloud_lower(file.substr(dot + 1));
    if (ext == "xyz" || ext == "txt" || ext == "asc" || ext == "pts") return PointCloudFormat::kXyz;
    if (ext == "csv") return PointCloudFormat::kCsv;
    if (ext == "ply") return PointCloudFormat::kPly;
    if (ext == "stl") return PointCloudFormat::kStl;
  }
  if (bytes.compare(0, 4, "ply\n") == 0 || bytes.compare(0, 5, "ply\r\n") == 0) return PointCloudFormat::kPly;
  if (stl_binary_size(bytes) || starts_with_solid(bytes)) return PointCloudFormat::kStl;
  return bytes.find(',') != std::string::npos ? PointCloudFormat::kCsv : PointCloudFormat::kXyz;
}

}  // namespace

const char* point_cloud_format_name(PointCloudFormat format) {
  switch (format) {
    case PointCloudFormat::kAuto: return "auto";
    case PointCloudFormat::kXyz: return "xyz";
    case PointCloudFormat::kCsv: return "csv";
    case PointCloudFormat::kPly: return "ply";
    case PointCloudFormat::kStl: return "stl";
  }
  return "auto";
}

PointCloud parse_point_cloud(const std::string& bytes, const std::string& file, const PointCloudReadOptions& opts) {
  if (!(opts.mm_per_unit > 0) || !std::isfinite(opts.mm_per_unit))
    throw ParameterError("mm_per_unit", "expected a positive finite scale, got " + std::to_string(opts.mm_per_unit));
  const PointCloudFormat format =
      opts.format == PointCloudFormat::kAuto ? detect_format(bytes, file) : opts.format;
  switch (format) {
    case PointCloudFormat::kPly: return parse_ply(bytes, file, opts.mm_per_unit);
    case PointCloudFormat::kStl: return parse_stl(bytes, file, opts.mm_per_unit);
    case PointCloudFormat::kCsv: return parse_xyz_text(bytes, file, true, opts.mm_per_unit);
    default: return parse_xyz_text(bytes, file, false, opts.mm_per_unit);
  }
}

PointCloud read_point_cloud(const std::string& path, const PointCloudReadOptions& opts) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw DataError(path, 0, "cannot open the file for reading");
  std::ostringstream buf;
  buf << f.rdbuf();
  if (f.bad()) throw DataError(path, 0, "read error");
  return parse_point_cloud(buf.str(), path, opts);
}

}  // namespace bliskrun
