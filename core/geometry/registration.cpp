#include "core/geometry/registration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <unordered_map>
#include <string>

#include <Eigen/Dense>

#include "core/common/error.h"
#include "core/common/progress.h"
#include "core/geometry/point_index.h"

namespace bliskrun {

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

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

double median_of(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Applies the solution (w, t) of the linearised problem as an exact rotation.
Frame step_of(const Vec6& x) {
  const Vec3 w = x.head<3>(), t = x.tail<3>();
  Frame step = Frame::Identity();
  if (w.norm() > 0) step.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  step.translation() = t;
  return step;
}

std::vector<Vec3> every_nth(const std::vector<Vec3>& v, size_t at_most) {
  if (v.size() <= at_most) return v;
  std::vector<Vec3> out;
  const double stride = static_cast<double>(v.size()) / static_cast<double>(at_most);
  for (size_t i = 0; i < at_most; ++i) out.push_back(v[static_cast<size_t>(i * stride)]);
  return out;
}

// The coarse stage's ICP: the closest `keep` fraction of the pairs within
// `reach` (trimmed ICP: no threshold to tune against an unknown start).
// Levenberg-Marquardt damped, in the scan's centroid frame with rotations
// scaled by its radius: against the coarse model's sampling error a
// direction the pairs hardly fix (a flank sliding along itself) would
// otherwise walk off the model; and each step capped so that a poorly
// paired first step cannot throw the scan away.
void coarse_icp(const std::vector<Vec3>& scan, const ModelSample& model, const std::vector<int>& model_ids,
                const PointIndex& index, double reach, Frame& pose) {
  constexpr double keep = 0.8, max_turn = 0.035, max_shift_mm = 2;  // 2 deg, 2 mm per step
  std::vector<int> pair(scan.size());
  std::vector<double> dist(scan.size());
  for (int it = 0; it < 40; ++it) {
    cancellation_point();
    Vec3 c = Vec3::Zero();
    for (size_t i = 0; i < scan.size(); ++i) {
      const Vec3 p = pose * scan[i];
      c += p;
      const int k = index.nearest(p, reach);
      pair[i] = k >= 0 ? model_ids[k] : -1;
      dist[i] = k >= 0 ? (model.points[pair[i]] - p).norm() : reach;
    }
    c /= static_cast<double>(scan.size());
    double lever = 0;
    for (const Vec3& q : scan) lever += (pose * q - c).squaredNorm();
    lever = std::max(1e-6, std::sqrt(lever / static_cast<double>(scan.size())));
    std::vector<double> sorted = dist;
    const size_t cut = static_cast<size_t>(keep * static_cast<double>(scan.size()));
    std::nth_element(sorted.begin(), sorted.begin() + cut, sorted.end());
    const double limit = std::min(sorted[cut], reach * (1 - 1e-12));
    Mat6 a = Mat6::Zero();
    Vec6 b = Vec6::Zero();
    int used = 0;
    for (size_t i = 0; i < scan.size(); ++i) {
      if (pair[i] < 0 || dist[i] > limit) continue;
      const Vec3 p = pose * scan[i];
      const Vec3& n = model.normals[pair[i]];
      Vec6 row;
      row << (p - c).cross(n) / lever, n;
      a += row * row.transpose();
      b += row * (model.points[pair[i]] - p).dot(n);
      ++used;
    }
    if (used < 12) return;
    a.diagonal().array() += 1e-3 * a.trace();
    const Vec6 x = a.ldlt().solve(b);
    const Vec3 w = x.head<3>() / lever, t = x.tail<3>();
    const double scale = std::min({1.0, max_turn / std::max(w.norm(), 1e-300), max_shift_mm / std::max(t.norm(), 1e-300)});
    // Turned by scale * w about c, shifted by scale * t.
    Frame step = Frame::Identity();
    if (w.norm() > 0) step.linear() = Eigen::AngleAxisd(scale * w.norm(), w.normalized()).toRotationMatrix();
    step.translation() = c + scale * t - step.linear() * c;
    pose = step * pose;
    if (scale == 1 && t.norm() + w.norm() * lever < 1e-4) break;
  }
}

// How well a pose puts the scan on the model: the median point-to-plane
// distance to the nearest sample of the full model, a point with none
// within `reach` counting as `reach`. Point-to-plane, because a wrong pose
// that lays the blade on itself (flipped, the flanks swapped) can be as
// close point-to-point as the true one at the coarse sampling, but not
// along the normals.
double placement_score(const std::vector<Vec3>& scan, const ModelSample& model, const PointIndex& index, double reach,
                       const Frame& pose) {
  std::vector<double> e(scan.size(), reach);
  for (size_t i = 0; i < scan.size(); ++i) {
    const Vec3 p = pose * scan[i];
    const int k = index.nearest(p, reach);
    if (k >= 0) e[i] = std::abs((model.points[k] - p).dot(model.normals[k]));
  }
  return median_of(e);
}

// One model sample per cube of side h (the first met): an even subsample
// whatever the order of the samples (a grid's every n-th point is not).
std::vector<int> voxel_subsample(const std::vector<Vec3>& points, double h) {
  std::unordered_map<std::uint64_t, int> first;
  std::vector<int> out;
  for (size_t i = 0; i < points.size(); ++i) {
    const auto key = [&](int a) { return static_cast<std::uint64_t>(std::floor(points[i][a] / h) + (1 << 20)) & 0x1fffff; };
    if (first.emplace((key(0) << 42) | (key(1) << 21) | key(2), static_cast<int>(i)).second) out.push_back(static_cast<int>(i));
  }
  return out;
}

// Principal frame (centroid, axes as columns, right-handed) of points.
Frame principal_frame(const std::vector<Vec3>& points) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : points) c += p;
  c /= static_cast<double>(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) cov += (p - c) * (p - c).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Frame f = Frame::Identity();
  f.linear() = eig.eigenvectors();
  if (f.linear().determinant() < 0) f.linear().col(0) *= -1;
  f.translation() = c;
  return f;
}

