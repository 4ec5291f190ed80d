#pragma once
// Blade leading/trailing-edge finishing with the bottom of a flat-end mill
// (SPEC §6.2, edge paper §3.2): rows around the edge at constant span v of
// the edge region (core/parts/edge_region.h), stepped by chord height
// (plan_row_steps), each contact positioned on the cutter bottom with (l, φ)
// optimised for the widest strip (core/planning/edge_strip.h) — on the
// corner torus with the smallest gouge-free lead where the bottom cannot cut
// — rows spaced by the row's smallest strip, every pose and motion proved
// against the world (neighbouring blades, hub, the blade itself for shank
// and holder: core/collision), links retracting along the tool axis. The
// same rows are also measured for the conventional side-edge positioning
// (corner contact, φ = 0, smallest gouge-free lead from a minimum lead), so
// the paper's comparison (Fig. 8: strip width along a row; Fig. 9: row
// counts, 31 vs 48) comes out of the same run.
//
// The result has the drum finish's shape (rows of poses, links) and its
// program is the one toolpath type (core/toolpath/move.h), so the posts and
// a whole-blisk job take it as they take a drum-finish plan.
#include <memory>
#include <string>
#include <vector>

#include "core/collision/collision_world.h"
#include "core/collision/tilt.h"
#include "core/common/progress.h"
#include "core/geometry/revolution.h"
#include "core/geometry/surface.h"
#include "core/toolpath/move.h"
#include "core/planning/edge_strip.h"
#include "core/planning/links.h"
#include "core/planning/row_steps.h"
#include "core/sim/undercut.h"
#include "core/tools/tool.h"

