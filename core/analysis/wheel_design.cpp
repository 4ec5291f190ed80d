#include "core/analysis/wheel_design.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/common/error.h"

namespace bliskrun {

namespace {

void require_positive(const char* name, double value) {
  if (!(value > 0) || !std::isfinite(value)) {
    std::ostringstream msg;
    msg << "expected a positive finite number, got " << value;
    throw ParameterError(name, msg.str());
  }
}

double sized(const char* name, double limit, double step) {
  const double size = largest_multiple_below(limit, step);
  if (!(size > 0)) {
    std::ostringstream msg;
    msg << "no size that is a multiple of " << step << " mm fits below the limit of " << limit
        << " mm";
    throw ParameterError(name, msg.str());
  }
  return size;
}

}  // namespace

double largest_multiple_below(double limit, double step) {
  // Relative slack so that a limit that is a multiple up to rounding (e.g.
  // 8.000000000001) still counts as "equal" and is excluded.
  const double n = std::ceil(limit / step - 1e-9) - 1;
  return n > 0 ? n * step : 0.0;
}

WheelDesign design_drum_wheel(const WheelDesignInput& in, const WheelDesignOptions& opts) {
  require_positive("k1_max", in.k1_max_per_mm);
  require_positive("ke_max", in.ke_max_per_mm);
  require_positive("d_min", in.d_min_mm);
  require_positive("diameter_step", opts.diameter_step_mm);
  require_positive("drum_radius_step", opts.drum_radius_step_mm);
  if (!(opts.passage_clearance_mm >= 0) || !std::isfinite(opts.passage_clearance_mm))
    throw ParameterError("passage_clearance", "expected a finite number >= 0");
  if (in.ke_max_per_mm > in.k1_max_per_mm * (1 + 1e-12))
    throw ParameterError("ke_max", "k_e is a normal curvature and cannot exceed k1 max (eq. 14)");

  const double diameter_limit =
      std::min(2.0 / in.k1_max_per_mm, in.d_min_mm - opts.passage_clearance_mm);
  const double diameter = sized("passage_clearance", diameter_limit, opts.diameter_step_mm);

  WheelDesign out;
  out.traditional.radius_limit_mm = 1.0 / in.k1_max_per_mm;
  out.traditional.drum_radius_mm =
      sized("k1_max", out.traditional.radius_limit_mm, opts.drum_radius_step_mm);
  out.extended.radius_limit_mm = 1.0 / in.ke_max_per_mm;
  out.extended.drum_radius_mm =
      sized("ke_max", out.extended.radius_limit_mm, opts.drum_radius_step_mm);
  for (WheelChoice* c : {&out.traditional, &out.extended}) {
    c->diameter_limit_mm = diameter_limit;
    c->diameter_mm = diameter;
  }
  return out;
}

}  // namespace bliskrun
