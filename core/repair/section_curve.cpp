#include "core/repair/section_curve.h"

#include <Eigen/Sparse>
#include <unsupported/Eigen/FFT>
#include <algorithm>
#include <cmath>
#include <complex>
#include <string>

#include "core/common/error.h"
#include "core/common/parallel.h"
#include "core/common/progress.h"
#include "core/repair/section_points.h"

namespace bliskrun {

SmoothedSection smooth_section(const std::vector<Vec3>& loop, double smoothing_length_mm) {
  if (!(smoothing_length_mm >= 0 && std::isfinite(smoothing_length_mm)))
    throw ParameterError("smoothing_length", "expected a length >= 0 mm");
  const int n = static_cast<int>(loop.size());
  if (n < 5) throw ParameterError("loop", "smoothing a closed loop needs at least 5 points, got " + std::to_string(n));
  for (int i = 0; i < n; ++i)
    if (!loop[i].allFinite()) throw ParameterError("loop", "point " + std::to_string(i) + " is not finite");
  std::vector<double> h(n);
  for (int i = 0; i < n; ++i) {
    h[i] = (loop[(i + 1) % n] - loop[i]).norm();
    if (!(h[i] > 0))
      throw ParameterError("loop", "points " + std::to_string(i) + " and " + std::to_string((i + 1) % n) +
                                       " coincide");
  }
  const auto prev = [n](int i) { return (i + n - 1) % n; };
  std::vector<Eigen::Triplet<double>> w_entries, d_entries;
  for (int i = 0; i < n; ++i) {
    const double hp = h[prev(i)], hn = h[i];
    w_entries.emplace_back(i, i, 0.5 * (hp + hn));
    const double f = 2 / (hp + hn);
    d_entries.emplace_back(i, prev(i), f / hp);
    d_entries.emplace_back(i, i, -f * (1 / hp + 1 / hn));
    d_entries.emplace_back(i, (i + 1) % n, f / hn);
  }
  Eigen::SparseMatrix<double> W(n, n), D(n, n);
  W.setFromTriplets(w_entries.begin(), w_entries.end());
  D.setFromTriplets(d_entries.begin(), d_entries.end());
  const double L4 = std::pow(smoothing_length_mm, 4);
  const Eigen::SparseMatrix<double> A = W + L4 * Eigen::SparseMatrix<double>(D.transpose() * W * D);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success) throw Error("smooth_section: the smoothing system could not be factorised");
  Eigen::MatrixXd P(n, 3);
  for (int i = 0; i < n; ++i) P.row(i) = loop[i].transpose();
  const Eigen::MatrixXd Q = solver.solve(Eigen::MatrixXd(W * P));

  SmoothedSection out;
  out.points.reserve(n);
  double sum2 = 0;
  for (int i = 0; i < n; ++i) {
    out.points.push_back(Q.row(i).transpose());
    const double d = (out.points.back() - loop[i]).norm();
    out.max_shift_mm = std::max(out.max_shift_mm, d);
    sum2 += d * d;
  }
  out.rms_shift_mm = std::sqrt(sum2 / n);
  out.curve = interpolate_closed_cubic(out.points);
  return out;
}

StartAlignment align_start(const CurvatureProfile& reference, const CurvatureProfile& section, int max_shift_samples) {
  const int n = static_cast<int>(section.curvature.size());
  if (n < 16 || reference.curvature.size() != section.curvature.size() || section.t.size() != section.curvature.size())
    throw ParameterError("profiles", "expected two curvature profiles of the same number (>= 16) of samples, got " +
                                         std::to_string(reference.curvature.size()) + " and " + std::to_string(n));
  const auto centred = [n](const std::vector<double>& y) {
    double mean = 0;
    for (double v : y) mean += v / n;
    std::vector<std::complex<double>> out(n);
    for (int i = 0; i < n; ++i) out[i] = y[i] - mean;
    return out;
  };
  const std::vector<std::complex<double>> ya = centred(reference.curvature), yb = centred(section.curvature);
  double var_a = 0, var_b = 0, size_a = 0, size_b = 0;
  for (int i = 0; i < n; ++i) {
    var_a += std::norm(ya[i]), var_b += std::norm(yb[i]);
    size_a += reference.curvature[i] * reference.curvature[i], size_b += section.curvature[i] * section.curvature[i];
  }
  StartAlignment out;
  out.t_start = section.t[0];
  // Constant curvature (to rounding and the spline's ripple): nothing to align by.
  if (!(var_a > 1e-10 * size_a && var_b > 1e-10 * size_b)) return out;
  // c(s) = Σ_i ya_i yb_{i+s} = IFFT(conj(FFT ya) · FFT yb).
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> fa, fb, c;
  fft.fwd(fa, ya);
  fft.fwd(fb, yb);
  for (int k = 0; k < n; ++k) fa[k] = std::conj(fa[k]) * fb[k];
  fft.inv(c, fa);
  int best = 0;
  for (int s = 1; s < n; ++s) {
    if (max_shift_samples >= 0 && std::min(s, n - s) > max_shift_samples) continue;
    if (c[s].real() > c[best].real()) best = s;
  }
  const double cm = c[(best + n - 1) % n].real(), c0 = c[best].real(), cp = c[(best + 1) % n].real();
  const double curve2 = cm - 2 * c0 + cp;
  const double delta = curve2 < 0 ? std::clamp(0.5 * (cm - cp) / curve2, -0.5, 0.5) : 0.0;
  out.correlation = c0 / std::sqrt(var_a * var_b);
  out.shift_samples = std::fmod(best + delta + n, static_cast<double>(n));
  out.shift_mm = out.shift_samples * section.length_mm / n;
  // The new start's parameter, between the samples it falls between.
  const int j = static_cast<int>(std::floor(out.shift_samples));
  const double f = out.shift_samples - j;
  const double t0 = section.t[j];
  double t1 = j + 1 < n ? section.t[j + 1] : section.t[0] + section.period;
  if (t1 < t0) t1 += section.period;  // the samples wrapped past the parameter seam
  out.t_start = t0 + f * (t1 - t0);
  return out;
}

AlignedSections align_section_starts(const std::vector<ClosedCurve>& sections, int samples, int threads) {
  AlignedSections out;
  if (sections.empty()) return out;
  std::vector<CurvatureProfile> own(sections.size());
  parallel_for_index(sections.size(), threads, [&](size_t k) {
    cancellation_point();
    own[k] = curvature_profile(sections[k], samples);
  });
  out.curves.push_back(sections[0]);
  out.alignments.emplace_back();
  CurvatureProfile reference = own[0];
  for (size_t k = 1; k < sections.size(); ++k) {
    cancellation_point();
    const StartAlignment a = align_start(reference, own[k]);
    out.curves.push_back(sections[k].started_at(a.t_start));
    out.alignments.push_back(a);
    reference = curvature_profile(out.curves.back(), samples);
  }
  return out;
}

}  // namespace bliskrun
