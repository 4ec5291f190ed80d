#pragma once
// Roughing a blisk channel in levels (issue 41): the channel between two
// neighbouring blades — blade k's pressure flank on one side, blade k+1's
// suction flank on the other — cleared from the blank's top (the casing, or
// a blank's outer surface of revolution) down to the hub, leaving a uniform
// stock on both flanks and on the hub for the finishers.
//
// Strategy (docs/lua_api/jobs.md, "Blisk channel roughing", gives the
// evidence): five-axis slot milling in levels with a (tapered) ball end, its
// axis tilted to stay between the blades — the levels-and-offsets scheme of
// the commercial blisk roughing strategies (PowerMill's Blisk Area
// Clearance: ball or tapered ball-end mills, levels from the shroud, a
// thickness left on the blades and hub) rather than plunge milling, which
// roughs large open blisks with dedicated plunge cutters but leaves a
// scallop between plunges on both flanks and needs a semi-finish to even it.
//
// Geometry. Like notching and widening (channel_roughing.h) the channel
// lies between two faces in the SPEC §2 orientation (u hub -> tip, pu x pv
// into the channel) over a hub of revolution about Z. A point of the hub's
// meridian, m(u), with its unit normal n(u) towards the blades' tips,
// carries the channel's levels: the ball centre of level l (1 = the top,
// L = on the hub) at station u lies D_l(u) along n(u), turned about Z,
//   D_l(u) = T(u) + r - l (T(u) - s_hub) / L,
// T(u) the height of the top over the hub along n(u), r the ball radius,
// s_hub the hub stock: level l's ball reaches (T - s_hub) l / L below the
// top, level L runs on the hub's offset by the stock. Across the channel a
// level's ball centres lie on the circle of radius |m(u) + D n(u)| about
// Z, between the angle where the ball is r + stock from the left face
// (signed distance along the face's normal) and the angle where it is that
// far from the right face: the two contacts, which leave the stock on the
// faces. A level runs from where the first contact's foot enters its face's
// chord part to where the last one leaves it, in `stations` equal steps of
// u, so every level covers both faces' chords edge to edge. The blades are
// staggered: at the channel's mouths one face ends before the other's
// contact has reached its edge. There that side's contact keeps r + stock
// off the rest of its blade (ChannelFace::blade: its edge round, its other
// flank), and where that blade is out of the ball's reach altogether the
// side reaches to the angle of its face's end.
//
// Passes of a level, in cutting order: the slot in the middle (the angle
// halfway between the contacts), then paths towards the left face up to
// its contact, then towards the right face; N per side so that neighbouring
// paths are at most step_over apart at every station, measured across the
// paths' direction (the level's circles cross the channel obliquely; on
// the hub level also close enough that the cusp they leave on the hub is
// within `scallop`). Passes alternate direction along the channel
// (zigzag). The paths that leave the stock — the contacts and the hub
// level — run through every station; the paths between, which only clear
// material, through `interior_stations` of them (ends included).
//
// Tool axis: at a contact the face's span direction (the unit pu at the
// contact's foot) turned away from the face, in the plane of pu and the
// face normal, by the cutter's cone half angle plus `tilt_deg`, so the
// flute above the ball leans off the face; in the middle the normalised sum
// of the two contact axes; between, path k of N blends from the middle's to
// the contact's (eq. 14's blend). A pose that is not clear is turned about
// its ball centre (the stock it leaves is the ball's) to blends further
// towards and beyond the middle's axis, or beyond the contact's, the
// nearest first, before it is refused.
//
// What it leaves, measured not assumed: on each face between two levels'
// contacts the cusp of the two balls over the face offset by the stock (the
// face sampled between the contacts' ball centres, the height each ball
// leaves along the face normal); where it exceeds `scallop` at any station,
// L grows by one and the levels are laid out again. On the hub between the
// hub level's paths the same measure over the hub offset by its stock (one
// more path on that side where it is exceeded). Contact paths and the hub
// level keep their ball centres within chord_tol_mm of where they belong
// between stations (poses inserted, halving).
//
// Engagement: a level takes at most step_down (axial depth a_p along n)
// below the one before — plus the cusps the paths above left on its floor,
// reported as axial_engagement_max_mm — and a path at most step_over
// (radial engagement a_e) beside its neighbour; the slot takes the ball's
// full width at that depth. Levels are cut top down and each level fully
// before the next, so a path never cuts deeper than one level.
//
// Proofs: every pose with the whole tool against `world` (both channel
// blades — flanks to the top, edge rounds — and the hub, the cutter's clearance
// the stock less what the world's tessellation and the motion tolerance
// take), every motion between poses of a pass (where one is not clear the
// pass's own pose halfway is inserted, proved and turned like the others,
// down to 1/16 of the motion, before the pass is split); consecutive passes are
// joined by a direct step at the feed where it is proved (at the same
// station: a step across a level, or the ramp down to the next level's
// slot, the step across a level kept on the level's circle), otherwise by
// a link up the tool axis (links.h) proved the same way; the lead-in and
// lead-out go up the axis (channel_roughing.h, join_channel_pieces).
#include <vector>

