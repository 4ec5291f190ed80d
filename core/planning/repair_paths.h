#pragma once
// Repair toolpaths of a damaged blade (repair paper §2, SPEC §6.5): after
// the damaged region has been built up by welding, the deposit is machined
// off down to the design surface in offset layers — roughing layers on the
// design surface offset outward by the stock and k layers (outside first),
// the finishing layer on the design surface itself (§1.5/§2) — with a
// ball-end mill, by the paper's iso-parametric method:
//
//  - Zigzag (§2.1, edge damage): passes along iso-u lines (u the span, so a
//    pass runs around the edge at constant height), stepped across by the
//    scallop height (belt_step_over_exact: the ball's cross-section is the
//    belt wheel's circle, so the same closed form), along by the chord
//    tolerance (plan_row_steps, measured guarantee). At each end of a pass
//    an arc (§2.1 (2)): it starts tangent to the pass, lies in the plane of
//    the end tangent and the surface normal, turns away from the surface
//    through `arc_angle_rad` with the end pose's tool axis. Between the arcs
//    of consecutive passes a bridge (§2.1 (3)): a cubic Hermite curve from
//    the end of one arc to the start of the next, tangent to both, the axis
//    turned uniformly with the bridge's length. The passes alternate in
//    direction, so every bridge lies at one end of the region; each layer
//    starts at the end where the layer before ended, so the link between
//    layers stays on one side (round an edge, the other side is through
//    the blade).
//  - Spiral (§2.2, tip damage): the region goes once around the blade
//    (v in [0, 1] of a surface periodic in v); the contacts of the iso-u
//    lines u_k are moved onto the slanted line from (u_k, 0) to (u_k+1, 1)
//    of the parameter plane (Fig. 19a), which makes one spiral around the
//    blade (Fig. 19b) with no pass-to-pass link. The pitch u_k+1 - u_k is
//    the scallop step-over of the turn; the first and last turn run flat at
//    the region's ends, so the ends are machined to their edge. Layers
//    alternate ascending and descending.
//
// Tool axis (the paper computes it but does not say how): the surface
// normal turned forward by a lead angle towards the feed — axis_from_lead_tilt
// with λ = 90° − lead, w = −90° — and, where the shank or holder is not
// clear of the world (the blade itself, the fixture), tilted until clear
// (tilt_until_clear: λ raised through the normal to the back side, w varied
// sideways); a contact with no clear axis is refused and splits its pass.
// On the finishing layer a tilted axis moves the swept ball between two
// contacts a little: where that motion dips below the design, contacts are
// put in between (halving, up to four times, each settled and tilted like
// any other) and the pass is split only where that does not clear it.
// A ball has the same cutting surface whatever its axis, so the tilt does
// not move the contact.
//
// Verified, not assumed: on the finishing layer every pose is checked
// against the design surface (core/sim GougeGuard over the whole surface,
// so the undamaged blade next to the region is protected) and refused
// where the ball would cut below it by more than the chord tolerance (a
// region narrower than the ball) it is first lifted off along the normal
// until it no longer does — it rides over a trough narrower than itself,
// as a gouge-avoiding CAM system lifts a tool, and leaves the trough's
// depth — and refused only where that lift would exceed max_lift_mm;
// every cutting segment is swept through the guard and halved where it
// dips deeper than the chord tolerance (the new contact lifted alike). Every
// arc, bridge and link motion is proved against the world (whole tool,
// holder included) and the guard (allowed overcut); a bridge that does not
// prove is replaced by the shared link (plan_link between the arcs' ends,
// else between the passes); layers are joined by plan_link; whatever does
// not prove is refused (a Stop), never emitted as a move.
#include <memory>
#include <string>
#include <vector>

#include "core/collision/collision_world.h"
#include "core/collision/tilt.h"
#include "core/common/progress.h"
#include "core/geometry/surface.h"
#include "core/toolpath/move.h"
#include "core/planning/links.h"
#include "core/planning/row_steps.h"
#include "core/sim/undercut.h"
#include "core/tools/tool.h"

