#pragma once
// Robot programs read back and replayed (SPEC §7, issue 15 item 5).
//
// Both dialects program a part-in-hand cell the same way: the grinding wheel
// is a fixed ("stationary", "external") TCP and the blade is a work object
// carried by the robot, so every target is the wheel's contact frame
// expressed in the blade frame, T = blade <- station:
//   ABB RAPID   tooldata with robhold FALSE (the station), wobjdata with
//               robhold TRUE (the blade on the flange); MoveL / MoveJ to
//               robtargets [[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[9E9,...]]
//   KUKA KRL    $IPO_MODE = #TCP, $TOOL the station, $BASE the blade on the
//               flange; LIN / PTP {E6POS: X, Y, Z, A, B, C, S, T} with
//               A, B, C the Z-Y-X angles (deg) and S, T the status and turn.
// The flange for a target follows from the cell: F = S T⁻¹ G⁻¹ (S the
// station's contact frame, G the grip). The configuration the program asks
// for (cfx / S) chooses the branch of the inverse kinematics; cf1/cf4/cf6 (ABB)
// or T (KUKA) the turns. Replaying means: solve each target with the
// program's configuration, compare with the plan the program was written
// from, and put the blade's contact back through the forward kinematics.
#include <array>
#include <string>
#include <vector>

#include "core/machine/robot_cell.h"

namespace bliskrun {

enum class RobotDialect { AbbRapid, KukaKrl };

struct RobotTarget {
  Frame station_in_blade = Frame::Identity();  // T
  int branch = 0;                               // from cfx (ABB) or S (KUKA), core/machine/robot.h's bits
  // ABB: the quadrants cf1, cf4, cf6 (floor(q / 90°)); KUKA: -1 unless the
  // turn bit of the joint is set (then the joint is negative).
  std::array<int, 3> quadrants{0, 0, 0};
  int turn_bits = 0;   // KUKA T: bit i set when joint i+1 < 0
  bool linear = true;  // MoveL / LIN (false: MoveJ / PTP)
  int line = 0;        // of the program text, 1-based
};

// The targets of the program's motion statements in order. Throws Error
// naming the line on a statement it cannot read.
std::vector<RobotTarget> read_robot_program(const std::string& text, RobotDialect dialect);

// Writes the parts a post needs and the reader inverts: the target of a
// planned move, and its configuration fields.
Frame robot_target_frame(const RobotCell& cell, const BeltStation& station, const RobotMove& move);
std::array<int, 3> abb_quadrants(const JointAngles& joints);  // cf1, cf4, cf6
int kuka_turn_bits(const JointAngles& joints);

struct RobotVerifyReport {
  int moves = 0;
  double max_position_mm = 0;   // replayed contact from where the plan puts it (wheel contact or lift-off)
  double max_angle_deg = 0;     // replayed flange orientation from the planned one
  double max_joint_deg = 0;     // replayed joints from the planned ones
  int configuration_flips = 0;  // targets whose configuration is not the plan's
  int unreachable = 0;          // targets no solution with the program's configuration reaches within limits
  std::vector<std::string> problems;  // "line N: ..." for each of the above
};

// Replays `targets` against the plan they were written from (same count and
// order). Tolerances decide what is a problem.
RobotVerifyReport verify_robot_program(const RobotCell& cell, const BeltStation& station,
                                       const RobotGrindingPlan& plan, const std::vector<RobotTarget>& targets,
                                       RobotDialect dialect, double position_tol_mm = 0.002,
                                       double angle_tol_deg = 0.001);

}  // namespace bliskrun
