#include "core/machine/motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/common/error.h"
#include "core/geometry/segment.h"

namespace bliskrun {

namespace {

constexpr int kMaxSamples = 4096;

MachineAxes lerp(const MachineAxes& a, const MachineAxes& b, double t) {
  MachineAxes q;
  q.linear_mm = a.linear_mm + t * (b.linear_mm - a.linear_mm);
  for (int i = 0; i < 2; ++i) q.rotary_rad[i] = a.rotary_rad[i] + t * (b.rotary_rad[i] - a.rotary_rad[i]);
  return q;
}

bool same_axes(const MachineAxes& a, const MachineAxes& b) {
  return (a.linear_mm - b.linear_mm).cwiseAbs().maxCoeff() < 1e-12 &&
         std::abs(a.rotary_rad[0] - b.rotary_rad[0]) < 1e-12 &&
         std::abs(a.rotary_rad[1] - b.rotary_rad[1]) < 1e-12;
}

bool same_rotaries(const MachineAxes& a, const MachineAxes& b) {
  return std::abs(a.rotary_rad[0] - b.rotary_rad[0]) < 1e-9 && std::abs(a.rotary_rad[1] - b.rotary_rad[1]) < 1e-9;
}

// Whether the controller's rapid from `a` to `b` runs along the planned
// segment by itself (see motion.h): no rotary turns, and one linear axis moves
// or the controller interpolates rapids linearly.
bool rapid_follows_segment(const MachineDefinition& machine, const MachineAxes& a, const MachineAxes& b) {
  if (!same_rotaries(a, b)) return false;
  if (machine.rapid.linear) return true;
  int moving = 0;
  for (int i = 0; i < 3; ++i) moving += std::abs(a.linear_mm[i] - b.linear_mm[i]) > 1e-9;
  return moving <= 1;
}

std::string rotary_words(const MachineDefinition& machine, const MachineAxes& q) {
  std::ostringstream out;
  out.precision(6);
  out << machine.rotary[0].name << rad_to_deg(q.rotary_rad[0]) << " " << machine.rotary[1].name
      << rad_to_deg(q.rotary_rad[1]);
  return out.str();
}

std::string describe(long index, const PlannedMove& m) {
  std::ostringstream out;
  out.precision(6);
  out << "move " << index + 1;  // counted from 1, as a person (and Lua) counts
  if (m.row >= 0) out << " (row " << m.row << ")";
  out << " tip (" << m.pose.tip.x() << ", " << m.pose.tip.y() << ", " << m.pose.tip.z()
      << ") axis (" << m.pose.axis.x() << ", " << m.pose.axis.y() << ", " << m.pose.axis.z()
      << ")";
  return out.str();
}

// The F word of a block and how fast its cutter moves (see MotionOptions).
// The block's duration is the longest of: the tip over its length at the
// planned feed; the cutter's fastest point (tip length + cutter reach x the
// relative turn of tool and part) at `cutter_feed_factor` x the planned
// feed; each rotary axis at its top speed. Positioning moves (not cutting)
// skip the cutter's term.
struct BlockFeed {
  double word = 0;
  double minutes = 0, tip_minutes = 0;  // the block's duration, and the tip's alone at the planned feed
  bool untimed = false;  // TCP: the tip moves too little for F to time the block
  double cutter_ratio = 0;  // fastest cutter point / planned feed
  bool slowed = false;
  std::array<double, 2> rotary_rad_per_min{0.0, 0.0};
};

BlockFeed block_feed(const Kinematics& kin, FeedMode mode, bool tcp, double feed_mm_per_min, double tip_mm,
                     const MachineAxes& a, const MachineAxes& b, const ToolReach& reach, double factor,
                     bool cutting) {
  const double d0 = b.rotary_rad[0] - a.rotary_rad[0], d1 = b.rotary_rad[1] - a.rotary_rad[1];
  const double turn = std::sqrt(std::max(0.0, d0 * d0 + d1 * d1 + 2 * std::abs(d0 * d1) * kin.rotary_axes_cos()));
  const double cutter_mm = tip_mm + reach.active() * turn;
  double minutes = tip_mm / feed_mm_per_min;
  const double tip_minutes = minutes;
  if (cutting && factor > 0) minutes = std::max(minutes, cutter_mm / (factor * feed_mm_per_min));
  for (int i = 0; i < 2; ++i) {
    const double top = kin.machine().rotary[i].max_speed_rad_per_min;
    if (std::isfinite(top) && top > 0) minutes = std::max(minutes, std::abs(i == 0 ? d0 : d1) / top);
  }
  BlockFeed f;
  // The controller's own measure of a block: with TCP the tip's path;
  // without, the combined axis distance (mm and degrees), as it times a
  // per-minute feed with rotary words.
  double combined = (b.linear_mm - a.linear_mm).squaredNorm();
  for (double d : {d0, d1}) combined += std::pow(rad_to_deg(d), 2);
  combined = std::sqrt(combined);
  if (!(minutes > 0)) {
    // Nothing the tool does bounds the time (no tip motion, no reach, no
    // stated speeds): timed as the controller times it, the combined
    // distance at the planned feed.
    minutes = combined / feed_mm_per_min;
    if (!(minutes > 0)) minutes = 1e-9;
  }
  f.slowed = minutes > tip_minutes * (1 + 1e-9) + 1e-15;
  f.minutes = minutes;
  f.tip_minutes = tip_minutes;
  if (mode == FeedMode::InverseTime) f.word = 1 / minutes;
  else if (!cutting) f.word = feed_mm_per_min;  // positioning: the rapid feed as the controller reads it
  else if (tcp) {
    // F is the tip's speed. A block that hardly moves the tip cannot be
    // timed by it: at least 1 mm/min is written (what the post's one
    // decimal keeps), and the block counted — its time is then the
    // controller's, its rotary axes at their own speed limits.
    f.word = tip_mm / minutes;
    if (f.word < 1.0) {
      f.word = std::max(1.0, std::min(feed_mm_per_min, tip_mm > 1e-9 ? 1.0 : feed_mm_per_min));
      f.untimed = true;
    }
  }
  else f.word = combined / minutes;
  // Under TCP a block that hardly moves the tip is timed by the controller
  // (its rotary speed), not by F: its ratio is measured at the top speeds.
  f.cutter_ratio = cutter_mm / minutes / feed_mm_per_min;
  f.rotary_rad_per_min = {std::abs(d0) / minutes, std::abs(d1) / minutes};
  return f;
}

class MotionPlanner {
 public:
  MotionPlanner(const Kinematics& kin, const MotionOptions& options, MachineProgram& program, const ToolReach& reach)
      : kin_(kin), options_(options), program_(program), reach_(reach) {}

