#pragma once
// A blade rebuilt from its measured sections in one call, the steps of
// repair paper §1.1–1.4 in order: each section's scattered points ordered
// (strays rejected), all sections oriented about the stacking axis, smoothed,
// start-aligned, lofted, and the kept points measured against the loft.
// Every section must be complete: a section with a gap (the missing edge of
// a damaged blade) does not correspond sample by sample to its neighbours;
// the paper rebuilds it from a loft of the complete ones (§1.4.1), a later
// step. The stages are in section_points.h, section_curve.h and
// section_loft.h.
#include <algorithm>
#include <vector>

#include "core/common/types.h"
#include "core/geometry/section_loft.h"
#include "core/repair/section_points.h"

namespace bliskrun {

struct RebuildOptions {
  SectionOrderOptions order;
  // The smoothing length of smooth_section, mm (section_curve.h): below the
  // smallest edge radius that must survive, above the point spacing for the
  // noise to be averaged and the curvature profiles to align. Too short for
  // the noise and the alignment fails: measured on a 30 mm chord, 0.13 mm
  // spacing, L = 0.15 mm, the least start correlation is 0.99 at 1 um
  // noise, 0.92 at 4 um, and at 8 um falls to 0.24-0.37 on some sections,
  // whose starts then jump by 10-80 mm and twist the loft by millimetres.
  // RebuiltSection::start_correlation shows it.
  double smoothing_mm = 0.1;
  int align_samples = 2048;  // curvature samples per section for the alignment
  Vec3 axis = Vec3::UnitZ();  // stacking direction: sections given from the first along it to the last
  SectionLoftOptions loft;
  // Sections ordered and smoothed, points measured, on this many threads;
  // the result does not depend on it.
  int threads = 1;
  // Thinning on the way in (issue 43: ten million points rebuilt in under a
  // minute): a section of more than thin_above points is thinned before it
  // is ordered, by thin_section (section_points.h: measured points, lone
  // strays dropped) to points thin_spacing_mm apart — 0: a quarter of the
  // smoothing length (25 um at 0.1 mm), at least 1 um, which leaves four or
  // more points in every smoothing length. 0 points: never.
  int thin_above = 20000;
  double thin_spacing_mm = 0;
  double thin_spacing() const { return thin_spacing_mm > 0 ? thin_spacing_mm : std::max(0.25 * smoothing_mm, 1e-3); }
};

struct RebuiltSection {
  int thinned = 0;                 // points the thinning dropped (options.thin_above)
  int kept = 0;                    // points used
  std::vector<int> rejected;       // indices into the section's input
  int chains = 0;                  // as OrderedSection
  double spacing_mm = 0;
  double smoothing_shift_mm = 0;   // RMS |q - p| of the smoothing
  double start_shift_mm = 0;       // how far the alignment moved the start (0 for the first)
  double start_correlation = 0;    // its Pearson rho (0 for the first)
};

struct RebuiltBlade {
  SectionLoft loft;
  LoftDeviation deviation;  // of all sections' kept points, in section order
  std::vector<RebuiltSection> sections;
};

// The points of a section the rebuild orders, as indices into it: at most
// thin_spacing() apart when there are more than thin_above;
// empty when all are used.
std::vector<int> section_thinning(const std::vector<Vec3>& points, const RebuildOptions& options);

// Throws ParameterError ("sections") for fewer than 2 sections or a section
// with a gap (named, with the gap's length), ("smoothing") for a negative or
// non-finite length, and whatever the stages throw for their own input.
RebuiltBlade rebuild_blade(const std::vector<std::vector<Vec3>>& sections, const RebuildOptions& options = {});

}  // namespace bliskrun
