#include "core/tools/pose.h"

#include <algorithm>
#include <cmath>

#include "core/common/error.h"

namespace bliskrun {

Vec3 unit_axis(const Vec3& axis, const char* name) {
  const double n = axis.norm();
  if (!std::isfinite(n) || n < 1e-12) {
    throw ParameterError(name, "tool axis must be a finite non-zero vector");
  }
  return axis / n;
}

Eigen::Isometry3d tool_to_part(const ToolPose& pose) {
  const Vec3 a = unit_axis(pose.axis);
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  // FromTwoVectors picks an arbitrary perpendicular for the half turn, but
  // deterministically; every tool is axisymmetric so any choice is valid.
  frame.linear() = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), a).toRotationMatrix();
  if (!pose.tip.allFinite()) throw ParameterError("tip", "tool reference point must be finite");
  frame.translation() = pose.tip;
  return frame;
}

double axis_angle_rad(const Vec3& a, const Vec3& b) {
  // atan2 of |a×b| and a·b keeps precision for tiny angles, unlike acos.
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

PoseMotion::PoseMotion(const ToolPose& from, const ToolPose& to)
    : from_frame_(tool_to_part(from)), tip_from_(from.tip), tip_to_(to.tip) {
  const Vec3 a = unit_axis(from.axis, "from.axis");
  const Vec3 b = unit_axis(to.axis, "to.axis");
  if (!to.tip.allFinite()) throw ParameterError("to.tip", "tool reference point must be finite");
  angle_rad_ = axis_angle_rad(a, b);
  translation_mm_ = (tip_to_ - tip_from_).norm();
  const Vec3 n = a.cross(b);
  if (n.norm() > 1e-15) {
    rotation_axis_ = n.normalized();
  } else if (angle_rad_ > 1.0) {
    throw ParameterError("to.axis", "the axis reverses between consecutive poses; the motion is undefined");
  }
}

Eigen::Isometry3d PoseMotion::frame_at(double t) const {
  Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
  f.linear() = Eigen::AngleAxisd(angle_rad_ * t, rotation_axis_).toRotationMatrix() *
               from_frame_.linear();
  f.translation() = tip_from_ + t * (tip_to_ - tip_from_);
  return f;
}

ToolPose PoseMotion::pose_at(double t) const {
  const Eigen::Isometry3d f = frame_at(t);
  return ToolPose{f.translation(), f.linear().col(2)};
}

}  // namespace bliskrun
