#pragma once
// Tilt until clear (blisk paper §3.3–3.4): from the contact point's local
// frame and an initial lead/pitch λ and tilt w, raise λ in steps (and, where
// allowed, vary w) until cutter, shank and holder are clear of every check
// surface by their clearances, the motion from the previous accepted pose is
// clear, and the machine can reach the axis. Poses that cannot be cleared
// are refused with the reason; they are never emitted.
#include <functional>
#include <string>
#include <vector>

#include "core/collision/collision_world.h"
#include "core/common/progress.h"

namespace bliskrun {

// A machine's limit on the tool axis: "" when the machine can point the tool
// along `axis` (unit, part frame), else why not. Machine definitions supply
// these; an empty function means no limit.
using AxisLimit = std::function<std::string(const Vec3& axis)>;

// One rotary axis's range, measured as in the blisk paper (§2.2, Fig. 3–4):
// the tool axis is turned into the machine's working plane — projected on
// the plane perpendicular to `rotary_axis` — and its signed angle from
// `reference` (right-handed about `rotary_axis`) must lie in [min, max]. The
// paper's machine: rotary_axis Z (vertical), working plane horizontal,
// reference Y, C in [−30°, +30°]. An axis parallel to the rotary axis has no
// angle; any setting of that axis reaches it, so it is allowed.
struct RotaryAxisLimit {
  std::string name = "C";
  Vec3 rotary_axis = Vec3::UnitZ();
  Vec3 reference = Vec3::UnitY();  // must be perpendicular to rotary_axis
  double min_rad = -kPi / 6;
  double max_rad = kPi / 6;

  // Signed angle, radians in (−pi, pi]; NaN when the axis is parallel to
  // the rotary axis.
  double angle_rad(const Vec3& axis) const;
  std::string violation(const Vec3& axis) const;
};
// Validates the limit (unit-able axes, perpendicular reference, min <= max).
AxisLimit make_axis_limit(const RotaryAxisLimit& limit);

// The local frame at a contact point (paper Fig. 8): X_SL the path tangent,
// Z_SL the surface normal out of the material, Y_SL = Z_SL × X_SL.
struct ContactFrame {
  Vec3 point = Vec3::Zero();
  Vec3 tangent = Vec3::UnitX();
  Vec3 normal = Vec3::UnitZ();
};

// Tool axis for lead/pitch λ (angle between the axis and the tangent plane,
// towards the normal) and tilt w (turn of the tool's local frame about the
// normal from X_SL): a = cos λ (−sin w X + cos w Y) + sin λ Z. At λ = w = 0
// the axis is +Y_SL, lying in the tangent plane across the path, as the
// drum wheel flanks the blade; orient the tangent so +Y points towards the
// spindle.
Vec3 axis_from_lead_tilt(const ContactFrame& frame, double lead_rad, double tilt_rad);

// Places the tool so it touches the tangent plane at the contact point: the
// cutter point whose outward normal is −normal goes to the contact point.
ToolPose place_tool(const Tool& tool, const ContactFrame& frame, const Vec3& axis);

struct TiltSettings {
  double lead0_rad = 0;                  // initial λ (paper: 0)
  double tilt0_rad = 0;                  // initial w (paper: 0)
  // λ steps from lead0 towards lead_max. Negative: λ falls — a bottom-
  // cutting tool (λ = 90° puts the axis along the normal) leaning further
  // from the normal to clear.
  double lead_step_rad = deg_to_rad(0.5);
  double lead_max_rad = deg_to_rad(45);
  bool allow_tilt = false;               // also vary w by ± steps around w0
  double tilt_step_rad = deg_to_rad(1);
  double tilt_range_rad = deg_to_rad(10);  // |w − w0| at most this
  Clearances clearances;
  double motion_tol_mm = 1e-3;           // CollisionWorld::check_motion
  AxisLimit axis_limit;                  // empty: none
  // What the operation itself requires of a pose, checked before the world
  // (cheaper): "" accepts, else why not (e.g. the cutter would gouge the
  // finished surface). Empty: every pose.
  std::function<std::string(const ToolPose& pose)> pose_filter;
  // The same, asked only of a pose the world has cleared (and the motion
  // to it): for requirements dearer than the world query (e.g. the whole
  // tool swept against the design surfaces). Counted with pose_filter's.
  std::function<std::string(const ToolPose& pose)> clear_pose_filter;
};

struct TiltAccepted {
  int index = 0;  // of the contact in the path
  ToolPose pose;
  double lead_rad = 0, tilt_rad = 0;
  PoseCheck check;  // distances resolved up to each part's clearance only
  int tries = 0;    // axes tried
};

struct TiltRefusal {
  int index = 0;
  Vec3 contact = Vec3::Zero();
  std::string reason;
};

struct TiltOutcome {
  bool accepted = false;
  TiltAccepted pose;     // valid when accepted
  TiltRefusal refusal;   // valid otherwise
};

// One contact. `previous` (may be null) is the last accepted pose: the motion
// from it must be clear too.
TiltOutcome tilt_until_clear(const CollisionWorld& world, const ToolBody& body, const ContactFrame& contact,
                             int index, const TiltSettings& settings, const ToolPose* previous = nullptr);

struct TiltRun {
  std::vector<TiltAccepted> poses;    // in path order
  std::vector<TiltRefusal> refusals;  // in path order
};

// A path of contacts: each against the last accepted pose before it.
TiltRun tilt_path(const CollisionWorld& world, const ToolBody& body, const std::vector<ContactFrame>& contacts,
                  const TiltSettings& settings, Progress& progress = Progress::none());

}  // namespace bliskrun
