#pragma once
// Undercut simulation (SPEC §8): what material is left on, or cut below, a
// design surface after a tool has followed a toolpath. Stands in for the
// commercial machining simulation of the blisk paper (Tables 4–5, Fig. 15).
//
// Method (normal-line sampling, "lawn mower"): each sample of the design
// surface carries a line along its unit normal (out of the material). Every
// tool position cuts that line where the tool occupies it; the material left
// at the sample is the lowest point of the line the tool ever reached,
// measured from the design surface: > 0 material left (undercut), < 0 cut
// below the design (overcut, gouge). Between consecutive poses of a pass the
// tool is swept (PoseMotion: tip on the straight segment, axis turning at
// constant rate), sub-sampled so that no tool point moves more than
// `sweep_step_mm` between two evaluated positions; the material this misses
// between positions is below d^2 / (8 R) for a cutter of radius R in the feed
// plane (0.08 um for d = 0.05 mm, R = 4 mm).
//
// Each line is cut by sphere tracing the tool's exact signed distance, which
// is 1-Lipschitz, so a root is never stepped over. The same Lipschitz bound
// prunes whole groups of samples: samples are grouped in parameter-space
// tiles of 4 x 4, tiles in groups of 4 x 4, and so on for four levels, each
// with a bounding sphere, and a group whose centre is farther from the
// cutter than its radius plus the search range is skipped. Each tool
// position so visits only the samples near it: the cost is (tool
// positions) x (samples near one position), not samples x poses.
#include <limits>
#include <memory>
#include <vector>

#include "core/common/progress.h"
#include "core/geometry/surface.h"
#include "core/tools/pose.h"
#include "core/tools/tool.h"