// The coarse pre-alignment (see the header): the best of several starts.
Frame pre_align(const std::vector<Vec3>& scan, const ModelSample& model, const PointIndex& fine_index,
                const RegistrationOptions& o, const Frame& initial, RegistrationResult& r) {
  // Subsamples: enough points to see the shape, few enough that forty
  // iterations from eleven starts cost about what the fine ICP does.
  const std::vector<Vec3> sub = every_nth(scan, 1500);
  const double model_spacing = mean_spacing(model.points);
  const double h = model_spacing * std::max(1.0, std::sqrt(static_cast<double>(model.points.size()) / 15000));
  const std::vector<int> model_ids = voxel_subsample(model.points, h);
  std::vector<Vec3> model_sub;
  for (int i : model_ids) model_sub.push_back(model.points[i]);
  // Far enough to pair from the worst start: the offset plus the turn over
  // the scan's extent about its centroid, plus the subsample's spacing.
  const Frame scan_axes = principal_frame(sub);
  double radius = 0;
  for (const Vec3& p : sub) radius = std::max(radius, (p - scan_axes.translation()).norm());
  const double reach = o.capture_mm + deg_to_rad(o.capture_deg) * radius + 4 * h;
  // Cells of a quarter of the reach: a point with no model sample within
  // reach (most, from a far start) costs a few shells of cells, not
  // (reach / spacing)^3 of them.
  const PointIndex index(model_sub, std::max(2 * h, reach / 4));

  std::vector<Frame> starts{initial};
  const Vec3 c = initial * scan_axes.translation();
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      // Turned about the scan's centroid (where it lands), not the origin.
      Frame turn = Frame::Identity();
      turn.linear() = Eigen::AngleAxisd(sign * deg_to_rad(o.capture_deg), Vec3::Unit(axis)).toRotationMatrix();
      turn.translation() = c - turn.linear() * c;
      starts.push_back(turn * initial);
    }
  const Frame model_axes = principal_frame(model_sub);
  for (const Vec3& flip : {Vec3(1, 1, 1), Vec3(-1, -1, 1), Vec3(-1, 1, -1), Vec3(1, -1, -1)}) {
    Frame m = model_axes;
    m.linear() = m.linear() * flip.asDiagonal();
    starts.push_back(m * scan_axes.inverse());
  }
  r.starts = static_cast<int>(starts.size());
  double best = 1e300;
  Frame chosen = initial;
  const double score_reach = 2 * h;
  for (size_t s = 0; s < starts.size(); ++s) {
    Frame pose = starts[s];
    coarse_icp(sub, model, model_ids, index, reach, pose);
    const double score = placement_score(sub, model, fine_index, score_reach, pose);
    if (score < best * (1 - 1e-9)) {
      best = score;
      chosen = pose;
      r.start = static_cast<int>(s);
    }
  }
  r.coarse_median_mm = best;
  return chosen;
}

}  // namespace

