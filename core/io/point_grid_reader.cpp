#include "core/io/point_grid_reader.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/common/atomic_file.h"
#include "core/common/error.h"
#include "core/common/progress.h"

namespace bliskrun {

namespace {

const char* const kAxisName[3] = {"x", "y", "z"};

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const size_t e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

// Splits on commas when the line has any, else on whitespace.
std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  if (line.find(',') != std::string::npos) {
    std::string field;
    std::istringstream in(line);
    while (std::getline(in, field, ',')) fields.push_back(trim(field));
    if (!line.empty() && line.back() == ',') fields.emplace_back();
  } else {
    std::istringstream in(line);
    std::string field;
    while (in >> field) fields.push_back(field);
  }
  return fields;
}

bool parse_int(const std::string& s, int* out) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (*end != '\0' || errno != 0 || v < INT32_MIN || v > INT32_MAX) return false;
  *out = static_cast<int>(v);
  return true;
}

struct Header {
  long line = 0;
  int rows = 0, cols = 0;
  std::optional<GridOrder> order;
};

// "# grid ROWS COLS [order=row|column]"; returns false if the comment is not a
// grid header at all, throws if it is one but malformed.
bool parse_header(const std::string& comment, const std::string& file, long line, Header* h) {
  std::istringstream in(comment);
  std::string word;
  if (!(in >> word) || word != "grid") return false;
  const char* expected = "expected '# grid ROWS COLS [order=row|column]'";
  std::string rows_s, cols_s;
  if (!(in >> rows_s >> cols_s) || !parse_int(rows_s, &h->rows) || !parse_int(cols_s, &h->cols))
    throw DataError(file, line, std::string(expected) + " with integer ROWS and COLS");
  std::string opt;
  while (in >> opt) {
    if (opt == "order=row") h->order = GridOrder::kRowMajor;
    else if (opt == "order=column") h->order = GridOrder::kColumnMajor;
    else throw DataError(file, line, std::string(expected) + ", got '" + opt + "'");
  }
  h->line = line;
  return true;
}

const char* order_name(GridOrder o) { return o == GridOrder::kRowMajor ? "row" : "column"; }

}  // namespace

