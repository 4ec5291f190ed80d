#pragma once
// Robot programs read back the way their controller reads them, and
// replayed (SPEC §7, issues 15 and 39).
//
// A part-in-hand cell grinds with a fixed ("stationary", "external") TCP: the
// wheel stands in the world and the blade rides on the flange. Each dialect
// says so in its own data, and the reader takes the frames' roles from what
// the program writes, not from the cell:
//   ABB RAPID (Technical reference manual, RAPID Instructions, Functions and
//   Data types: tooldata, wobjdata, confdata, robtarget)
//     tooldata robhold FALSE: tframe is the stationary TCP in the world;
//     wobjdata robhold TRUE: uframe is the user frame on the flange (tool0),
//     oframe the object frame in it; a robtarget is the TCP in the object
//     frame. robhold TRUE / FALSE reverses both roles (a tool on the flange).
//     confdata [cf1, cf4, cf6, cfx]: cf1/cf4/cf6 the quadrant of axes 1, 4, 6
//     (floor(angle / 90°)); cfx for a serial arm: +4 wrist centre behind
//     axis 1, +2 wrist centre behind the lower arm (the line through axes 2
//     and 3), +1 axis 5 negative. MoveL / MoveJ with ConfL / ConfJ on (the
//     default) go to the written configuration or stop.
//     loaddata [mass, cog, aom, ix, iy, iz] (kg, mm, quaternion, kg·m²): a
//     tooldata's tload is in the wrist coordinate system (tool0) — for a
//     stationary tool, the load of the gripper holding the work object; the
//     payload set by GripLoad is in the tool coordinate system, and with a
//     stationary tool in the object frame of the work object the robot moves.
//   KUKA KRL (KSS 8.x): with $IPO_MODE = #TCP the tool is fixed: $BASE holds
//     the fixed tool (external TCP) relative to WORLD, $TOOL the robot-guided
//     workpiece relative to FLANGE; a position is the external TCP in the
//     workpiece frame, X Y Z A B C with A, B, C the Z-Y-X angles (deg). With
//     $IPO_MODE = #BASE (the default) the roles are the usual ones.
//     Status S: bit 0 the wrist root point's x in the A1 coordinate system
//     negative (overhead area), bit 1 A3 >= φ (φ the A3 at which the wrist
//     root point lies on the line through A2 and A3; 0° when A3 and A4
//     intersect), bit 2 A5 in [-180°, 0°) or >= 180°. Turn T: bit i set when
//     axis i+1 < 0°. S and T choose the solution of a PTP to a Cartesian
//     position; a LIN (CP motion) ignores them and keeps the configuration it
//     starts in.
//     $LOAD = {M, CM {X, Y, Z, A, B, C}, J {X, Y, Z}}: the whole load on the
//     flange (kg; centre of gravity and principal axes in FLANGE, mm and
//     Z-Y-X deg; principal moments, kg·m²).
// Where each convention comes from: docs/lua_api/robots.md.
// Replaying means: solve each target with the configuration the controller
// would take, compare with the plan the program was written from, put the
// blade's contact back through the forward kinematics, and check that the
// written speeds let the feed hold.
#include <array>
#include <map>
#include <string>
#include <vector>

#include "core/geometry/mass_properties.h"
#include "core/machine/robot_cell.h"

namespace bliskrun {

enum class RobotDialect { AbbRapid, KukaKrl };

struct RobotTarget {
  bool axis_move = false;                       // PTP {A1 ..} / MoveAbsJ: `joints` is the target
  JointAngles joints{};                         // axis moves, rad
  Frame target = Frame::Identity();             // the written position
  // The frames in force at this statement, in the roles the controller gives
  // them (see above): external TCP: flange = fixed · target⁻¹ · held⁻¹;
  // otherwise flange = fixed · target · held⁻¹.
  Frame fixed = Frame::Identity();              // in the world
  Frame held = Frame::Identity();               // on the flange
  bool external_tcp = false;
  int cfx = 0;                                  // ABB cfx / KUKA S, as written
  std::array<int, 3> quadrants{0, 0, 0};        // ABB cf1, cf4, cf6
  int turn_bits = 0;                            // KUKA T
  bool linear = true;                           // MoveL / LIN (false: MoveJ / PTP)
  double tcp_speed_mm_s = 0;                    // in force at the statement; 0 unknown
  double ori_speed_deg_s = 0;
  // The load on the flange in force at the statement, as the controller
  // adds it up (flange frame): KRL $LOAD; RAPID the tool's tload and the
  // GripLoad payload moved onto the flange through the frames that hold it.
  bool load_known = false;
  MassProperties load;
  std::string file;                             // the program the statement is in
  int line = 0;                                 // of that program, 1-based
};

// The motion statements of `entry` in the order the controller runs them:
// calls to the other programs of `programs` (KRL `name()`, RAPID `name;`)
// are followed. Throws Error naming the program and line on a statement it
// cannot read, data it does not know or a program called but absent.
std::vector<RobotTarget> read_robot_program(const std::map<std::string, std::string>& programs,
                                            const std::string& entry, RobotDialect dialect);
// One program without calls.
std::vector<RobotTarget> read_robot_program(const std::string& text, RobotDialect dialect);

// The configuration fields by each controller's definition, from joints.
std::array<int, 3> abb_quadrants(const JointAngles& joints);  // cf1, cf4, cf6
int abb_cfx(const RobotArm& arm, const JointAngles& joints);
int kuka_status(const RobotArm& arm, const JointAngles& joints);
int kuka_turn_bits(const JointAngles& joints);

// The target a post writes for a planned move: the wheel's contact frame in
// the blade frame.
Frame robot_target_frame(const RobotCell& cell, const BeltStation& station, const RobotMove& move);

struct RobotVerifyReport {
  int moves = 0;
  double max_position_mm = 0;   // replayed contact from where the plan puts it (wheel contact or lift-off)
  double max_angle_deg = 0;     // replayed flange orientation from the planned one
  double max_joint_deg = 0;     // replayed joints from the planned ones
  int configuration_flips = 0;  // targets the controller reaches in another configuration than the plan's
  int unreachable = 0;          // targets no solution with the controller's configuration reaches within limits
  int configuration_disagreements = 0;  // written S/T or confdata not the configuration reached
  int feed_capped = 0;          // grinding moves the orientation speed slows below the written feed
  int load_disagreements = 0;   // targets whose load in force is not the payload (when one is given)
  std::vector<std::string> problems;  // "file line N: ..." for each of the above
};

// Replays `targets` against the plan they were written from: the Cartesian
// targets one per planned move, in order, after at least one axis move (the
// known start). Tolerances decide what is a problem. With `payload` (the
// gripper and the part on the flange, flange frame) every Cartesian
// target's load in force must be it: mass within 2.5 g (RAPID's loads
// weigh at least 1 g each), centre of gravity
// within 0.05 mm (of a payload of 100 g or more), inertia within 1e-3 of its size or 5 kg·mm².
RobotVerifyReport verify_robot_program(const RobotCell& cell, const BeltStation& station,
                                       const RobotGrindingPlan& plan, const std::vector<RobotTarget>& targets,
                                       RobotDialect dialect, double position_tol_mm = 0.002,
                                       double angle_tol_deg = 0.001, const MassProperties* payload = nullptr);

}  // namespace bliskrun
