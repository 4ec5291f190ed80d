#include "core/machine/robot_program.h"

#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>

#include "core/common/error.h"

namespace bliskrun {

namespace {

[[noreturn]] void fail(int line, const std::string& what) {
  throw Error("robot program line " + std::to_string(line) + ": " + what);
}

std::string trimmed(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

bool starts_with_word(const std::string& s, const std::string& word) {
  return s.size() > word.size() && s.compare(0, word.size(), word) == 0 &&
         (s[word.size()] == ' ' || s[word.size()] == '\t' || s[word.size()] == '{');
}

// The numbers of a bracketed RAPID aggregate, in order ([[1,2],[3]] -> 1 2 3).
std::vector<double> numbers_in(const std::string& s, int line) {
  std::vector<double> out;
  const char* p = s.c_str();
  while (*p) {
    if (std::isdigit(static_cast<unsigned char>(*p)) || *p == '-' || *p == '+' || *p == '.') {
      char* end = nullptr;
      const double v = std::strtod(p, &end);
      if (end == p) fail(line, "unreadable number near '" + std::string(p).substr(0, 12) + "'");
      if (!std::isfinite(v)) fail(line, "non-finite number");
      out.push_back(v);
      p = end;
    } else {
      ++p;
    }
  }
  return out;
}

// The first balanced [...] in s from `from`, or "".
std::string bracketed(const std::string& s, size_t from) {
  const size_t a = s.find('[', from);
  if (a == std::string::npos) return "";
  int depth = 0;
  for (size_t i = a; i < s.size(); ++i) {
    if (s[i] == '[') ++depth;
    if (s[i] == ']' && --depth == 0) return s.substr(a, i - a + 1);
  }
  return "";
}

RobotTarget rapid_target(const std::string& aggregate, int line) {
  const std::vector<double> v = numbers_in(aggregate, line);
  if (v.size() != 17) fail(line, "expected a robtarget of 17 numbers, got " + std::to_string(v.size()));
  RobotTarget t;
  t.line = line;
  Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
  if (std::abs(q.norm() - 1) > 1e-4) fail(line, "the orientation quaternion is not of unit length");
  t.station_in_blade.linear() = q.normalized().toRotationMatrix();
  t.station_in_blade.translation() = Vec3(v[0], v[1], v[2]);
  t.quadrants = {static_cast<int>(v[7]), static_cast<int>(v[8]), static_cast<int>(v[9])};
  t.branch = static_cast<int>(v[10]);
  if (t.branch < 0 || t.branch > 7) fail(line, "cfx must be 0..7");
  return t;
}

std::vector<RobotTarget> read_rapid(const std::string& text) {
  std::vector<RobotTarget> out;
  std::map<std::string, RobotTarget> named;
  std::istringstream in(text);
  std::string raw;
  int line = 0;
  while (std::getline(in, raw)) {
    ++line;
    std::string s = trimmed(raw);
    if (s.empty() || s[0] == '!') continue;
    if (s.rfind("CONST robtarget ", 0) == 0 || s.rfind("PERS robtarget ", 0) == 0) {
      const size_t name_at = s.find("robtarget ") + 10, assign = s.find(":=");
      if (assign == std::string::npos) fail(line, "robtarget declaration without ':='");
      named[trimmed(s.substr(name_at, assign - name_at))] = rapid_target(bracketed(s, assign), line);
      continue;
    }
    const bool move_l = starts_with_word(s, "MoveL"), move_j = starts_with_word(s, "MoveJ");
    if (!move_l && !move_j) continue;
    const std::string rest = trimmed(s.substr(5));
    RobotTarget t;
    if (!rest.empty() && rest[0] == '[') {
      t = rapid_target(bracketed(rest, 0), line);
    } else {
      const std::string name = trimmed(rest.substr(0, rest.find(',')));
      const auto it = named.find(name);
      if (it == named.end()) fail(line, "unknown robtarget '" + name + "'");
      t = it->second;
      t.line = line;
    }
    t.linear = move_l;
    out.push_back(t);
  }
  return out;
}

// KRL's S and T: a decimal integer or 'B0101' binary.
int krl_bits(const std::string& s, int line) {
  const std::string v = trimmed(s);
  if (v.size() > 2 && v[0] == '\'' && (v[1] == 'B' || v[1] == 'b')) {
    int bits = 0;
    for (size_t i = 2; i < v.size() && v[i] != '\''; ++i) {
      if (v[i] != '0' && v[i] != '1') fail(line, "bad binary status '" + v + "'");
      bits = bits * 2 + (v[i] - '0');
    }
    return bits;
  }
  char* end = nullptr;
  const long n = std::strtol(v.c_str(), &end, 10);
  if (end == v.c_str()) fail(line, "bad status or turn '" + v + "'");
  return static_cast<int>(n);
}

std::vector<RobotTarget> read_krl(const std::string& text) {
  std::vector<RobotTarget> out;
  std::istringstream in(text);
  std::string raw;
  int line = 0;
  while (std::getline(in, raw)) {
    ++line;
    std::string s = trimmed(raw.substr(0, raw.find(';')));
    const bool lin = starts_with_word(s, "LIN"), ptp = starts_with_word(s, "PTP");
    if (!lin && !ptp) continue;
    const size_t a = s.find('{'), b = s.find('}');
    if (a == std::string::npos || b == std::string::npos || b < a) fail(line, "expected a position {X .., ...}");
    std::string body = s.substr(a + 1, b - a - 1);
    if (const size_t colon = body.find(':'); colon != std::string::npos) body = body.substr(colon + 1);
    std::map<std::string, std::string> fields;
    std::istringstream parts(body);
    std::string part;
    while (std::getline(parts, part, ',')) {
      part = trimmed(part);
      const size_t sp = part.find(' ');
      if (sp == std::string::npos) fail(line, "expected 'NAME value' in '" + part + "'");
      fields[part.substr(0, sp)] = trimmed(part.substr(sp + 1));
    }
    double v[6];
    const char* keys[6] = {"X", "Y", "Z", "A", "B", "C"};
    for (int i = 0; i < 6; ++i) {
      const auto it = fields.find(keys[i]);
      if (it == fields.end()) fail(line, std::string("missing ") + keys[i]);
      char* end = nullptr;
      v[i] = std::strtod(it->second.c_str(), &end);
      if (end == it->second.c_str() || !std::isfinite(v[i])) fail(line, std::string("bad ") + keys[i]);
    }
    if (!fields.count("S") || !fields.count("T")) fail(line, "missing S or T (the configuration is part of the target)");
    RobotTarget t;
    t.line = line;
    t.linear = lin;
    t.station_in_blade.linear() = (Eigen::AngleAxisd(deg_to_rad(v[3]), Vec3::UnitZ()) *
                                   Eigen::AngleAxisd(deg_to_rad(v[4]), Vec3::UnitY()) *
                                   Eigen::AngleAxisd(deg_to_rad(v[5]), Vec3::UnitX()))
                                      .toRotationMatrix();
    t.station_in_blade.translation() = Vec3(v[0], v[1], v[2]);
    const int status = krl_bits(fields["S"], line);
    // S bit 0: wrist centre behind axis 1, bit 1: elbow, bit 2: axis 5 negative.
    t.branch = ((status & 1) << 2) | (status & 2) | ((status >> 2) & 1);
    t.turn_bits = krl_bits(fields["T"], line);
    out.push_back(t);
  }
  return out;
}

// A joint on a quadrant boundary (or at zero, for KUKA's turn bits) reads
// back on either side of it: within 1e-6 rad either side matches.
bool configuration_matches(const RobotTarget& t, const RobotSolution& s, RobotDialect dialect) {
  if (s.branch != t.branch) return false;
  constexpr double kSlack = 1e-6;
  if (dialect == RobotDialect::AbbRapid) {
    const int joint[3] = {0, 3, 5};
    for (int i = 0; i < 3; ++i) {
      JointAngles lo = s.joints, hi = s.joints;
      lo[joint[i]] -= kSlack;
      hi[joint[i]] += kSlack;
      if (abb_quadrants(lo)[i] != t.quadrants[i] && abb_quadrants(hi)[i] != t.quadrants[i]) return false;
    }
    return true;
  }
  const int bits = kuka_turn_bits(s.joints);
  for (int i = 0; i < 6; ++i)
    if (((bits ^ t.turn_bits) >> i & 1) && std::abs(s.joints[i]) > kSlack) return false;
  return true;
}

double rotation_angle_deg(const Mat3& a, const Mat3& b) {
  return rad_to_deg(Eigen::AngleAxisd(a.transpose() * b).angle());
}

}  // namespace

std::vector<RobotTarget> read_robot_program(const std::string& text, RobotDialect dialect) {
  return dialect == RobotDialect::AbbRapid ? read_rapid(text) : read_krl(text);
}

Frame robot_target_frame(const RobotCell& cell, const BeltStation& station, const RobotMove& move) {
  const Frame blade_in_base = robot_forward(cell.arm, move.joints) * cell.grip;
  return blade_in_base.inverse() * station.contact;
}

std::array<int, 3> abb_quadrants(const JointAngles& q) {
  auto quadrant = [](double rad) { return static_cast<int>(std::floor(rad_to_deg(rad) / 90.0 + 1e-9)); };
  return {quadrant(q[0]), quadrant(q[3]), quadrant(q[5])};
}

int kuka_turn_bits(const JointAngles& q) {
  int bits = 0;
  for (int i = 0; i < 6; ++i)
    if (q[i] < 0) bits |= 1 << i;
  return bits;
}

RobotVerifyReport verify_robot_program(const RobotCell& cell, const BeltStation& station,
                                       const RobotGrindingPlan& plan, const std::vector<RobotTarget>& targets,
                                       RobotDialect dialect, double position_tol_mm, double angle_tol_deg) {
  RobotVerifyReport r;
  r.moves = static_cast<int>(targets.size());
  if (targets.size() != plan.moves.size()) {
    r.problems.push_back("the program has " + std::to_string(targets.size()) + " motion targets, the plan " +
                         std::to_string(plan.moves.size()) + " moves");
    return r;
  }
  const Vec3 wheel = station.contact.translation(), out = station.contact.linear().col(2);
  JointAngles previous = plan.moves.empty() ? cell.home : plan.moves.front().joints;
  for (size_t k = 0; k < targets.size(); ++k) {
    const RobotTarget& t = targets[k];
    const RobotMove& m = plan.moves[k];
    const std::string where = "line " + std::to_string(t.line) + " (move " + std::to_string(k + 1) + ")";
    const Frame flange = station.contact * t.station_in_blade.inverse() * cell.grip.inverse();
    RobotIkOptions ik;
    ik.previous = previous;
    const RobotSolution* chosen = nullptr;
    const auto solutions = robot_inverse(cell.arm, flange, ik);
    for (const RobotSolution& s : solutions)
      if (s.within_limits && configuration_matches(t, s, dialect)) {
        chosen = &s;
        break;
      }
    if (t.branch != m.branch) {
      ++r.configuration_flips;
      r.problems.push_back(where + ": configuration " + std::to_string(t.branch) + ", the plan's is " +
                           std::to_string(m.branch));
    }
    if (!chosen) {
      ++r.unreachable;
      r.problems.push_back(where + ": no solution with the program's configuration within the joint limits");
      continue;
    }
    previous = chosen->joints;
    for (int j = 0; j < 6; ++j)
      r.max_joint_deg = std::max(r.max_joint_deg, rad_to_deg(std::abs(chosen->joints[j] - m.joints[j])));
    const Frame replayed = robot_forward(cell.arm, chosen->joints);
    const Vec3 contact = (replayed * cell.grip) * m.contact.point;
    const double dev = (contact - (wheel + m.offset_mm * out)).norm();
    const double ang = rotation_angle_deg(replayed.linear(), robot_forward(cell.arm, m.joints).linear());
    r.max_position_mm = std::max(r.max_position_mm, dev);
    r.max_angle_deg = std::max(r.max_angle_deg, ang);
    if (dev > position_tol_mm)
      r.problems.push_back(where + ": the contact lands " + std::to_string(1e3 * dev) + " um from the plan's");
    else if (ang > angle_tol_deg)
      r.problems.push_back(where + ": the part is turned " + std::to_string(ang) + " deg from the plan");
  }
  return r;
}

}  // namespace bliskrun