namespace bliskrun {

// Which bottom optimum the emitted path uses.
enum class EdgeOptimum {
  Paper,  // §3.2: φ averaged over the l_j's two-sided searches, then l balanced
  Joint,  // ours: each l_j keeps its own best φ, then l balanced (no averaging)
};

// How each contact is positioned (issue 38 item 4: the paper's comparison
// like for like). Either way the rows go through the same steps — spacing
// and stopping rule, tilting clear of the world, partial rows, checks,
// links — so the two programs differ by the positioning alone.
enum class EdgeMethod {
  Bottom,  // the paper's: the flat bottom (l, φ) where it cuts, the corner torus where it cannot
  Side,    // the conventional side-edge positioning: corner torus, φ = 0, smallest gouge-free lead >= side_min_lead
};

// Strip sampling for an edge region: condition ① on 41 samples over the
// whole region around (its round is a fraction of the tool's size) on every
// 4th line across.
inline StripSampling edge_sampling() {
  StripSampling s;
  s.gouge_whole_u = true;
  s.gouge_along = 41;
  return s;
}

struct EdgeFinishRequest {
  std::shared_ptr<const Surface> edge;  // edge region: u around, v span (build_edge_region)
  // The two flanks the region was built from (EdgeRegionRequest first and
  // second, with its span range): condition ① is checked on them too, a
  // tool radius into each from its edge end, so the flat bottom reaching
  // over a concave flank beyond the edge region is seen. Optional.
  std::shared_ptr<const Surface> first, second;
  double span_u0 = 0, span_u1 = 1;
  // Span window to machine (edge-region v): by default the whole edge, hub
  // and casing narrowing it (below).
  double v0 = 0, v1 = 1;
  // The hub and the casing (surfaces of revolution about Z), optional; they
  // narrow the window. With a hub, the first row is the lowest span >= v0
  // at which every contact, positioned as planned, keeps the cutter
  // hub_clearance_mm outside the hub: lower, the bottom's disc (R either
  // side of the feed) sits in the hub. The strip below is left for the
  // hub-fillet operation, as the drum finish leaves its own
  // (DrumFinishRequest::hub_clearance_mm), and reported. With a casing, the
  // window ends where the whole row lies outside it (past the blade's tip).
  std::shared_ptr<const SurfaceOfRevolution> hub, casing;
  double hub_clearance_mm = 0.05;
  const Tool* tool = nullptr;           // a flat-end mill
  const CollisionWorld* world = nullptr;
  Band band;                            // e1 (overcut), e2 (undercut)
  double r_e_mm = 1.0;                  // condition ③: l >= r_e
  int l_count = 6;                      // discretised l in [r_e, R - r]
  EdgeOptimum optimum = EdgeOptimum::Paper;
  EdgeMethod method = EdgeMethod::Bottom;
  SideSlipSearch search;
  // On a nearly cylindrical edge the width has two equal peaks (φ of either
  // sign, the tool centre towards the hub or the tip across the feed) and
  // which one the search keeps is noise; the strip is then lopsided to
  // alternate sides from contact to contact and the row spacing (this row's
  // smallest reach up + the next's smallest reach down) collapses. Ours, not
  // the paper's: keep the peak from -90° (centre towards the tip, the disc
  // away from the hub) unless the other is wider by this fraction.
  double peak_preference = 0.02;
  StripSampling sampling = edge_sampling();
  // Chord tolerance around the edge (the paper's 0.001 mm). Constant chord
  // height with the measured guarantee: the variable method's δ only
  // shrinks after the round's curvature peak (eq. 18-19 never lets it grow
  // back above the ratio), which on a 0.4 mm round left steps of 0.2 µm.
  StepOptions steps{ChordMethod::Constant, 0.001, true, 0.5, 1e-4};
  bool zigzag = true;                   // one-way links go round the edge
  double side_min_lead_rad = 3.0 * kPi / 180.0;  // conventional side-edge positioning (EdgeMethod::Side)
  // Tilting a contact clear of the world (the drum finish's interference
  // loop, core/collision/tilt.h): corner leads θ from tilt_lead_step up to
  // tilt_lead_max, side-slips all round in tilt_slip_step steps, axes within
  // the machine's range (empty: no limit).
  double tilt_lead_step_rad = 5.0 * kPi / 180.0;
  double tilt_lead_max_rad = 80.0 * kPi / 180.0;
  double tilt_slip_step_rad = 15.0 * kPi / 180.0;
  // Extra clearance of the shank and holder an axis is first sought with
  // (links between tilted poses need room to pass); the bare clearances
  // where none has it.
  double tilt_room_mm = 0.5;
  AxisLimit axis_limit;
  // The machine's reach in the setup the edge is cut in: every emitted axis
  // between reach_min_rad and reach_max_rad of reach_axis (unit; zero: no
  // limit) — e.g. within 118 deg of the table's axis for a B head or A
  // cradle that tilts to 120, and at least 35 deg off it for a cradle whose
  // other side reaches 30 deg (below that a path may have to change sides
  // between moves, which no motion along it does). An axis outside is
  // tilted like one that interferes, or refused.
  Vec3 reach_axis = Vec3::Zero();
  double reach_min_rad = 0, reach_max_rad = kPi;
  // With a reach, its axis is the table's, the pole of the machine's rotary
  // axes: every link keeps its turning axis this far off it (LinkOptions::
  // pole_clearance_rad; a link 0.002 deg off it was refused by the post).
  double pole_clearance_rad = 1.0 * kPi / 180.0;
  Clearances clearances;
  double motion_tol_mm = 1e-3;
  double retract_mm = 3.0;              // links: up the tool axis
  // With short_lift_mm > 0, two passes whose ends are near (within the
  // tool's diameter, axes within 45 deg) that no straight cutting motion
  // joins are joined by a lift of this much up both axes, across and down,
  // fed (EdgeFinishLink::lifted): one pass, not a retract of retract_mm, a
  // traverse and a plunge (rapid). Off by default: on the built-in TE it
  // makes 107 passes 41, but the lifts' 234 mm are fed where the retracts
  // were rapid (bench/RESULTS.md), and on Rotor 67 each lift tried costs a
  // link's proof more.
  double short_lift_mm = 0;
  double tool_tol_mm = 1e-3;            // ToolBody meshing tolerance
  int threads = 1;                      // workers for a row's contacts; results do not depend on it
  int comparison_row = -1;              // row whose widths are reported in full (-1: the middle one)
};

struct EdgeFinishPose {
  ToolPose pose;
  Vec3 contact = Vec3::Zero(), normal = Vec3::UnitZ();
  double u = 0, v = 0;
  EdgePosition position;
  double width_mm = 0, left_mm = 0, right_mm = 0;  // strip at this pose
  int segment = 0;  // passes within the row (a refused contact splits the row)
  bool break_before = false;  // bottom <-> corner switch: a link, not a cut, from the previous pose
  int piece = 0;              // the part of a partial row it belongs to (no cut across parts)
  bool inserted = false;      // added so the motion from the previous pose stays within e1
  bool tilted = false;        // the optimum was not clear of the world: corner with more lead instead
  double lift_mm = 0;         // lifted off along the normal: it cut the blade beside its strip (< 3 um)
  std::shared_ptr<const ContactStrip> strip;  // the contact's samples
};

struct EdgeContactRefusal {
  double u = 0;
  Vec3 contact = Vec3::Zero();
  std::string reason;
};

struct EdgeFinishRow {
  double v = 0;
  bool reversed = false;
  // A partial row between two rows, over only the part around the edge
  // where their strips as emitted (tilted poses cut narrower ones) leave
  // material between them (see plan_edge_finish).
  bool infill = false;
  double width_mm = 0;                 // balanced row width (the emitted method)
  double left_min_mm = 0, right_min_mm = 0;
  double spacing_mm = 0;               // to the next row (0 on the last)
  double paper_width_mm = 0, joint_width_mm = 0;  // row width by either optimum
  double side_width_mm = 0;            // conventional side-edge positioning
  int bottom_contacts = 0, corner_contacts = 0;
  double max_deviation_mm = 0;         // measured chord deviation
  std::vector<EdgeFinishPose> poses;   // emitted, in cutting order
  std::vector<EdgeContactRefusal> refusals;
  int strip_evaluations = 0;
  int inserted_contacts = 0;           // motion refinement (see plan_edge_finish)
  int tilted_contacts = 0;             // corner positions taken for clearance
};

// Between consecutive passes: rows, and the pieces of a row split by a
// refused contact or a bottom <-> corner switch.
// Planned by the shared plan_link (core/planning/links.h).
struct EdgeFinishLink {
  int from_row = 0, to_row = 0;
  std::vector<ToolPose> moves;  // via poses (rapid)
  std::vector<LinkLeg> legs;    // legs[k]: the motion into moves[k] (then one more into the next pass)
  double offset_mm = 0;         // retract distance up the axis that proved
  // The next pass reached straight from the last, cutting, without leaving
  // the surface: the motion proved clear of the world and within e1 of the
  // blade by the design guards (no moves; the two passes are one).
  bool direct = false;
  // Reached by a short lift (EdgeFinishRequest::short_lift_mm): `moves` up
  // the axis, across and down, proved as any link's legs and fed, the two
  // passes one (edge_finish_moves: Feed moves).
  bool lifted = false;
  bool clear = false;
  std::string reason;
};

// The paper's Fig. 8 for one row: strip widths per contact for each method.
struct EdgeWidthComparison {
  int row = -1;
  double v = 0;
  std::vector<double> u, bottom_mm, paper_mm, joint_mm, side_mm;
  std::vector<std::string> contact;  // "bottom" / "corner" per contact
};

struct EdgeFinishResult {
  // The span window machined: the request's, narrowed by hub and casing.
  double v0 = 0, v1 = 0;
  // Largest span distance (mm, along the region's rows) between the
  // request's v0 or the hub, whichever is higher, and the first row: the
  // strip left to the hub-fillet operation (0 without a hub).
  double hub_strip_mm = 0;
  // Largest span distance (mm) from the window's end v1 up to where the
  // edge leaves the casing (the highest span with a point of the row still
  // inside it; the region's end without a casing): the strip at the top
  // left unmachined — 0 when the window reaches the casing, as it does by
  // default (no other operation finishes the edge's top).
  double top_strip_mm = 0;
  // The span the design guards sample on the edge region (and the recipe's
  // simulation measures overcut over): the window and a tool radius + 1 mm
  // beyond either end, where the rows' discs reach.
  double checked_v0 = 0, checked_v1 = 1;
  std::vector<EdgeFinishRow> rows;
  std::vector<EdgeFinishLink> links;
  // Off the first pose and off the last, up the tool axis, proved as a
  // link's legs (plan_departure): the path begins and ends in the air, so a
  // job's link into it or out of it never ends on the blade.
  PlannedDeparture lead_in, lead_out;
  int total_poses = 0, total_refusals = 0, refused_links = 0;
  // Refused links proved by cutting the rows either side the other way or
  // in the other order (zigzag only; see plan_edge_finish).
  int rearranged_rows = 0;
  // Cutting motions the gouge guard (core/sim, the whole edge region and
  // both flanks) found cutting beyond e1: reached by a link instead.
  long gouge_breaks = 0;
  // Rows the side-edge positioning needs over the same window, by the same
  // spacing and stopping rule (plan_rows): with EdgeMethod::Side the rows
  // planned, otherwise side-edge rows planned over the window for the count.
  int side_rows = 0;
  double side_window_mm = 0;     // span length covered (along the round's middle)
  EdgeWidthComparison comparison;
  double max_deviation_mm = 0;
  int infill_rows = 0;           // partial rows among `rows` (EdgeFinishRow::infill)
  int lifted_contacts = 0;       // emitted poses lifted off by < 3 um (EdgeFinishPose::lift_mm)
  int simulated_infill_rows = 0; // of infill_rows: where the simulated rows left more than e2
  // rows_seconds: the bottom method's rows and the window's fit to the hub
  // (rows planned for their margin from it).
  double rows_seconds = 0, checks_seconds = 0, side_seconds = 0;
  double clear_seconds = 0;      // tilting clear of the world and the partial rows
  double simulation_seconds = 0; // of checks_seconds: the rows simulated for material left
  double links_seconds = 0;      // of checks_seconds: the links, lead-in and lead-out
};

// Throws ParameterError for a missing edge/tool/world, a tool that is not a
// flat-end mill, an empty span window, band e1 > 0 or e2 <= e1.
EdgeFinishResult plan_edge_finish(const EdgeFinishRequest& request, Progress& progress = Progress::none());

// Rows' poses (Feed), link poses (Rapid), Stop where a contact or link was
// refused — a Toolpath like drum_finish_moves'.
Toolpath edge_finish_moves(const EdgeFinishResult& result);

// The program's shape (issue 38 item 5): cutting passes (runs of Feed
// moves), the tip's path length cutting (Feed to a Feed "cut") and not
// (every leg into, between or out of Rapid moves, and a short lift's fed
// legs: retracts, traverses, plunges).
struct EdgeProgramStats {
  int passes = 0;
  int single_move_passes = 0;  // passes of one or two poses (at most one cutting move)
  double cutting_mm = 0, non_cutting_mm = 0;
  int direct_links = 0;        // passes joined on the surface (EdgeFinishLink::direct)
  int lifted_links = 0;        // passes joined by a short lift, fed (EdgeFinishLink::lifted)
  double lift_mm = 0;          // of non_cutting_mm: the short lifts' legs (fed, not rapid)
  // Of non_cutting_mm: the links' rapid legs (retracts, traverses, rapid
  // approaches, lead-in and lead-out) and the fed plunges from a rapid into
  // each pass's first pose.
  double rapid_mm = 0, plunge_mm = 0;
};
EdgeProgramStats edge_program_stats(const EdgeFinishResult& result);

// Every move as simulation passes (a Stop ends a pass), rows and links,
// with the index of each pass's first move (toolpath_passes).
ToolpathPasses edge_finish_passes(const EdgeFinishResult& result);

// The edge's thickness after machining against the design (issue 14 item
// 7), from the simulation's material left on the edge region. At span v the
// section u -> S(u, v) is a U round the edge; its camber direction t runs
// from the middle of its two ends to its farthest point (the front). The
// thickness `behind_mm` behind the front is measured in the plane
// perpendicular to t there, between the section's two sides: the design's
// points S(u_i, v) and the machined ones S + r n (r the material left,
// interpolated between the simulation's sample rows, n out of the
// material), each side's polyline cut by the plane. Not measured where a
// side does not reach that far or the tool left a sample on the way
// untouched (r = +infinity).
struct EdgeThickness {
  double v = 0, behind_mm = 0;
  bool measured = false;
  double design_mm = 0, machined_mm = 0;
};
// `simulation` with `options` as simulate_undercut ran them on `edge`.
// Throws ParameterError for a residual map of another size, a span outside
// [options.v0, options.v1] or a negative distance.
std::vector<EdgeThickness> edge_thickness(const Surface& edge, const UndercutResult& simulation,
                                          const UndercutOptions& options, const std::vector<double>& spans_v,
                                          const std::vector<double>& behind_mm);

// APT/CL text (header, GOTO/x,y,z,i,j,k, RAPID before link moves).
std::string edge_finish_apt(const EdgeFinishResult& result, const EdgeFinishRequest& request,
                            const std::string& name);

}  // namespace bliskrun
