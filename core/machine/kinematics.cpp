#include "core/machine/kinematics.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/common/error.h"

namespace bliskrun {

namespace {

// Below this |sin| of the angle between the tool axis and the primary axis the
// primary angle is undetermined. Keeping the previous angle there leaves an
// orientation error of at most this many radians.
constexpr double kSingularSin = 1e-9;
// Slack on travel limits so that a pose planned exactly at a limit is taken.
constexpr double kLimitSlackRad = 1e-9;
constexpr double kTwoPi = 2 * kPi;

Eigen::Isometry3d rotation_about(const Vec3& pivot, const Vec3& direction, double angle_rad) {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.linear() = Eigen::AngleAxisd(angle_rad, direction).toRotationMatrix();
  m.translation() = pivot - m.linear() * pivot;
  return m;
}

Vec3 rotate(const Vec3& v, const Vec3& d, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return v * c + d.cross(v) * s + d * (d.dot(v) * (1 - c));
}

std::string fixed_deg_text(double rad) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(3);
  out << rad_to_deg(rad);
  return out.str();
}

struct Unwrapped {
  double value;
  bool within;
};

// The equivalent of `raw` (mod 2*pi) within travel nearest to `previous`; if
// none lies within travel, the equivalent nearest to `previous`.
Unwrapped unwrap(double raw, double previous, const RotaryAxis& axis) {
  const double nearest = raw + kTwoPi * std::round((previous - raw) / kTwoPi);
  if (axis.continuous()) return {nearest, true};
  const double lo = axis.min_rad - kLimitSlackRad, hi = axis.max_rad + kLimitSlackRad;
  if (nearest >= lo && nearest <= hi) return {nearest, true};
  const double n_lo = std::ceil((lo - raw) / kTwoPi), n_hi = std::floor((hi - raw) / kTwoPi);
  if (n_lo > n_hi) return {nearest, false};
  const double n = std::clamp(std::round((previous - raw) / kTwoPi), n_lo, n_hi);
  return {raw + kTwoPi * n, true};
}

}  // namespace

Kinematics::Kinematics(MachineDefinition machine, double tool_length_mm)
    : machine_(std::move(machine)), tool_length_mm_(tool_length_mm) {
  validate(machine_);
  if (!std::isfinite(tool_length_mm_) || tool_length_mm_ < 0)
    throw ParameterError("tool_length", "expected a length >= 0 mm");
  for (int i = 0; i < 2; ++i)
    (machine_.rotary[i].carrier == AxisCarrier::Part ? part_axes_ : tool_axes_).push_back(i);
  // Orientation sequence: table axes from the part outwards, then head axes
  // from the base inwards; the first one is the primary axis.
  std::vector<int> sequence(part_axes_.rbegin(), part_axes_.rend());
  sequence.insert(sequence.end(), tool_axes_.begin(), tool_axes_.end());
  primary_ = sequence[0];
  secondary_ = sequence[1];
  auto sign = [&](int i) { return machine_.rotary[i].carrier == AxisCarrier::Part ? -1.0 : 1.0; };
  primary_sign_ = sign(primary_);
  secondary_sign_ = sign(secondary_);
  const Vec3& s = machine_.spindle;
  gauge_local_ = machine_.tool_length == ToolLengthMode::Tip ? Vec3(tool_length_mm_ * s)
                                                              : Vec3::Zero();
  tip_local_ = gauge_local_ - tool_length_mm_ * s;
}

Eigen::Isometry3d Kinematics::part_to_machine(const std::array<double, 2>& r) const {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  for (int i : part_axes_) {
    const RotaryAxis& a = machine_.rotary[i];
    m = m * rotation_about(a.pivot_mm, a.direction, r[i]);
  }
  return m * Eigen::Translation3d(machine_.part_origin_mm);
}

Eigen::Isometry3d Kinematics::head_map(const std::array<double, 2>& r) const {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  for (int i : tool_axes_) {
    const RotaryAxis& a = machine_.rotary[i];
    m = m * rotation_about(gauge_local_ + a.pivot_mm, a.direction, r[i]);
  }
  return m;
}

ToolPose Kinematics::forward(const MachineAxes& q) const {
  const Eigen::Isometry3d head = head_map(q.rotary_rad);
  const Vec3 tip_machine = q.linear_mm + head * tip_local_;
  const Vec3 axis_machine = head.linear() * machine_.spindle;
  const Eigen::Isometry3d part = part_to_machine(q.rotary_rad);
  ToolPose pose;
  pose.tip = part.inverse() * tip_machine;
  pose.axis = part.linear().transpose() * axis_machine;
  return pose;
}

