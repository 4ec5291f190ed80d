#include "core/geometry/registration.h"

#include <gtest/gtest.h>

#include <random>

#include "core/common/error.h"

namespace bliskrun {
namespace {

// An ellipsoid patch with three different semi-axes: no rigid motion maps it
// onto itself, so a scan of it pins down all six degrees of freedom.
ModelSample ellipsoid(double a, double b, double c, int n, double th0, double th1) {
  ModelSample m;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double th = th0 + (th1 - th0) * i / (n - 1), ph = -1.2 + 2.4 * j / (n - 1);
      const Vec3 p(a * std::sin(th) * std::cos(ph), b * std::sin(th) * std::sin(ph), c * std::cos(th));
      m.points.push_back(p);
      m.normals.push_back(Vec3(p.x() / (a * a), p.y() / (b * b), p.z() / (c * c)).normalized());
    }
  return m;
}

Frame clamping_error() {
  Frame t = Frame::Identity();
  t.linear() = Eigen::AngleAxisd(deg_to_rad(0.5), Vec3(1, 2, 3).normalized()).toRotationMatrix();
  t.translation() = Vec3(0.3, 0.4, -0.2);
  return t;
}

void expect_recovers(const Frame& found, const Frame& truth, double mm, double deg) {
  // found maps the scan back onto the model: found * truth = identity.
  const Frame residual = found * truth;
  EXPECT_LT(residual.translation().norm(), mm);
  EXPECT_LT(rad_to_deg(Eigen::AngleAxisd(residual.linear()).angle()), deg);
}

TEST(Registration, RecoversAKnownClampingErrorExactlyWithoutNoise) {
  const ModelSample model = ellipsoid(60, 40, 25, 200, 0.3, 1.4);
  const Frame truth = clamping_error();
  std::vector<Vec3> scan;
  const ModelSample part = ellipsoid(60, 40, 25, 60, 0.35, 1.35);  // other points, inside the model
  for (const Vec3& p : part.points) scan.push_back(truth * p);
  const RegistrationResult r = register_points(scan, model);
  EXPECT_TRUE(r.converged);
  // The model is a sample 0.3 mm apart: point-to-plane pairs are exact to the
  // surface's curvature between samples (~ s^2 / 8R), sub-micrometre here.
  expect_recovers(r.transform, truth, 1e-3, 1e-3);
}

TEST(Registration, RecoversItWithNoiseOutliersAndPartialCoverage) {
  const ModelSample model = ellipsoid(60, 40, 25, 300, 0.3, 1.4);
  const Frame truth = clamping_error();
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0, 0.005);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Vec3> scan;
  // Only part of the surface is seen (th in [0.5, 1.2]); 5 % stray points
  // 1-3 mm off the surface (gripper, dust); 5 um noise along the normal.
  const ModelSample seen = ellipsoid(60, 40, 25, 150, 0.5, 1.2);
  for (size_t i = 0; i < seen.points.size(); ++i) {
    Vec3 p = seen.points[i] + noise(rng) * seen.normals[i];
    if (unit(rng) < 0.05) p += (1 + 2 * unit(rng)) * seen.normals[i];
    scan.push_back(truth * p);
  }
  const RegistrationResult r = register_points(scan, model);
  EXPECT_TRUE(r.converged);
  expect_recovers(r.transform, truth, 0.002, 0.002);   // within the noise, averaged over 22 500 points
  EXPECT_NEAR(r.rms_mm, 0.005, 0.002);                 // what is left is the noise
  EXPECT_GT(r.outliers, static_cast<int>(0.04 * scan.size()));  // the stray points were dropped
}

TEST(Registration, ASphereCannotBeRegisteredAndSaysSo) {
  const ModelSample sphere = ellipsoid(30, 30, 30, 100, 0.3, 1.4);
  std::vector<Vec3> scan;
  for (const Vec3& p : ellipsoid(30, 30, 30, 40, 0.4, 1.3).points) scan.push_back(p + Vec3(0.1, 0, 0));
  try {
    register_points(scan, sphere);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("six degrees of freedom"), std::string::npos) << e.what();
  }
  EXPECT_THROW(register_points({}, sphere), ParameterError);
}

}  // namespace
}  // namespace bliskrun