  // Appends the feed move from (pose_a, axes_a) to (pose_b, axes_b), split
  // until the whole tool stays within tolerance of the planned motion.
  void feed(const ToolPose& pose_a, const MachineAxes& axes_a, const ToolPose& pose_b,
            const MachineAxes& axes_b, const PlannedMove& planned, long index, int depth,
            bool last_piece) {
    const double tol = options_.chord_tol_mm, body_tol = options_.body_tol_mm;
    const ToolDeviation dev = tool_deviation(kin_, options_.controller(), axes_a, axes_b, pose_a.tip, pose_b.tip,
                                             pose_a, pose_b, reach_, 0.25 * tol, 0.25 * body_tol);
    if (dev.cutter_bound_mm <= tol && dev.body_bound_mm <= body_tol) {
      program_.max_deviation_mm = std::max(program_.max_deviation_mm, dev.cutter_bound_mm);
      program_.max_body_deviation_mm = std::max(program_.max_body_deviation_mm, dev.body_bound_mm);
      emit(pose_b, axes_a, axes_b, planned, index, !last_piece);
      return;
    }
    if (depth >= options_.max_depth) {
      std::ostringstream msg;
      msg.precision(4);
      msg << describe(index, planned) << ": as the controller moves (" << to_string(options_.controller())
          << ") the cutter departs " << dev.cutter_bound_mm << " mm and the tool " << dev.body_bound_mm
          << " mm from the planned motion (tool axis " << rad_to_deg(dev.axis_rad)
          << " deg off), and splitting does not bring it within " << tol << " / " << body_tol
          << " mm (a branch change forced by travel, or a move through the singularity of the primary "
             "rotary axis?)";
      throw Error(msg.str());
    }
    // A departure shrinks with the square of the piece's length.
    const double ratio = std::max(dev.cutter_bound_mm / tol, dev.body_bound_mm / body_tol);
    const int pieces = std::clamp(static_cast<int>(std::ceil(1.2 * std::sqrt(ratio))), 2, 256);
    ToolPose from = pose_a;
    MachineAxes from_axes = axes_a;
    for (int i = 1; i <= pieces; ++i) {
      const ToolPose to = i == pieces ? pose_b : interpolate_pose(pose_a, pose_b, double(i) / pieces);
      // Every piece is solved from the one before, the end of the move too, so
      // the rotaries stay continuous along the pieces.
      const MachineAxes to_axes = inverse(to, from_axes, planned, index);
      feed(from, from_axes, to, to_axes, planned, index, depth + 1, last_piece && i == pieces);
      from = to;
      // The next piece starts where this one's blocks ended: splitting it
      // re-solves its own pieces, and near the pole the last of them may
      // land on the other branch of the same tool axis (B -> -B, C + 180).
      // Starting from to_axes would then put a 180 deg turn of C between
      // two blocks that no check saw.
      from_axes = program_.moves.back().axes;
    }
  }

  void emit(const ToolPose& pose, const MachineAxes& from, const MachineAxes& to,
            const PlannedMove& planned, long index, bool inserted) {
    MachineMove m;
    m.kind = planned.kind;
    m.axes = to;
    m.pose = pose;
    m.source = index;
    m.row = planned.row;
    m.inserted = inserted;
    m.rotary_reset = pending_reset_;
    pending_reset_ = {0, 0};
    if (planned.kind == MoveKind::Feed) {
      const BlockFeed f = block_feed(kin_, program_.feed_mode, options_.tcp, planned.feed_mm_per_min,
                                     (pose.tip - last_tip_).norm(), from, to, reach_, options_.cutter_feed_factor,
                                     !positioning_);
      m.feed = f.word;
      program_.minutes += f.minutes;
      program_.tip_feed_minutes += f.tip_minutes;
      if (!positioning_) {
        m.cutter_speed_ratio = f.cutter_ratio;
        program_.max_cutter_speed_ratio = std::max(program_.max_cutter_speed_ratio, f.cutter_ratio);
      }
      program_.slowed_moves += f.slowed;
      program_.untimed_moves += f.untimed;
      for (int i = 0; i < 2; ++i)
        program_.max_rotary_speed_rad_per_min[i] =
            std::max(program_.max_rotary_speed_rad_per_min[i], f.rotary_rad_per_min[i]);
    }
    last_tip_ = pose.tip;
    program_.inserted_moves += inserted;
    program_.moves.push_back(m);
  }

