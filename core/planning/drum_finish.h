#pragma once
// Blisk flank finishing with a drum wheel (SPEC §6.1, blisk paper §3):
// trim the flank between hub and casing (§3.1 Fig. 5), space rows by the
// drum wheel's cut width against the normal curvature across the feed
// (§3.1 Fig. 6), step along each row to the chord tolerance, orient the
// axis by the paper's λ/w rule with tilt-until-clear (§3.3), and link the
// rows with collision-checked retract/traverse/approach moves.
#include <memory>
#include <string>
#include <vector>

#include "core/collision/collision_world.h"
#include "core/collision/tilt.h"
#include "core/common/progress.h"
#include "core/geometry/revolution.h"
#include "core/geometry/surface.h"
#include "core/planning/links.h"
#include "core/planning/row_steps.h"
#include "core/planning/trimmed_surface.h"
#include "core/sim/undercut.h"
#include "core/tools/tool.h"
#include "core/toolpath/move.h"

namespace bliskrun {

struct DrumFinishRequest {
  std::shared_ptr<const Surface> flank;       // u hub→tip, v along the chord
  const SurfaceOfRevolution* hub = nullptr;    // lower trim (u' = 0)
  const SurfaceOfRevolution* casing = nullptr; // upper trim (u' = 1)
  const Tool* tool = nullptr;
  bool flip_normal = false;    // material lies on the +pu×pv side
  const CollisionWorld* world = nullptr;       // neighbouring blades, hub
  double residual_height_mm = 0.014;
  StepOptions steps;
  TiltSettings tilt;
  bool zigzag = true;
  // Rows cut from the tip down to the hub instead of up from it (the rows,
  // their poses and spacing are the same; only their order and the links
  // between them change). After a roughing that left stock on the flank the
  // wheel's shank runs along the flank above its row, 0.15-0.34 mm off it
  // on the built-in blisk's concave pressure flank: cut from the hub up, the
  // flank there still carries the stock and the shank stands in it; from the
  // tip down it is already finished (and the blade keeps the stiffness of
  // its unfinished root while its tip is cut).
  bool top_down = false;
  int width_samples = 40;      // contact points per row sampled for the width
  int trim_samples_v = 200;    // iso-v lines intersected with hub and casing
  // Links between rows (core/planning/links.h). A drum wheel cuts with its
  // side, its axis along the span nearly tangent to the flank: it leaves
  // along the flank normal, never along its axis. Every link is proved
  // against the world and against the finished flank itself (the whole
  // trimmed flank, sampled every guard_spacing_mm) with
  // links.allowed_overcut_mm.
  LinkOptions links;
  double guard_spacing_mm = 0.1;
  // Every cutting segment is also swept through the guard's samples and
  // halved where it dips below the flank by more than the chord tolerance.
  bool verify_rows = true;
  double tool_tol_mm = 1e-3;   // ToolBody meshing tolerance
  // Hub clearance rule: at u' = 0 the contact is on the hub curve and the
  // half of the wheel below its widest point would sit in the hub. The first
  // row is raised to the lowest u' at which the wheel, at every sampled
  // contact of the row with its initial axis, stays this far outside the hub
  // surface of revolution (sampled on the cutter's surface). The strip below
  // is left for the hub-fillet operation and reported. The interference loop
  // still proves every pose against the world, which should hold the hub.
  double hub_clearance_mm = 0.02;
};

struct DrumFinishPose {
  ToolPose pose;
  Vec3 contact = Vec3::Zero();
  double u = 0, v = 0;  // trimmed-surface parameters of the contact
  double lead_rad = 0, tilt_rad = 0;
};

struct DrumFinishRow {
  double u = 0;                // u' of the row
  double width_mm = 0;         // smallest cut width along the row (initial axis)
  // Smallest reach of the cut within the residual height towards the hub /
  // the tip over the row's poses as tilted (width/2 each at lead 0).
  double reach_below_mm = 0, reach_above_mm = 0;
  double spacing_du = 0;       // u' step to the next row cut (0 on the last; > 0 either way)
  int contacts = 0;            // contact points planned along the row
  double max_deviation_mm = 0; // measured chord deviation
  bool reversed = false;       // zigzag: row run from v = 1 to v = 0
  // The row's contact parameters v (increasing, whatever the cutting
  // direction) and the measured chord deviation of each segment between
  // them (the paper's Fig. 13).
  std::vector<double> v, deviation_mm;
  std::vector<DrumFinishPose> poses;  // emitted, in cutting order
  std::vector<TiltRefusal> refusals;  // contacts with no clear axis
};

// Move from the end of one row to the start of the next (plan_link):
// retract along the flank normal, traverse, approach along the normal.
// Emitted only when every segment is proved clear of the world and of the
// finished flank; otherwise the link is a refusal.
struct DrumFinishLink {
  int from_row = 0, to_row = 0;
  std::vector<ToolPose> moves;  // the via poses (rapid), in order
  std::vector<LinkLeg> legs;    // legs[i] ends at moves[i]; the last (to the next row) is the approach
  double offset_mm = 0;         // the normal offset the proof used
  double turn_rad = 0;          // the direction turned from the normal up the axis (plan_link)
  double deepest_cut_mm = 0;    // deepest sampled dip below the flank (<= 0, within the allowance)
  bool clear = false;
  std::string reason;           // why it was refused, when not clear
};

// The way into the first row and out of the last: from / to the pose
// `offset_mm` along the flank normal, proved like a link leg
// (plan_departure). A job links these to its clearance surface.
using DrumFinishEnd = PlannedDeparture;

struct DrumFinishResult {
  std::shared_ptr<const TrimmedSurface> trimmed;
  double first_row_u = 0;      // u' of the first row (hub clearance rule)
  double hub_strip_mm = 0;     // largest 3-D gap from the hub curve to the first row
  std::vector<DrumFinishRow> rows;
  std::vector<DrumFinishLink> links;
  DrumFinishEnd lead_in, lead_out;
  // refused_links counts refused links and a refused lead-in or lead-out.
  int total_poses = 0, total_refusals = 0, refused_links = 0;
  // Rows inserted because tilted neighbours no longer met within the
  // residual height, and neighbouring rows that still do not after the
  // refinement (reported, not hidden).
  int inserted_rows = 0, uncovered_gaps = 0;
  // Row tilts redone after halving segments where the axis turned enough
  // between two poses that chord + ρ θ²/8 exceeded the chord tolerance.
  int turn_splits = 0;
  // Row tilts redone after halving segments whose swept wheel the guard
  // found dipping below the finished flank by more than the chord tolerance.
  int gouge_splits = 0;
  double max_deviation_mm = 0;
  double guard_spacing_mm = 0;  // largest spacing of the finished-flank samples the links were proved on
  double trim_seconds = 0, rows_seconds = 0, tilt_seconds = 0, link_seconds = 0;
};

// Throws ParameterError for a missing flank/hub/casing/tool/world or
// non-positive residual height, width_samples < 2, bad link options or
// guard_spacing_mm <= 0.
DrumFinishResult plan_drum_finish(const DrumFinishRequest& request, Progress& progress = Progress::none());

// Plans several flanks (e.g. every blade of a blisk) on `threads` worker
// threads. Results are in request order and do not depend on the thread
// count. Each request's world and surfaces must stay alive and must not be
// shared mutably; const sharing is fine. Reports one step per finished flank;
// cancelling `progress` stops every worker at its next safe point.
std::vector<DrumFinishResult> plan_drum_finish_all(const std::vector<DrumFinishRequest>& requests, int threads,
                                                   Progress& progress = Progress::none());

// The toolpath of a plan in cutting order (core/toolpath/move.h): the
// lead-in pose (Rapid, "start"), each row's poses (Feed, "cut"; a row's
// first "approach", or "start" after a Stop), the proved link poses to the
// next row (Rapid, named by their leg), the lead-out pose (Rapid,
// "retract"); where a link (or the lead-in/out) was refused a Stop carrying
// the reason — so no unchecked move is implied.
Toolpath drum_finish_moves(const DrumFinishResult& result);

// drum_finish_moves as simulation passes (toolpath_passes).
ToolpathPasses drum_finish_passes(const DrumFinishResult& result);

// The undercut simulation (core/sim) of the whole program against its
// design flank: the whole trimmed flank u' in [0, 1] is sampled and swept
// by every move (rows, retracts, traverses, approaches) in program order
// with the motion the checks assume (PoseMotion); the undercut statistics
// cover the machined window u' in [first_row_u, 1] (the strip under the
// first row is the hub operation's), the overcut covers every sample. The
// options' samples_u (over the machined window), v window and sweep are the
// caller's; below the machined window the samples continue at the same
// spacing down to the hub curve (u0, u1, the machined window and
// flip_normal are set here).
struct DrumFinishSimulation {
  UndercutResult undercut;
  int first_machined_row = 0;  // sample row of the first drum row (rows below: the hub strip)
  // The move that cut the deepest overcut (index into drum_finish_moves,
  // -1 when nothing cut below the design), its motion and row.
  long overcut_move = -1;
  std::string overcut_motion;
  int overcut_row = -1;
};
DrumFinishSimulation simulate_drum_finish(const DrumFinishResult& result, const DrumFinishRequest& request,
                                          UndercutOptions options, Progress& progress = Progress::none());

// Cut width row spacing at u' (exposed for tests): smallest cut width over
// `samples` points of the row, and the u' step that keeps the 3-D gap
// within it everywhere.
struct RowWidth {
  double width_mm = 0;
  double du = 0;
};
// flip_normal as in DrumFinishRequest.
RowWidth row_width(const Surface& trimmed, const Tool& tool, double u, double residual_height_mm, int samples,
                   bool flip_normal = false);

// APT/CL text: header naming tool and tolerances, GOTO/x,y,z,i,j,k per
// pose (tool tip and axis), RAPID before each link move; fixed 6-digit
// formatting so output is deterministic.
std::string drum_finish_apt(const DrumFinishResult& result, const DrumFinishRequest& request);
void write_drum_finish_apt(const std::string& path, const DrumFinishResult& result,
                           const DrumFinishRequest& request);

}  // namespace bliskrun
