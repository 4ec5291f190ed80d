#include "core/geometry/section_loft.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/common/error.h"
#include "core/common/parallel.h"
#include "core/common/progress.h"
#include "core/geometry/interpolation.h"
#include "core/geometry/point_index.h"
#include "core/geometry/curve_profile.h"
#include "core/geometry/projection.h"

namespace bliskrun {

namespace {

double wrap01(double v) {
  v -= std::floor(v);
  return v >= 1 ? 0.0 : v;
}

// The loft started half a period on around v: the same C2 closed surface,
// with its seam where the loft has none, for points near the loft's seam.
class HalfTurned : public Surface {
 public:
  explicit HalfTurned(const Surface& s) : s_(s) {}
  SurfaceDerivs eval(double u, double v) const override { return s_.eval(u, wrap01(v + 0.5)); }

 private:
  const Surface& s_;
};

}  // namespace

SectionLoft loft_sections(const std::vector<ClosedCurve>& sections, const SectionLoftOptions& o) {
  const int n = static_cast<int>(sections.size());
  if (n < 2) throw ParameterError("sections", "a loft needs at least 2 sections, got " + std::to_string(n));
  if (o.samples < 16) throw ParameterError("samples", "need at least 16 per section, got " + std::to_string(o.samples));
  const int m = o.samples;

  // Equal arc-length samples from each section's start (the parameters
  // curvature_profile already finds at equal arc length).
  std::vector<std::vector<Vec3>> rows(n);
  for (int k = 0; k < n; ++k) {
    cancellation_point();
    const CurvatureProfile at = curvature_profile(sections[k], m);
    for (int j = 0; j < m; ++j) rows[k].push_back(sections[k].point(at.t[j]));
  }
  // v against the sections' direction when they turn counter-clockwise about
  // the stacking direction, so that pu x pv points outwards.
  Vec3 first = Vec3::Zero(), last = Vec3::Zero();
  for (int j = 0; j < m; ++j) {
    first += rows.front()[j] / m;
    last += rows.back()[j] / m;
  }
  if (vector_area(rows.front()).dot(last - first) > 0)
    for (std::vector<Vec3>& r : rows) std::reverse(r.begin() + 1, r.end());  // the start stays at v = 0

  SectionLoft out;
  out.grid = PointGrid(n, m);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < m; ++j) out.grid.at(k, j) = rows[k][j];
  try {
    out.section_u = averaged_grid_parameters(out.grid).u;
  } catch (const ParameterError& e) {
    throw ParameterError("sections", std::string("cannot loft: ") + e.what());
  }

  // Around: one closed cubic per section at the same uniform knots.
  std::vector<double> knots_v(m + 1);
  for (int j = 0; j <= m; ++j) knots_v[j] = static_cast<double>(j) / m;
  std::vector<BSplineCurve> around(n);
  for (int k = 0; k < n; ++k) around[k] = interpolate_closed_cubic(rows[k], knots_v);
  const int cols = static_cast<int>(around[0].control_points().size());  // m + 3

  // Along the span: each column of those control points through the sections.
  std::vector<Vec3> ctrl;
  std::vector<double> knots_u;
  std::vector<Vec3> column(n);
  int span_rows = 0;
  for (int j = 0; j < cols; ++j) {
    for (int k = 0; k < n; ++k) column[k] = around[k].control_points()[j];
    const BSplineCurve c = interpolate_cubic(column, out.section_u);
    if (j == 0) {
      knots_u = c.knots();
      span_rows = static_cast<int>(c.control_points().size());
      ctrl.resize(static_cast<size_t>(span_rows) * cols);
    }
    for (int i = 0; i < span_rows; ++i) ctrl[static_cast<size_t>(i) * cols + j] = c.control_points()[i];
  }
  out.surface = BSplineSurface(3, 3, std::move(knots_u), around[0].knots(), span_rows, cols, std::move(ctrl));
  return out;
}

LoftDeviation loft_deviation(const SectionLoft& loft, const std::vector<Vec3>& points,
                             std::vector<PointDeviation>* each, int threads) {
  if (points.empty()) throw ParameterError("points", "no point to measure");
  for (size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite()) throw ParameterError("points", "point " + std::to_string(i) + " is not finite");
  const PointGrid& g = loft.grid;
  // Cell about the samples' spacing around a section.
  double perimeter = 0;
  for (int j = 0; j < g.cols; ++j) perimeter += (g.at(0, (j + 1) % g.cols) - g.at(0, j)).norm();
  const PointIndex index(g.points, std::max(perimeter / g.cols, 1e-6));
  Vec3 lo = g.points[0], hi = g.points[0];
  for (const Vec3& p : g.points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const HalfTurned turned(loft.surface);

  // Each point projected into its own slot, then summed in order.
  struct Projected {
    double distance = 0;
    PointDeviation deviation;
    std::string failure;
  };
  std::vector<Projected> at(points.size());
  parallel_for_index(points.size(), threads, [&](size_t i) {
    if (i % 1024 == 0) cancellation_point();
    const Vec3& q = points[i];
    const int s = index.nearest(q, (hi - lo).norm() + (q - 0.5 * (lo + hi)).norm());
    const int k = s / g.cols, j = s % g.cols;
    const double v = static_cast<double>(j) / g.cols;
    const bool near_seam = v < 0.25 || v > 0.75;
    ProjectionOptions po;
    po.seed = Eigen::Vector2d(loft.section_u[k], near_seam ? wrap01(v - 0.5) : v);
    const SurfaceProjection pr = project_to_surface(near_seam ? static_cast<const Surface&>(turned) : loft.surface, q, po);
    if (!pr.ok) {
      at[i].failure = pr.failure;
      return;
    }
    at[i].distance = pr.distance;
    if (each) {
      const double v_on = near_seam ? wrap01(pr.v + 0.5) : pr.v;
      const SurfaceDerivs d = loft.surface.eval(pr.u, v_on);
      const double side = (q - pr.point).dot(d.pu.cross(d.pv)) >= 0 ? 1.0 : -1.0;
      at[i].deviation = PointDeviation{pr.u, v_on, side * pr.distance};
    }
  });

  LoftDeviation out;
  if (each) each->clear();
  double sum = 0, sum2 = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!at[i].failure.empty())
      throw Error("loft deviation: point " + std::to_string(i) + " does not project onto the loft: " + at[i].failure);
    const double distance = at[i].distance;
    if (each) each->push_back(at[i].deviation);
    sum += distance;
    sum2 += distance * distance;
    if (distance > out.max_mm || out.worst < 0) {
      out.max_mm = distance;
      out.worst = static_cast<int>(i);
    }
  }
  out.points = static_cast<int>(points.size());
  out.mean_mm = sum / out.points;
  out.rms_mm = std::sqrt(sum2 / out.points);
  return out;
}

}  // namespace bliskrun
