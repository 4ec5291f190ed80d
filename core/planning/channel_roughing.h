#pragma once
// Notching and widening of an impeller channel (impeller paper §4.1–4.2,
// eq. 12–14; SPEC §6.4): the channel between two blades is opened in its
// middle (notching), then widened towards both blades along the hub, which
// finishes the hub in the same passes.
//
// The channel lies between two blade faces, `left` and `right`, each in the
// SPEC §2 orientation (u hub -> shroud along the rulings, v along the chord,
// pu x pv out of the material, i.e. into the channel), over a hub of
// revolution about Z. Stations t in [0, 1] run along the channel from the
// inlet (LE) to the outlet (TE); a face's v at station t is t, or 1 - t when
// its v runs TE -> LE; or a part of the chord (ChannelFace). At a station the channel's hub section
// is the hub's parallel circle through the two faces' hub points (their
// mean meridian parameter), between the faces' angles.
//
// Stations are the hub's parallel circles from where both faces have
// begun to where the first ends, so both faces' hub points lie on each
// station's circle whatever their chord parametrisations.
//
// Notching (§4.1, Fig. 3): the middle of the channel — the ball centre
// (stock + r over the hub) as far from one face as from the other — with
// the axis the sum of the two faces' ruling vectors there, so the tool
// leans with both blades. The ball centre goes down in levels from the
// channel's middle at the shroud (the faces' shroud points' midpoint: the
// blank is turned to the shroud contour) to `stock` above the hub, no
// level more than `depth_step` deeper than the one before at any station.
//
// Widening with hub finishing (§4.2): on the hub, from the notch towards
// each blade. A ball of radius r leaves a scallop h between paths f apart:
// f = 2√(2rh − h²) exactly (eq. 12, f ≈ 2√(Dh), is its first order and a
// little too wide). Each side ends with the finishing (swarf) pose of the
// cutter grown by the stock (flank_axis with FlankCutter::grown): the
// real cutter there leaves the stock along its whole flute, not only at
// the ball. Per side S is the length over the hub at the outlet from the
// notch's ball centre to that pose's; N = ⌈S / f⌉ paths (eq. 13), their
// centres at equal steps along the line between the two, put back over
// the hub, at every station. The axis of path k = 1..N from the notch is
// normalize(n_b + (n_s − n_b) k / N) — eq. 14 with i = N − k — n_b the
// notch axis, n_s the finishing axis of that side's face at the station.
//
// The scallop between neighbouring paths (notch included) is measured on
// the hub at every station (the stock surface under the line between two
// ball centres sampled, the height the nearer ball leaves there along the
// hub normal), not taken from the formula; where it exceeds h anywhere,
// that side gets one more path (eq. 13's N is a proof only on a flat hub
// of constant width).
//
// A widening pose that is not clear is turned further towards the
// finishing axis about its ball centre (in quarters of what is left)
// before it is refused: near a blade leaning over the channel the flute
// needs more of the blade's lean than the blend gives.
//
// Hub stock apart from the faces' (hub_stock_mm): the paper finishes the
// hub in the widening passes while the faces keep their stock for flank
// finishing. The deepest notch level and every widening path then run with
// the ball r + hub stock over the hub, and each side's last path is the
// grown cutter's finishing pose slid down its own axis onto that offset (the
// flute keeps its line along the face). Between stations a straight move
// of the ball centre leaves the hub's curved offset (above it on a convex
// hub, below on a concave one): poses are inserted, halving, until the
// middle of every move is within hub_chord_tol_mm of the offset.
//
// Every pose is checked with the whole tool against the world (the two
// faces and the hub with `clearances`, at least the stock for the cutter)
// and so is the motion from the previous pose. Passes alternate direction
// (zigzag); at a turn the next pass is reached by a direct step-over or
// step-down where that motion is proved clear. A refused pose splits its
// pass and the next clear pose is reached by a link; links go up the tool
// axis and back down (links.h), proved the same way; a link that cannot
// be proved ends the plan there, with the reason.
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/collision/collision_world.h"
#include "core/common/progress.h"
#include "core/geometry/revolution.h"
#include "core/geometry/surface.h"
#include "core/planning/flank_milling.h"
#include "core/planning/links.h"
#include "core/tools/pose.h"
#include "core/toolpath/move.h"

