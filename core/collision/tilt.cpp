#include "core/collision/tilt.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "core/common/error.h"

namespace bliskrun {
namespace {

std::string deg_text(double rad) {
  std::ostringstream os;
  os.precision(4);
  os << rad_to_deg(rad) << " deg";
  return os.str();
}

std::string mm_text(double mm) {
  std::ostringstream os;
  os.precision(4);
  os << mm << " mm";
  return os.str();
}

// Orthonormal X, Y, Z of the contact frame; throws on degenerate input.
void contact_axes(const ContactFrame& f, Vec3& x, Vec3& y, Vec3& z) {
  z = unit_axis(f.normal, "normal");
  const Vec3 t = f.tangent - f.tangent.dot(z) * z;
  if (!(t.norm() > 1e-12)) throw ParameterError("tangent", "path tangent must not be parallel to the surface normal");
  x = t.normalized();
  y = z.cross(x);
}

}  // namespace

double RotaryAxisLimit::angle_rad(const Vec3& axis) const {
  const Vec3 c = rotary_axis.normalized();
  const Vec3 in_plane = axis - axis.dot(c) * c;
  if (in_plane.norm() < 1e-12) return std::numeric_limits<double>::quiet_NaN();
  const Vec3 ref = reference.normalized();
  return std::atan2(ref.cross(in_plane).dot(c), ref.dot(in_plane));
}

std::string RotaryAxisLimit::violation(const Vec3& axis) const {
  const double a = angle_rad(axis);
  if (std::isnan(a) || (a >= min_rad - 1e-12 && a <= max_rad + 1e-12)) return "";
  return "axis limit: " + name + " = " + deg_text(a) + " outside [" + deg_text(min_rad) + ", " +
         deg_text(max_rad) + "]";
}

AxisLimit make_axis_limit(const RotaryAxisLimit& limit) {
  const Vec3 c = unit_axis(limit.rotary_axis, "rotary_axis");
  const Vec3 r = unit_axis(limit.reference, "reference");
  if (std::abs(c.dot(r)) > 1e-9) throw ParameterError("reference", "must be perpendicular to the rotary axis");
  if (!(limit.min_rad <= limit.max_rad)) throw ParameterError("min", "rotary axis range needs min <= max");
  return [limit](const Vec3& axis) { return limit.violation(axis); };
}

Vec3 axis_from_lead_tilt(const ContactFrame& frame, double lead_rad, double tilt_rad) {
  Vec3 x, y, z;
  contact_axes(frame, x, y, z);
  return std::cos(lead_rad) * (-std::sin(tilt_rad) * x + std::cos(tilt_rad) * y) + std::sin(lead_rad) * z;
}

ToolPose place_tool(const Tool& tool, const ContactFrame& frame, const Vec3& axis_in) {
  const Vec3 a = unit_axis(axis_in);
  const Vec3 n = unit_axis(frame.normal, "normal");
  // The cutter touches with its outward normal opposite the surface normal.
  const Vec3 m = -n;
  const double mz = m.dot(a);
  const Vec3 radial = m - mz * a;
  const double mr = radial.norm();
  const ProfilePoint c = tool.cutter().point_with_normal(Vec2(mr, mz));
  Vec3 e_r = Vec3::Zero();
  if (mr > 1e-12) {
    e_r = radial / mr;
  } else if (c.point.x() > 0) {
    e_r = a.unitOrthogonal();  // any meridian touches a flat face
  }
  return ToolPose{frame.point - c.point.y() * a - c.point.x() * e_r, a};
}

TiltOutcome tilt_until_clear(const CollisionWorld& world, const ToolBody& body, const ContactFrame& contact,
                             int index, const TiltSettings& s, const ToolPose* previous) {
  if (!(s.lead_step_rad != 0)) throw ParameterError("lead_step", "must be a non-zero angle");
  if (s.allow_tilt && !(s.tilt_step_rad > 0)) throw ParameterError("tilt_step", "must be a positive angle");
  if (!((s.lead_max_rad - s.lead0_rad) * s.lead_step_rad >= 0))
    throw ParameterError("lead_max", s.lead_step_rad > 0 ? "must not be below the initial lead"
                                                         : "must not be above the initial lead (lead_step < 0)");
  if (s.allow_tilt && !(s.tilt_range_rad >= 0)) throw ParameterError("tilt_range", "must be a non-negative angle");

  std::vector<double> tilts{s.tilt0_rad};
  if (s.allow_tilt) {
    for (int k = 1; k * s.tilt_step_rad <= s.tilt_range_rad + 1e-12; ++k) {
      tilts.push_back(s.tilt0_rad + k * s.tilt_step_rad);
      tilts.push_back(s.tilt0_rad - k * s.tilt_step_rad);
    }
  }
  const int lead_count = static_cast<int>(std::floor((s.lead_max_rad - s.lead0_rad) / s.lead_step_rad + 1e-9)) + 1;

  int tries = 0, beyond_limit = 0, filtered = 0, interfering = 0, motion_blocked = 0;
  // The refusal names the last interference found and the first axis the
  // machine cannot reach: together they say what would have to change.
  std::string last_interference, first_beyond_limit, last_filtered;
  for (int i = 0; i < lead_count; ++i) {
    const double lead = s.lead0_rad + i * s.lead_step_rad;
    for (double tilt : tilts) {
      ++tries;
      const Vec3 axis = axis_from_lead_tilt(contact, lead, tilt);
      const std::string at = "at lead " + deg_text(lead) + ", tilt " + deg_text(tilt) + ": ";
      if (s.axis_limit) {
        const std::string why = s.axis_limit(axis);
        if (!why.empty()) {
          if (beyond_limit++ == 0) first_beyond_limit = at + why;
          continue;
        }
      }
      const ToolPose pose = place_tool(body.tool(), contact, axis);
      // The operation's own test (either filter): counted, and the last
      // refusal kept for the report.
      auto refused_by = [&](const std::function<std::string(const ToolPose&)>& filter) {
        if (!filter) return false;
        const std::string why = filter(pose);
        if (why.empty()) return false;
        ++filtered;
        last_filtered = at + why;
        return true;
      };
      if (refused_by(s.pose_filter)) continue;
      // Horizon 0: only clear / not clear matters here (fastest query).
      const PoseCheck check = world.check(body, pose, s.clearances, 0);
      if (!check.clear) {
        ++interfering;
        const PartClearance& w = check.parts[check.worst];
        last_interference = at + to_string(w.part) + " " + mm_text(w.distance_mm) + " from '" + world.name(w.object) +
                      "', needs " + mm_text(s.clearances.of(w.part));
        continue;
      }
      if (previous) {
        const MotionCheck motion = world.check_motion(body, *previous, pose, s.clearances, s.motion_tol_mm);
        if (!motion.clear) {
          ++motion_blocked;
          const PartClearance& w = motion.at.parts[motion.at.worst];
          std::ostringstream os;
          os << "motion from the previous pose " << (motion.undecided ? "undecided" : "interferes") << " at t = "
             << motion.t << ": " << to_string(w.part) << " " << mm_text(w.distance_mm) << " from '"
             << world.name(w.object) << "', needs " << mm_text(s.clearances.of(w.part));
          last_interference = at + os.str();
          continue;
        }
      }
      if (refused_by(s.clear_pose_filter)) continue;
      TiltOutcome out;
      out.accepted = true;
      out.pose = TiltAccepted{index, pose, lead, tilt, check, tries};
      return out;
    }
  }
  std::ostringstream os;
  os << "no axis clears: lead " << deg_text(s.lead0_rad) << " to " << deg_text(s.lead_max_rad) << " in "
     << deg_text(s.lead_step_rad) << " steps";
  if (s.allow_tilt) os << ", tilt " << deg_text(s.tilt0_rad) << " ± " << deg_text(s.tilt_range_rad);
  os << "; of " << tries << " axes " << beyond_limit << " beyond the axis limit, ";
  if (s.pose_filter || s.clear_pose_filter) os << filtered << " refused by the operation, ";
  os << interfering
     << " interfere at the pose, " << motion_blocked << " interfere in the motion";
  if (!last_interference.empty()) os << "; last interference " << last_interference;
  if (!first_beyond_limit.empty()) os << "; first beyond the limit " << first_beyond_limit;
  if (!last_filtered.empty()) os << "; last refused by the operation " << last_filtered;
  TiltOutcome out;
  out.refusal = TiltRefusal{index, contact.point, os.str()};
  return out;
}

TiltRun tilt_path(const CollisionWorld& world, const ToolBody& body, const std::vector<ContactFrame>& contacts,
                  const TiltSettings& settings, Progress& progress) {
  TiltRun run;
  progress.begin("tilt until clear", static_cast<long>(contacts.size()));
  for (size_t i = 0; i < contacts.size(); ++i) {
    const ToolPose* previous = run.poses.empty() ? nullptr : &run.poses.back().pose;
    TiltOutcome o = tilt_until_clear(world, body, contacts[i], static_cast<int>(i), settings, previous);
    if (o.accepted) {
      run.poses.push_back(std::move(o.pose));
    } else {
      run.refusals.push_back(std::move(o.refusal));
    }
    progress.step(static_cast<long>(i + 1));
  }
  progress.end();
  return run;
}

}  // namespace bliskrun
