#pragma once
// The edge finish's steps (core/planning/edge_finish.h), shared between the
// files of core/planning/edge_finish/: each file one idea —
//   contacts.cpp        a contact's positions and strip (the paper's §3.2 search)
//   rows.cpp            rows around the edge, spaced by their strips
//   comparison.cpp      the paper's comparison with the side-edge positioning
//   window.cpp          the span window fitted to hub and casing
//   checks.cpp          the design guards and the checks of a row in cutting order
//   tilt.cpp            poses tilted (or lifted) clear of the world
//   partial_rows.cpp    partial rows where the strips as emitted leave gaps
//   simulated_gaps.cpp  partial rows where the simulated passes leave material
//   links.cpp           cutting order and the links between passes
//   program.cpp         the moves and the APT program
//   thickness.cpp       the edge's thickness after machining
// Not a public interface: only these files and edge_finish.cpp include it.
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/planning/edge_finish.h"

namespace bliskrun::edge_detail {

// Parts of a row around the edge, [u0, u1] each, in u order.
using Intervals = std::vector<std::pair<double, double>>;

// Everything one contact contributes to its row.
struct ContactPlan {
  double u = 0;
  EdgeFrame frame;
  bool bottom = false, any = false;   // a bottom position exists / any position exists
  std::vector<double> paper_w, joint_w;  // per l_j (0 = infeasible)
  std::vector<double> joint_phi;
  double paper_phi = 0;
  EdgePosition corner;                // when !bottom
  double corner_w = 0;
  double side_w = 0;                  // conventional side-edge positioning
  int evaluations = 0;
  int piece = 0;  // which part of a partial row (plan_row's `only`) it belongs to
  std::shared_ptr<const ContactStrip> strip;
};

// A row's condition-① samples beyond its contacts' strips: they depend on
// the row's span alone, not on the contact, so a row samples them once and
// its contacts' strips share them (of a contact's 2946 samples on the
// built-in LE, 1680 are the flanks' and 861 these lines; a third of the
// poses are contacts inserted between others, each sampling its strip):
//  - the flanks' (the flank u of the row's v, from the flanks' edge ends);
//  - with gouge_whole_u, the edge region's: every gouge_stride-th line
//    across the feed, each over the whole round, the lines spaced for the
//    row's smallest |pv| so they reach half_width_mm either side at every
//    contact (a contact's own strip samples are spaced for its own |pv|).
using RowGougeSamples = std::shared_ptr<const SharedGougeSamples>;

// The positions a row's contacts took as planned (before any tilt), in u
// order: where a partial row between two rows starts its own (RowSeeds).
struct SeedContact {
  double u = 0;
  EdgePosition position;
};
using RowSeed = std::vector<SeedContact>;

// The rows either side of a partial row (either may be null).
struct RowSeeds {
  const RowSeed* below = nullptr;
  const RowSeed* above = nullptr;
};

struct PlannedRow {
  EdgeFinishRow row;
  // Where the row is cut, in v order (row.v unless it is a partial row cut
  // after the row above it: see the simulated partial rows).
  std::optional<double> cut_after_v;
  // Per pose of row.poses (in planned order): clear_row proved it against
  // the design guards as it stands (clear, lifted clear, or tilted clear),
  // so the checks need not sweep the guards over it again.
  std::vector<char> design_proved;
  RowGougeSamples row_samples;  // the row's condition-① samples beyond its strips (row_gouge_samples)
  bool simulated = false;       // its passes are in the simulated partial rows' material map (simulated_gaps.cpp)
  std::vector<ContactPlan> contacts;
  BalancedRow emitted;
};

// ---- contacts and strips (contacts.cpp) ----

// A strip's width as the searches score it: 0 where it gouges or leaves more
// than e2 at the contact.
double score(const StripWidth& w);
// The discretised l_j in [r_e, R - r] (the bottom's radius alone when
// count is 1 or r_e reaches it).
std::vector<double> l_grid(const FlatEnd& f, double r_e, int count);
RowGougeSamples row_gouge_samples(const EdgeFinishRequest& rq, double v);
std::shared_ptr<const ContactStrip> make_strip(const EdgeFinishRequest& rq, const EdgeFrame& frame, double u,
                                               double v, const RowGougeSamples& row_samples);
// A contact's positions: with `seeds`, a partial row's (seeded_contact);
// with side_only, the side-edge positioning alone.
ContactPlan plan_contact(const EdgeFinishRequest& rq, double u, double v, const std::vector<double>& ls,
                         bool side_only, const RowGougeSamples& row_samples, const RowSeeds* seeds = nullptr);
// Row width of a table by balance_l, corner contacts taking their one width
// at every l.
BalancedRow balance(const std::vector<ContactPlan>& cs, bool paper, size_t nl);
// The position a contact takes in the emitted path, or false.
bool chosen_position(const EdgeFinishRequest& rq, const ContactPlan& c, int l_index, const std::vector<double>& ls,
                     EdgePosition& pos);
// The positions a planned row's contacts took (RowSeed).
RowSeed seed_of(const EdgeFinishRequest& rq, const PlannedRow& pr, const std::vector<double>& ls);

// ---- rows (rows.cpp) ----

// A row at v: `only` (may be null) plans just the contacts within these
// parts of the row, for a partial row.
PlannedRow plan_row(const EdgeFinishRequest& rq, double v, const std::vector<double>& ls, bool side_only,
                    Progress& progress, const Intervals* only = nullptr, const RowSeeds* seeds = nullptr);
// The emitted positions of a planned row as poses; returns its narrowest
// strip (+inf when it has none).
double emit_poses(const EdgeFinishRequest& rq, double v, const std::vector<double>& ls, PlannedRow& pr);
// The deepest the motion a -> b goes below either strip's surface,
// sampled at t = 1/8 ... 7/8.
double motion_deepest(const EdgeFinishPose& a, const EdgeFinishPose& b, const ContactStrip& sa, const ContactStrip& sb);
// The contact half-way between two poses of a row, at `position`, with its
// strip's width there.
std::pair<EdgeFinishPose, StripWidth> halfway_pose(const EdgeFinishRequest& rq, const RowGougeSamples& row_samples,
                                                   const EdgeFinishPose& a, const EdgeFinishPose& b,
                                                   const EdgePosition& position);
// Span speed: the largest |pv| over the row at v.
double max_pv(const EdgeFinishRequest& rq, double v);
// The rows of the bottom method over rq's window, spaced by their strips.
// `first` (may be empty): the row at rq.v0 already planned (WindowEnds::first_row).
std::vector<PlannedRow> plan_rows(const EdgeFinishRequest& rq, const std::vector<double>& ls, Progress& progress,
                                  std::optional<PlannedRow> first = std::nullopt);

// ---- the paper's comparison (comparison.cpp) ----

EdgeWidthComparison compare_widths(const EdgeFinishRequest& rq, const std::vector<PlannedRow>& planned);
// Sets out.side_rows (the side-edge method's rows over rq's window, by
// plan_rows) and out.side_window_mm.
void plan_side_rows(const EdgeFinishRequest& rq, const std::vector<double>& ls, EdgeFinishResult& out,
                    Progress& progress);
// Sets out.side_window_mm: the window's length along the round's middle.
void set_side_window(const EdgeFinishRequest& rq, EdgeFinishResult& out);

// ---- the window (window.cpp) ----

// The strips the window leaves at either end (EdgeFinishResult::
// hub_strip_mm, top_strip_mm).
struct WindowEnds {
  double hub_strip_mm = 0, top_strip_mm = 0;
  // The row the hub's fit planned at the window's start (plan_row, not yet
  // emitted), for plan_rows to take as its first rather than plan it again.
  std::optional<PlannedRow> first_row;
};
// Narrows rq's window to the hub and casing; returns the strips left.
WindowEnds fit_window_to_hub_and_casing(EdgeFinishRequest& rq, const std::vector<double>& ls, Progress& progress);

// ---- checks (checks.cpp) ----

// The most a pose that cuts the blade beside its strip is lifted off its
// contact (lift_clear), mm.
constexpr double kMaxLiftMm = 0.003;

// What every pose and cutting motion is proved against beyond the world:
// the design surfaces the way the independent simulation sweeps them
// (core/sim GougeGuard: the edge region over the machined span and both
// flanks near their edge ends, dense samples, the whole swept tool). The
// contact strips see only samples across the feed through each contact: a
// motion into a tilted pose was found cutting 4.4 um into the round between
// them on the built-in LE, and on Rotor 67's TE untilted corner contacts on
// the round cut up to 14 um beside their strips (84 of 1900 poses in a
// tenth of the span) — the torus leaning over a round smaller than itself.
// Allowed: the band's overcut less what the samples can miss.
struct DesignGuards {
  std::unique_ptr<GougeGuard> edge;
  std::vector<std::unique_ptr<GougeGuard>> flanks;
  double e1_mm = 0;
  // What the guards' samples can miss (the largest of the guards; a quarter
  // of |e1| unless a sample count was capped): design_guards.
  double miss_mm = 0;
  // The radius the edge region's samples around the edge are spaced for:
  // the corner's and the round's together, 1 / (1/r + 1/ρ).
  double edge_radius_mm = 0;
  double v0 = 0, v1 = 1;  // the edge region's span the edge guard samples (the window and the tool's reach)
  // The surface a guard samples and how (its window and counts):
  // edge_window is the edge guard's (the edge region, u 0..1 over v0..v1),
  // flank_windows[k] flanks[k]'s.
  struct Window {
    const Surface* surface = nullptr;
    UndercutOptions sampling;
  };
  Window edge_window;
  std::vector<Window> flank_windows;