  MachineAxes inverse(const ToolPose& pose, const MachineAxes& previous, const PlannedMove& planned,
                      long index) {
    try {
      return kin_.inverse(pose, previous);
    } catch (const ParameterError& e) {
      const std::string what = e.what();
      throw ParameterError(e.name(), describe(index, planned) + ": " +
                                         what.substr(std::min(what.size(), e.name().size() + 2)));
    }
  }

  void set_last_tip(const Vec3& tip) { last_tip_ = tip; }
  void set_positioning(bool on) { positioning_ = on; }
  // The next move emitted carries a reset of the rotary displays.
  void reset_before_next(const std::array<int, 2>& turns) { pending_reset_ = turns; }

 private:
  const Kinematics& kin_;
  const MotionOptions& options_;
  MachineProgram& program_;
  ToolReach reach_;
  Vec3 last_tip_ = Vec3::Zero();
  bool positioning_ = false;
  std::array<int, 2> pending_reset_{0, 0};
};

// A rapid move (or the first) is where the rotary branch may change freely.
// Continuity alone would pick the solution nearest the previous row's end,
// which can run into travel mid-row and force a branch change inside a feed
// move. So each solution within travel is followed along the feed moves that
// come next, and the one that carries furthest before travel forces a branch
// change (the solution continuity reaches is not the nearest one) wins; among
// equals, the least rotary motion. Not a fixed jump in the angles: where the
// tool axis passes close to the primary axis (an impeller's outlet, the axis
// along the part's) the secondary axis turns fast on the same branch.
MachineAxes choose_branch(const Kinematics& kin, const std::vector<PlannedMove>& path, size_t i,
                          const MachineAxes& previous, MotionPlanner& planner, const MotionOptions& options) {
  const MachineAxes nearest = planner.inverse(path[i].pose, previous, path[i], static_cast<long>(i));
  const std::vector<RotarySolution> solutions = kin.rotary_solutions(path[i].pose.axis, previous.rotary_rad);
  if (solutions.size() < 2) return nearest;
  auto motion = [](const std::array<double, 2>& a, const std::array<double, 2>& b) {
    return std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]);
  };
  auto reach = [&](MachineAxes q) {
    size_t j = i + 1, end = std::min(path.size(), i + 1 + options.branch_lookahead);
    for (; j < end && path[j].kind == MoveKind::Feed; ++j) {
      MachineAxes next;
      try {
        next = kin.inverse(path[j].pose, q);
      } catch (const ParameterError&) {
        break;
      }
      double nearest = std::numeric_limits<double>::infinity();
      for (const RotarySolution& s : kin.rotary_solutions(path[j].pose.axis, q.rotary_rad))
        nearest = std::min(nearest, motion(s.rotary_rad, q.rotary_rad));
      if (motion(next.rotary_rad, q.rotary_rad) > nearest + 1e-9) break;  // travel forced the other branch
      q = next;
    }
    return j;
  };
  MachineAxes best = nearest;
  size_t best_reach = reach(nearest);
  for (const RotarySolution& s : solutions) {
    if (!s.within_limits) continue;
    MachineAxes q;
    q.rotary_rad = s.rotary_rad;
    try {
      q = kin.inverse(path[i].pose, q);  // the same branch, with its linear axes checked
    } catch (const ParameterError&) {
      continue;
    }
    const size_t r = reach(q);
    if (r > best_reach) {
      best = q;
      best_reach = r;
    }
  }
  return best;
}

}  // namespace

const char* to_string(ControllerMotion motion) {
  switch (motion) {
    case ControllerMotion::JointLinear: return "joint-linear";
    case ControllerMotion::TcpRotaryLinear: return "TCP, rotaries linear";
    case ControllerMotion::TcpVector: return "TCP, vector orientation";
  }
  return "?";
}

const char* to_string(SafeMove move) {
  switch (move) {
    case SafeMove::None: return "";
    case SafeMove::Retract: return "retract";
    case SafeMove::Rotate: return "rotate";
    case SafeMove::Position: return "position";
    case SafeMove::Descend: return "descend";
    case SafeMove::Lift: return "lift";
  }
  return "?";
}

ToolPose interpolate_pose(const ToolPose& a, const ToolPose& b, double t) {
  ToolPose p;
  p.tip = a.tip + t * (b.tip - a.tip);
  const Vec3 ka = a.axis.normalized(), kb = b.axis.normalized();
  const Vec3 n = ka.cross(kb);
  const double angle = std::atan2(n.norm(), ka.dot(kb));
  if (n.norm() < 1e-12) {
    if (ka.dot(kb) < 0) throw ParameterError("axis", "opposite tool axes: no unique motion between them");
    p.axis = ka;
    return p;
  }
  p.axis = Eigen::AngleAxisd(t * angle, n.normalized()) * ka;
  return p;
}

