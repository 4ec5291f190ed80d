#pragma once
// How long a belt-grinding robot program runs: an estimate from the plan the
// program is written from (robot_cell.h) and the arm's joint speeds, for the
// setup sheet (issue 37 item 3).
//
// The model (a planning figure, not a promise; the robot's own path planner
// decides the real one):
//   - From the cell's home to the first target and from the last back home:
//     joint moves (PTP / MoveJ / MoveAbsJ) at full joint speed, the slowest
//     joint deciding, with the joint's ramp at `joint_accel_rad_s2`.
//   - A grinding path is one continuous motion (LIN / MoveL through its
//     targets with approximation) at the planned contact speed, slowed on
//     a step where a joint would exceed its maximum speed; it starts and
//     ends at rest, so it pays one ramp at `tcp_accel_mm_s2`
//     (rest_to_rest_seconds of cycle_time.h: L/v + v/a for a long path).
//   - Every link move (retract, traverse point, approach) runs from rest to
//     rest at the link speed (each is a corner of the lift-off), likewise
//     slowed where a joint binds.
// The distance of a step is the contact's (or the lift-off point's) travel
// in the blade frame — the path length the feed is programmed on.
#include "core/machine/robot_cell.h"

namespace bliskrun {

struct RobotCycleTimeOptions {
  // Path acceleration of the TCP, mm/s^2. 1 m/s^2 is a moderate value for a
  // 100+ kg payload arm (both vendors' defaults are higher; the controllers
  // reduce them with the load).
  double tcp_accel_mm_s2 = 1000;
  double joint_accel_rad_s2 = 2.0;  // for the home moves
  bool from_home = true;            // add home -> first target
  bool to_home = true;              // add last target -> home
};

struct RobotCycleTime {
  double total_s = 0;
  double grinding_s = 0;  // on the wheel: the paths
  double link_s = 0;      // off the wheel: retract, traverse, approach
  double home_s = 0;      // home -> first target, last target -> home
  double grinding_mm = 0, link_mm = 0;
  int paths = 0;
  int joint_limited_steps = 0;  // steps slowed below their programmed speed by a joint's maximum
};

// Throws ParameterError on accelerations <= 0.
RobotCycleTime estimate_robot_cycle_time(const RobotCell& cell, const RobotGrindingPlan& plan,
                                         const RobotCycleTimeOptions& options = {});

}  // namespace bliskrun
