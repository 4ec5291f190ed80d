#pragma once
// Measured blade sections as curves (repair paper §1.2–1.3): an ordered,
// oriented loop of noisy points is smoothed into a closed curve, and the start
// points of the sections of a blade are aligned by their curvature profiles,
// so that a loft through them has no twist the blade has not.
//
// Smoothing (§1.2). The paper's system of springs: the smoothed points q_i
// minimise E = α ∫ k² ds + β Σ |p_i − q_i|² (eq. 1–2), with k taken from
// q_{i-1}, q_i, q_{i+1} as in LI et al. (the simplification the paper uses).
// Discretisation used here: with h_i = |p_{i+1} − p_i| and w_i = (h_{i-1} +
// h_i) / 2,
//     E / β = Σ w_i |q_i − p_i|² + L⁴ Σ w_i |D_i q|²,
//     D_i q = 2 [(q_{i+1} − q_i) / h_i − (q_i − q_{i-1}) / h_{i-1}] / (h_{i-1} + h_i),
// D_i q being the second derivative by arc length, whose length is the
// curvature where the parameter is arc length (measured chord length here).
// E is then quadratic: one sparse symmetric positive-definite solve,
// cyclic pentadiagonal, O(n), for all three coordinates. Two choices beyond
// the paper: the springs are weighted by the length w_i they stand for, so a
// densely probed stretch does not outweigh a sparse one (with even spacing h
// this is the paper's form with α/β = L⁴ / h); and the one parameter is a
// length, L = (α h / β)^¼, in mm: on a smooth stretch the smoothing acts as
// the filter 1 / (1 + (2πL/λ)⁴) on a wavelength λ — a wave of length 2πL
// keeps half its amplitude, noise at the point spacing is averaged over ~L,
// and an evenly sampled circle of radius R shrinks by exactly 1 / (1 + (L/R)⁴)
// (so L = R/10 costs 10⁻⁴ R). Choose L below the smallest edge radius that
// must survive. A gap in the loop is bridged by the smoothest curve.
//
// Alignment (§1.3). Each section's curvature is sampled at n points of equal
// arc length from its start; section b is re-started where the circular
// cross-correlation of its profile with its neighbour a's is largest —
// Pearson's ρ (eq. 3–4) at every shift, its means and variances not changing
// with the shift. All n shifts by one FFT, O(n log n) (the paper's table of
// E(Y_a Y_b) is O(n²)); the maximum is refined between samples by the
// parabola through it and its two neighbours (the paper: a cubic spline
// through all n values, the same to within the sampling). The curvature is
// signed, positive where the loop turns towards its own vector-area normal
// (convex): a blade's concave pressure side then differs from its suction
// side in sign, not only in size. Curvature is a second derivative, so the
// smoothing length decides how much of it is noise (measured on a 60 mm
// blade section, 0.1 mm spacing, 4 um noise: ρ ≈ 0.3 at L = 0.05 mm,
// ≈ 0.91 at L = 0.1 mm; the recovered start within 0.01 mm at the latter).
#include <vector>

#include "core/common/types.h"
#include "core/geometry/closed_curve.h"
#include "core/geometry/curve_profile.h"  // curvature_profile

namespace bliskrun {

struct SmoothedSection {
  std::vector<Vec3> points;  // q_i, one per input point
  ClosedCurve curve;         // closed C2 cubic through them, t = 0 at q_0
  double max_shift_mm = 0;   // largest and RMS |q_i − p_i|
  double rms_shift_mm = 0;
};

// Smooths one ordered closed loop (first point not repeated). L = 0 keeps the
// points. Throws ParameterError ("loop") for fewer than 5 points, a
// non-finite point or two consecutive points that coincide, and
// ("smoothing_length") unless L >= 0 and finite.
SmoothedSection smooth_section(const std::vector<Vec3>& loop, double smoothing_length_mm);

struct StartAlignment {
  double shift_samples = 0;  // in [0, samples): how far the start moved, in samples
  double shift_mm = 0;       // the same as arc length along the section
  double t_start = 0;        // curve parameter of the new start
  double correlation = 0;    // Pearson ρ of the profiles at the best whole-sample shift
};

// Where `section` should start so that its profile lines up with
// `reference` (§1.3). A section of constant curvature (a circle) has nothing
// to align by: it keeps its start, with correlation 0. Throws ParameterError ("profiles") unless both have the
// same number of samples (>= 16).
// With max_shift_samples >= 0 the start moves at most that many samples
// either way: a refinement of a start known roughly (the design's, in
// rebuild_damaged's retry), where the best shift overall may be a wrong one.
StartAlignment align_start(const CurvatureProfile& reference, const CurvatureProfile& section,
                           int max_shift_samples = -1);

struct AlignedSections {
  std::vector<ClosedCurve> curves;           // re-started; the first as given
  std::vector<StartAlignment> alignments;    // per section; the first is zero
};

// The paper's sweep: section k+1 aligned to the aligned section k, from the
// first (the hub or root) to the last. Sections must already run the same
// way (orient_sections, section_points.h) and be complete: a section with a
// gap (OrderedSection::gaps) has a shorter profile whose samples do not
// correspond to its neighbour's; the paper rebuilds those from the loft of
// the complete ones (§1.4).
// Each section's own curvature profile is taken on `threads` threads; the
// result does not depend on it.
AlignedSections align_section_starts(const std::vector<ClosedCurve>& sections, int samples = 2048, int threads = 1);

}  // namespace bliskrun
