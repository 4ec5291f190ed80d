#pragma once
// Basic value types shared by every subsystem.
//
// Units inside core: lengths in millimetres, angles in radians. The Lua
// boundary converts degrees to radians (see lua_api/).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <vector>

namespace bliskrun {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDeg = kPi / 180;  // one degree in radians: 5 * kDeg
inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline double deg_to_rad(double deg) { return deg * kPi / 180.0; }
inline double rad_to_deg(double rad) { return rad * 180.0 / kPi; }
// An angle wrapped to (-pi, pi].
inline double wrap_angle(double rad) {
  const double a = std::remainder(rad, 2 * kPi);  // [-pi, pi]
  return a <= -kPi ? a + 2 * kPi : a;
}
// p turned by a radians about the origin.
inline Vec2 rotate(const Vec2& p, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return Vec2(c * p.x() - s * p.y(), s * p.x() + c * p.y());
}

}  // namespace bliskrun
