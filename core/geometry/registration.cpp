#include "core/geometry/registration.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "core/common/error.h"
#include "core/common/progress.h"
#include "core/geometry/point_index.h"

namespace bliskrun {

namespace {

double mean_spacing(const std::vector<Vec3>& points) {
  // From the bounding box and count: the spacing of a surface sample of that
  // many points over the box's two largest extents.
  Vec3 lo = points.front(), hi = points.front();
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  Vec3 e = hi - lo;
  std::sort(e.data(), e.data() + 3);
  return std::max(1e-3, std::sqrt(e[1] * e[2] / static_cast<double>(points.size())));
}

}  // namespace

RegistrationResult register_points(const std::vector<Vec3>& scan, const ModelSample& model,
                                   const RegistrationOptions& o, const Frame& initial) {
  if (scan.empty()) throw ParameterError("scan", "expected at least one point");
  if (model.points.empty()) throw ParameterError("model", "expected at least one sample");
  if (model.normals.size() != model.points.size())
    throw ParameterError("model", "expected one normal per sample point");
  const double cell = o.cell_mm > 0 ? o.cell_mm : 2 * mean_spacing(model.points);
  const PointIndex index(model.points, cell);

  RegistrationResult r;
  r.transform = initial;
  double reach = o.initial_reach_mm;
  std::vector<int> pair(scan.size());
  std::vector<double> dist(scan.size());
  for (r.iterations = 1; r.iterations <= o.max_iterations; ++r.iterations) {
    cancellation_point();
    // Pair and measure.
    std::vector<double> found;
    found.reserve(scan.size());
    for (size_t i = 0; i < scan.size(); ++i) {
      const Vec3 p = r.transform * scan[i];
      pair[i] = index.nearest(p, reach);
      dist[i] = pair[i] >= 0 ? (model.points[pair[i]] - p).norm() : 1e300;
      if (pair[i] >= 0) found.push_back(dist[i]);
    }
    if (found.size() < 6) throw Error("registration: fewer than 6 scan points within " + std::to_string(reach) +
                                      " mm of the model (is the scan in the model's frame?)");
    std::nth_element(found.begin(), found.begin() + found.size() / 2, found.end());
    r.median_mm = found[found.size() / 2];
    // Point-to-plane normal equations over the inliers.
    Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 6> model_constraint = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
    double sq = 0;
    r.inliers = r.outliers = 0;
    for (size_t i = 0; i < scan.size(); ++i) {
      if (pair[i] < 0 || dist[i] > reach) {
        ++r.outliers;
        continue;
      }
      const Vec3 p = r.transform * scan[i];
      const Vec3& q = model.points[pair[i]];
      const Vec3& n = model.normals[pair[i]];
      Eigen::Matrix<double, 6, 1> row;
      row << p.cross(n), n;
      const double e = (q - p).dot(n);
      a += row * row.transpose();
      b += row * e;
      Eigen::Matrix<double, 6, 1> on_model;
      on_model << q.cross(n), n;
      model_constraint += on_model * on_model.transpose();
      sq += e * e;
      ++r.inliers;
    }
    r.rms_mm = std::sqrt(sq / std::max(1, r.inliers));
    // Six degrees of freedom must be constrained by the model where the scan
    // lands (not by the scan's current misplacement): the smallest
    // eigenvalue of the model's normal matrix against the largest.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(model_constraint);
    if (eig.eigenvalues()(0) < 1e-10 * eig.eigenvalues()(5))
      throw Error("registration: the scan does not constrain all six degrees of freedom (a flat or "
                  "rotationally symmetric piece alone cannot be registered)");
    const Eigen::Matrix<double, 6, 1> x = a.ldlt().solve(b);
    const Vec3 w = x.head<3>(), t = x.tail<3>();
    Frame step = Frame::Identity();
    if (w.norm() > 0) step.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
    step.translation() = t;
    r.transform = step * r.transform;
    // How far the update moved the scan at most (rotation over the scan's
    // extent plus translation).
    double extent = 0;
    for (size_t i = 0; i < scan.size(); i += std::max<size_t>(1, scan.size() / 64))
      extent = std::max(extent, (r.transform * scan[i]).norm());
    const double moved = t.norm() + w.norm() * extent;
    reach = std::max(o.min_reach_mm, o.outlier_factor * r.median_mm);
    if (moved < o.converged_mm) {
      r.converged = true;
      break;
    }
  }
  r.iterations = std::min(r.iterations, o.max_iterations);
  return r;
}

}  // namespace bliskrun
