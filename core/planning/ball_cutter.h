#pragma once
// What the ball-end planners (the hub finish, point milling) read from a
// ball or tapered ball end's profile: the ball's radius and the taper's half
// angle. One place, so both planners agree on the tool they cut with.
#include "core/tools/tool.h"

namespace bliskrun {

// The ball's radius: the tip's radius of curvature (R^2 = 2 r z - z^2 on
// the ball; a tapered ball's cutter is wider above it).
double ball_radius(const Tool& tool);
// The taper's half angle: the cone's slope near the top of the flute (0 for
// a plain ball end's cylinder).
double taper_rad(const Tool& tool);

}  // namespace bliskrun
