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
// tiles and tiles in super-tiles, each with a bounding sphere, and a group
// whose centre is farther from the cutter than its radius plus the search
// range is skipped. Each tool position so visits only the samples near it:
// the cost is (tool positions) x (samples near one position), not
// samples x poses.
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
  int threads = 2;               // results do not depend on it
  double tol_mm = 1e-5;          // sphere-tracing stop
};

// A pass: poses the tool moves through while cutting, in order. Motion between
// passes (linking, retract) does not cut.
using ToolPass = std::vector<ToolPose>;

struct UndercutResult {
  int samples_u = 0, samples_v = 0;
  // Per sample (row-major, u outer): material left along the normal, mm;
  // +infinity where the tool never came within search_above_mm.
  std::vector<double> residual_mm;
  int untouched = 0;   // samples the tool never reached
  // Statistics over touched samples of max(residual, 0) (the paper's Table 5
  // reports undercut magnitudes) and the deepest gouge.
  double undercut_max_mm = 0, undercut_mean_mm = 0, undercut_median_mm = 0, undercut_std_mm = 0;
  double overcut_mm = 0;  // most negative residual (0 if none)
  long tool_positions = 0;     // evaluated tool positions including sweeps
  long line_evaluations = 0;   // (sample, position) pairs examined
};

UndercutResult simulate_undercut(const Surface& design, const Tool& tool,
                                 const std::vector<ToolPass>& passes,
                                 const UndercutOptions& options,
                                 Progress& progress = Progress::none());

}  // namespace bliskrun
