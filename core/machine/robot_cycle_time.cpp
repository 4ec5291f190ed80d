#include "core/machine/robot_cycle_time.h"

#include <algorithm>
#include <cmath>

#include "core/common/error.h"
#include "core/common/types.h"
#include "core/machine/cycle_time.h"

namespace bliskrun {
namespace {

// A joint move from rest to rest: the slowest joint's trapezoid.
double joint_move_seconds(const RobotArm& arm, const JointAngles& a, const JointAngles& b, double accel) {
  double t = 0;
  for (int j = 0; j < 6; ++j) {
    const double d = std::abs(b[j] - a[j]);
    if (d > 0) t = std::max(t, rest_to_rest_seconds(d, arm.joints[j].max_speed_rad_s, accel, kInf));
  }
  return t;
}

}  // namespace

RobotCycleTime estimate_robot_cycle_time(const RobotCell& cell, const RobotGrindingPlan& plan,
                                         const RobotCycleTimeOptions& options) {
  if (!(options.tcp_accel_mm_s2 > 0)) throw ParameterError("tcp_accel", "expected an acceleration > 0 in mm/s^2");
  if (!(options.joint_accel_rad_s2 > 0)) throw ParameterError("joint_accel", "expected an acceleration > 0 in rad/s^2");
  RobotCycleTime out;
  const std::vector<RobotMove>& moves = plan.moves;
  if (moves.empty()) return out;
  if (options.from_home) out.home_s += joint_move_seconds(cell.arm, cell.home, moves.front().joints,
                                                         options.joint_accel_rad_s2);
  if (options.to_home) out.home_s += joint_move_seconds(cell.arm, moves.back().joints, cell.home,
                                                       options.joint_accel_rad_s2);
  // One grinding path at a time: its steps' times at the feed (or the
  // binding joint), plus the ramp of a rest-to-rest motion of its length.
  double run_s = 0, run_mm = 0, run_feed = 0;
  auto close_run = [&] {
    if (run_mm > 0) {
      out.grinding_s += run_s + (rest_to_rest_seconds(run_mm, run_feed, options.tcp_accel_mm_s2, kInf) -
                                 run_mm / run_feed);
      ++out.paths;
    }
    run_s = run_mm = run_feed = 0;
  };
  for (size_t i = 1; i < moves.size(); ++i) {
    const RobotMove& p = moves[i - 1];
    const RobotMove& m = moves[i];
    const double mm = (programmed_point(m) - programmed_point(p)).norm();
    const double joints_s = robot_joint_move_time(cell.arm, p.joints, m.joints);
    const bool grinding = !m.link && !p.link && m.path == p.path;
    if (grinding) {
      const double feed_s = mm / m.feed_mm_s;
      if (joints_s > feed_s) ++out.joint_limited_steps;
      run_s += std::max(feed_s, joints_s);
      run_mm += mm;
      run_feed = m.feed_mm_s;
      out.grinding_mm += mm;
    } else {
      close_run();
      const double feed_s = mm > 0 ? rest_to_rest_seconds(mm, m.feed_mm_s, options.tcp_accel_mm_s2, kInf) : 0;
      if (joints_s > feed_s) ++out.joint_limited_steps;
      out.link_s += std::max(feed_s, joints_s);
      out.link_mm += mm;
    }
  }
  close_run();
  out.total_s = out.grinding_s + out.link_s + out.home_s;
  return out;
}

}  // namespace bliskrun