ToolPose controller_pose(const Kinematics& kin, ControllerMotion motion, const MachineAxes& from,
                         const MachineAxes& to, const Vec3& tip_from, const Vec3& tip_to, double t) {
  if (motion == ControllerMotion::JointLinear) return kin.forward(lerp(from, to, t));
  ToolPose p;
  p.tip = tip_from + t * (tip_to - tip_from);
  if (motion == ControllerMotion::TcpRotaryLinear) {
    p.axis = kin.tool_axis(lerp(from, to, t).rotary_rad);
  } else {
    p.axis = interpolate_pose({tip_from, kin.tool_axis(from.rotary_rad)}, {tip_to, kin.tool_axis(to.rotary_rad)}, t)
                 .axis;
  }
  return p;
}

MachineAxes controller_axes(const Kinematics& kin, ControllerMotion motion, const MachineAxes& from,
                            const MachineAxes& to, const Vec3& tip_from, const Vec3& tip_to, double t) {
  MachineAxes q = lerp(from, to, t);
  if (motion == ControllerMotion::JointLinear) return q;
  if (motion == ControllerMotion::TcpVector) {
    const ToolPose p = controller_pose(kin, motion, from, to, tip_from, tip_to, t);
    // Each solution measured from the linear rotaries, not from the last
    // one taken.
    const std::array<double, 2> linear = q.rotary_rad;
    double best = std::numeric_limits<double>::infinity();
    for (const RotarySolution& s : kin.rotary_solutions(p.axis, linear)) {
      const double d = std::abs(s.rotary_rad[0] - linear[0]) + std::abs(s.rotary_rad[1] - linear[1]);
      if (d < best) {
        best = d;
        q.rotary_rad = s.rotary_rad;
      }
    }
  }
  q.linear_mm = kin.linear_for(tip_from + t * (tip_to - tip_from), q.rotary_rad);
  return q;
}

// Between two samples h apart (in t) a function f with |f''| <= A strays at
// most A h^2 / 8 above the chord through the samples. For the whole tool
// the deviation is |tip_c - tip_p| + reach |k_c - k_p| with
//   |tip_c''| <= 2 W^2 rho + 2 W v   (joint-linear: rotations at rates summing
//                                     to W about pivots within rho, linear
//                                     axes at speed v; 0 under TCP)
//   |k_c''|   <= W^2                 (the axis turned by the rotaries)
//   |k_p''|   <= Theta^2 (t'')^2 ... (the great circle of angle Theta, at the
//                                     place t' the tip projects to: under TCP
//                                     t' = t; joint-linear, t' moves at most
//                                     |tip'| / len and accelerates at most
//                                     |tip''| / len).
ToolDeviation tool_deviation(const Kinematics& kin, ControllerMotion motion, const MachineAxes& from,
                             const MachineAxes& to, const Vec3& tip_from, const Vec3& tip_to,
                             const ToolPose& plan_from, const ToolPose& plan_to, const ToolReach& reach,
                             double margin_mm, double body_margin_mm) {
  const bool joint = motion == ControllerMotion::JointLinear;
  const double w = std::abs(to.rotary_rad[0] - from.rotary_rad[0]) + std::abs(to.rotary_rad[1] - from.rotary_rad[1]);
  const Vec3 seg = plan_to.tip - plan_from.tip;
  const double len = seg.norm();
  const Vec3 ka = plan_from.axis.normalized(), kb = plan_to.axis.normalized();
  const double theta = std::atan2(ka.cross(kb).norm(), ka.dot(kb));
  // Along the planned motion: joint-linear, at the tip's projection where
  // the segment is long enough to place it (beside the micrometres a rounded
  // rotary word moves the tip through the lever arm), else at the same t
  // (any planned pose bounds the distance; on a short block the tip lags
  // along it by less than the block's length).
  const bool by_place = joint && len > 0.05;
  const double v = joint ? (to.linear_mm - from.linear_mm).norm() : (tip_to - tip_from).norm();
  // The block's ends as the controller reaches them, off the planned ends by
  // what the program's rounded words put there (zero for the planner's own
  // axes). The tip is placed after taking that offset off, shared linearly
  // along the block: a block end rounded back along the segment by 1 um is
  // still the planned end, not a pose 1 um / len of the planned turn earlier
  // (0.078 mm blocks turning 0.36 deg put a 90 mm cutter's axis 9 um off at
  // its own end, a posted point-milling row refused for the rounding).
  Vec3 end_from = Vec3::Zero(), end_to = Vec3::Zero();
  if (by_place) {
    end_from = controller_pose(kin, motion, from, to, tip_from, tip_to, 0).tip - plan_from.tip;
    end_to = controller_pose(kin, motion, from, to, tip_from, tip_to, 1).tip - plan_to.tip;
  }
  auto sample = [&](double t, double& tip_d, double& axis_d) {
    const ToolPose c = controller_pose(kin, motion, from, to, tip_from, tip_to, t);
    double tp = t;
    if (by_place)
      tp = std::clamp((c.tip - end_from - t * (end_to - end_from) - plan_from.tip).dot(seg) / (len * len), 0.0, 1.0);
    const ToolPose p = interpolate_pose(plan_from, plan_to, tp);
    tip_d = (c.tip - p.tip).norm();
    axis_d = (c.axis.normalized() - p.axis).norm();
  };
  ToolDeviation dev;
  const double margin = std::max(margin_mm, 1e-9);
  const double body_margin = body_margin_mm > 0 ? body_margin_mm : margin;
  double rho = 0;
  if (joint && w > 0) rho = std::max(kin.pivot_reach_mm(from), kin.pivot_reach_mm(to)) + v;
  // Second-derivative bounds (above), refined with the sampled reach.
  auto coefficients = [&](double rho_now, double& tip_a, double& axis_a) {
    tip_a = joint ? 2 * w * w * rho_now + 2 * w * v : 0.0;
    double planned = theta * theta;
    if (by_place) {
      // The place moves with the tip, less the ends' offset (linear in t).
      const double speed = (v + w * rho_now + (end_to - end_from).norm()) / len;
      planned = theta * theta * speed * speed + theta * tip_a / len;
    }
    axis_a = (motion == ControllerMotion::TcpVector ? theta * theta : w * w) + planned;
  };
  double tip_a = 0, axis_a = 0;
  coefficients(rho, tip_a, axis_a);
  auto needed = [&](double m, double r) { return std::sqrt((tip_a + r * axis_a) / (8 * m)); };
  int n = std::clamp(static_cast<int>(std::ceil(std::max(needed(margin, reach.cutter_mm),
                                                         needed(body_margin, reach.body_mm)))) + 1,
                     2, kMaxSamples);
  if (w == 0 && theta == 0 && !joint) n = 1;  // TCP, fixed orientation: both ends say everything
  for (;;) {
    double cutter = 0, body = 0, axis = 0, worst_t = 0, reach_seen = 0;
    for (int i = 0; i <= n; ++i) {
      const double t = double(i) / n;
      double tip_d = 0, axis_d = 0;
      sample(t, tip_d, axis_d);
      const double c = tip_d + reach.cutter_mm * axis_d;
      if (c > cutter) {
        cutter = c;
        worst_t = t;
      }
      body = std::max(body, tip_d + reach.body_mm * axis_d);
      axis = std::max(axis, axis_d);
      if (joint && w > 0) reach_seen = std::max(reach_seen, kin.pivot_reach_mm(lerp(from, to, t)));
    }
    const double h = 1.0 / n;
    if (joint && w > 0) {
      // Between samples the reach grows at most by the tip speed times h/2.
      coefficients(reach_seen + 0.5 * h * (v + w * reach_seen), tip_a, axis_a);
    }
    const double between_cutter = (tip_a + reach.cutter_mm * axis_a) * h * h / 8;
    const double between_body = (tip_a + reach.body_mm * axis_a) * h * h / 8;
    dev.cutter_mm = cutter;
    dev.body_mm = body;
    dev.cutter_bound_mm = cutter + between_cutter;
    dev.body_bound_mm = body + between_body;
    dev.axis_rad = 2 * std::asin(std::min(1.0, 0.5 * axis));
    dev.worst_t = worst_t;
    dev.samples = n;
    const double over = std::max(between_cutter / margin, between_body / body_margin);
    if (over <= 1 || n >= kMaxSamples) return dev;
    n = std::min(kMaxSamples, static_cast<int>(std::ceil(n * std::sqrt(over) * 1.05)));
  }
}

