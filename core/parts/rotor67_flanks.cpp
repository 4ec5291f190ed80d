#include "core/parts/rotor67_flanks.h"

#include <utility>

#include "core/parts/blade_model.h"

namespace bliskrun {

RotorFlanks rotor_flank_grids(const StreamSurfaceRotor& rotor, int cols, double margin) {
  LoftOptions o;
  o.cols = cols;
  o.edge_margin = margin;
  o.span_extension = 0;  // rows are the stream surfaces
  BladeLoft loft = loft_blade(blade_sections(rotor), o);
  return {std::move(loft.pressure), std::move(loft.suction)};
}

}  // namespace bliskrun