namespace bliskrun {

// One side of the channel: a blade face and the part of its chord that
// bounds the channel, v_inlet -> v_outlet (v_inlet > v_outlet when the
// face's v runs outlet -> inlet). A splitter divides the outer part of a
// channel: main face from where the splitter starts, splitter face whole.
struct ChannelFace {
  const Surface* face = nullptr;
  double v_inlet = 0, v_outlet = 1;
  // The rest of the blade the face belongs to — its edge rounds, its other
  // flank — which a ball beyond the face's chord may come nearer than the
  // face itself: the levels' contacts keep the stock off them too
  // (channel_levels.h). Not read by notching and widening.
  std::vector<const Surface*> blade;
  double v_at(double t) const { return v_inlet + (v_outlet - v_inlet) * t; }
};

struct ChannelRequest {
  ChannelFace left, right;
  const SurfaceOfRevolution* hub = nullptr;
  const FlankCutter* cutter = nullptr;     // ball or tapered ball end
  const CollisionWorld* world = nullptr;   // may be null: no checks (geometry tests)
  const ToolBody* body = nullptr;          // with world
  Clearances clearances;                   // cutter: at least what the stock allows
  int stations = 41;                       // along the channel, inlet to outlet
  double stock_mm = 0.3;                   // left on the faces for finishing
  double hub_stock_mm = -1;                // left on the hub; < 0: stock_mm. 0: the passes on the hub
                                           // finish it (§4.2) — the world must then not hold the hub for
                                           // the cutter itself (see hub_finishing_world in impeller_world.lua)
  double hub_chord_tol_mm = 0.005;         // ball centres of the passes on the hub keep to the hub's offset
                                           // within this between stations (poses inserted)
  double scallop_mm = 0.01;                // h on the hub (eq. 12)
  double depth_step_mm = 5.0;              // notching: deepest step between levels
  bool widen = true;                       // false: notching only
  int scallop_samples = 16;                // hub samples between two neighbouring paths
  double motion_tol_mm = 1e-3;
  LinkOptions link = {RetractDirection::ToolAxis, 5.0, 0.1, 0, 0.002};
};

enum class ChannelPassKind { Notch, WidenLeft, WidenRight };
const char* to_string(ChannelPassKind kind);

// A pass of a channel plan. The impeller's notching and widening (this
// file): a notch level or a widening path. A blisk channel's levels
// (channel_levels.h): at level `level`, the slot in the level's middle
// (Notch, index 0) or the k-th path from it towards the left or right face
// (WidenLeft / WidenRight, index k).
struct ChannelPass {
  ChannelPassKind kind = ChannelPassKind::Notch;
  int index = 0;                  // notch level 1..L (deepest last) or widening path k = 1..N
  int level = 0;                  // a level of channel_levels.h (1 = the top); 0 here
  std::vector<double> t;          // station of each pose
  std::vector<ToolPose> poses;    // tip and axis; a refusal splits a pass into two
};

struct ChannelRefusal {
  ChannelPassKind kind = ChannelPassKind::Notch;
  int index = 0;
  int level = 0;
  double t = 0;
  std::string reason;
};

// The proved path of a channel, whichever strategy made it: its passes in
// cutting order and how each is reached from the one before.
struct ChannelPath {
  std::vector<ChannelPass> passes;       // in cutting order
  std::vector<PlannedLink> links;        // links[i]: from passes[i]'s last pose to passes[i + 1]'s first;
                                         // no via poses: a direct step at the feed (zigzag turn)
  std::vector<ChannelRefusal> refusals;
  PlannedDeparture lead_in, lead_out;    // up the tool axis at the first and last pose (with a world)
  bool complete = true;                  // false: a link could not be proved; the plan stops there
  std::string stopped;                   // why, when not complete
  long poses = 0;
  long turned = 0;                       // poses whose axis was turned further to clear a blade
  long inserted = 0;                     // poses inserted between stations (chord tolerance)
};

struct ChannelPlan : ChannelPath {
  int notch_levels = 0;
  int widen_left = 0, widen_right = 0;   // N per side
  int paths_added = 0;                   // beyond eq. 13's N, where a station's measured cusp exceeded h
  double step_over_mm = 0;               // f
  double outlet_width_left_mm = 0, outlet_width_right_mm = 0;  // S per side (over the hub at the outlet)
  double scallop_max_mm = 0;             // measured on the hub over every station
  double scallop_outlet_mm = 0;          // measured at the outlet station
  double deepest_step_mm = 0;            // largest depth between notch levels at any station
  double hub_stock_mm = 0;               // as planned (the request's, or the stock)
};

// The toolpath in cutting order (core/toolpath/move.h; row = the index into
// ChannelPlan::passes): the lead-in's away pose (Rapid, "start"), each
// pass's poses (Feed, "cut"; the first "approach", or "step" after a direct
// step), the links' via poses (Rapid, named by their leg), the lead-out's
// away pose (Rapid, "retract"). Nothing after a link that could not be
// proved, and no Stop: the plan's `stopped` says why it ends there.
Toolpath channel_moves(const ChannelPath& plan);

// How far above the stock surface point q, along its unit normal n, the
// ball (centre c, radius r) leaves material: the lower intersection of the
// normal line with the sphere, or +infinity when the line misses it — the
// scallop height as the impeller paper draws it (Fig. 4), not the distance
// to the ball along the line to its centre.
double height_to_ball(const Vec3& q, const Vec3& n, const Vec3& c, double r);

// What a channel's poses, motions and links are proved against (both
// strategies): `world` may be null (no checks: geometry tests).
struct ChannelChecks {
  const CollisionWorld* world = nullptr;
  const ToolBody* body = nullptr;
  Clearances clearances;
  double motion_tol_mm = 1e-3;
  LinkOptions link;
};

// Takes the poses of passes, in cutting order, into proved pieces: a pose
// that is not clear is refused and splits its pass; a pose whose motion from
// the previous one is not clear starts a new piece (reached by a link). With
// no world every pose is taken.
class ChannelPieces {
 public:
  ChannelPieces(const ChannelChecks& checks, std::vector<ChannelPass>& pieces, std::vector<ChannelRefusal>& refusals)
      : checks_(checks), pieces_(pieces), refusals_(refusals) {}
  void begin(ChannelPassKind kind, int index, int level = 0);
  // `checked`: the pose's check when the caller already has it; `motion`:
  // the check of the motion from the pose before, likewise.
  void add(const ToolPose& pose, double t, const PoseCheck* checked = nullptr, const MotionCheck* motion = nullptr);
  // The piece being built (empty after a refusal).
  const ChannelPass& current() const { return current_; }
  // Closes the pass's last piece.
  void end() { close(); }