PoseUncertainty pose_uncertainty(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                                 const std::vector<double>& residuals) {
  if (normals.size() != points.size() || residuals.size() != points.size())
    throw ParameterError("pose_uncertainty", "expected one normal and one residual per point");
  PoseUncertainty u;
  u.pairs = static_cast<int>(points.size());
  if (points.size() < 7) return u;
  for (const Vec3& p : points) u.centroid += p;
  u.centroid /= static_cast<double>(points.size());
  double lever2 = 0, sq = 0;
  for (const Vec3& p : points) lever2 += (p - u.centroid).squaredNorm();
  u.lever_mm = std::sqrt(lever2 / static_cast<double>(points.size()));
  const double lever = std::max(u.lever_mm, 1e-9);
  Mat6 a = Mat6::Zero();  // scaled: rotations in mm at the lever
  for (size_t i = 0; i < points.size(); ++i) {
    Vec6 row;
    row << (points[i] - u.centroid).cross(normals[i]) / lever, normals[i];
    a += row * row.transpose();
    sq += residuals[i] * residuals[i];
  }
  const double variance = sq / static_cast<double>(points.size() - 6);
  const Eigen::SelfAdjointEigenSolver<Mat6> eig(a);
  const Vec6 lambda = eig.eigenvalues();
  const Mat6& v = eig.eigenvectors();
  const double floor = 1e-12 * lambda(5);
  u.unconstrained = 0;
  for (int k = 0; k < 6; ++k)
    if (lambda(k) <= floor) ++u.unconstrained;
  u.condition = u.unconstrained > 0 ? PoseUncertainty::kInf : lambda(5) / lambda(0);
  u.weakest_rotation = v.col(0).head<3>() / lever;
  u.weakest_translation = v.col(0).tail<3>();
  // Covariance over the constrained directions; a degree of freedom an
  // unconstrained direction moves is unconstrained.
  Mat6 cov = Mat6::Zero();
  Vec6 free_part = Vec6::Zero();
  for (int k = 0; k < 6; ++k) {
    if (lambda(k) <= floor)
      free_part += v.col(k).cwiseAbs();
    else
      cov += variance / lambda(k) * v.col(k) * v.col(k).transpose();
  }
  for (int d = 0; d < 6; ++d) {
    const double sigma = free_part(d) > 1e-6 ? PoseUncertainty::kInf : std::sqrt(cov(d, d));
    if (d < 3)
      u.sigma_rotation_rad(d) = sigma / lever;
    else
      u.sigma_translation_mm(d - 3) = sigma;
  }
  if (u.unconstrained > 0) return u;
  // A point's displacement is w x (p - c) + t: its covariance J cov J^T.
  double worst = 0;
  for (size_t i = 0; i < points.size(); i += std::max<size_t>(1, points.size() / 2000)) {
    Eigen::Matrix<double, 3, 6> j;
    const Vec3 d = (points[i] - u.centroid) / lever;
    j << 0, d.z(), -d.y(), 1, 0, 0,  //
        -d.z(), 0, d.x(), 0, 1, 0,   //
        d.y(), -d.x(), 0, 0, 0, 1;
    const Eigen::Matrix3d c = j * cov * j.transpose();
    worst = std::max(worst, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(c).eigenvalues()(2));
  }
  u.sigma_point_mm = std::sqrt(worst);
  return u;
}

