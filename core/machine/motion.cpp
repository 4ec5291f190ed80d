#include "core/machine/motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/common/error.h"

namespace bliskrun {

namespace {

constexpr int kMaxSamples = 4096;

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

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

// Feed word for a move of the tip over `tip_mm` (machine axes from a to b).
double feed_word(FeedMode mode, double feed_mm_per_min, double tip_mm, const MachineAxes& a,
                 const MachineAxes& b) {
  if (mode == FeedMode::PerMinute) return feed_mm_per_min;
  // Inverse time: 1 / duration in minutes. A move that only turns the tool
  // has no tip length; it is timed as the controller times per-minute feed,
  // over the combined axis distance (mm and degrees).
  double length = tip_mm;
  if (length < 1e-6) {
    double d2 = (b.linear_mm - a.linear_mm).squaredNorm();
    for (int i = 0; i < 2; ++i) d2 += std::pow(rad_to_deg(b.rotary_rad[i] - a.rotary_rad[i]), 2);
    length = std::sqrt(d2);
  }
  return feed_mm_per_min / length;
}

class Planner {
 public:
  Planner(const Kinematics& kin, const MotionOptions& options, MachineProgram& program)
      : kin_(kin), options_(options), program_(program) {}

  // Appends the feed move from (pose_a, axes_a) to (pose_b, axes_b), split
  // until each piece stays within the chord tolerance.
  void feed(const ToolPose& pose_a, const MachineAxes& axes_a, const ToolPose& pose_b,
            const MachineAxes& axes_b, const PlannedMove& planned, long index, int depth,
            bool last_piece) {
    if (options_.tcp) {
      emit(pose_b, axes_a, axes_b, planned, index, !last_piece);
      return;
    }
    const double tol = options_.chord_tol_mm;
    const MoveDeviation dev =
        move_deviation(kin_, axes_a, axes_b, pose_a.tip, pose_b.tip, 0.25 * tol);
    if (dev.bound_mm <= tol) {
      program_.max_deviation_mm = std::max(program_.max_deviation_mm, dev.bound_mm);
      emit(pose_b, axes_a, axes_b, planned, index, !last_piece);
      return;
    }
    if (depth >= options_.max_depth)
      throw Error(describe(index, planned) + ": the tip departs " + std::to_string(dev.bound_mm) +
                  " mm from the planned segment and splitting does not bring it within " +
                  std::to_string(tol) + " mm (a branch change forced by travel, or a move "
                  "close to the singularity of the primary rotary axis?)");
    // The departure of a rotary move shrinks with the square of its length.
    const int pieces = std::clamp(static_cast<int>(std::ceil(1.2 * std::sqrt(dev.bound_mm / tol))), 2, 256);
    ToolPose from = pose_a;
    MachineAxes from_axes = axes_a;
    for (int i = 1; i <= pieces; ++i) {
      const ToolPose to = i == pieces ? pose_b : interpolate_pose(pose_a, pose_b, double(i) / pieces);
      // Every piece is solved from the one before, the end of the move too, so
      // the rotaries stay continuous along the pieces.
      const MachineAxes to_axes = inverse(to, from_axes, planned, index);
      feed(from, from_axes, to, to_axes, planned, index, depth + 1, last_piece && i == pieces);
      from = to;
      from_axes = to_axes;
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
    if (planned.kind == MoveKind::Feed)
      m.feed = feed_word(program_.feed_mode, planned.feed_mm_per_min,
                         (pose.tip - last_tip_).norm(), from, to);
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

 private:
  const Kinematics& kin_;
  const MotionOptions& options_;
  MachineProgram& program_;
  Vec3 last_tip_ = Vec3::Zero();
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
                          const MachineAxes& previous, Planner& planner, const MotionOptions& options) {
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
                                   const MotionOptions& options, Progress& progress) {
  if (!(options.chord_tol_mm > 0)) throw ParameterError("chord_tol", "expected a tolerance > 0 mm");
  MachineProgram program;
  // Under TCP control F is the tip's speed, which is what the plan gives.
  program.feed_mode = options.tcp ? FeedMode::PerMinute : kin.machine().feed;
  program.tcp = options.tcp;
  Planner planner(kin, options, program);
  progress.begin("machine motion", static_cast<long>(path.size()));
  MachineAxes axes = options.start;
  ToolPose pose = kin.forward(axes);
  planner.set_last_tip(pose.tip);
  for (size_t i = 0; i < path.size(); ++i) {
    const PlannedMove& m = path[i];
    const long index = static_cast<long>(i);
    if (m.kind == MoveKind::Feed && !(m.feed_mm_per_min > 0))
      throw ParameterError("feed", describe(index, m) + ": expected a feed > 0 mm/min");
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
      try {
        planner.feed(pose, axes, m.pose, next, positioning, index, 0, true);
      } catch (const Error& e) {
        throw Error(std::string("a rapid posted as a positioning move cannot follow the planned segment: ") +
                    e.what() + "; retract the tool to where any motion is safe before it");
      }
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
  return program;
}

MachineProgram plan_machine_motion_tools(const std::vector<const Kinematics*>& kins,
                                         const std::vector<PlannedMove>& path, const std::vector<int>& tool_of,
                                         const MotionOptions& options, Progress& progress) {
  if (tool_of.size() != path.size()) throw ParameterError("tools", "need one tool index per move");
  if (kins.empty()) throw ParameterError("tools", "need at least one tool");
  MachineProgram program;
  bool first = true;
  for (size_t begin = 0; begin < path.size();) {
    const int tool = tool_of[begin];
    if (tool < 0 || tool >= static_cast<int>(kins.size()))
      throw ParameterError("tools", "move " + std::to_string(begin + 1) + ": no tool " + std::to_string(tool + 1));
    size_t end = begin;
    while (end < path.size() && tool_of[end] == tool) ++end;
    const std::vector<PlannedMove> segment(path.begin() + static_cast<long>(begin), path.begin() + static_cast<long>(end));
    MotionOptions o = options;
    if (!first) o.start = program.moves.empty() ? options.start : program.moves.back().axes;
    MachineProgram part;
    if (begin == 0 && end == path.size()) {
      part = plan_machine_motion(*kins[tool], segment, o, progress);  // one tool: messages as they are
    } else {
      try {
        part = plan_machine_motion(*kins[tool], segment, o, progress);
      } catch (const Error& e) {
        throw Error("tool " + std::to_string(tool + 1) + ", whose moves start at move " + std::to_string(begin + 1) +
                    " (move numbers below count from there): " + e.what());
      }
    }
    if (first) {
      program.feed_mode = part.feed_mode;
      program.tcp = part.tcp;
    }
    for (MachineMove m : part.moves) {
      m.tool = tool;
      m.source += static_cast<long>(begin);
      program.moves.push_back(m);
    }
    program.max_deviation_mm = std::max(program.max_deviation_mm, part.max_deviation_mm);
    program.inserted_moves += part.inserted_moves;
    program.skipped_moves += part.skipped_moves;
    program.positioning_moves += part.positioning_moves;
    first = false;
    begin = end;
  }
  return program;
}

}  // namespace bliskrun
