#include "core/analysis/passage.h"

#include <algorithm>
#include <vector>

#include "core/common/error.h"
#include "core/common/progress.h"
#include "core/geometry/projection.h"

namespace bliskrun {

PassageDistance narrowest_passage(const Surface& a, const Surface& b, int nu, int nv) {
  if (nu < 2 || nv < 2) throw ParameterError("samples", "need at least 2 x 2 samples");
  struct Candidate {
    double d, ua, va;
  };
  std::vector<Candidate> candidates;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      cancellation_point();  // each sample is a whole projection search
      const double u = static_cast<double>(i) / (nu - 1), v = static_cast<double>(j) / (nv - 1);
      const SurfaceProjection p = project_to_surface(b, a.point(u, v));
      if (p.ok && !p.on_boundary) candidates.push_back({p.distance, u, v});
    }
  if (candidates.empty()) throw Error("narrowest_passage: the surfaces do not face each other");
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) { return x.d < y.d; });
  candidates.resize(std::min<size_t>(candidates.size(), 5));

  PassageDistance best;
  best.distance_mm = candidates.front().d;
  best.ua = candidates.front().ua;
  best.va = candidates.front().va;
  for (const Candidate& c : candidates) {
    double ua = c.ua, va = c.va, ub = 0, vb = 0, d = c.d;
    for (int it = 0; it < 50; ++it) {
      const SurfaceProjection on_b = project_to_surface(b, a.point(ua, va));
      if (!on_b.ok) break;
      const SurfaceProjection on_a = project_to_surface(a, on_b.point);
      if (!on_a.ok) break;
      ub = on_b.u;
      vb = on_b.v;
      const double moved = (a.point(on_a.u, on_a.v) - a.point(ua, va)).norm();
      ua = on_a.u;
      va = on_a.v;
      d = on_a.distance;
      if (moved < 1e-7) break;
    }
    if (d < best.distance_mm) best = {d, ua, va, ub, vb};
  }
  return best;
}

}  // namespace bliskrun
