#include "core/machine/machine_sim.h"

#include <fcl/fcl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/common/error.h"
#include "core/machine/motion.h"
#include "core/tools/tool.h"
#include "core/tools/profile.h"

namespace bliskrun {

namespace machine_sim_detail {

constexpr double kSimInf = std::numeric_limits<double>::infinity();

Eigen::Isometry3d sim_turn_about(const Vec3& pivot, const Vec3& direction, double angle_rad) {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.linear() = Eigen::AngleAxisd(angle_rad, direction).toRotationMatrix();
  m.translation() = pivot - m.linear() * pivot;
  return m;
}

// A rotation taking +Z to `d` (unit).
Eigen::Matrix3d sim_z_to(const Vec3& d) {
  return Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), d).toRotationMatrix();
}

// One solid of the simulation: its FCL geometry placed in its link.
struct SimBody {
  std::string name;
  int link = 0;
  enum Role { Machine, Fixture, Stock, ToolPart } role = Machine;
  int tool = -1;  // ToolPart: index into the tools
  std::shared_ptr<fcl::CollisionGeometryd> geometry;
  Eigen::Isometry3d local = Eigen::Isometry3d::Identity();  // link home coordinates from the geometry's
  Vec3 centre = Vec3::Zero();  // bounding sphere, link home coordinates
  double radius = 0;
};

SimBody sim_primitive(const MachineBody& b, int link, SimBody::Role role, const Vec3& offset) {
  SimBody s;
  s.name = b.name;
  s.link = link;
  s.role = role;
  bounding_sphere(b, s.centre, s.radius);
  s.centre += offset;
  if (b.shape == BodyShape::Box) {
    const Vec3 size = b.max_mm - b.min_mm;
    s.geometry = std::make_shared<fcl::Boxd>(size.x(), size.y(), size.z());
    s.local.translation() = 0.5 * (b.min_mm + b.max_mm) + offset;
    return s;
  }
  const Vec3 axis = b.to_mm - b.from_mm;
  const double length = axis.norm();
  if (b.shape == BodyShape::Cylinder)
    s.geometry = std::make_shared<fcl::Cylinderd>(b.radius_mm, length);
  else
    s.geometry = std::make_shared<fcl::Coned>(b.radius_mm, length);  // apex at +length/2
  s.local.linear() = sim_z_to(axis / length);
  s.local.translation() = 0.5 * (b.from_mm + b.to_mm) + offset;
  return s;
}

// The distance of two placed bodies; a contact comes back as minus its
// penetration depth.
double sim_pair_distance(const SimBody& a, const Eigen::Isometry3d& pa, const SimBody& b, const Eigen::Isometry3d& pb) {
  const fcl::Transform3d ta = pa * a.local, tb = pb * b.local;
  fcl::DistanceRequestd request;
  request.gjk_solver_type = fcl::GST_LIBCCD;
  fcl::DistanceResultd result;
  fcl::distance(a.geometry.get(), ta, b.geometry.get(), tb, request, result);
  if (result.min_distance > 0) return result.min_distance;
  fcl::CollisionRequestd creq(1, true);
  fcl::CollisionResultd cres;
  fcl::collide(a.geometry.get(), ta, b.geometry.get(), tb, creq, cres);
  if (!cres.isCollision()) return 0;
  double depth = 0;
  for (size_t i = 0; i < cres.numContacts(); ++i) depth = std::max(depth, cres.getContact(i).penetration_depth);
  return -depth;
}

struct SimPairState {
  int a = 0, b = 0;
  double last = std::numeric_limits<double>::quiet_NaN();  // distance at the last sample
  double used = 0;  // motion bound summed since
  BodyApproach best;
};

}  // namespace machine_sim_detail

using namespace machine_sim_detail;

MachineChain::MachineChain(const MachineDefinition& m, double tool_length_mm) : machine_(m) {
  if (m.tool_length == ToolLengthMode::Tip) gauge_ = tool_length_mm * m.spindle;
  links_.push_back(Link{});  // the base
  for (const RotaryAxis& a : m.rotary) pivots_.push_back(a.pivot_mm);
  auto side = [&](bool tool) {
    int parent = 0;
    for (int s : tool ? m.tool_slides : m.part_slides) {
      Link l = links_[static_cast<size_t>(parent)];
      l.parent = parent;
      l.tool_side = tool;
      l.slide = s;
      l.rotary = -1;
      l.slides.push_back(s);
      links_.push_back(l);
      parent = links() - 1;
    }
    for (int i = 0; i < 2; ++i) {
      if ((m.rotary[static_cast<size_t>(i)].carrier == AxisCarrier::Tool) != tool) continue;
      Link l = links_[static_cast<size_t>(parent)];
      l.parent = parent;
      l.tool_side = tool;
      l.slide = -1;
      l.rotary = i;
      l.rotaries.push_back(i);
      links_.push_back(l);
      parent = links() - 1;
    }
    return parent;
  };
  part_ = side(false);
  spindle_ = side(true);
}

