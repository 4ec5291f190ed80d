#pragma once
// Six-axis industrial arms: forward and inverse kinematics (robot belt
// grinding, SPEC §6.3).
//
// The arms bliskrun drives (ABB IRB 6650S, KUKA KR 120 class) are
// ortho-parallel with a spherical wrist: axes 2 and 3 parallel and
// orthogonal to axis 1, axes 4, 5, 6 meeting in one point, the wrist centre.
// Seven lengths describe them (Brandstötter, Angerer, Hofbaur, "An analytical
// solution of the inverse kinematics problem of industrial serial
// manipulators with an ortho-parallel basis and a spherical wrist", 2014):
//
//     a1  axis 2 ahead of axis 1          c1  axis 2 above the base
//     a2  wrist offset across the forearm c2  upper arm (axis 2 to axis 3)
//     b   sideways offset of the arm      c3  forearm (axis 3 to the wrist centre)
//                                         c4  wrist centre to the flange
//
// In these "OPW angles" θ, all zero means the arm standing straight up with
// the flange facing +Z; the base frame has Z up and X forward. Positive θ2,
// θ3 lean the arm forward. Then
//     wrist centre C = Rz(θ1) (a1 + c2 sin θ2 + k sin(θ2+θ3+ψ3), b,
//                              c1 + c2 cos θ2 + k cos(θ2+θ3+ψ3)),
//     k = √(a2² + c3²), ψ3 = atan2(a2, c3),
//     flange frame R = Rz(θ1) Ry(θ2+θ3) · Rz(θ4) Ry(θ5) Rz(θ6),
//     flange origin = C + c4 · R ẑ.
// Inverse: C from the flange; θ1 two ways (shoulder in front of or behind
// axis 1), θ2/θ3 two ways each (elbow up or down, law of cosines in the arm
// plane), the wrist two ways (θ5 positive or negative, ZYZ angles of the
// wrist rotation): up to 8 solutions, all returned.
//
// A controller's joint values q differ from OPW angles by a zero and a
// direction per joint: θ = zero + sign · q (RobotJoint). Machine files give
// both, so the same solver serves ABB's and KUKA's conventions.
//
// Wrist singularity: when sin θ5 ≈ 0, axes 4 and 6 line up and only θ4 ± θ6
// is determined. The solver keeps θ4 where it was (the previous joints) and
// gives the whole rotation to θ6, and flags the solution, so a path through
// the singularity does not spin axis 4.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/common/types.h"

namespace bliskrun {

using Frame = Eigen::Isometry3d;
using JointAngles = std::array<double, 6>;  // the controller's joint values, rad

struct OpwGeometry {
  double a1_mm = 0, a2_mm = 0, b_mm = 0;
  double c1_mm = 0, c2_mm = 0, c3_mm = 0, c4_mm = 0;
};

struct RobotJoint {
  double zero_rad = 0;  // OPW angle θ at the controller's joint zero
  int sign = 1;         // +1 when the controller's positive direction is OPW's
  double min_rad = -kPi;
  double max_rad = kPi;
  double max_speed_rad_s = 1.0;
};

struct RobotArm {
  std::string name;
  OpwGeometry geometry;
  std::array<RobotJoint, 6> joints;
  // Throws ParameterError naming the field: lengths finite, c2, c3 > 0 and
  // c4 >= 0, signs ±1, min < max, speeds > 0.
  void validate() const;
};

// One inverse-kinematics solution.
struct RobotSolution {
  JointAngles joints{};
  // The branch, 0..7: bit 2 shoulder behind axis 1, bit 1 elbow down, bit 0
  // wrist flipped (θ5 < 0). A path keeps its branch unless it must change.
  int branch = 0;
  bool wrist_singular = false;  // |sin θ5| below the tolerance
  bool within_limits = true;
  int violated_joint = -1;      // 0-based, when outside the limits
  double violated_value_rad = 0;
};

// Flange frame in the robot base frame (mm) for the controller's joints.
Frame robot_forward(const RobotArm& arm, const JointAngles& joints);

// Wrist centre in the base frame (the point axes 4, 5, 6 meet).
Vec3 robot_wrist_centre(const RobotArm& arm, const JointAngles& joints);

// The OPW angles θ of the controller's joints (θ = zero + sign · q), for
// definitions stated in the arm's geometry (a controller's status bits).
std::array<double, 6> robot_opw_angles(const RobotArm& arm, const JointAngles& joints);

struct RobotIkOptions {
  // Joint values each solution is unwrapped towards (angle + 2πn nearest,
  // within the limits when one is), and whose θ4 is kept at the singularity.
  std::optional<JointAngles> previous;
  double singular_tolerance = 1e-4;  // |sin θ5| below which the wrist is singular
};

// Every solution (up to 8) that puts the flange at `flange`, limits marked,
// not filtered. Empty when the wrist centre is out of the arm's reach.
std::vector<RobotSolution> robot_inverse(const RobotArm& arm, const Frame& flange,
                                         const RobotIkOptions& options = {});

// The solution to move to from `previous`: within the limits, fewest seconds
// at full joint speed (the slowest joint decides), the same branch preferred
// when it is within 1 % of the best. nullopt when none is within the limits.
std::optional<RobotSolution> robot_choose(const RobotArm& arm, const std::vector<RobotSolution>& solutions,
                                          const JointAngles& previous, int previous_branch = -1);

// Seconds the slowest joint needs to go from `a` to `b` at full speed.
double robot_joint_move_time(const RobotArm& arm, const JointAngles& a, const JointAngles& b);

}  // namespace bliskrun