#include "core/common/progress.h"
#include "core/planning/channel_roughing.h"

namespace bliskrun {

struct ChannelLevelsRequest {
  ChannelFace left, right;
  const SurfaceOfRevolution* hub = nullptr;
  const SurfaceOfRevolution* top = nullptr;  // the blank's top over the channel (a blisk's casing)
  const FlankCutter* cutter = nullptr;       // ball or tapered ball end
  const CollisionWorld* world = nullptr;     // may be null: no checks (geometry tests)
  const ToolBody* body = nullptr;            // with world
  Clearances clearances;                     // cutter: the stock less the world's and the motion's tolerances
  int stations = 41;                         // per level, inlet to outlet: the paths that leave the stock
  int interior_stations = 11;                // the same stations, fewer: the paths between (<= stations)
  double stock_mm = 0.5;                     // left on both faces
  double hub_stock_mm = -1;                  // left on the hub; < 0: stock_mm
  double step_down_mm = 1.0;                 // largest depth between levels along the hub normal (a_p)
  double step_over_mm = 2.0;                 // largest distance between neighbouring paths' ball centres (a_e)
  double scallop_mm = 0.03;                  // cusp over the stock: on the faces between levels, on the hub
  double chord_tol_mm = 0.005;               // contact paths and the hub level between stations
  double tilt_deg = 3.0;                     // contact axes leaning off the face beyond the cone's half angle
  double motion_tol_mm = 1e-3;
  int threads = 1;                           // the plan does not depend on it
  LinkOptions link = {RetractDirection::ToolAxis, 5.0, 0.1, 0, 0.002};
};

struct ChannelLevelsPlan : ChannelPath {
  int levels = 0;                     // L
  int levels_added = 0;               // beyond the step-down's, where a face's measured cusp exceeded `scallop`
  int paths_added = 0;                // on the hub level beyond the step-over's, for the hub's cusp
  std::vector<int> paths_left, paths_right;  // N per side, per level (index level - 1)
  double level_step_max_mm = 0;       // largest depth between consecutive levels (<= step_down)
  double step_over_max_mm = 0;        // largest distance between neighbouring paths' ball centres
  double axial_engagement_max_mm = 0; // level step plus the largest cusp the level above left between its paths
  double slot_width_mm = 0;           // the ball's width at the deepest level step (the slot's radial engagement)
  double face_cusp_max_mm[2] = {0, 0};  // measured between levels, left and right face
  double hub_cusp_max_mm = 0;         // measured between the hub level's paths
  double top_height_min_mm = 0, top_height_max_mm = 0;  // T over the channel's stations
  double hub_stock_mm = 0;            // as planned
  double station_step_max_mm = 0;    // largest ball-centre move between two stations of a contact path
  // Heights over the hub (along its normal) of the contacts' feet on each
  // face (left, right): the highest of the hub level's — over it every face
  // point lies between two levels' contacts, under it is the ball's corner
  // with the hub — and the lowest of the top level's.
  double corner_mm[2] = {0, 0}, contact_top_mm[2] = {0, 0};
  // The hub level's stations, in the hub's meridian parameter.
  double hub_u_in = 0, hub_u_out = 0;
};

// Throws ParameterError naming the missing or impossible option, Error when
// the channel's geometry cannot be found (the ball with its stock not
// fitting between the faces, a level with no station on both faces).
ChannelLevelsPlan plan_channel_levels(const ChannelLevelsRequest& request, Progress& progress = Progress::none());

}  // namespace bliskrun
