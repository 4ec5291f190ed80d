#include "core/collision/fast_check.h"

#include <cmath>
#include <limits>

#include "core/collision/collision_world.h"

namespace bliskrun {

FastCheck fast_check(const Tool& tool, const ToolPose& pose, const std::vector<Vec3>& points,
                     const Clearances& clearances) {
  const Vec3 axis = unit_axis(pose.axis);
  FastCheck out;
  out.min_margin_mm = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < points.size(); ++i) {
    // Only Z and ρ matter for a solid of revolution, so the rotation T of
    // eq. (20) reduces to a projection on the axis.
    const Vec3 rel = points[i] - pose.tip;
    const double z = rel.dot(axis);
    const double rho = (rel - z * axis).norm();
    for (int k = 0; k < kToolPartCount; ++k) {
      const auto id = static_cast<ToolPartId>(k);
      if (!tool.has(id)) continue;
      const Profile& p = tool.profile(id);
      if (z < p.z_min() || z > p.z_max()) continue;
      const double margin = rho - p.radius_at(z) - clearances.of(id);
      if (margin < out.min_margin_mm) out.min_margin_mm = margin;
      if (margin < 0) {
        if (out.conflicts == 0) {
          out.first_conflict = static_cast<long>(i);
          out.part = id;
        }
        ++out.conflicts;
        out.clear = false;
        break;
      }
    }
  }
  return out;
}

}  // namespace bliskrun
