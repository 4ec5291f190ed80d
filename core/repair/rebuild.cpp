#include "core/repair/rebuild.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "core/common/error.h"
#include "core/common/parallel.h"
#include "core/common/progress.h"
#include "core/repair/section_curve.h"

namespace bliskrun {

std::vector<int> section_thinning(const std::vector<Vec3>& points, const RebuildOptions& o) {
  if (o.thin_above <= 0 || static_cast<int>(points.size()) <= o.thin_above) return {};
  std::vector<int> kept = thin_section(points, o.thin_spacing());
  if (kept.size() == points.size()) kept.clear();
  return kept;
}

RebuiltBlade rebuild_blade(const std::vector<std::vector<Vec3>>& sections, const RebuildOptions& o) {
  const int n = static_cast<int>(sections.size());
  if (n < 2) throw ParameterError("sections", "a blade needs at least 2 sections, got " + std::to_string(n));
  if (!(o.smoothing_mm >= 0 && std::isfinite(o.smoothing_mm)))
    throw ParameterError("smoothing", "must be a finite length >= 0 mm");

  RebuiltBlade out;
  out.sections.resize(n);
  std::vector<std::vector<Vec3>> loops(n);
  // Sections are independent until they are oriented together: ordered on
  // o.threads, each into its own slot (an error is the lowest section's).
  parallel_for_index(n, o.threads, [&](size_t k) {
    cancellation_point();
    const std::string what = "section " + std::to_string(k + 1);
    OrderedSection s;
    const std::vector<int> thinned = section_thinning(sections[k], o);
    const std::vector<Vec3> points = thinned.empty() ? sections[k] : pick(sections[k], thinned);
    try {
      s = order_section(points, o.order);
    } catch (const ParameterError& e) {
      throw ParameterError(what, e.what());
    }
    if (!s.gaps.empty()) {
      char len[32];
      std::snprintf(len, sizeof len, "%.3f", s.gaps.front().length_mm);
      throw ParameterError("sections", what + " has a gap of " + len +
                                           " mm (a damaged section: it does not correspond to its neighbours "
                                           "sample by sample; leave it out)");
    }
    RebuiltSection& r = out.sections[k];
    r.thinned = static_cast<int>(sections[k].size() - points.size());
    r.kept = static_cast<int>(s.order.size());
    r.rejected = s.rejected;
    if (!thinned.empty())
      for (int& i : r.rejected) i = thinned[i];
    r.chains = s.chains;
    r.spacing_mm = s.spacing_mm;
    loops[k] = pick(points, s.order);
  });
  const std::vector<OrientedSection> oriented = orient_sections(loops, o.axis);
  std::vector<ClosedCurve> curves(n);
  parallel_for_index(n, o.threads, [&](size_t k) {
    cancellation_point();
    const SmoothedSection s = smooth_section(oriented[k].loop, o.smoothing_mm);
    out.sections[k].smoothing_shift_mm = s.rms_shift_mm;
    curves[k] = s.curve;
  });
  std::vector<Vec3> kept;
  for (int k = 0; k < n; ++k) kept.insert(kept.end(), oriented[k].loop.begin(), oriented[k].loop.end());
  const AlignedSections aligned = align_section_starts(curves, o.align_samples, o.threads);
  for (int k = 0; k < n; ++k) {
    out.sections[k].start_shift_mm = aligned.alignments[k].shift_mm;
    out.sections[k].start_correlation = aligned.alignments[k].correlation;
  }
  out.loft = loft_sections(aligned.curves, o.loft);
  out.deviation = loft_deviation(out.loft, kept, nullptr, o.threads);
  return out;
}

}  // namespace bliskrun