MoveDeviation move_deviation(const Kinematics& kin, const MachineAxes& from, const MachineAxes& to,
                             const Vec3& tip_from, const Vec3& tip_to, double margin_mm) {
  const double v = (to.linear_mm - from.linear_mm).norm();
  const double w = std::abs(to.rotary_rad[0] - from.rotary_rad[0]) +
                   std::abs(to.rotary_rad[1] - from.rotary_rad[1]);
  MoveDeviation dev;
  if (w == 0) {
    // Fixed rotaries: the tip moves on a straight line in the part frame.
    dev.samples = 1;
    for (const MachineAxes* q : {&from, &to}) {
      const double d = distance_to_segment(kin.forward(*q).tip, tip_from, tip_to);
      dev.sampled_mm = std::max(dev.sampled_mm, d);
    }
    dev.bound_mm = dev.sampled_mm;
    return dev;
  }
  // First guess of the samples from the endpoints' reach; refined below.
  const double reach0 = std::max(kin.pivot_reach_mm(from), kin.pivot_reach_mm(to)) + v;
  const double margin = std::max(margin_mm, 1e-9);
  int n = std::clamp(static_cast<int>(std::ceil(w * std::sqrt((w * w * reach0 + w * v) / (4 * margin)))) + 2, 4, kMaxSamples);
  for (;;) {
    double sampled = 0, reach = 0;
    for (int i = 0; i <= n; ++i) {
      const MachineAxes q = lerp(from, to, double(i) / n);
      sampled = std::max(sampled, distance_to_segment(kin.forward(q).tip, tip_from, tip_to));
      reach = std::max(reach, kin.pivot_reach_mm(q));
    }
    const double h = 1.0 / n;
    // Between samples the reach grows at most by the tip speed times h/2.
    reach += 0.5 * h * (v + w * reach);
    const double accel = 2 * w * w * reach + 2 * w * v;
    const double between = accel * h * h / 8;
    dev.sampled_mm = sampled;
    dev.bound_mm = sampled + between;
    dev.samples = n;
    if (between <= margin || n >= kMaxSamples) return dev;
    n = std::min(kMaxSamples, static_cast<int>(std::ceil(n * std::sqrt(between / margin) * 1.05)));
  }
}

