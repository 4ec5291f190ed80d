#pragma once
// Point grids exported from CAD: one point per line, "x y z" or "x,y,z",
// '#' starts a comment. The grid shape comes from a header comment
//
//   # grid ROWS COLS [order=row|column]
//
// or from the caller's options (options win where both are given and agree;
// a disagreement is an error). Row order lists all points of u-row 0 first
// (along v), column order lists all points of v-column 0 first (along u).
// Rows run along u (span, hub -> tip), columns along v (chord), as in
// core/geometry/point_grid.h.
//
// Every error is a DataError "<file>:<line>: <what was expected>".
#include <optional>
#include <string>

#include "core/geometry/point_grid.h"

namespace bliskrun {

enum class GridOrder { kRowMajor, kColumnMajor };

struct PointGridReadOptions {
  std::optional<int> rows;
  std::optional<int> cols;
  std::optional<GridOrder> order;  // default row-major when neither says
};

// Parses `text` as the contents of a file named `file_label` (used only in
// messages).
PointGrid parse_point_grid(const std::string& text, const std::string& file_label,
                           const PointGridReadOptions& opts = {});

// Reads `path`; DataError(path, 0, ...) if it cannot be read.
PointGrid read_point_grid(const std::string& path, const PointGridReadOptions& opts = {});

// Writes the grid with a "# grid ROWS COLS order=row" header, row-major, with
// 17 significant digits so that reading it back gives the same doubles.
// Written with write_file_atomic.
void write_point_grid(const PointGrid& grid, const std::string& path);

// The text write_point_grid writes.
std::string format_point_grid(const PointGrid& grid);

}  // namespace bliskrun