int MachineChain::link_of(const std::string& frame) const {
  if (frame == "base") return 0;
  if (frame == "spindle") return spindle_;
  if (frame == "part") return part_;
  for (int k = 1; k < links(); ++k) {
    const Link& l = links_[static_cast<size_t>(k)];
    const std::string name = l.slide >= 0 ? machine_.linear[static_cast<size_t>(l.slide)].name
                                          : machine_.rotary[static_cast<size_t>(l.rotary)].name;
    if (name == frame) return k;
  }
  throw ParameterError("frame", "'" + frame + "' is no frame of machine " + machine_.name);
}

bool MachineChain::adjacent(int a, int b) const {
  return links_[static_cast<size_t>(a)].parent == b || links_[static_cast<size_t>(b)].parent == a;
}

Eigen::Isometry3d MachineChain::pose(int link, const MachineAxes& q) const {
  std::vector<int> path;
  for (int k = link; k > 0; k = links_[static_cast<size_t>(k)].parent) path.push_back(k);
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  const bool tool = links_[static_cast<size_t>(link)].tool_side;
  // The slides move the tool relative to the part by +q: a part-side slide
  // carries the part by -q.
  for (auto it = path.rbegin(); it != path.rend(); ++it) {
    const Link& l = links_[static_cast<size_t>(*it)];
    if (l.slide >= 0) {
      Vec3 d = Vec3::Zero();
      d[l.slide] = (tool ? 1.0 : -1.0) * q.linear_mm[l.slide];
      m = m * Eigen::Translation3d(d);
    } else {
      const RotaryAxis& a = machine_.rotary[static_cast<size_t>(l.rotary)];
      m = m * sim_turn_about(tool ? Vec3(gauge_ + a.pivot_mm) : a.pivot_mm, a.direction, q.rotary_rad[l.rotary]);
    }
  }
  // Links the Z slide carries stand the tool length higher in tip mode
  // (the Z word is the tip's; their coordinates are the gauge point's).
  const std::vector<int>& carried = links_[static_cast<size_t>(link)].slides;
  if (tool && std::find(carried.begin(), carried.end(), 2) != carried.end()) m = m * Eigen::Translation3d(gauge_);
  return m;
}

double MachineChain::reach(int link, int axis, const Vec3& centre, double radius) const {
  const std::vector<int>& r = rotaries(link);
  const auto at = std::find(r.begin(), r.end(), axis);
  if (at == r.end()) return 0;
  double out = (centre - pivots_[static_cast<size_t>(axis)]).norm() + radius;
  // Turning about an outer pivot keeps the distance to it; to this pivot it
  // changes by at most twice the pivots' distance.
  for (auto it = at + 1; it != r.end(); ++it)
    out += 2 * (pivots_[static_cast<size_t>(*it)] - pivots_[static_cast<size_t>(axis)]).norm();
  return out;
}