MachineProgram plan_machine_motion(const Kinematics& kin, const std::vector<PlannedMove>& path,
                                   const MotionOptions& options, Progress& progress, const ToolReach& reach) {
  if (!(options.chord_tol_mm > 0)) throw ParameterError("chord_tol", "expected a tolerance > 0 mm");
  if (!(options.body_tol_mm > 0)) throw ParameterError("body_tol", "expected a tolerance > 0 mm");
  MachineProgram program;
  // Under TCP control F is the tip's speed, which is what the plan gives.
  program.feed_mode = options.tcp ? FeedMode::PerMinute : kin.machine().feed;
  program.tcp = options.tcp;
  program.controller = options.controller();
  MotionPlanner planner(kin, options, program, reach);
  progress.begin("machine motion", static_cast<long>(path.size()));
  MachineAxes axes = options.start;
  ToolPose pose = kin.forward(axes);
  planner.set_last_tip(pose.tip);
  for (size_t i = 0; i < path.size(); ++i) {
    const PlannedMove& m = path[i];
    const long index = static_cast<long>(i);
    if (m.kind == MoveKind::Feed && !(m.feed_mm_per_min > 0))
      throw ParameterError("feed", describe(index, m) + ": expected a feed > 0 mm/min");
    if (i > 0 && m.kind == MoveKind::Rapid && options.rotary_reset) {
      // A link: where a continuous axis has wound past a turn, its display
      // is reset before the link (no motion; the controller's M94).
      std::array<int, 2> turns{0, 0};
      for (int r = 0; r < 2; ++r) {
        if (!kin.machine().rotary[r].continuous() || std::abs(axes.rotary_rad[r]) <= 2 * kPi) continue;
        // The controller reduces the value it was given (rounded): within a
        // hair of a whole turn it may count one turn more or less than we
        // would, so the reset waits for the next link.
        const double turn_part = axes.rotary_rad[r] / (2 * kPi) - std::floor(axes.rotary_rad[r] / (2 * kPi));
        if (turn_part < 1e-4 || turn_part > 1 - 1e-4) continue;
        turns[r] = static_cast<int>(std::floor(axes.rotary_rad[r] / (2 * kPi)));
        axes.rotary_rad[r] -= 2 * kPi * turns[r];
      }
      if (turns[0] != 0 || turns[1] != 0) {
        planner.reset_before_next(turns);
        ++program.rotary_resets;
      }
    }
    const MachineAxes next = (m.kind == MoveKind::Rapid || i == 0)
                                 ? choose_branch(kin, path, i, axes, planner, options)
                                 : planner.inverse(m.pose, axes, m, index);
    if (same_axes(next, axes) && i > 0) {
      ++program.skipped_moves;
    } else if (i > 0 && m.kind == MoveKind::Rapid && !rapid_follows_segment(kin.machine(), axes, next)) {
      // The branch continuity reaches is the one a motion along the segment
      // ends on; choose_branch may have preferred another for travel.
      const MachineAxes continued = planner.inverse(m.pose, axes, m, index);
      if (!same_rotaries(continued, next))
        throw Error(describe(index, m) + ": this rapid changes the rotary branch (" +
                    rotary_words(kin.machine(), axes) + " to " + rotary_words(kin.machine(), next) +
                    " where following the motion ends at " + rotary_words(kin.machine(), continued) +
                    "), which no motion along the planned segment does; retract the tool to where "
                    "any motion is safe before it, or plan the link so the branch is kept");
      PlannedMove positioning = m;
      positioning.kind = MoveKind::Feed;
      positioning.feed_mm_per_min = kin.machine().rapid.feed_mm_per_min;
      const size_t first = program.moves.size();
      planner.set_positioning(true);
      try {
        planner.feed(pose, axes, m.pose, next, positioning, index, 0, true);
      } catch (const Error& e) {
        throw Error(std::string("a rapid posted as a positioning move cannot follow the planned segment: ") +
                    e.what() + "; retract the tool to where any motion is safe before it");
      }
      planner.set_positioning(false);
      for (size_t k = first; k < program.moves.size(); ++k) program.moves[k].positioning = true;
      ++program.positioning_moves;
      axes = program.moves.back().axes;
      pose = m.pose;
      if ((i & 255) == 0) progress.step(index + 1);
      continue;
    } else if (m.kind == MoveKind::Rapid || i == 0) {
      // The first move starts from wherever the machine is, not from a
      // planned pose: there is no segment to stay on.
      planner.emit(m.pose, axes, next, m, index, false);
    } else {
      planner.feed(pose, axes, m.pose, next, m, index, 0, true);
      // Splitting re-solves the pieces from the start; continue from where
      // the last piece ended.
      axes = program.moves.back().axes;
      pose = m.pose;
      if ((i & 255) == 0) progress.step(index + 1);
      continue;
    }
    axes = next;
    pose = m.pose;
    if ((i & 255) == 0) progress.step(index + 1);
  }
  progress.end();
  // What the controller takes: a continuous axis beyond its input range.
  for (const MachineMove& mm : program.moves) {
    for (int r = 0; r < 2; ++r) {
      if (std::abs(mm.axes.rotary_rad[r]) <= options.rotary_input_limit_rad) continue;
      std::ostringstream msg;
      msg.precision(10);
      msg << describe(mm.source, path[static_cast<size_t>(mm.source)]) << ": " << kin.machine().rotary[r].name
          << " = " << rad_to_deg(mm.axes.rotary_rad[r]) << " deg, beyond the controller's input range of +-"
          << rad_to_deg(options.rotary_input_limit_rad) << " deg"
          << (options.rotary_reset ? "" : " (this post cannot reset the axis' display between links)");
      throw ParameterError(kin.machine().rotary[r].name, msg.str());
    }
  }
  return program;
}