  // The band's overcut less what the samples can miss.
  double allowed() const;
  double least_allowed() const;
  // The deepest cut below the allowance of the tool moving a -> b (the ends
  // included or not), over the edge region and the flanks; 0 if none.
  double deepest(const Tool& tool, const ToolPose& a, const ToolPose& b, bool ends) const;
};

// The checks a pose must pass: the whole tool clear of the world, and the
// design guards.
struct PoseChecks {
  const ToolBody& body;
  const DesignGuards& guards;
  // Why the pose itself fails the guards ("" if it does not); with
  // `liftable`, only by more than a lift can take off (lift_clear).
  std::string gouge(const Tool& tool, const ToolPose& pose, bool liftable = false) const;
};

// The smallest span speed |pv| around the edge region at v (21 samples).
double min_pv(const Surface& edge, double v);
// The design guards over rq's window and as far beyond it as a pose reaches.
DesignGuards design_guards(const EdgeFinishRequest& rq, const FlatEnd& fe);
// The traverse legs' world: rq.world's unchecked pairs (the cutter against
// its own blade) less the triangles of its meshes the design guards sample
// (the flanks' near their edge ends, the edge round's over the edge guard's
// span); null when nothing is left (links.cpp).
std::shared_ptr<const CollisionWorld> own_blade_beyond_guards(const EdgeFinishRequest& rq,
                                                              const DesignGuards& guards);
// Whether a pose's axis is within the machine's reach.
bool within_reach(const EdgeFinishRequest& rq, const ToolPose& pose);
// The row checked in cutting order (reversed or not): passes, tilts,
// refusals; returns its gouge breaks.
long check_row(const EdgeFinishRequest& rq, const PoseChecks& checks, const std::vector<double>& ls, PlannedRow& pr,
               bool reversed, Progress& row_progress);
// check_row for every row, rows on rq.threads workers (the zigzag's odd
// rows reversed); returns the gouge breaks.
long check_rows(const EdgeFinishRequest& rq, const PoseChecks& checks, const std::vector<double>& ls,
                std::vector<PlannedRow>& planned, Progress& progress);

// ---- tilt (tilt.cpp) ----

bool lift_clear(const EdgeFinishRequest& rq, const PoseChecks& checks, EdgeFinishPose& p);
TiltOutcome clear_alternative(const EdgeFinishRequest& rq, const PoseChecks& checks, EdgeFinishPose& p,
                              const TiltAccepted* hint);
void clear_row(const EdgeFinishRequest& rq, const PoseChecks& checks, PlannedRow& pr);
// clear_row for every row, on rq.threads workers.
void clear_rows(const EdgeFinishRequest& rq, const PoseChecks& checks, std::vector<PlannedRow>& planned,
                Progress& progress);

// ---- partial rows (partial_rows.cpp) ----

// Samples around the edge at which gaps are looked for.
constexpr int kGapSamples = 200;
PlannedRow infill_row(const EdgeFinishRequest& rq, const PoseChecks& checks, double v, const std::vector<double>& ls,
                      const Intervals& where, const RowSeeds& seeds, Progress& progress);
// Partial rows between every two rows where their strips leave a gap,
// merged into `planned` in v order; returns how many.
int fill_partial_rows(const EdgeFinishRequest& rq, const PoseChecks& checks, const std::vector<double>& ls,
                      std::vector<PlannedRow>& planned, Progress& progress);

// ---- partial rows from the simulation (simulated_gaps.cpp) ----

// Partial rows where the rows' passes as checked, simulated, leave
// material; added to `planned` (checked), counted in out.
void fill_simulated_gaps(const EdgeFinishRequest& rq, const PoseChecks& checks, const std::vector<double>& ls,
                         std::vector<PlannedRow>& planned, EdgeFinishResult& out, Progress& progress);

// ---- order and links (links.cpp) ----

// Poses in the other cutting order; a break moves with the pair it separates.
void reverse_poses(std::vector<EdgeFinishPose>& ps);
// The links between the passes of out.rows (in cutting order), the lead-in
// and the lead-out, each proved; a refused link may rearrange the rows
// around it (zigzag).
void link_passes(const EdgeFinishRequest& rq, const ToolBody& body, const DesignGuards& guards, EdgeFinishResult& out,
                 Progress& progress);

}  // namespace bliskrun::edge_detail
