#pragma once
// The best ruled surface through a blade face given as a point grid (issue 12
// item 2): a shop decides from the fit whether a face may be flank milled.
//
// The rulings run along the grid's span columns (rows hub -> tip): each
// column's points get their least-squares line (through the centroid, along
// the principal direction), and the ruled surface joins the lines' hub and
// tip ends (the feet of the first and last fitted row), each end curve a
// cubic through the column ends at averaged chord-length parameters. Keeping
// each ruling in its column bounds the best ruled fit from above: a ruling
// free to cross columns could only fit as well or better.
#include <memory>

#include "core/geometry/point_grid.h"
#include "core/geometry/surface.h"

namespace bliskrun {

struct RuledFit {
  double max_mm = 0;   // largest distance of a fitted grid point from its column's line
  double rms_mm = 0;
  int worst_row = -1, worst_col = -1;
  // u along the rulings (u = 0 at the first fitted row's foot, 1 at the
  // last's; linear, so it extends past both), v along the columns. Same
  // orientation as the grid (pu x pv as the grid's surface).
  std::shared_ptr<const Surface> surface;
};

// Fits rows [row0, row1] (0-based, at least 2 rows, at least 4 columns).
// Throws ParameterError("rows") for a bad row range.
RuledFit fit_ruled(const PointGrid& grid, int row0, int row1);

}  // namespace bliskrun