Vec3 Kinematics::tool_axis(const std::array<double, 2>& r) const {
  const Vec3 v = rotate(machine_.spindle, machine_.rotary[secondary_].direction,
                        secondary_sign_ * r[secondary_]);
  return rotate(v, machine_.rotary[primary_].direction, primary_sign_ * r[primary_]);
}

Vec3 Kinematics::linear_for(const Vec3& tip, const std::array<double, 2>& r) const {
  return part_to_machine(r) * tip - head_map(r) * tip_local_;
}

std::vector<RotarySolution> Kinematics::rotary_solutions(
    const Vec3& axis_in, const std::array<double, 2>& previous) const {
  if (!axis_in.allFinite() || axis_in.norm() < 1e-12)
    throw ParameterError("axis", "expected a non-zero finite tool axis");
  const Vec3 k = axis_in.normalized();
  const Vec3& d1 = machine_.rotary[primary_].direction;
  const Vec3& d2 = machine_.rotary[secondary_].direction;
  const Vec3& s = machine_.spindle;

  // d1 . R(d2, b) s = d1 . k  ->  P cos b + Q sin b = W
  const double d12 = d1.dot(d2), d2s = d2.dot(s);
  const double P = d1.dot(s) - d2s * d12;
  const double Q = d1.dot(d2.cross(s));
  const double W = d1.dot(k) - d12 * d2s;
  const double r = std::hypot(P, Q);
  std::vector<RotarySolution> out;
  if (r < 1e-12) return out;
  double c = W / r;
  if (std::abs(c) > 1 + 1e-12) return out;
  c = std::clamp(c, -1.0, 1.0);
  const double phi = std::atan2(Q, P), gamma = std::acos(c);

  const Vec3 kp = k - d1 * d1.dot(k);
  const bool singular = kp.norm() < kSingularSin;
  for (double b : {phi + gamma, phi - gamma}) {
    double a = primary_sign_ * previous[primary_];
    if (!singular) {
      const Vec3 v = rotate(s, d2, b);
      const Vec3 vp = v - d1 * d1.dot(v);
      a = std::atan2(d1.dot(vp.cross(kp)), vp.dot(kp));
    }
    std::array<double, 2> raw{};
    raw[primary_] = primary_sign_ * a;
    raw[secondary_] = secondary_sign_ * b;
    RotarySolution sol;
    sol.singular = singular;
    for (int i = 0; i < 2; ++i) {
      const double prev = previous[i];
      // Keep the singular primary angle exactly as it was.
      const Unwrapped u = (singular && i == primary_)
                              ? unwrap(raw[i], prev, machine_.rotary[i])
                              : unwrap(wrap_angle(raw[i]), prev, machine_.rotary[i]);
      sol.rotary_rad[i] = u.value;
      if (!u.within && sol.within_limits) {
        sol.within_limits = false;
        sol.violated_axis = i;
        sol.violated_value_rad = u.value;
      }
    }
    bool duplicate = false;
    for (const RotarySolution& o : out)
      duplicate |= std::abs(o.rotary_rad[0] - sol.rotary_rad[0]) < 1e-12 &&
                   std::abs(o.rotary_rad[1] - sol.rotary_rad[1]) < 1e-12;
    if (!duplicate) out.push_back(sol);
  }
  return out;
}

