// The ball and taper of a ball-end profile (core/planning/ball_cutter.h).
#include "core/planning/ball_cutter.h"

#include <cmath>

namespace bliskrun {

double ball_radius(const Tool& tool) {
  const double z = 1e-3 * tool.cutter().z_max();
  const double R = tool.cutter().radius_at(z);
  return (R * R + z * z) / (2 * z);
}

double taper_rad(const Tool& tool) {
  const Profile& p = tool.cutter();
  const double z1 = p.z_min() + 0.8 * (p.z_max() - p.z_min()), z2 = p.z_min() + 0.9 * (p.z_max() - p.z_min());
  return std::atan2(p.radius_at(z2) - p.radius_at(z1), z2 - z1);
}

}  // namespace bliskrun