 private:
  void close();
  const ChannelChecks& checks_;
  std::vector<ChannelPass>& pieces_;
  std::vector<ChannelRefusal>& refusals_;
  ChannelPass current_;
};

// Poses to insert between the end of one piece and the start of the next
// when they may be joined by a direct step at the feed (`between`, in
// order); false: they are to be joined by a link.
using ChannelStep = std::function<bool(const ChannelPass& from, const ChannelPass& to,
                                       std::vector<std::pair<double, ToolPose>>& between)>;

// Joins pieces (in cutting order) into `plan`: a direct step at the feed
// where `step` allows it and every pose and motion of it is proved,
// otherwise a link up the tool axis (links.h; link.retract_mm, then twice,
// four and eight times as far), and the lead-in and lead-out up the axis.
// A link that cannot be proved ends the plan there (complete = false,
// stopped = why). Without a world nothing is proved and no link is made
// (plan.links stays empty).
void join_channel_pieces(std::vector<ChannelPass> pieces, const ChannelChecks& checks, const ChannelStep& step,
                         ChannelPath& plan);

// Throws ParameterError naming the missing or impossible option, Error when
// the channel's geometry cannot be found (a face not meeting the hub's
// parallel circles, the ball not fitting the channel at a station).
ChannelPlan plan_channel(const ChannelRequest& request);

// Several channels (a blade's three around its splitter) on `threads`
// workers: plans in request order, the same for any thread count. The
// requests may share their world, faces, hub and cutter (read only).
std::vector<ChannelPlan> plan_channels(const std::vector<ChannelRequest>& requests, int threads,
                                       Progress& progress = Progress::none());

}  // namespace bliskrun