RegistrationResult register_points(const std::vector<Vec3>& scan, const ModelSample& model,
                                   const RegistrationOptions& o, const Frame& initial) {
  if (scan.empty()) throw ParameterError("scan", "expected at least one point");
  if (model.points.empty()) throw ParameterError("model", "expected at least one sample");
  if (model.normals.size() != model.points.size())
    throw ParameterError("model", "expected one normal per sample point");
  const double cell = o.cell_mm > 0 ? o.cell_mm : 2 * mean_spacing(model.points);

  const PointIndex index(model.points, cell);
  RegistrationResult r;
  r.transform = o.pre_align && scan.size() >= 12 ? pre_align(scan, model, index, o, initial, r) : initial;
  double reach = o.initial_reach_mm;
  double gate = 1e300;  // point-to-plane: open until the first residuals are seen
  std::vector<int> pair(scan.size());
  std::vector<double> dist(scan.size());
  std::vector<Vec3> in_points, in_normals;
  std::vector<double> in_residuals;
  for (r.iterations = 1; r.iterations <= o.max_iterations; ++r.iterations) {
    cancellation_point();
    // Pair and measure.
    std::vector<double> found, normal_found;
    found.reserve(scan.size());
    for (size_t i = 0; i < scan.size(); ++i) {
      const Vec3 p = r.transform * scan[i];
      pair[i] = index.nearest(p, reach);
      dist[i] = pair[i] >= 0 ? (model.points[pair[i]] - p).norm() : 1e300;
      if (pair[i] >= 0) {
        found.push_back(dist[i]);
        normal_found.push_back(std::abs((model.points[pair[i]] - p).dot(model.normals[pair[i]])));
      }
    }
    if (found.size() < 6) throw Error("registration: fewer than 6 scan points within " + std::to_string(reach) +
                                      " mm of the model (is the scan in the model's frame?)");
    r.median_mm = median_of(found);
    // 1.4826 x the median absolute value: sigma of normally distributed
    // residuals, unmoved by the stray points it is there to drop.
    gate = std::max(o.min_reach_mm, o.normal_gate_factor * 1.4826 * median_of(normal_found));
    // Point-to-plane normal equations over the inliers.
    Mat6 a = Mat6::Zero();
    Mat6 model_constraint = Mat6::Zero();
    Vec6 b = Vec6::Zero();
    double sq = 0;
    r.inliers = r.outliers = 0;
    in_points.clear();
    in_normals.clear();
    in_residuals.clear();
    for (size_t i = 0; i < scan.size(); ++i) {
      if (pair[i] < 0 || dist[i] > reach) {
        ++r.outliers;
        continue;
      }
      const Vec3 p = r.transform * scan[i];
      const Vec3& q = model.points[pair[i]];
      const Vec3& n = model.normals[pair[i]];
      const double e = (q - p).dot(n);
      if (std::abs(e) > gate) {
        ++r.outliers;
        continue;
      }
      Vec6 row;
      row << p.cross(n), n;
      a += row * row.transpose();
      b += row * e;
      Vec6 on_model;
      on_model << q.cross(n), n;
      model_constraint += on_model * on_model.transpose();
      sq += e * e;
      ++r.inliers;
      in_points.push_back(p);
      in_normals.push_back(n);
      in_residuals.push_back(e);
    }
    r.rms_mm = std::sqrt(sq / std::max(1, r.inliers));
    // Six degrees of freedom must be constrained by the model where the scan
    // lands (not by the scan's current misplacement): the smallest
    // eigenvalue of the model's normal matrix against the largest.
    const Eigen::SelfAdjointEigenSolver<Mat6> eig(model_constraint);
    if (eig.eigenvalues()(0) < 1e-10 * eig.eigenvalues()(5))
      throw Error("registration: the scan does not constrain all six degrees of freedom (a flat or "
                  "rotationally symmetric piece alone cannot be registered)");
    const Vec6 x = a.ldlt().solve(b);
    const Vec3 w = x.head<3>(), t = x.tail<3>();
    r.transform = step_of(x) * r.transform;
    // How far the update moved the scan at most (rotation over the scan's
    // extent plus translation).
    double extent = 0;
    for (size_t i = 0; i < scan.size(); i += std::max<size_t>(1, scan.size() / 64))
      extent = std::max(extent, (r.transform * scan[i]).norm());
    const double moved = t.norm() + w.norm() * extent;
    reach = std::max(o.min_reach_mm, o.outlier_factor * r.median_mm);
    // Converged when the update is below converged_mm, or below a hundredth
    // of what the scan's noise leaves uncertain anyway (a point's sigma):
    // with noisy pairs the nearest samples can flip back and forth between
    // two poses nanometres apart and the update never gets to zero.
    bool done = moved < o.converged_mm;
    if (!done && moved < 1e-3) {
      r.uncertainty = pose_uncertainty(in_points, in_normals, in_residuals);
      done = moved < 0.01 * r.uncertainty.sigma_point_mm;
    }
    if (done) {
      r.converged = true;
      break;
    }
  }
  r.iterations = std::min(r.iterations, o.max_iterations);
  // The last pairs were formed a step (below converged_mm when converged)
  // before the final pose: their residuals are the fit's.
  r.uncertainty = pose_uncertainty(in_points, in_normals, in_residuals);
  return r;
}

