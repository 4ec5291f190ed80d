#pragma once
// Links between cutting passes: leave the surface, traverse, come back —
// one builder for every strategy, each choosing how its tool leaves.
//
// A side-cutting tool (a drum wheel, a flank mill) has its axis nearly
// tangent to the surface: pulled back along the axis it slides along the
// finished surface and, where that surface is concave, into it (a straight
// line tangent to a circle of radius rho enters it by ~ s^2 / (2 rho) after
// a distance s). It must leave along the surface normal, away from the
// material. A bottom-cutting tool (a flat end on an edge) leaves along its
// axis. So the retract direction is a property of the operation.
//
// A link from pose a (end of a pass) to pose b (start of the next) is
//   a -> a + d e_a [-> + e axis_a] -> [b + d e_b + e axis_b ->] b + d e_b -> b
// where e is the retract direction (normal or axis) and the optional second
// leg along the tool axis. Every segment is proved, in the motion the
// machine makes (PoseMotion), against the check surfaces (whole tool,
// core/collision) and — for the cutter — against the finished surface
// itself (core/sim GougeGuard) with the operation's allowed overcut. The
// offset d is the largest that proves clear, from `retract_mm` halving down
// to `min_retract_mm` (in a narrow passage the largest offset can reach the
// neighbouring blade). Where no offset straight along the normal proves
// (e.g. the hub right under a first row planned at its hub clearance), the
// direction is turned 30, then 60 degrees from the normal up the tool axis
// — still lifting off the surface at once. A link that nothing proves is
// refused, never emitted.
#include <memory>
#include <string>
#include <vector>

#include "core/collision/collision_world.h"
#include "core/sim/undercut.h"
#include "core/tools/pose.h"

namespace bliskrun {

enum class RetractDirection {
  SurfaceNormal,  // side-cutting operations: away from the material first
  ToolAxis,       // bottom-cutting operations: up the tool
};

struct LinkOptions {
  RetractDirection direction = RetractDirection::SurfaceNormal;
  double retract_mm = 5.0;        // largest offset tried
  double min_retract_mm = 0.1;    // smallest offset tried (halving from retract_mm)
  double axis_retract_mm = 0;     // a second leg up the tool axis after the first (0: none)
  double allowed_overcut_mm = 0.002;  // how far a non-cutting move may dip below the finished surface
  // The pole of the machine's rotary configuration in the part frame (the
  // primary rotary axis: the C table's on an A/C or B/C machine; zero: no
  // pole), and how far every axis a link turns through keeps off it: a leg
  // whose axis would pass nearer (both its ends farther) is routed round
  // the pole at twice that (around_pole). Through the pole the primary
  // axis must turn half a revolution at once, which a post cannot follow
  // (the built-in blisk job's trailing edge: a link 0.002 deg off it).
  Vec3 pole = Vec3::Zero();
  double pole_clearance_rad = 0;
};

// The least angle between the tool axis and the line of `pole` (unit) as
// the axis turns from a to b along the great circle (PoseMotion's), rad.
double angle_off_pole(const Vec3& a, const Vec3& b, const Vec3& pole);

// The poses of a link's leg a -> b whose axis would pass within
// `clearance_rad` of the pole's line while a and b are farther: the axis
// carried round the pole instead, its angle off it at least twice the
// clearance and its azimuth turning the way the great circle passed, the
// tip on the straight segment; poses between a and b, none when the leg
// keeps off the pole (or an end is within the clearance: nothing keeps it
// off then).
std::vector<ToolPose> around_pole(const ToolPose& a, const ToolPose& b, const Vec3& pole, double clearance_rad);

// One end of a link: the cutting pose and the surface normal out of the
// material at its contact.
struct LinkEnd {
  ToolPose pose;
  Vec3 normal = Vec3::UnitZ();
};

// What a link is proved against. `guard` may be null (no finished surface
// to protect, e.g. roughing); `world` and `body` may not.
struct LinkChecks {
  const CollisionWorld* world = nullptr;
  const ToolBody* body = nullptr;
  Clearances clearances;
  double motion_tol_mm = 1e-3;
  const GougeGuard* guard = nullptr;
  // Subtracted from the allowed overcut for what the guard's samples can
  // miss (GougeGuard::between_samples_mm).
  double guard_margin_mm = 0;
  // Further finished surfaces proved the same way, each with its own margin
  // (an edge region and the two flanks beside it).
  struct Guard {
    const GougeGuard* guard = nullptr;
    double margin_mm = 0;
  };
  std::vector<Guard> more_guards;
  // Optional: the traverse legs also proved against this world — the
  // guards sample the finished surface only near the pass, and the world
  // leaves the blade being machined to them for the cutter (which touches
  // it by design); a traverse that goes beyond their reach (along the
  // span, round a blade) is proved against the whole blade with the cutter
  // too (CollisionWorld::unchecked_pairs), at the same clearances.
  std::shared_ptr<const CollisionWorld> traverse_world;
};

enum class LinkLeg { Retract, Traverse, Approach };
const char* link_leg_name(LinkLeg leg);

struct PlannedLink {
  bool clear = false;
  std::vector<ToolPose> via;   // the poses between a and b, in order
  std::vector<LinkLeg> legs;   // legs[i]: the motion from (a, via...)[i] to (via..., b)[i]; via.size() + 1 of them
  double offset_mm = 0;        // the offset d used
  double turn_rad = 0;         // how far the direction was turned from the normal up the axis
  double deepest_cut_mm = 0;   // deepest dip below the finished surface over the link (<= 0)
  std::string reason;          // why it was refused
};

// A lead-in or lead-out: the pose `d` along the retract direction from a
// cutting pose, d the largest offset (retract_mm halving down to
// min_retract_mm) whose straight motion to the pose is proved like a link
// leg. A lead-out moves pose -> away, a lead-in away -> pose: the same
// swept tool, the same proof.
struct PlannedDeparture {
  bool clear = false;
  ToolPose away;
  double offset_mm = 0;
  double turn_rad = 0;
  double deepest_cut_mm = 0;
  std::string reason;
};
PlannedDeparture plan_departure(const LinkEnd& at, const LinkChecks& checks, const LinkOptions& options);

// Throws ParameterError for missing world/body, non-positive retract_mm,
// min_retract_mm outside (0, retract_mm], negative axis_retract_mm or
// allowed_overcut_mm.
// `traverse_via`: poses the traverse passes through between the two
// retracted poses (e.g. round the front of a blade edge when the tool axis
// turns by more than 90 degrees between the passes); each leg is proved.
PlannedLink plan_link(const LinkEnd& from, const LinkEnd& to, const LinkChecks& checks,
                      const LinkOptions& options, const std::vector<ToolPose>& traverse_via = {});

// Any other non-cutting motion through `chain` (PoseMotion between
// consecutive poses) proved as a link's legs are: every motion against the
// world, and against each guard (when given) with `allowed_mm` less the
// guard's margin (what its samples can miss). The first
// and last pose's own cut is left to their passes when first_cuts /
// last_cuts (a lead arc or bridge that leaves or reaches a cutting pose).
// Stops at the first motion that does not prove (segment: its index).
struct ChainProof {
  bool clear = true;
  int segment = -1;
  double deepest_cut_mm = 0;
  std::string reason;
};
ChainProof prove_chain(const std::vector<ToolPose>& chain, const LinkChecks& checks, double allowed_mm,
                       bool first_cuts, bool last_cuts);

}  // namespace bliskrun
