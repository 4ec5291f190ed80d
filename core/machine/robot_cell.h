#pragma once
// A belt-grinding robot cell (belt paper §1, SPEC §6.3): a six-axis arm
// holding the blade in its gripper, and fixed belt stations whose contact
// wheels the blade is pressed against. The program moves the *part*: for a
// contact point p on the blade (blade frame, normal n out of the material,
// path tangent t) the flange is placed so that p lies on the wheel's contact
// point, n points into the wheel and t lies along the wheel's axis (the
// wheel's width along the path, core/planning/belt_paths.h). The one free
// choice left — t along or against the wheel axis, the part turned 180°
// about the normal — is made per path for reach, limits and continuity.
#include <string>
#include <vector>

#include "core/machine/robot.h"

namespace bliskrun {

struct BeltStation {
  std::string name;
  // Base <- station: origin on the wheel's surface where it touches the part,
  // z the wheel's outward normal there (towards the part), x the wheel axis.
  Frame contact = Frame::Identity();
  double wheel_radius_mm = 0;
  double wheel_width_mm = 0;
  std::string belt;            // "ceramic, 120 grit"
  double belt_speed_m_s = 0;
  // How far the rubber of the wheel and the belt on it give under the
  // grinding force: blade points this deep below the contact's tangent plane
  // are contact, deeper ones collide (core/machine/wheel_clearance.h).
  double compliance_mm = 0.5;
  double belt_run_mm = 150;    // the belt's strands behind the wheel's centre
};

struct RobotCell {
  std::string name;
  RobotArm arm;
  Frame grip = Frame::Identity();  // flange <- blade: where the gripper holds the part
  JointAngles home{};              // joints the program starts from and returns to
  std::vector<BeltStation> stations;
  // Throws ParameterError naming the field (the arm's, a station's frame not
  // orthonormal, a wheel size <= 0).
  void validate() const;
  const BeltStation& station(const std::string& name) const;  // ParameterError("station") if absent
};

// A contact on the blade, blade frame: point, unit normal out of the
// material (towards the wheel), unit path tangent.
struct BladeContact {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  Vec3 tangent = Vec3::UnitX();
};

// The flange frame that puts `c` on the station's wheel; `turned` turns the
// part 180° about the normal (t against the wheel axis).
Frame flange_for_contact(const RobotCell& cell, const BeltStation& station, const BladeContact& c, bool turned);

// Where the contact point of the blade is, and its normal, for a flange
// frame (the inverse of flange_for_contact, for replaying programs).
BladeContact contact_in_base(const RobotCell& cell, const Frame& flange, const BladeContact& c);

struct RobotMove {
  JointAngles joints{};
  int branch = 0;
  bool wrist_singular = false;
  bool turned = false;
  int path = -1;              // -1 on links
  bool link = false;          // away from the wheel (retract, traverse, approach)
  BladeContact contact;       // blade frame; on links the contact this move is offset from
  double offset_mm = 0;       // along the normal away from the wheel (links)
  double feed_mm_s = 0;       // along the path at the contact
  double joint_speed_ratio = 0;  // largest |dq/dt| / max speed over the joints for the move into this one
};

// The blade point a move programs: its contact, or on a link the point
// `offset_mm` off it along the normal (blade frame). Feeds are programmed
// on its travel.
Vec3 programmed_point(const RobotMove& move);

// Largest |dq/dt| / max speed over the joints for the motion from `from`
// into `to` at `to`'s feed along the programmed points' travel.
double joint_speed_ratio(const RobotArm& arm, const RobotMove& from, const RobotMove& to);

struct BladeBody;

// The wheel and belt against the whole blade over every move and the motion
// between moves (core/machine/wheel_clearance.h).
struct WheelContactReport {
  bool checked = false;            // false: no blade body was given
  long poses = 0;                  // poses checked (moves and the samples between them)
  double max_conformity_mm = 0;    // deepest blade point within the contact cap
  long collisions = 0;             // poses where a blade point is in the wheel below the cap, or in the belt
  double max_collision_depth_mm = 0;
  std::string first_collision;     // which face, where, how deep, in what
};

struct RobotGrindingOptions {
  double feed_mm_s = 20;        // contact speed along the path
  double link_feed_mm_s = 200;  // traverses between paths, away from the wheel
  double retract_mm = 10;       // lift off the wheel along the normal between paths
  double traverse_step_mm = 10; // back along the last path, retract_mm off it, points this far apart
  JointAngles start{};          // joints before the first move (the cell's home)
  // The whole blade, to check the wheel and belt against on every move and
  // between moves; a path whose moves (or the link into it) collide is tried
  // turned, then refused. nullptr: not checked (kinematics only).
  const BladeBody* blade = nullptr;
};

struct RobotGrindingPlan {
  std::vector<RobotMove> moves;
  int paths = 0;
  int turned_paths = 0;          // paths ground with the part turned 180° about the normal
  int turn_changes = 0;          // between consecutive paths (kept unless a path needs it)
  int branch_changes = 0;        // between consecutive moves (0 is what a smooth program has)
  int singular_moves = 0;
  // > 1: a joint would have to move faster than it can. On grinding moves
  // the contact speed would not be held; on links (lift-off, approach) the
  // controller slows down, so only the time grows.
  double max_joint_speed_ratio = 0;
  double max_link_joint_speed_ratio = 0;
  std::vector<std::string> refusals;  // paths no choice could reach within the limits or clear of the wheel
  WheelContactReport wheel;           // over every emitted move and the motion into it
};

// Every path of contacts (blade frame) on one station: per path the turn
// that keeps every point within the joint limits — the previous path's turn
// unless it cannot, else the one with the fewest branch changes and least
// joint motion — solved point by point with continuity;
// between paths a retract along the normal, a traverse back along the last
// path `retract_mm` off it, and an approach.
// A path that no choice reaches is refused (named in `refusals`) and not
// emitted.
RobotGrindingPlan plan_robot_grinding(const RobotCell& cell, const BeltStation& station,
                                      const std::vector<std::vector<BladeContact>>& paths,
                                      const RobotGrindingOptions& options);

}  // namespace bliskrun