MachineSimReport simulate_machine(const std::vector<ProgramMove>& blocks, const MachineDefinition& machine,
                                  const std::vector<SimTool>& tools, const std::vector<MachineBody>& fixture,
                                  const std::vector<MachineBody>& stock, const MachineSimOptions& options) {
  if (!(options.clearance_mm > 0)) throw ParameterError("clearance", "expected a clearance > 0 mm");
  if (tools.empty()) throw ParameterError("tools", "expected at least one tool");
  validate(machine);
  const std::vector<std::string> frames = body_frames(machine);
  validate_bodies(fixture, frames, "fixture");
  validate_bodies(stock, frames, "stock");
  MachineSimReport report;
  report.clearance_mm = options.clearance_mm;
  const double c = options.clearance_mm;

  // One chain and kinematics per tool (the tool length places the head).
  std::vector<Kinematics> kins;
  std::vector<MachineChain> chains;
  kins.reserve(tools.size());
  chains.reserve(tools.size());
  for (const SimTool& t : tools) {
    kins.emplace_back(machine, t.length_mm);
    chains.emplace_back(kins.back().machine(), t.length_mm);
  }
  const MachineChain& chain0 = chains.front();

  // The bodies. Part-frame coordinates are the part side's home
  // coordinates less part_origin.
  std::vector<SimBody> bodies;
  auto add = [&](const std::vector<MachineBody>& list, SimBody::Role role) {
    for (const MachineBody& b : list) {
      const int link = chain0.link_of(b.frame);
      const Vec3 offset = b.frame == "part" ? machine.part_origin_mm : Vec3::Zero();
      bodies.push_back(sim_primitive(b, link, role, offset));
    }
  };
  add(machine.bodies, SimBody::Machine);
  add(fixture, SimBody::Fixture);
  add(stock, SimBody::Stock);
  for (size_t k = 0; k < tools.size(); ++k) {
    if (!tools[k].body) {
      report.unchecked.push_back("T" + std::to_string(tools[k].number));
      continue;
    }
    // Each part of the tool as six stacked cylinders, each of the part's
    // largest radius over its sixth of the length (sampled at nine heights
    // and the ends, plus 0.01 mm): they enclose a profile that is monotone
    // or barrel-like over a slice (cutters, shanks, holders) and FCL
    // measures a cylinder against a box in microseconds, where the part's
    // mesh took ~0.6 ms.
    static const char* kPart[] = {"cutter", "shank", "holder"};
    constexpr int kSlices = 6, kSamples = 9;
    for (ToolPartId id : {ToolPartId::Cutter, ToolPartId::Shank, ToolPartId::Holder}) {
      if (!tools[k].body->has(id)) continue;
      const Profile& profile = tools[k].body->profile(id);
      const double length = profile.z_max() - profile.z_min();
      if (!(length > 0) || !(profile.max_radius() > 0)) continue;
      for (int slice = 0; slice < kSlices; ++slice) {
        const double z0 = profile.z_min() + length * slice / kSlices, z1 = profile.z_min() + length * (slice + 1) / kSlices;
        double radius = 0;
        for (int j = 0; j <= kSamples; ++j)
          radius = std::max(radius, profile.radius_at(std::min(z1, z0 + (z1 - z0) * j / kSamples)));
        radius += 0.01;
        SimBody s;
        s.name = "T" + std::to_string(tools[k].number) + " " + kPart[static_cast<int>(id)];
        s.link = chain0.spindle_link();
        s.role = SimBody::ToolPart;
        s.tool = static_cast<int>(k);
        s.geometry = std::make_shared<fcl::Cylinderd>(radius, z1 - z0);
        // Tool frame: tip at the origin, axis +Z; the tip sits the tool
        // length below the gauge point along the spindle.
        const Vec3 middle = (0.5 * (z0 + z1) - tools[k].length_mm) * machine.spindle;
        s.local.linear() = sim_z_to(machine.spindle);
        s.local.translation() = middle;
        s.centre = middle;
        s.radius = std::hypot(0.5 * (z1 - z0), radius);
        bodies.push_back(s);
      }
    }
  }

  // The pairs that can meet (see machine_sim.h).
  std::vector<SimPairState> pairs;
  for (int i = 0; i < static_cast<int>(bodies.size()); ++i)
    for (int j = i + 1; j < static_cast<int>(bodies.size()); ++j) {
      const SimBody &a = bodies[static_cast<size_t>(i)], &b = bodies[static_cast<size_t>(j)];
      if (a.link == b.link) continue;
      if (a.role == SimBody::Machine && b.role == SimBody::Machine && chain0.adjacent(a.link, b.link)) continue;
      const bool a_tool = a.role == SimBody::ToolPart, b_tool = b.role == SimBody::ToolPart;
      if (a_tool && b_tool) continue;
      if ((a_tool && b.role == SimBody::Stock) || (b_tool && a.role == SimBody::Stock)) continue;
      SimPairState p;
      p.a = i;
      p.b = j;
      p.best.a = a.name;
      p.best.b = b.name;
      p.best.distance_mm = kSimInf;
      pairs.push_back(p);
    }
  report.pairs = static_cast<long>(pairs.size());

  auto tool_index = [&](int number) {
    for (size_t k = 0; k < tools.size(); ++k)
      if (tools[k].number == number) return static_cast<int>(k);
    return 0;  // before the first tool call: the first tool's length
  };

  struct State {
    MachineAxes axes;  // physical: slide words, rotaries
    Vec3 tip = Vec3::Zero();
  };
  State previous;
  previous.axes = options.start;
  previous.tip = kins.front().forward(options.start).tip;
  std::vector<double> speed(bodies.size());
  std::vector<Eigen::Isometry3d> link_pose(static_cast<size_t>(chain0.links()));
  report.blocks = static_cast<long>(blocks.size());

  // How far below the closest approach so far a pair may stray unmeasured
  // (machine_sim.h): the clearance, or a tenth of a distance far above it.
  const auto allowance = [c](double m) { return std::max(c, 0.1 * m); };
  for (size_t i = 0; i < blocks.size(); ++i) {
    const ProgramMove& got = blocks[i];
    const int k = tool_index(got.tool);
    const Kinematics& kin = kins[static_cast<size_t>(k)];
    const MachineChain& chain = chains[static_cast<size_t>(k)];
    State from = previous;
    for (int r = 0; r < 2; ++r) from.axes.rotary_rad[static_cast<size_t>(r)] -= 2 * kPi * got.rotary_reset[static_cast<size_t>(r)];
    State to;
    to.axes.rotary_rad = got.axes.rotary_rad;
    if (got.tcp) {
      to.tip = got.axes.linear_mm;
      to.axes.linear_mm = kin.linear_for(to.tip, to.axes.rotary_rad);
    } else {
      // After TCP control is switched off the reader's modal words are the
      // last block's tip: a word not written again (same value) leaves its
      // slide where it stood.
      to.axes.linear_mm = got.axes.linear_mm;
      if (i > 0 && blocks[i - 1].tcp)
        for (int a = 0; a < 3; ++a)
          if (got.axes.linear_mm[a] == blocks[i - 1].axes.linear_mm[a]) to.axes.linear_mm[a] = from.axes.linear_mm[a];
      to.tip = kin.forward(to.axes).tip;
    }
    previous = to;
    const bool swept = i > 0 && got.tool == blocks[i - 1].tool;
    ControllerMotion motion = !got.tcp ? ControllerMotion::JointLinear
                                       : (got.vector ? ControllerMotion::TcpVector : ControllerMotion::TcpRotaryLinear);
    if (got.tcp != (i > 0 && blocks[i - 1].tcp)) motion = ControllerMotion::JointLinear;  // the switching block
    auto axes_at = [&](double t) {
      return swept ? controller_axes(kin, motion, from.axes, to.axes, from.tip, to.tip, t) : to.axes;
    };
    // Motion bounds of this block (per unit t).
    std::array<double, 2> turn{0.0, 0.0};
    if (swept) {
      if (motion == ControllerMotion::TcpVector) {
        MachineAxes q0 = from.axes;
        for (int s = 1; s <= 16; ++s) {
          const MachineAxes q1 = axes_at(s / 16.0);
          for (int r = 0; r < 2; ++r) turn[static_cast<size_t>(r)] += std::abs(q1.rotary_rad[static_cast<size_t>(r)] - q0.rotary_rad[static_cast<size_t>(r)]);
          q0 = q1;
        }
      } else {
        for (int r = 0; r < 2; ++r)
          turn[static_cast<size_t>(r)] = std::abs(to.axes.rotary_rad[static_cast<size_t>(r)] - from.axes.rotary_rad[static_cast<size_t>(r)]);
      }
      double slides = (to.axes.linear_mm - from.axes.linear_mm).norm();
      if (motion != ControllerMotion::JointLinear) {
        // The slides follow the tip and swing with the rotaries: the tip's
        // reach from each pivot, over the segment (part side: it moves on a
        // straight line, so its ends bound it) or fixed (tool side).
        const Vec3 mid = machine.part_origin_mm + 0.5 * (from.tip + to.tip);
        const double half = 0.5 * (to.tip - from.tip).norm();
        slides = 2 * half;
        const Vec3 tip_local = -kin.tool_length_mm() * machine.spindle;
        for (int r = 0; r < 2; ++r) {
          const bool head = machine.rotary[static_cast<size_t>(r)].carrier == AxisCarrier::Tool;
          const int link = head ? chain.spindle_link() : chain.part_link();
          slides += turn[static_cast<size_t>(r)] * (head ? chain.reach(link, r, tip_local, 0) : chain.reach(link, r, mid, half));
        }
      }
      for (size_t b = 0; b < bodies.size(); ++b) {
        const SimBody& body = bodies[b];
        double v = 0;
        if (motion == ControllerMotion::JointLinear) {
          Vec3 d = Vec3::Zero();
          for (int s : chain.slides(body.link)) d[s] = to.axes.linear_mm[s] - from.axes.linear_mm[s];
          v = d.norm();
        } else if (!chain.slides(body.link).empty()) {
          v = slides;
        }
        for (int r : chain.rotaries(body.link)) v += turn[static_cast<size_t>(r)] * chain.reach(body.link, r, body.centre, body.radius);
        speed[b] = v;
      }
    }
    // Poses at t, computed once per t for all pairs asking.
    double posed_t = -1;
    MachineAxes posed_q;
    auto poses_at = [&](double t) {
      if (t == posed_t) return;
      posed_t = t;
      posed_q = axes_at(t);
      for (int l = 0; l < chain.links(); ++l) link_pose[static_cast<size_t>(l)] = chain.pose(l, posed_q);
    };
    bool block_collided = false;
    for (SimPairState& p : pairs) {
      const SimBody &a = bodies[static_cast<size_t>(p.a)], &b = bodies[static_cast<size_t>(p.b)];
      if ((a.role == SimBody::ToolPart && a.tool != k) || (b.role == SimBody::ToolPart && b.tool != k)) continue;
      const double v = swept ? speed[static_cast<size_t>(p.a)] + speed[static_cast<size_t>(p.b)] : 0;
      double t = swept ? 0 : 1;
      if (swept && !std::isnan(p.last)) {
        // What is left of the last sample's budget (see machine_sim.h).
        const double m_so_far = std::min(p.best.distance_mm, p.last);
        const double left = p.last - p.used - m_so_far + allowance(m_so_far);
        if (left >= v) {
          p.used += v;
          ++report.skipped;
          continue;
        }
        t = std::max(0.0, left) / v;
      }
      for (;;) {
        poses_at(t);
        const double d = sim_pair_distance(a, link_pose[static_cast<size_t>(a.link)], b, link_pose[static_cast<size_t>(b.link)]);
        ++report.queries;
        if (d < p.best.distance_mm) {
          p.best.distance_mm = d;
          p.best.block = static_cast<long>(i);
          p.best.line = got.line;
          p.best.t = t;
          p.best.axes = posed_q;
        }
        if (d <= 0) {
          block_collided = true;
          const BodyApproach& f = report.first_collision;
          if (!report.collided || (static_cast<long>(i) == f.block && t < f.t)) {
            report.first_collision = p.best;
            report.first_collision.distance_mm = d;
            report.first_collision.t = t;
            report.first_collision.axes = posed_q;
            report.first_collision.block = static_cast<long>(i);
            report.first_collision.line = got.line;
          }
          report.collided = true;
        }
        p.last = d;
        p.used = 0;
        if (t >= 1) break;
        const double step = v > 0 ? (d - p.best.distance_mm + allowance(p.best.distance_mm)) / v : kSimInf;
        if (t + step >= 1) {
          p.used = v * (1 - t);
          break;
        }
        t += step;
      }
    }
    if (swept) ++report.swept_blocks; else ++report.unswept_blocks;
    if (block_collided) ++report.colliding_blocks;
  }
  for (const SimPairState& p : pairs)
    if (std::isfinite(p.best.distance_mm)) report.closest.push_back(p.best);
  std::sort(report.closest.begin(), report.closest.end(),
            [](const BodyApproach& x, const BodyApproach& y) { return x.distance_mm < y.distance_mm; });
  return report;
}

std::string machine_sim_summary(const MachineSimReport& r) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(3);
  if (r.collided) {
    const BodyApproach& f = r.first_collision;
    out << "FAIL: collision " << f.a << " / " << f.b << " at line " << f.line << " (block " << f.block + 1
        << ", t " << f.t << "), depth " << -f.distance_mm << " mm; " << r.colliding_blocks << " blocks collide";
  } else if (r.closest.empty()) {
    out << "PASS: no pair of bodies to check";
  } else {
    const BodyApproach& n = r.closest.front();
    out << "PASS: closest approach " << n.distance_mm << " mm (" << n.a << " / " << n.b << ", line " << n.line << ")";
  }
  out << ", clearance " << r.clearance_mm << " mm";
  return out.str();
}

}  // namespace bliskrun