namespace bliskrun {

struct UndercutOptions {
  int samples_u = 200;           // along u (span)
  int samples_v = 1000;          // along v (chord)
  double u0 = 0, u1 = 1, v0 = 0, v1 = 1;  // sampled parameter window
  double search_above_mm = 0.1;  // how far above the surface material is tracked (finishing)
  double search_below_mm = 0.1;  // how deep a gouge is measured (deeper reads as this)
  double sweep_step_mm = 0.05;   // largest cutter-point motion between evaluated positions
  // The points whose motion sweep_step_mm bounds: those within this
  // distance of the tool's reference point (0: the whole cutter, its
  // reach). Points farther move more between positions, so their sweep is
  // read coarser: never less material left than the sweep leaves, only
  // more — for a caller that looks for material left (simulate_undercut;
  // not a gouge guard) and whose cutter touches the surface near its end.
  double sweep_reach_mm = 0;
  int threads = 2;               // results do not depend on it
  double tol_mm = 1e-5;          // sphere-tracing stop
  // The normal out of the material is -(pu x pv) instead of pu x pv.
  bool flip_normal = false;
  // Undercut statistics cover the samples with u in [machined_u0,
  // machined_u1] (the window an operation machines); the overcut and its
  // location cover every sample, so a move that dips into a strip the
  // operation leaves (e.g. the hub strip under the first row) is still seen.
  double machined_u0 = -std::numeric_limits<double>::infinity();
  double machined_u1 = std::numeric_limits<double>::infinity();
  // A sample once left at or below this is traced no more: for a caller
  // that asks only where more than it is left (e.g. the edge finish's gap
  // search), the cuts after that change nothing it reads. Such a sample's
  // residual is then only known to be at most this (which of the cuts
  // reached it first depends on the order), and the overcut statistics
  // read it so; off (-inf) by default.
  double settled_mm = -std::numeric_limits<double>::infinity();
};

// A pass: poses the tool moves through, in order, each to the next by
// PoseMotion (the motion the collision checks and the posts assume). Every
// move the program makes belongs in a pass — links, retracts and approaches
// too, since any of them can cut; between passes the tool is taken to make
// no motion near the part (e.g. a refused link, where the program stops).
using ToolPass = std::vector<ToolPose>;

struct UndercutResult {
  int samples_u = 0, samples_v = 0;
  // Per sample (row-major, u outer): material left along the normal, mm;
  // +infinity where the tool never came within search_above_mm.
  std::vector<double> residual_mm;
  int untouched = 0;   // samples of the machined window the tool never reached
  // Statistics over touched samples of max(residual, 0) (the paper's Table 5
  // reports undercut magnitudes) and the deepest gouge.
  double undercut_max_mm = 0, undercut_mean_mm = 0, undercut_median_mm = 0, undercut_std_mm = 0;
  double overcut_mm = 0;  // most negative residual (0 if none)
  // Where the deepest overcut is and which motion cut it: the sample
  // (row-major index) and the pass and the pose index in that pass at which
  // the motion ends (the motion from pose k-1 to pose k; k = 0 for a pass of
  // one pose). -1 when there is no overcut.
  long overcut_sample = -1;
  int overcut_pass = -1;
  long overcut_pose = -1;
  long tool_positions = 0;     // evaluated tool positions including sweeps
  long line_evaluations = 0;   // (sample, position) pairs examined
};

UndercutResult simulate_undercut(const Surface& design, const Tool& tool,
                                 const std::vector<ToolPass>& passes,
                                 const UndercutOptions& options,
                                 Progress& progress = Progress::none());

// The statistics of a residual map (untouched, the undercut figures, the
// deepest overcut and its sample) from r.residual_mm, r.samples_u/v and the
// options' windows — e.g. of the lowest of several simulations' maps over
// the same samples. A NaN sample is outside the region measured (a caller's
// mask) and counts in no figure. Leaves overcut_pass and overcut_pose alone.
void summarise_residual(UndercutResult& r, const UndercutOptions& options);

// Passes one tool cuts (borrowed: both must outlive the call).
struct ToolRun {
  const Tool* tool = nullptr;
  const std::vector<ToolPass>* passes = nullptr;
};
// Several tools in turn — a job's roughing, then its finishing: the material
// left is the lowest any of them reached. overcut_pass counts the passes of
// all runs in order (run 0's first).
UndercutResult simulate_undercut(const Surface& design, const std::vector<ToolRun>& runs,
                                 const UndercutOptions& options,
                                 Progress& progress = Progress::none());

// Samples of `s` over [u0, u1] x [v0, v1] about spacing_mm apart in both
// directions, for a GougeGuard (the window and the counts; the caller sets
// the rest): lengths are the longest of 9 iso-lines each way, as 64-segment
// polylines; counts between 8 and 8000.
UndercutOptions guard_sampling(const Surface& s, double spacing_mm, double u0 = 0, double u1 = 1, double v0 = 0,
                               double v1 = 1);
// guard_sampling of the whole surface set up for a planner's link guard:
// the normal flipped as given, dips traced only 20 um deep (only dips below
// the allowance matter, and deeper ones still read as beyond it: a shorter
// trace per sample), one thread (the planner's own threads call it).
UndercutOptions link_guard_sampling(const Surface& s, double spacing_mm, bool flip_normal);

// The design surface sampled once for many gouge queries of single motions —
// a planner's proof that a non-cutting move (retract, traverse, approach)
// does not cut below the finished surface. Same samples, normal lines,
// sweep and trace as simulate_undercut, so a motion the guard accepts is one
// the simulation of the program cannot find cutting deeper.
//
// Between two samples h apart the tool's surface can dip below what the
// samples see by about h^2 / (8 r) for a cutter of radius r there; the
// planner subtracts that from its allowance (between_samples_mm()).
class GougeGuard {
 public:
  // Uses o.samples_u/v, u0..v1, flip_normal, sweep_step_mm, tol_mm and
  // search_below_mm (the depth below which every gouge reads as that depth).
  GougeGuard(const Surface& design, const UndercutOptions& o);
  ~GougeGuard();
  GougeGuard(const GougeGuard&) = delete;
  GougeGuard& operator=(const GougeGuard&) = delete;

  struct Cut {
    double depth_mm = 0;   // deepest entry below the design (<= 0); 0 if none below -allowed
    double t = -1;         // motion parameter of the position that cut it
    Vec3 point = Vec3::Zero();  // the design-surface sample it cut
  };
  // The deepest cut below -allowed_mm of the tool moving from `from` to
  // `to` (PoseMotion), at the evaluated positions t in (0, 1) plus the end
  // points unless excluded (a motion leaving or reaching a cutting pose
  // leaves that pose's cut to the pass it belongs to).
  // `step_mm` > 0 overrides the sampling's sweep step for this motion.
  Cut deepest_cut(const Tool& tool, const ToolPose& from, const ToolPose& to, double allowed_mm,
                  bool include_from = false, bool include_to = false, double step_mm = 0) const;
  // Largest distance between neighbouring samples, mm.
  double spacing_mm() const;
  // About what the samples can miss for a cutter whose surface has no
  // curvature radius below r_mm where it crosses the design surface:
  // spacing^2 / (8 r). For a drum wheel crossing a flank that is the barrel's
  // radius about its axis (its meridian radius R_c is far larger).
  double between_samples_mm(double r_mm) const;

 private:
  struct Index;
  std::unique_ptr<Index> index_;
  UndercutOptions options_;
};

}  // namespace bliskrun