MachineAxes Kinematics::inverse(const ToolPose& pose, const MachineAxes& previous) const {
  if (!pose.tip.allFinite()) throw ParameterError("tip", "expected finite coordinates");
  const std::vector<RotarySolution> solutions = rotary_solutions(pose.axis, previous.rotary_rad);
  if (solutions.empty())
    throw ParameterError(machine_.rotary[secondary_].name,
                         "no position of the rotary axes gives this tool axis");
  auto motion = [&](const RotarySolution& s) {
    return std::abs(s.rotary_rad[0] - previous.rotary_rad[0]) +
           std::abs(s.rotary_rad[1] - previous.rotary_rad[1]);
  };
  std::vector<const RotarySolution*> order;
  for (const RotarySolution& s : solutions) order.push_back(&s);
  std::stable_sort(order.begin(), order.end(), [&](const RotarySolution* a, const RotarySolution* b) {
    return motion(*a) < motion(*b);
  });
  // Why each solution fails, nearest first; the error names the nearest
  // solution's axis and lists every reason.
  std::string axis_name, reasons;
  auto refuse = [&](const std::string& axis, const std::string& reason) {
    if (axis_name.empty()) axis_name = axis;
    reasons += (reasons.empty() ? "" : "; the other solution: ") + reason;
  };
  for (const RotarySolution* s : order) {
    if (!s->within_limits) {
      const RotaryAxis& a = machine_.rotary[s->violated_axis];
      refuse(a.name, a.name + " = " + fixed_deg_text(s->violated_value_rad) + " deg, outside travel [" +
                         fixed_deg_text(a.min_rad) + ", " + fixed_deg_text(a.max_rad) + "] deg");
      continue;
    }
    MachineAxes q;
    q.rotary_rad = s->rotary_rad;
    q.linear_mm = linear_for(pose.tip, q.rotary_rad);
    bool ok = true;
    for (int i = 0; i < 3 && ok; ++i) {
      const LinearAxis& a = machine_.linear[i];
      // Travel is the slides': the spindle gauge point, whatever the length
      // convention of the program words.
      const double slide = q.linear_mm[i] + gauge_local_[i];
      if (slide < a.min_mm - 1e-9 || slide > a.max_mm + 1e-9) {
        ok = false;
        std::ostringstream msg;
        msg.setf(std::ios::fixed);
        msg.precision(3);
        msg << a.name << " = " << q.linear_mm[i] << " mm (gauge point at " << slide
            << "), outside travel [" << a.min_mm << ", " << a.max_mm << "] mm";
        refuse(a.name, msg.str() + " with " + machine_.rotary[0].name + " = " +
                           fixed_deg_text(q.rotary_rad[0]) + ", " + machine_.rotary[1].name + " = " +
                           fixed_deg_text(q.rotary_rad[1]) + " deg");
      }
    }
    if (ok) return q;
  }
  throw ParameterError(axis_name, "needs " + reasons);
}

bool Kinematics::reachable(const Vec3& axis) const {
  for (const RotarySolution& s : rotary_solutions(axis, {0.0, 0.0}))
    if (s.within_limits) return true;
  return false;
}

// Calls f(point, direction) for each rotary axis line where it is at `q`,
// machine frame; returns the tip in the machine frame.
template <class F>
static Vec3 visit_axis_lines(const MachineDefinition& m, const std::vector<int>& part_axes,
                             const std::vector<int>& tool_axes, const Vec3& gauge_local,
                             const Vec3& tip_local, const MachineAxes& q, F&& f) {
  Eigen::Isometry3d prefix = Eigen::Isometry3d::Identity();
  for (int i : part_axes) {
    const RotaryAxis& a = m.rotary[i];
    f(Vec3(prefix * a.pivot_mm), Vec3(prefix.linear() * a.direction));
    prefix = prefix * rotation_about(a.pivot_mm, a.direction, q.rotary_rad[i]);
  }
  prefix = Eigen::Isometry3d::Identity();
  for (int i : tool_axes) {
    const RotaryAxis& a = m.rotary[i];
    const Vec3 pivot = gauge_local + a.pivot_mm;
    f(Vec3(q.linear_mm + prefix * pivot), Vec3(prefix.linear() * a.direction));
    prefix = prefix * rotation_about(pivot, a.direction, q.rotary_rad[i]);
  }
  return q.linear_mm + prefix * tip_local;
}

double Kinematics::lever_arm_mm(const MachineAxes& q) const {
  std::vector<std::pair<Vec3, Vec3>> lines;
  const Vec3 tip = visit_axis_lines(machine_, part_axes_, tool_axes_, gauge_local_, tip_local_, q,
                                    [&](const Vec3& p, const Vec3& d) { lines.emplace_back(p, d); });
  double arm = 0;
  for (const auto& [p, d] : lines) {
    const Vec3 r = tip - p;
    arm = std::max(arm, (r - d * d.dot(r)).norm());
  }
  return arm;
}

double Kinematics::safe_z_mm() const {
  if (std::isfinite(machine_.safe_z_mm)) return machine_.safe_z_mm;
  const double top = machine_.linear[2].max_mm;
  if (!std::isfinite(top))
    throw ParameterError("safe_z", "the machine states neither a safe height (safe_z) nor the top of its Z travel");
  return top - gauge_local_.z();
}

double Kinematics::rotary_axes_cos() const {
  return std::abs(machine_.rotary[0].direction.normalized().dot(machine_.rotary[1].direction.normalized()));
}

double Kinematics::pivot_reach_mm(const MachineAxes& q) const {
  std::array<Vec3, 2> pivots;
  int n = 0;
  const Vec3 tip = visit_axis_lines(machine_, part_axes_, tool_axes_, gauge_local_, tip_local_, q,
                                    [&](const Vec3& p, const Vec3&) { pivots[n++] = p; });
  return std::max((tip - pivots[0]).norm(), (tip - pivots[1]).norm());
}

}  // namespace bliskrun
