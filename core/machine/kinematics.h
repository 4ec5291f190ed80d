#pragma once
// Forward and inverse kinematics of a 5-axis machine (see machine_definition.h
// for frames and chain conventions).
//
// Orientation. Whatever the configuration, the tool axis in the part frame is
//     k = R(d1, s1*t1) * R(d2, s2*t2) * spindle
// where the factors are the table axes from the part outwards (angles negated:
// the table turns the part, not the tool) followed by the head axes from the
// base inwards. d1 is the *primary* axis (C on A/C, B/C trunnions, C on a
// head-table with a C table, C on a C/B head). Solving R(d2) first from the
// component of k along d1 gives two secondary angles t2 = phi +- gamma, and for
// each the primary angle that turns the result onto k: the two solutions of
// every 5-axis machine. When k is parallel to d1 the primary angle is free (the
// singularity): the previous primary angle is kept, so the machine passes
// through the pole without turning the primary axis.
//
// Choice. Each solution's angles are unwrapped to the equivalent (angle +
// 2*pi*n) nearest the previous move that lies within travel; solutions outside
// travel are dropped, the remaining one with the smallest total rotary motion
// wins. Then the linear axes follow in closed form from the tip.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/common/types.h"
#include "core/machine/machine_definition.h"
#include "core/tools/pose.h"  // ToolPose: tip + unit axis, part frame

namespace bliskrun {

// Machine axis positions, in the order of MachineDefinition::linear / rotary.
struct MachineAxes {
  Vec3 linear_mm = Vec3::Zero();
  std::array<double, 2> rotary_rad{0.0, 0.0};
};

// One rotary solution of the orientation problem, after unwrapping.
struct RotarySolution {
  std::array<double, 2> rotary_rad{0.0, 0.0};
  bool singular = false;     // tool axis parallel to the primary axis
  bool within_limits = true;
  // When outside travel: the axis that is, and the value it would need.
  int violated_axis = -1;
  double violated_value_rad = 0.0;
};

class Kinematics {
 public:
  // `tool_length_mm`: tip to spindle gauge point, used by the tool-length
  // convention and by head pivots. Validates the machine.
  Kinematics(MachineDefinition machine, double tool_length_mm);

  const MachineDefinition& machine() const { return machine_; }
  double tool_length_mm() const { return tool_length_mm_; }
  int primary_axis() const { return primary_; }      // index into machine().rotary
  int secondary_axis() const { return secondary_; }

  // Tool tip and axis in the part frame for the given machine axes.
  ToolPose forward(const MachineAxes& axes) const;
  // Tool axis in the part frame for the given rotary angles.
  Vec3 tool_axis(const std::array<double, 2>& rotary_rad) const;
  // Linear axes that bring the tip to `tip` (part frame) at these rotaries.
  Vec3 linear_for(const Vec3& tip, const std::array<double, 2>& rotary_rad) const;

  // Both rotary solutions for `axis` (part frame, normalised here), unwrapped
  // towards `previous` and checked against travel. Empty if no rotation of
  // this machine gives the axis (e.g. beyond a fork's reach). Solutions that
  // coincide are reported once. Throws ParameterError("axis") on a zero or
  // non-finite axis.
  std::vector<RotarySolution> rotary_solutions(const Vec3& axis,
                                               const std::array<double, 2>& previous_rad) const;

  // Full inverse kinematics with branch choice by travel and continuity.
  // Throws ParameterError naming the machine axis ("A", "X", ...) and the
  // value it would need when the pose is out of reach.
  MachineAxes inverse(const ToolPose& pose, const MachineAxes& previous) const;

  // Whether some rotary position within travel gives this tool axis — the
  // question the interference loop asks before accepting a tilt (blisk paper
  // §2.2: C in [-30, +30] deg).
  bool reachable(const Vec3& axis) const;

  // Largest distance from `tip` (part frame, at these axes) to any rotary
  // axis line: the lever arm that turns a rotary error into a tip error.
  double lever_arm_mm(const MachineAxes& axes) const;
  // Largest distance from the tip to any rotary pivot point (a bound for the
  // tip's motion when the rotaries turn).
  double pivot_reach_mm(const MachineAxes& axes) const;

  // The Z word of the safe height (MachineDefinition::safe_z_mm, or the top
  // of the Z slide's travel for this tool). Throws ParameterError("safe_z")
  // when neither is stated.
  double safe_z_mm() const;
  // |cos| of the angle between the two rotary axis lines: constant in any
  // position (an axis carried by another turns about it, keeping the angle),
  // so the relative angular speed of tool and part is at most
  // sqrt(w1^2 + w2^2 + 2 |w1 w2| rotary_axes_cos()).
  double rotary_axes_cos() const;

 private:
  Eigen::Isometry3d part_to_machine(const std::array<double, 2>& rotary_rad) const;
  Eigen::Isometry3d head_map(const std::array<double, 2>& rotary_rad) const;

  MachineDefinition machine_;
  double tool_length_mm_;
  int primary_ = 0, secondary_ = 1;
  double primary_sign_ = 1, secondary_sign_ = 1;  // -1 for table axes
  std::vector<int> part_axes_, tool_axes_;        // chain order, base outwards
  Vec3 tip_local_ = Vec3::Zero();                  // tool tip relative to XYZ at home
  Vec3 gauge_local_ = Vec3::Zero();
};

}  // namespace bliskrun