PointGrid parse_point_grid(const std::string& text, const std::string& file,
                           const PointGridReadOptions& opts) {
  std::optional<Header> header;
  std::vector<Vec3> points;
  std::vector<long> point_lines;
  std::istringstream in(text);
  std::string raw;
  long line_no = 0;
  while (std::getline(in, raw)) {
    ++line_no;
    if ((line_no & 1023) == 0) cancellation_point();
    std::string line = raw;
    const size_t hash = line.find('#');
    if (hash != std::string::npos) {
      Header h;
      if (parse_header(line.substr(hash + 1), file, line_no, &h)) {
        if (header)
          throw DataError(file, line_no,
                          "expected one '# grid' header, another is at line " +
                              std::to_string(header->line));
        if (!points.empty())
          throw DataError(file, line_no, "expected the '# grid' header before the first point");
        header = h;
      }
      line.resize(hash);
    }
    line = trim(line);
    if (line.empty()) continue;
    const std::vector<std::string> fields = split_fields(line);
    if (fields.size() != 3)
      throw DataError(file, line_no,
                      "expected 3 fields (x y z), got " + std::to_string(fields.size()));
    Vec3 p;
    for (int k = 0; k < 3; ++k) {
      const std::string& f = fields[k];
      char* end = nullptr;
      errno = 0;
      const double v = f.empty() ? 0.0 : std::strtod(f.c_str(), &end);
      if (f.empty() || *end != '\0' || errno == ERANGE)
        throw DataError(file, line_no,
                        std::string("expected a number in column ") + std::to_string(k + 1) +
                            " (" + kAxisName[k] + "), got '" + f + "'");
      if (!std::isfinite(v))
        throw DataError(file, line_no,
                        std::string("expected a finite number in column ") +
                            std::to_string(k + 1) + " (" + kAxisName[k] + "), got '" + f + "'");
      p[k] = v;
    }
    points.push_back(p);
    point_lines.push_back(line_no);
  }

  // Shape: header and options must agree where both speak.
  const long shape_line = header ? header->line : 0;
  int rows = 0, cols = 0;
  if (header) {
    rows = header->rows;
    cols = header->cols;
  }
  if (opts.rows) {
    if (header && *opts.rows != rows)
      throw DataError(file, shape_line,
                      "header says " + std::to_string(rows) + " rows, options say " +
                          std::to_string(*opts.rows));
    rows = *opts.rows;
  }
  if (opts.cols) {
    if (header && *opts.cols != cols)
      throw DataError(file, shape_line,
                      "header says " + std::to_string(cols) + " columns, options say " +
                          std::to_string(*opts.cols));
    cols = *opts.cols;
  }
  GridOrder order = GridOrder::kRowMajor;
  if (header && header->order) order = *header->order;
  if (opts.order) {
    if (header && header->order && *header->order != *opts.order)
      throw DataError(file, shape_line,
                      std::string("header says order=") + order_name(*header->order) +
                          ", options say " + order_name(*opts.order));
    order = *opts.order;
  }
  if (!header && !(opts.rows && opts.cols))
    throw DataError(file, 0,
                    "expected a '# grid ROWS COLS [order=row|column]' header or rows and cols "
                    "options");
  if (rows < 2 || cols < 2)
    throw DataError(file, shape_line,
                    "expected at least 2 rows and 2 columns, got " + std::to_string(rows) + " x " +
                        std::to_string(cols));
  const size_t expected = static_cast<size_t>(rows) * static_cast<size_t>(cols);
  if (points.size() != expected)
    throw DataError(file, points.size() > expected ? point_lines[expected] : line_no,
                    "expected " + std::to_string(rows) + " x " + std::to_string(cols) + " = " +
                        std::to_string(expected) + " points, got " +
                        std::to_string(points.size()));

  PointGrid grid(rows, cols);
  std::vector<long> src_line(expected);
  for (size_t k = 0; k < expected; ++k) {
    int i, j;
    if (order == GridOrder::kRowMajor) {
      i = static_cast<int>(k / cols);
      j = static_cast<int>(k % cols);
    } else {
      j = static_cast<int>(k / rows);
      i = static_cast<int>(k % rows);
    }
    grid.at(i, j) = points[k];
    src_line[static_cast<size_t>(i) * cols + j] = point_lines[k];
  }

  // A repeated consecutive point makes a zero-length chord: interpolation
  // cannot parametrise it (eq. 3), so it is a data error here, not later.
  auto line_of = [&](int i, int j) { return src_line[static_cast<size_t>(i) * cols + j]; };
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      if (j + 1 < cols && grid.at(i, j) == grid.at(i, j + 1))
        throw DataError(file, line_of(i, j + 1),
                        "expected distinct consecutive points along row " + std::to_string(i) +
                            ", point (" + std::to_string(i) + ", " + std::to_string(j + 1) +
                            ") repeats line " + std::to_string(line_of(i, j)));
      if (i + 1 < rows && grid.at(i, j) == grid.at(i + 1, j))
        throw DataError(file, line_of(i + 1, j),
                        "expected distinct consecutive points along column " + std::to_string(j) +
                            ", point (" + std::to_string(i + 1) + ", " + std::to_string(j) +
                            ") repeats line " + std::to_string(line_of(i, j)));
    }
  }
  return grid;
}

PointGrid read_point_grid(const std::string& path, const PointGridReadOptions& opts) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw DataError(path, 0, "cannot open the file for reading");
  std::ostringstream buf;
  buf << f.rdbuf();
  if (f.bad()) throw DataError(path, 0, "read error");
  return parse_point_grid(buf.str(), path, opts);
}

std::string format_point_grid(const PointGrid& grid) {
  std::string out = "# grid " + std::to_string(grid.rows) + " " + std::to_string(grid.cols) +
                    " order=row\n";
  out.reserve(out.size() + grid.points.size() * 72);
  char buf[96];
  for (const Vec3& p : grid.points) {
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    out += buf;
  }
  return out;
}

void write_point_grid(const PointGrid& grid, const std::string& path) {
  if (grid.rows < 2 || grid.cols < 2 ||
      grid.points.size() != static_cast<size_t>(grid.rows) * grid.cols)
    throw ParameterError("grid", "expected at least 2 x 2 points and rows * cols points");
  write_file_atomic(path, format_point_grid(grid));
}

}  // namespace bliskrun
