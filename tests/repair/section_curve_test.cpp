#include "core/repair/section_curve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "core/common/error.h"
#include "repair/section_shapes.h"

namespace bliskrun {
namespace {

using test::add_noise;
using test::blade_profile;

std::vector<Vec3> circle_points(double R, int n) {
  std::vector<Vec3> out;
  for (int i = 0; i < n; ++i) out.emplace_back(R * std::cos(2 * kPi * i / n), R * std::sin(2 * kPi * i / n), 0);
  return out;
}

// Largest and RMS distance of the curve from the circle of radius R about
// the origin, over 20 samples per point.
std::pair<double, double> off_circle(const ClosedCurve& c, double R, int n) {
  double worst = 0, sum2 = 0;
  const int m = 20 * n;
  for (int j = 0; j < m; ++j) {
    const double d = std::abs(c.point(c.t_min() + c.period() * j / m).norm() - R);
    worst = std::max(worst, d);
    sum2 += d * d;
  }
  return {worst, std::sqrt(sum2 / m)};
}

TEST(SectionSmoothing, ShrinksANoiseFreeCircleByExactlyTheStatedFactor) {
  // With points evenly spaced on a circle the discrete energy's minimiser is
  // the circle of radius R / (1 + (L/R)^4) (section_curve.h).
  const double R = 10, L = 2;
  const SmoothedSection s = smooth_section(circle_points(R, 400), L);
  const double expected = R / (1 + std::pow(L / R, 4));
  for (const Vec3& q : s.points) EXPECT_NEAR(q.norm(), expected, 1e-9);
  EXPECT_NEAR(s.max_shift_mm, R - expected, 1e-9);
  // L = 0 keeps the points.
  const std::vector<Vec3> noisy = [] {
    std::vector<Vec3> p = circle_points(10, 100);
    add_noise(p, 0.01, 1);
    return p;
  }();
  const SmoothedSection kept = smooth_section(noisy, 0);
  for (size_t i = 0; i < noisy.size(); ++i) EXPECT_LT((kept.points[i] - noisy[i]).norm(), 1e-12);
}

TEST(SectionSmoothing, ANoisyCircleConvergesToTheCircleAsTheNoiseVanishes) {
  // R = 10 mm, 400 points 0.157 mm apart, L = 0.6 mm (bias R (L/R)^4 = 0.13 um).
  // The same noise pattern scaled: the smoothing is linear, so the error is
  // the bias plus sigma times a fixed pattern's.
  const double R = 10, L = 0.6;
  const double bias = R - R / (1 + std::pow(L / R, 4));  // the noise-free limit's shrink
  double last_max = INFINITY;
  for (const double sigma : {0.04, 0.02, 0.01, 0.005, 0.0025, 0.0}) {
    std::vector<Vec3> p = circle_points(R, 400);
    add_noise(p, sigma, 7);
    const SmoothedSection s = smooth_section(p, L);
    double mean_r = 0;
    for (const Vec3& q : s.points) mean_r += q.norm() / s.points.size();
    const auto [worst, rms] = off_circle(s.curve, R, 400);
    std::printf("[ measured ] circle R 10 mm, L 0.6 mm, noise %.4f mm: radius error %.2e mm, curve off the circle "
                "max %.2e / rms %.2e mm\n",
                sigma, mean_r - R, worst, rms);
    EXPECT_LT(std::abs(mean_r - R), 0.2 * sigma + bias + 1e-9);  // the noise's own mean: 0.05 sigma
    EXPECT_LT(worst, 1.2 * sigma + bias + 1e-6);  // the raw points reach ~3 sigma; 1e-6: the cubic between points
    EXPECT_LT(rms, 0.35 * sigma + bias + 1e-6);   // ~0.26 sigma in theory for radial noise
    EXPECT_LT(worst, last_max);
    last_max = worst;
  }
  EXPECT_NEAR(last_max, bias, 1e-6);  // converges to the stated limit
}

TEST(SectionSmoothing, CurvatureOfTheSmoothedCircleIsOneOverItsRadius) {
  const double R = 10, L = 0.6;
  const double shrunk = R / (1 + std::pow(L / R, 4));
  for (bool clockwise : {false, true}) {
    std::vector<Vec3> p = circle_points(R, 400);
    if (clockwise) std::reverse(p.begin(), p.end());
    const CurvatureProfile exact = curvature_profile(smooth_section(p, L).curve, 1024);
    ASSERT_EQ(exact.curvature.size(), 1024u);
    EXPECT_NEAR(exact.length_mm, 2 * kPi * shrunk, 1e-6);
    for (double k : exact.curvature) EXPECT_NEAR(k * shrunk, 1.0, 5e-5);  // convex: positive either way
  }
  std::vector<Vec3> p = circle_points(R, 400);
  add_noise(p, 0.005, 8);
  const CurvatureProfile noisy = curvature_profile(smooth_section(p, L).curve, 1024);
  double mean = 0, worst = 0;
  for (double k : noisy.curvature) mean += k / noisy.curvature.size(), worst = std::max(worst, std::abs(k * R - 1));
  std::printf("[ measured ] circle R 10 mm, noise 5 um, L 0.6 mm: curvature mean %.5f /mm (1/R = 0.1), "
              "worst %.1f %% off\n",
              mean, 100 * worst);
  EXPECT_NEAR(mean * R, 1.0, 1e-3);
  EXPECT_LT(worst, 0.15);
}

TEST(SectionSmoothing, RejectsImpossibleInput) {
  EXPECT_THROW(smooth_section(circle_points(1, 20), -0.1), ParameterError);
  EXPECT_THROW(smooth_section(circle_points(1, 20), NAN), ParameterError);
  EXPECT_THROW(smooth_section(circle_points(1, 4), 0.1), ParameterError);
  std::vector<Vec3> p = circle_points(1, 20);
  p[5] = p[6];
  EXPECT_THROW(smooth_section(p, 0.1), ParameterError);
  p = circle_points(1, 20);
  p[5].z() = NAN;
  EXPECT_THROW(smooth_section(p, 0.1), ParameterError);
}

// The blade section moved as the next section up a blade would be: turned
// about its middle, scaled, raised, its points started `later` places on,
// with fresh noise.
std::vector<Vec3> next_section(const std::vector<Vec3>& clean, double twist_deg, double scale, int later,
                               unsigned seed) {
  const Mat3 r = Eigen::AngleAxisd(deg_to_rad(twist_deg), Vec3::UnitZ()).toRotationMatrix();
  const Vec3 middle(30, 3, 0);
  std::vector<Vec3> out;
  const size_t n = clean.size();
  for (size_t i = 0; i < n; ++i) out.push_back(middle + scale * (r * (clean[(i + later) % n] - middle)) + Vec3(0, 0, 5));
  add_noise(out, 0.004, seed);
  return out;
}

TEST(SectionAlignment, RecoversAKnownStartShiftFromTheCurvatureProfiles) {
  const std::vector<Vec3> clean = blade_profile(1200);
  std::vector<Vec3> a_points = clean;
  add_noise(a_points, 0.004, 11);
  // L = 0.1 mm: two thirds of the 0.15 mm edge radius (the edges are blunted
  // alike on both sections; a shorter L leaves the 4 um noise's curvature
  // larger than the flanks').
  const SmoothedSection a = smooth_section(a_points, 0.1);
  const CurvatureProfile pa = curvature_profile(a.curve);
  for (const int later : {0, 1, 337, 900, 1199}) {
    const std::vector<Vec3> b_points = next_section(clean, 2, 0.97, later, 12 + later);
    const SmoothedSection b = smooth_section(b_points, 0.1);
    const StartAlignment al = align_start(pa, curvature_profile(b.curve));
    // b's point (n - later) % n is a's first point moved.
    const int truth = static_cast<int>((clean.size() - later) % clean.size());
    const Mat3 r = Eigen::AngleAxisd(deg_to_rad(2), Vec3::UnitZ()).toRotationMatrix();
    const Vec3 target = Vec3(30, 3, 0) + 0.97 * (r * (clean[0] - Vec3(30, 3, 0))) + Vec3(0, 0, 5);
    const double miss = (b.curve.point(al.t_start) - target).norm();
    double arc_to_truth = 0;  // along the smoothed points, from b's start
    for (int i = 0; i < truth; ++i) arc_to_truth += (b.points[i + 1] - b.points[i]).norm();
    std::printf("[ measured ] start moved %4d points (%.3f mm): recovered %.3f mm, new start %.4f mm from the "
                "true one, rho %.4f\n",
                later, arc_to_truth, al.shift_mm, miss, al.correlation);
    EXPECT_LT(miss, 0.02);  // a fifth of the point spacing
    EXPECT_GT(al.correlation, 0.85);  // the noise's curvature is what is left
    // b's parameter is its chord length: the true start is at arc_to_truth.
    EXPECT_LT(std::abs(std::remainder(al.t_start - arc_to_truth, b.curve.period())), 0.02);
  }
}

TEST(SectionAlignment, TheSweepLinesUpEverySectionWithTheFirst) {
  // Five sections up a twisting blade, each started somewhere else.
  const std::vector<Vec3> clean = blade_profile(1000);
  const int starts[] = {0, 250, 731, 64, 999};
  std::vector<ClosedCurve> curves;
  for (int k = 0; k < 5; ++k) curves.push_back(smooth_section(next_section(clean, 1.5 * k, 1 - 0.02 * k, starts[k], 20 + k), 0.1).curve);
  const AlignedSections aligned = align_section_starts(curves, 1024);
  ASSERT_EQ(aligned.curves.size(), 5u);
  double worst = 0;
  for (int k = 0; k < 5; ++k) {
    const Mat3 r = Eigen::AngleAxisd(deg_to_rad(1.5 * k), Vec3::UnitZ()).toRotationMatrix();
    const Vec3 target = Vec3(30, 3, 0) + (1 - 0.02 * k) * (r * (clean[starts[0]] - Vec3(30, 3, 0))) + Vec3(0, 0, 5);
    worst = std::max(worst, (aligned.curves[k].point(aligned.curves[k].t_min()) - target).norm());
  }
  std::printf("[ measured ] sweep over 5 sections: starts within %.4f mm of the true line\n", worst);
  EXPECT_LT(worst, 0.03);
  EXPECT_EQ(aligned.alignments[0].shift_mm, 0);
}

TEST(SectionAlignment, AProfileOfConstantCurvatureKeepsItsStart) {
  CurvatureProfile flat;
  for (int j = 0; j < 64; ++j) flat.t.push_back(j * 0.5), flat.curvature.push_back(0.2);
  flat.length_mm = flat.period = 32;
  CurvatureProfile bumpy = flat;
  bumpy.curvature[10] = 3;
  for (const CurvatureProfile* other : {&flat, &bumpy}) {
    const StartAlignment a = align_start(*other, flat);
    EXPECT_EQ(a.shift_samples, 0);
    EXPECT_EQ(a.t_start, 0);
    EXPECT_EQ(a.correlation, 0);
  }
}

TEST(SectionAlignment, RejectsMismatchedOrTooShortProfiles) {
  const ClosedCurve c = smooth_section(circle_points(5, 100), 0).curve;
  const CurvatureProfile p = curvature_profile(c, 64);
  const StartAlignment same = align_start(p, p);  // a profile lines up with itself
  EXPECT_NEAR(same.shift_samples, 0, 1e-9);
  EXPECT_THROW(align_start(p, curvature_profile(c, 128)), ParameterError);
  EXPECT_THROW(curvature_profile(c, 8), ParameterError);
}

}  // namespace
}  // namespace bliskrun