namespace {


// The part-frame direction the tip moves for +1 mm of the machine's Z with
// the rotaries of `q`: the tool axis on a table-table machine (the spindle
// along Z), the part's own Z on a head-table machine with a C table.
Vec3 z_direction_in_part(const Kinematics& kin, const MachineAxes& q) {
  MachineAxes up = q;
  up.linear_mm.z() += 1.0;
  return kin.forward(up).tip - kin.forward(q).tip;
}

// How far up the machine's Z from `at` to the safe height, checked against
// what the plan proved: the line from `at` in the direction the Z slide
// moves the tip, which must be the tool axis (approach.proved_mm) or the
// part frame's +Z (approach.proved_up_mm).
double up_to_safe(const Kinematics& kin, const MachineMove& at, double safe_z, const ApproachOptions& approach,
                  const std::string& what) {
  std::ostringstream msg;
  msg.precision(6);
  const double s = safe_z - at.axes.linear_mm.z();
  if (s < 0) {
    msg << what << ": the pose lies above the safe height (Z " << at.axes.linear_mm.z() << " > " << safe_z << ")";
    throw Error(msg.str());
  }
  const Vec3 d = z_direction_in_part(kin, at.axes);
  double proved = -1;
  const char* along = "";
  if ((d - at.pose.axis.normalized()).norm() < 1e-6) {
    proved = approach.proved_mm;
    along = "the tool axis";
  } else if ((d - Vec3::UnitZ()).norm() < 1e-6) {
    proved = approach.proved_up_mm;
    along = "the part frame's +Z";
  }
  if (proved < 0) {
    msg << what << ": the machine's Z moves the tip along (" << d.x() << ", " << d.y() << ", " << d.z()
        << ") in the part frame here, neither the tool axis nor the part's +Z: no proved way to the safe height";
    throw Error(msg.str());
  }
  if (s > proved + 1e-9) {
    msg << what << ": the way up " << along << " to the safe height (Z " << safe_z << ") is " << s
        << " mm long; the plan proved " << proved << " mm of it clear";
    throw Error(msg.str());
  }
  return s;
}

MachineMove safe_move(const Kinematics& kin, SafeMove kind, const MachineAxes& q, long source, int tool) {
  MachineMove m;
  m.kind = MoveKind::Rapid;
  m.axes = q;
  m.pose = kin.forward(q);
  m.source = source;
  m.tool = tool;
  m.safe = kind;
  return m;
}

// A straight move with fixed rotaries (the descent, the lift): a rapid where
// the controller keeps it on the line by itself (one linear axis moves, or
// rapids are interpolated linearly), else a positioning feed move.
void along_axis_kind(const Kinematics& kin, MachineMove& m, const MachineAxes& from, FeedMode mode) {
  int moving = 0;
  for (int i = 0; i < 3; ++i) moving += std::abs(m.axes.linear_mm[i] - from.linear_mm[i]) > 1e-9;
  const RapidMotion& rapid = kin.machine().rapid;
  if (moving <= 1 || rapid.linear) {
    m.kind = MoveKind::Rapid;
    m.feed = 0;
    return;
  }
  m.kind = MoveKind::Feed;
  m.positioning = true;
  const double length = (m.axes.linear_mm - from.linear_mm).norm();
  m.feed = mode == FeedMode::InverseTime ? rapid.feed_mm_per_min / length : rapid.feed_mm_per_min;
}

// The point at the safe height straight up the machine's Z from `at`
// (the rotaries of `at`; within travel): its axes and pose.
MachineMove up_the_z(const Kinematics& kin, const MachineMove& at, const ApproachOptions& approach,
                     const std::string& what) {
  const double safe_z = std::isfinite(approach.safe_z_mm) ? approach.safe_z_mm : kin.safe_z_mm();
  const double s = up_to_safe(kin, at, safe_z, approach, what);
  MachineMove up = at;
  up.axes.linear_mm.z() = safe_z;
  up.pose = kin.forward(up.axes);
  up.pose.axis = at.pose.axis;
  up.inserted = false;
  up.rotary_reset = {0, 0};
  up.cutter_speed_ratio = 0;
  try {
    // Within travel: the same rotaries reach the point.
    const MachineAxes check = kin.inverse(up.pose, at.axes);
    if (std::abs(check.rotary_rad[0] - at.axes.rotary_rad[0]) > 1e-9 ||
        std::abs(check.rotary_rad[1] - at.axes.rotary_rad[1]) > 1e-9)
      throw ParameterError("approach", "it needs other rotary positions");
  } catch (const ParameterError& e) {
    throw Error(what + ": the point at the safe height, " + std::to_string(s) + " mm up the Z, is out of travel: " +
                e.what());
  }
  return up;
}

// The safe way in to a tool's first move `first` (MachineMove of the
// segment, already solved) from `before` (the axes the tool change left):
// the moves to put before it — Retract, Rotate, Position (SafeMove); `first`
// itself becomes the Descend.
std::vector<MachineMove> safe_way_in(const Kinematics& kin, const MachineMove& first, const MachineAxes& before,
                    const ApproachOptions& approach, const std::string& what) {
  const MachineMove entry = up_the_z(kin, first, approach, what);
  MachineAxes up = before;
  up.linear_mm.z() = entry.axes.linear_mm.z();
  MachineAxes turned = up;
  turned.rotary_rad = first.axes.rotary_rad;
  std::vector<MachineMove> way;
  way.push_back(safe_move(kin, SafeMove::Retract, up, first.source, first.tool));
  way.push_back(safe_move(kin, SafeMove::Rotate, turned, first.source, first.tool));
  MachineMove position = safe_move(kin, SafeMove::Position, entry.axes, first.source, first.tool);
  position.pose = entry.pose;  // the entry point on the first pose's axis line
  way.push_back(position);
  return way;
}

}  // namespace