namespace {

std::string format(const char* f, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

// The least constrained motion in words: a turn about an axis or a slide
// along a direction, whichever moves the points more.
std::string weakest_motion(const PoseUncertainty& u) {
  const Vec3 turn = u.weakest_rotation * u.lever_mm, slide = u.weakest_translation;
  if (turn.norm() >= slide.norm()) {
    const Vec3 a = turn.normalized();
    return format("turning about (%.2f, %.2f, %.2f)", a.x(), a.y(), a.z()) +
           format(" through (%.1f, %.1f, %.1f) mm", u.centroid.x(), u.centroid.y(), u.centroid.z());
  }
  const Vec3 d = slide.normalized();
  return format("sliding along (%.2f, %.2f, %.2f)", d.x(), d.y(), d.z());
}

}  // namespace

RegistrationCheck check_registration(const RegistrationResult& r, const RegistrationLimits& l) {
  RegistrationCheck c;
  const PoseUncertainty& u = r.uncertainty;
  if (!r.converged)
    c.problems.push_back(format("the fit did not converge in %.0f iterations (rms %.1f um): scan the whole blade "
                                "(both flanks, leading and trailing edge) and check that the scan is of this part "
                                "in its nominal place within the capture range",
                                r.iterations, 1e3 * r.rms_mm));
  if (u.condition <= l.max_condition && !(u.sigma_point_mm <= l.max_sigma_point_mm))
    c.problems.push_back(format("the scan fixes the pose too loosely for its noise (a point's position uncertain by "
                                "%.3g um, limit %.3g um; rms %.1f um)",
                                1e3 * u.sigma_point_mm, 1e3 * l.max_sigma_point_mm, 1e3 * r.rms_mm) +
                         ", weakest " + weakest_motion(u) +
                         ": scan more densely, and both flanks and the leading and trailing edges");
  else if (!(u.condition <= l.max_condition))
    c.problems.push_back(
        (std::isfinite(u.condition)
             ? format("the scan leaves the pose poorly constrained (condition %.3g, limit %.3g;", u.condition,
                      l.max_condition) +
                   format(" a point's position uncertain by %.3g um, limit %.3g um)", 1e3 * u.sigma_point_mm,
                          1e3 * l.max_sigma_point_mm)
             : std::string("the scan leaves the pose unconstrained")) +
        ", weakest " + weakest_motion(u) +
        ": scan both flanks and the leading and trailing edges (surfaces facing other ways fix that motion)");
  if (!(r.rms_mm <= l.rms_factor * l.noise_mm))
    c.problems.push_back(format("the fit's rms %.1f um is above %.3g x the scanner's noise", 1e3 * r.rms_mm, l.rms_factor) +
                         format(" (%.1f um): the scan does not match the model where it landed (a wrong part, a "
                                "damaged or unfinished blade, a wrong noise figure, or a scan needing cleaning of "
                                "fixture points): rescan or check the part",
                                1e3 * l.noise_mm));
  c.trusted = c.problems.empty();
  return c;
}

}  // namespace bliskrun