namespace bliskrun {

enum class RepairPattern { Zigzag, Spiral };
const char* repair_pattern_name(RepairPattern p);

// Tool axis defaults: lead 10° forward, raised through the normal to 30°
// back in 2° steps, each with sideways turns up to ±30° in 10° steps.
TiltSettings repair_tilt_defaults();

struct RepairPathRequest {
  // The design surface: u along the span, v around the section (closed:
  // S(u, 0) = S(u, 1), e.g. close_blade), pu x pv out of the material
  // unless flip_normal. For the zigzag an open face works too.
  std::shared_ptr<const Surface> design;
  bool flip_normal = false;
  RepairPattern pattern = RepairPattern::Zigzag;
  // The region (u0, u1) x (v0, v1) of the design; the spiral ignores v. A
  // window with v0 > v1 runs from v0 round through the seam v = 0 to v1:
  // the spiral takes it (it ignores v), the zigzag refuses it by name.
  double u0 = 0, u1 = 1, v0 = 0, v1 = 1;
  const Tool* tool = nullptr;             // a ball-end mill
  const CollisionWorld* world = nullptr;  // the blade (shank, holder) and the fixture (every part)
  // Layers: roughing on the offsets stock_mm + k layer_mm below deposit_mm,
  // outside first, then finishing on the design (offset 0).
  double deposit_mm = 2.0;   // thickness of the deposit over the region (its largest)
  double layer_mm = 0.5;     // depth of cut of a roughing layer
  double stock_mm = 0.2;     // left by the last roughing layer
  double scallop_mm = 0.005;        // finishing
  double rough_scallop_mm = 0.05;   // roughing
  // Constant chord height with the measured guarantee (as the edge finish:
  // the variable method's δ never grows back after an edge's curvature peak).
  StepOptions steps{ChordMethod::Constant, 0.002, true, 2.0, 1e-4};  // finishing chord
  double rough_chord_tol_mm = 0.01;
  TiltSettings tilt = repair_tilt_defaults();
  double arc_radius_mm = 1.0;               // lead-out / lead-in arcs
  double arc_angle_rad = kPi / 2;
  int arc_segments = 6;                     // straight moves per arc
  int bridge_segments = 12;                 // straight moves per bridge
  LinkOptions links;                        // between layers, and where a bridge does not prove
  double guard_spacing_mm = 0.1;            // design-surface samples of the gouge guard
  // Finishing: the most a contact is lifted off the design to keep the
  // ball from cutting the troughs beside it (0: refuse instead). A lifted
  // contact leaves up to the lift on top of the scallop there.
  double max_lift_mm = 0.005;
  int across_samples = 24;                  // points per pass where the curvature across is taken
  double tool_tol_mm = 1e-3;                // ToolBody meshing tolerance
  int threads = 1;                          // layers planned apart; the plan does not depend on it
};

struct RepairPose {
  ToolPose pose;
  Vec3 contact = Vec3::Zero(), normal = Vec3::UnitZ(), tangent = Vec3::UnitX();
  double u = 0, v = 0;     // design parameters of the contact (v in [0, 1))
  double t = 0;            // parameter along the pass (spiral: turns)
  bool tilted = false;     // the lead axis was not clear: tilted
  double lift_mm = 0;      // finishing: lifted off the design this much to clear the troughs beside it
};

struct RepairRefusal {
  int layer = 0;
  double u = 0, v = 0;
  Vec3 contact = Vec3::Zero();
  std::string reason;
};

// A stretch of cutting: a pass (zigzag), the spiral of a layer, or a piece
// of either between refused contacts.
struct RepairPass {
  int layer = 0;
  double u = 0;                 // zigzag: the iso-u line; spiral: its first turn's u
  bool reversed = false;        // run towards decreasing v (zigzag) / u (spiral)
  std::vector<RepairPose> poses;
  double max_deviation_mm = 0;  // measured chord deviation of its steps
  double step_over_mm = 0;      // zigzag: to the next pass (0 on the last)
};

// What joins one pass to the next (or starts and ends the program).
struct RepairConnection {
  enum class Kind { Bridge, Link, Departure };
  Kind kind = Kind::Bridge;
  int from_pass = -1, to_pass = -1;  // -1: the program's start / end
  // The motion in order, not including the passes' own poses; `motion[i]`
  // names the motion that ends at poses[i]: "lead-out", "bridge",
  // "lead-in", or a link's "retract" / "traverse" / "approach".
  std::vector<ToolPose> poses;
  std::vector<std::string> motion;
  bool rapid = false;  // links and departures; arcs and bridges are feed
  bool clear = false;
  std::string reason;
};

struct RepairLayer {
  double offset_mm = 0;          // above the design surface
  bool finishing = false;
  double scallop_mm = 0;
  double chord_tol_mm = 0;
  int first_pass = 0, passes = 0;  // into RepairPathResult::passes
  int poses = 0, tilted = 0, refusals = 0;
  double max_deviation_mm = 0;
  // Zigzag: the smallest and largest step-over between passes (mm);
  // spiral: between turns. The closed form's scallop at the largest.
  double step_over_min_mm = 0, step_over_max_mm = 0;
  int turns = 0;                 // spiral: turns including the two flat ones
};

struct RepairPathResult {
  RepairPattern pattern = RepairPattern::Zigzag;
  std::vector<RepairLayer> layers;
  std::vector<RepairPass> passes;
  // In program order: Departure (in), then between consecutive passes a
  // Bridge or Link, then Departure (out).
  std::vector<RepairConnection> connections;
  std::vector<RepairRefusal> refusals;
  int bridges = 0, links = 0, refused_connections = 0;
  int gouge_refusals = 0;        // finishing contacts where the ball cut into the design
  int gouge_splits = 0;          // finishing segments halved because the swept ball dipped below
  int tilt_fills = 0;            // finishing contacts put between two whose tilted motion dipped below
  int lifted = 0;                // finishing contacts lifted off the design (max_lift_mm)
  double max_lift_mm = 0;        // the largest of those lifts
  double max_deviation_mm = 0;   // finishing layer
  double guard_spacing_mm = 0;
  double paths_seconds = 0, checks_seconds = 0, connect_seconds = 0;
};

// Throws ParameterError for a missing design/tool/world, a tool that is not
// a ball-end mill, an empty or out-of-range region, a negative max_lift, non-positive scallop,
// layer or arc radius, stock below 0 or deposit below stock, and bad link
// options.
RepairPathResult plan_repair_paths(const RepairPathRequest& request, Progress& progress = Progress::none());

// The program in order, as the other planners' moves (posts, simulation):
// the lead-in (Rapid), each pass's poses (Feed, motion "cut"), each
// connection's poses (Feed for arcs and bridges, Rapid for links), a Stop
// with the reason where a connection was refused. `row` is the pass index;
// layer_of[i] the layer of move i.
struct RepairMoves {
  Toolpath moves;
  std::vector<int> layer_of;
};
RepairMoves repair_moves(const RepairPathResult& result);

// The moves of layers [first_layer, end) as simulation passes (a Stop ends
// one).
std::vector<ToolPass> repair_passes(const RepairPathResult& result, int first_layer = 0);

// The step-over (mm, along the surface across the passes) for scallop h of
// a ball of radius r on a surface of normal curvature k across the passes
// (> 0 convex: bending away from the tool): belt_step_over_exact.
double ball_step_over(double scallop_mm, double ball_radius_mm, double curvature_across);

}  // namespace bliskrun