MachineProgram plan_machine_motion_tools(const std::vector<MotionTool>& tools, const std::vector<PlannedMove>& path,
                                         const std::vector<int>& tool_of, const MotionOptions& options,
                                         Progress& progress) {
  if (tool_of.size() != path.size()) throw ParameterError("tools", "need one tool index per move");
  if (tools.empty()) throw ParameterError("tools", "need at least one tool");
  for (const MotionTool& t : tools)
    if (t.kin == nullptr) throw ParameterError("tools", "a tool without kinematics");
  MachineProgram program;
  bool first = true;
  MachineAxes left = options.start;  // where the last tool left the machine
  for (size_t begin = 0; begin < path.size();) {
    const int tool = tool_of[begin];
    if (tool < 0 || tool >= static_cast<int>(tools.size()))
      throw ParameterError("tools", "move " + std::to_string(begin + 1) + ": no tool " + std::to_string(tool + 1));
    const Kinematics& kin = *tools[static_cast<size_t>(tool)].kin;
    size_t end = begin;
    while (end < path.size() && tool_of[end] == tool) ++end;
    const std::vector<PlannedMove> segment(path.begin() + static_cast<long>(begin), path.begin() + static_cast<long>(end));
    MotionOptions o = options;
    o.start = left;
    MachineProgram part;
    const std::string prefix = begin == 0 && end == path.size()
                                   ? std::string()
                                   : "tool " + std::to_string(tool + 1) + ", whose moves start at move " +
                                         std::to_string(begin + 1) + " (move numbers below count from there): ";
    try {
      part = plan_machine_motion(kin, segment, o, progress, tools[static_cast<size_t>(tool)].reach);
      if (options.approach.enabled && !part.moves.empty()) {
        // In from the tool change position: Retract, Rotate, Position, then
        // the segment's first move becomes the Descend along its axis.
        MachineMove& descend = part.moves.front();
        const std::vector<MachineMove> in = safe_way_in(kin, descend, left, options.approach,
                                       "the way in to move 1 (the first of this tool)");
        descend.safe = SafeMove::Descend;
        along_axis_kind(kin, descend, in.back().axes, part.feed_mode);
        part.moves.insert(part.moves.begin(), in.begin(), in.end());
        // ... and out: up the last pose's axis to the safe height.
        const MachineMove& last = part.moves.back();
        MachineMove lift = up_the_z(kin, last, options.approach, "the way out from this tool's last move");
        lift.safe = SafeMove::Lift;
        along_axis_kind(kin, lift, last.axes, part.feed_mode);
        part.moves.push_back(lift);
      }
    } catch (const Error& e) {
      if (prefix.empty()) throw;
      throw Error(prefix + e.what());
    }
    if (first) {
      program.feed_mode = part.feed_mode;
      program.tcp = part.tcp;
      program.controller = part.controller;
    }
    for (MachineMove m : part.moves) {
      m.tool = tool;
      m.source += static_cast<long>(begin);
      program.moves.push_back(m);
    }
    if (!program.moves.empty()) left = program.moves.back().axes;
    program.max_deviation_mm = std::max(program.max_deviation_mm, part.max_deviation_mm);
    program.max_body_deviation_mm = std::max(program.max_body_deviation_mm, part.max_body_deviation_mm);
    program.inserted_moves += part.inserted_moves;
    program.skipped_moves += part.skipped_moves;
    program.positioning_moves += part.positioning_moves;
    program.slowed_moves += part.slowed_moves;
    program.untimed_moves += part.untimed_moves;
    program.minutes += part.minutes;
    program.tip_feed_minutes += part.tip_feed_minutes;
    program.rotary_resets += part.rotary_resets;
    program.max_cutter_speed_ratio = std::max(program.max_cutter_speed_ratio, part.max_cutter_speed_ratio);
    for (int r = 0; r < 2; ++r)
      program.max_rotary_speed_rad_per_min[r] =
          std::max(program.max_rotary_speed_rad_per_min[r], part.max_rotary_speed_rad_per_min[r]);
    first = false;
    begin = end;
  }
  return program;
}

}  // namespace bliskrun
