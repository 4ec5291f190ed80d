#pragma once
// The contact wheel and its belt as bodies against the whole blade (belt
// paper §2, SPEC §6.3): while the robot presents one contact to the wheel,
// no other part of the blade — the other flank, the edges, the rest of the
// ground face — may touch the wheel or the belt.
//
// The wheel is a cylinder (radius r, width w, axis along the station's x,
// touching the part at the station origin, its outward normal z). The belt
// wraps its front and runs back from it: the slab |x| <= w/2, |y| <= r
// behind the wheel's centre, `belt_run_mm` long. The blade is a dense point
// sample of its faces (blade frame).
//
// Where contact is meant: a rubber contact wheel gives under the grinding
// force, and the belt on it conforms to the face. So blade points inside the
// cap of the wheel no deeper than the station's `compliance_mm` below the
// contact's tangent plane (z >= -c) are the contact itself; their deepest
// radial depth is reported as the conformity the wheel must provide (on a
// face concave along the path the rigid wheel's ends dig in by (w/2)²κ/2).
// Any blade point inside the wheel below that cap, or inside the belt, is a
// collision.
//
// Motion between two robot moves is sampled the way the controller moves
// with an external TCP (LIN): the wheel's frame in the blade frame moves on a
// straight line and turns by slerp. Sampled at `step_mm` / `step_deg`; with
// samples at most s apart on the blade, a collision deeper than s²/(8r)
// cannot fall between them.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/common/types.h"
#include "core/geometry/point_index.h"
#include "core/geometry/surface.h"
#include "core/machine/robot_cell.h"

namespace bliskrun {

struct BladeBody {
  std::vector<std::string> face_names;
  std::vector<Vec3> points;  // blade frame
  std::vector<int> face;     // per point, an index into face_names
  double spacing_mm = 0;     // the largest distance between neighbouring samples, as asked

  // Each face sampled on a (u, v) lattice fine enough that neighbouring
  // samples are at most spacing_mm apart (arc lengths measured along iso
  // lines). Throws ParameterError("spacing") unless spacing_mm > 0 and
  // ParameterError("faces") when there are none.
  static BladeBody sample(const std::vector<std::pair<std::string, std::shared_ptr<const Surface>>>& faces,
                          double spacing_mm);
};

struct WheelClearanceOptions {
  double step_mm = 1.0;   // interpolation between moves: largest travel of the wheel per sample
  double step_deg = 1.0;  // and largest turn
};

// Checks the blade against one station's wheel and belt. Build once per
// station and blade; `check_motion` is thread-compatible (const).
class WheelClearance {
 public:
  WheelClearance(const BladeBody& blade, const BeltStation& station, WheelClearanceOptions options = {});

  // The pose of the blade in the station frame (station <- blade).
  void check_pose(const Frame& blade_in_station, WheelContactReport& report) const;
  // The motion from one pose to the next, excluding `from` (checked before).
  void check_motion(const Frame& from, const Frame& to, WheelContactReport& report) const;

 private:
  void check_wheel_in_blade(const Frame& wheel_in_blade, WheelContactReport& report) const;

  const BladeBody& blade_;
  double r_, half_w_, cap_, belt_run_;
  WheelClearanceOptions options_;
  // The blade's points in cells about a third of the wheel's radius, so a
  // wheel's box covers a few hundred cells at most.
  PointIndex index_;
};

// The blade in the station frame for a move of a plan (forward kinematics
// of its joints and the cell's grip).
Frame blade_in_station(const RobotCell& cell, const BeltStation& station, const RobotMove& move);
// The same for any joint values (a joint move's samples).
Frame blade_in_station(const RobotCell& cell, const BeltStation& station, const JointAngles& joints);

}  // namespace bliskrun
