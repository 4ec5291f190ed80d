#pragma once
// Tool poses and the tool frame.
//
// A pose is the tool's reference point (tip or centre, as each tool defines
// it; see tool.h) and the unit axis pointing from the reference point up the
// tool towards the shank. Every tool is a solid of revolution, so the pose
// fixes the occupied space; the rotation about the axis is free and
// tool_frame() picks one deterministically.
//
// Lives in core/tools because a pose is meaningless without the tool it
// places; planning, collision and machines include this header.
#include <Eigen/Geometry>

#include "core/common/types.h"

namespace bliskrun {

struct ToolPose {
  Vec3 tip = Vec3::Zero();       // reference point, part frame, mm
  Vec3 axis = Vec3::UnitZ();     // unit, part frame, towards the shank
};

// Rigid transform from the tool frame (origin at the reference point, +Z up
// the axis) to the part frame. X and Y complete the frame by the minimal
// rotation taking +Z to the axis. Throws ParameterError("axis") if the axis
// is zero or not finite; a non-unit axis is normalised.
Eigen::Isometry3d tool_to_part(const ToolPose& pose);

// Returns `axis` normalised; throws ParameterError(name) when it cannot be.
Vec3 unit_axis(const Vec3& axis, const char* name = "axis");

// Angle between two unit axes, radians in [0, pi].
double axis_angle_rad(const Vec3& a, const Vec3& b);

// The motion between two poses as the blisk paper's machine makes it
// (§3.4: "linear interpolation from the previous pose to the next"): the
// reference point moves on the straight segment, the axis turns at constant
// rate in the plane of the two axes. The axes must not be opposite.
class PoseMotion {
 public:
  PoseMotion(const ToolPose& from, const ToolPose& to);

  // Pose at t in [0, 1]; the rotation part is the minimal rotation of
  // tool_to_part(from) carrying its axis along the great circle.
  Eigen::Isometry3d frame_at(double t) const;
  ToolPose pose_at(double t) const;

  // Upper bound of the speed (mm per unit t) of any tool point within
  // `reach_mm` of the reference point: |Δtip| + θ·reach (the rotation moves
  // a point at distance ρ from the rotation's fixed point by at most θ·ρ).
  double max_point_speed(double reach_mm) const {
    return translation_mm_ + angle_rad_ * reach_mm;
  }
  double angle_rad() const { return angle_rad_; }
  double translation_mm() const { return translation_mm_; }

 private:
  Eigen::Isometry3d from_frame_;
  Vec3 tip_from_, tip_to_;
  Vec3 rotation_axis_ = Vec3::UnitZ();
  double angle_rad_ = 0;
  double translation_mm_ = 0;
};

}  // namespace bliskrun
