#include "core/machine/robot.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/common/error.h"

namespace bliskrun {

namespace {

Mat3 rot_z(double a) { return Eigen::AngleAxisd(a, Vec3::UnitZ()).toRotationMatrix(); }
Mat3 rot_y(double a) { return Eigen::AngleAxisd(a, Vec3::UnitY()).toRotationMatrix(); }

using OpwAngles = std::array<double, 6>;

OpwAngles to_opw(const RobotArm& arm, const JointAngles& q) {
  OpwAngles t{};
  for (int i = 0; i < 6; ++i) t[i] = arm.joints[i].zero_rad + arm.joints[i].sign * q[i];
  return t;
}

double to_joint(const RobotJoint& j, double theta) { return j.sign * (theta - j.zero_rad); }

// Forearm length from axis 3 to the wrist centre and its angle off the
// forearm's own direction (the wrist offset a2 across it).
double forearm_k(const OpwGeometry& g) { return std::hypot(g.a2_mm, g.c3_mm); }
double forearm_psi(const OpwGeometry& g) { return std::atan2(g.a2_mm, g.c3_mm); }

Vec3 wrist_centre(const OpwGeometry& g, const OpwAngles& t) {
  const double k = forearm_k(g), psi = forearm_psi(g);
  const Vec3 in_plane(g.a1_mm + g.c2_mm * std::sin(t[1]) + k * std::sin(t[1] + t[2] + psi), g.b_mm,
                      g.c1_mm + g.c2_mm * std::cos(t[1]) + k * std::cos(t[1] + t[2] + psi));
  return rot_z(t[0]) * in_plane;
}

// The angle + 2πn nearest `towards`.
double nearest_turn(double angle, double towards) {
  return angle + 2 * kPi * std::round((towards - angle) / (2 * kPi));
}

// Joint value equivalent to `q` (mod 2π), nearest `towards`, moved within the
// limits by whole turns when that is possible.
double unwrap_joint(const RobotJoint& j, double q, double towards) {
  double best = nearest_turn(q, towards);
  if (best >= j.min_rad && best <= j.max_rad) return best;
  double chosen = best, distance = 1e300;
  for (double c = nearest_turn(q, j.min_rad) - 2 * kPi; c <= j.max_rad + 2 * kPi; c += 2 * kPi) {
    if (c < j.min_rad || c > j.max_rad) continue;
    if (std::abs(c - towards) < distance) {
      distance = std::abs(c - towards);
      chosen = c;
    }
  }
  return chosen;
}

}  // namespace

void RobotArm::validate() const {
  const OpwGeometry& g = geometry;
  const std::pair<const char*, double> lengths[] = {{"a1", g.a1_mm}, {"a2", g.a2_mm}, {"b", g.b_mm},
                                                    {"c1", g.c1_mm}, {"c2", g.c2_mm}, {"c3", g.c3_mm},
                                                    {"c4", g.c4_mm}};
  for (const auto& [key, v] : lengths)
    if (!std::isfinite(v)) throw ParameterError(key, "expected a finite length in mm");
  if (!(g.c2_mm > 0)) throw ParameterError("c2", "expected the upper arm's length > 0");
  if (!(g.c3_mm > 0)) throw ParameterError("c3", "expected the forearm's length > 0");
  if (!(g.c4_mm >= 0)) throw ParameterError("c4", "expected the wrist-to-flange length >= 0");
  for (int i = 0; i < 6; ++i) {
    const RobotJoint& j = joints[i];
    const std::string key = "joints[" + std::to_string(i + 1) + "]";
    if (j.sign != 1 && j.sign != -1) throw ParameterError(key + ".sign", "expected 1 or -1");
    if (!std::isfinite(j.zero_rad)) throw ParameterError(key + ".zero", "expected a finite angle");
    if (!(std::isfinite(j.min_rad) && std::isfinite(j.max_rad) && j.min_rad < j.max_rad))
      throw ParameterError(key + ".limits", "expected finite limits with min < max");
    if (!(j.max_speed_rad_s > 0 && std::isfinite(j.max_speed_rad_s)))
      throw ParameterError(key + ".speed", "expected a joint speed > 0");
  }
}

std::array<double, 6> robot_opw_angles(const RobotArm& arm, const JointAngles& joints) { return to_opw(arm, joints); }

Vec3 robot_wrist_centre(const RobotArm& arm, const JointAngles& joints) {
  return wrist_centre(arm.geometry, to_opw(arm, joints));
}

Frame robot_forward(const RobotArm& arm, const JointAngles& joints) {
  const OpwAngles t = to_opw(arm, joints);
  const Mat3 r = rot_z(t[0]) * rot_y(t[1] + t[2]) * rot_z(t[3]) * rot_y(t[4]) * rot_z(t[5]);
  Frame f = Frame::Identity();
  f.linear() = r;
  f.translation() = wrist_centre(arm.geometry, t) + arm.geometry.c4_mm * r.col(2);
  return f;
}

std::vector<RobotSolution> robot_inverse(const RobotArm& arm, const Frame& flange, const RobotIkOptions& options) {
  const OpwGeometry& g = arm.geometry;
  const Mat3 r = flange.linear();
  const Vec3 c = flange.translation() - g.c4_mm * r.col(2);
  const double k = forearm_k(g), psi = forearm_psi(g);

  // θ4 kept at the singularity: the previous one's OPW angle.
  const double previous_t4 =
      options.previous ? arm.joints[3].zero_rad + arm.joints[3].sign * (*options.previous)[3] : 0.0;

  std::vector<RobotSolution> out;
  const double planar_sq = c.x() * c.x() + c.y() * c.y() - g.b_mm * g.b_mm;
  if (planar_sq < -1e-9) return out;  // the wrist centre lies inside the sideways offset's circle
  const double planar = std::sqrt(std::max(0.0, planar_sq));
  for (int shoulder = 0; shoulder < 2; ++shoulder) {
    // The arm plane's forward distance: + in front of axis 1, - behind it.
    const double x = shoulder == 0 ? planar : -planar;
    const double t1 = std::atan2(c.y(), c.x()) - std::atan2(g.b_mm, x);
    // In the arm plane, from axis 2: (nx, nz), measured from Z towards X.
    const double nx = x - g.a1_mm, nz = c.z() - g.c1_mm;
    const double s_sq = nx * nx + nz * nz;
    double cos_elbow = (s_sq - g.c2_mm * g.c2_mm - k * k) / (2 * g.c2_mm * k);
    if (std::abs(cos_elbow) > 1 + 1e-12) continue;  // beyond (or within) the arm's reach
    cos_elbow = std::clamp(cos_elbow, -1.0, 1.0);
    for (int elbow = 0; elbow < 2; ++elbow) {
      // φ = θ3 + ψ3: the forearm's turn off the upper arm.
      const double phi = elbow == 0 ? std::acos(cos_elbow) : -std::acos(cos_elbow);
      const double t3 = phi - psi;
      const double t2 = std::atan2(nx, nz) - std::atan2(k * std::sin(phi), g.c2_mm + k * std::cos(phi));
      // The wrist's own rotation, as ZYZ angles θ4, θ5, θ6.
      const Mat3 w = (rot_z(t1) * rot_y(t2 + t3)).transpose() * r;
      const double sin5 = std::hypot(w(0, 2), w(1, 2));
      const bool singular = sin5 < options.singular_tolerance;
      for (int flip = 0; flip < 2; ++flip) {
        double t4, t5, t6;
        if (singular) {
          // Only θ4 + θ6 (θ5 ≈ 0) or θ4 − θ6 (θ5 ≈ π) is fixed: keep θ4.
          t4 = previous_t4 + (flip ? kPi : 0.0);
          if (w(2, 2) > 0) {
            t5 = 0;
            t6 = std::atan2(w(1, 0), w(0, 0)) - t4;
          } else {
            t5 = flip ? -kPi : kPi;
            t6 = t4 - std::atan2(-w(1, 0), -w(0, 0));
          }
        } else {
          t5 = std::atan2(sin5, w(2, 2));
          t4 = std::atan2(w(1, 2), w(0, 2));
          t6 = std::atan2(w(2, 1), -w(2, 0));
          if (flip) {
            t5 = -t5;
            t4 += kPi;
            t6 += kPi;
          }
        }
        const OpwAngles t = {t1, t2, t3, t4, t5, t6};
        RobotSolution s;
        s.branch = shoulder * 4 + elbow * 2 + flip;
        s.wrist_singular = singular;
        for (int i = 0; i < 6; ++i) {
          const RobotJoint& j = arm.joints[i];
          const double towards = options.previous ? (*options.previous)[i] : 0.5 * (j.min_rad + j.max_rad);
          s.joints[i] = unwrap_joint(j, to_joint(j, t[i]), towards);
          if (s.within_limits && (s.joints[i] < j.min_rad || s.joints[i] > j.max_rad)) {
            s.within_limits = false;
            s.violated_joint = i;
            s.violated_value_rad = s.joints[i];
          }
        }
        out.push_back(s);
      }
    }
  }
  return out;
}

double robot_joint_move_time(const RobotArm& arm, const JointAngles& a, const JointAngles& b) {
  double t = 0;
  for (int i = 0; i < 6; ++i) t = std::max(t, std::abs(b[i] - a[i]) / arm.joints[i].max_speed_rad_s);
  return t;
}

std::optional<RobotSolution> robot_choose(const RobotArm& arm, const std::vector<RobotSolution>& solutions,
                                          const JointAngles& previous, int previous_branch) {
  const RobotSolution* best = nullptr;
  double best_time = 1e300;
  for (const RobotSolution& s : solutions) {
    if (!s.within_limits) continue;
    const double t = robot_joint_move_time(arm, previous, s.joints);
    if (t < best_time) {
      best_time = t;
      best = &s;
    }
  }
  if (!best) return std::nullopt;
  // Staying on the branch is worth 1 %: a branch change at a tie would flip
  // the arm's configuration for nothing (and change ABB's confdata).
  for (const RobotSolution& s : solutions)
    if (s.within_limits && s.branch == previous_branch &&
        robot_joint_move_time(arm, previous, s.joints) <= best_time * 1.01 + 1e-12)
      return s;
  return *best;
}

}  // namespace bliskrun
