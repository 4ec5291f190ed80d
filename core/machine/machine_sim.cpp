#include "core/machine/machine_sim.h"

#include <fcl/fcl.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <iterator>
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
  using Role = PlacedBody::Role;
  Role role = PlacedBody::Machine;
  int tool = -1;  // ToolPart: index into the tools
  ToolPartId tool_part = ToolPartId::Cutter;
  std::shared_ptr<fcl::CollisionGeometryd> geometry;
  bool mesh = false;
  // A mesh's box (its vertices' principal axes, the margin added), placed
  // by `coarse_local` in the link: the cheap lower bound asked first.
  std::shared_ptr<fcl::CollisionGeometryd> coarse;
  Eigen::Isometry3d coarse_local = Eigen::Isometry3d::Identity();
  double margin = 0;  // a mesh's: the true surface may lie this much nearer
  // A mesh's own names (MachineBody::mesh_names) by the first triangle of
  // each mesh in the hierarchy; empty: the body's name throughout.
  std::vector<std::pair<int, std::string>> names_from_triangle;
  // A primitive's (box, cylinder, cone) polyhedron containing it, no more
  // than hull_gap outside it, in the geometry's coordinates. Against a mesh
  // it is asked first: a BVH against a BVH prunes by boxes fitted to both
  // (FCL prunes a mesh against a shape by the shape's axis-aligned box in
  // the mesh's frame, loose for a tilted housing: ~20 ms a query for a
  // blade 150 mm away), and its distance is a lower bound within hull_gap.
  std::shared_ptr<fcl::CollisionGeometryd> hull;
  double hull_gap = 0;
  Eigen::Isometry3d local = Eigen::Isometry3d::Identity();  // link home coordinates from the geometry's
  Vec3 centre = Vec3::Zero();  // bounding sphere, link home coordinates
  double radius = 0;
  PlacedBody shape;  // for pictures: the shape in the geometry's coordinates
};

// The name a report gives `body` where its nearest point is its triangle
// `triangle` (FCL's primitive index; -1: not known).
const std::string& sim_name_at(const SimBody& body, int triangle) {
  if (body.names_from_triangle.empty() || triangle < 0) return body.name;
  auto after = std::upper_bound(body.names_from_triangle.begin(), body.names_from_triangle.end(), triangle,
                                [](int t, const std::pair<int, std::string>& m) { return t < m.first; });
  return after == body.names_from_triangle.begin() ? body.name : std::prev(after)->second;
}

// Whether a report's `name` is the body's: its own, or one of its meshes'.
bool sim_answers_to(const SimBody& body, const std::string& name) {
  if (body.name == name) return true;
  for (const auto& m : body.names_from_triangle)
    if (m.second == name) return true;
  return false;
}

// A BVH over triangles (fcl's).
std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> sim_bvh(const std::vector<std::pair<std::vector<Vec3>, std::vector<Eigen::Vector3i>>>& parts) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  model->beginModel();
  for (const auto& [vertices, triangles] : parts) {
    std::vector<fcl::Vector3d> v(vertices.begin(), vertices.end());
    std::vector<fcl::Triangle> t;
    t.reserve(triangles.size());
    for (const Eigen::Vector3i& x : triangles)
      t.emplace_back(static_cast<size_t>(x[0]), static_cast<size_t>(x[1]), static_cast<size_t>(x[2]));
    model->addSubModel(v, t);
  }
  model->endModel();
  return model;
}

// The distance a primitive's hull may stand off it (mm): the circles of
// cylinders and cones are circumscribed by polygons this close.
constexpr double kHullGap = 0.01;

// A polyhedron containing a cylinder (apex_radius = radius) or a cone
// (apex_radius = 0) of FCL's placement — axis z, from -length/2 to
// +length/2, a cone's apex at +length/2: its circles circumscribed by
// polygons of n sides, n chosen so that they stand off no more than
// kHullGap (r (1 / cos(pi/n) - 1)).
std::shared_ptr<fcl::CollisionGeometryd> sim_round_hull(double radius, double apex_radius, double length, double* gap) {
  int n = 8;
  while (radius * (1 / std::cos(kPi / n) - 1) > kHullGap && n < 4096) n *= 2;
  *gap = radius * (1 / std::cos(kPi / n) - 1);
  const double rc = radius / std::cos(kPi / n), rt = apex_radius / std::cos(kPi / n);
  std::vector<Vec3> v;
  std::vector<Eigen::Vector3i> t;
  const double z0 = -0.5 * length, z1 = 0.5 * length;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * kPi * i / n;
    v.emplace_back(rc * std::cos(a), rc * std::sin(a), z0);
  }
  if (apex_radius > 0) {
    for (int i = 0; i < n; ++i) {
      const double a = 2 * kPi * i / n;
      v.emplace_back(rt * std::cos(a), rt * std::sin(a), z1);
    }
  } else {
    v.emplace_back(0, 0, z1);
  }
  const int bottom = static_cast<int>(v.size()), top = bottom + 1;
  v.emplace_back(0, 0, z0);
  v.emplace_back(0, 0, z1);
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    t.emplace_back(bottom, j, i);
    if (apex_radius > 0) {
      t.emplace_back(i, j, n + j);
      t.emplace_back(i, n + j, n + i);
      t.emplace_back(top, n + i, n + j);
    } else {
      t.emplace_back(i, j, n);
    }
  }
  return sim_bvh({{v, t}});
}

std::shared_ptr<fcl::CollisionGeometryd> sim_box_hull(const Vec3& size) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i)
    v.emplace_back((i & 1 ? 0.5 : -0.5) * size.x(), (i & 2 ? 0.5 : -0.5) * size.y(), (i & 4 ? 0.5 : -0.5) * size.z());
  const std::vector<Eigen::Vector3i> t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                          {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return sim_bvh({{v, t}});
}

SimBody sim_body(const MachineBody& b, int link, SimBody::Role role, const Vec3& offset) {
  SimBody s;
  s.name = b.name;
  s.link = link;
  s.role = role;
  bounding_sphere(b, s.centre, s.radius);
  s.centre += offset;
  s.shape.name = b.name;
  s.shape.role = role;
  s.shape.shape = b.shape;
  if (b.shape == BodyShape::Mesh) {
    // One hierarchy over all the body's meshes, in their own coordinates:
    // the placement and the part origin are the query's transform.
    std::vector<std::pair<std::vector<Vec3>, std::vector<Eigen::Vector3i>>> parts;
    int first = 0;
    for (size_t k = 0; k < b.meshes.size(); ++k) {
      const auto& m = b.meshes[k];
      parts.emplace_back(m->vertices, m->triangles);
      if (!b.mesh_names.empty()) s.names_from_triangle.emplace_back(first, b.mesh_names[k]);
      first += static_cast<int>(m->triangles.size());
    }
    s.geometry = sim_bvh(parts);
    s.mesh = true;
    // The box along the vertices' principal axes (a blade's: its chord,
    // span and thickness with the twist).
    Vec3 mean = Vec3::Zero();
    size_t n = 0;
    for (const auto& m : b.meshes)
      for (const Vec3& v : m->vertices) mean += v, ++n;
    mean /= static_cast<double>(n);
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto& m : b.meshes)
      for (const Vec3& v : m->vertices) cov += (v - mean) * (v - mean).transpose();
    Eigen::Matrix3d axes = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors();
    if (axes.determinant() < 0) axes.col(0) = -axes.col(0);
    Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
    for (const auto& m : b.meshes)
      for (const Vec3& v : m->vertices) {
        const Vec3 q = axes.transpose() * (v - mean);
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
    const Vec3 size = (hi - lo).cwiseMax(Vec3::Constant(1e-6)) + Vec3::Constant(2 * b.margin_mm);
    s.coarse = std::make_shared<fcl::Boxd>(size.x(), size.y(), size.z());
    Eigen::Isometry3d box = Eigen::Isometry3d::Identity();
    box.linear() = axes;
    box.translation() = mean + axes * (0.5 * (lo + hi));
    s.margin = b.margin_mm;
    s.local = Eigen::Translation3d(offset) * b.placement;
    s.coarse_local = s.local * box;
    s.shape.meshes = b.meshes;
    return s;
  }
  if (b.shape == BodyShape::Box) {
    const Vec3 size = b.max_mm - b.min_mm;
    s.geometry = std::make_shared<fcl::Boxd>(size.x(), size.y(), size.z());
    s.hull = sim_box_hull(size);
    s.local.translation() = 0.5 * (b.min_mm + b.max_mm) + offset;
    s.shape.size_mm = size;
    return s;
  }
  const Vec3 axis = b.to_mm - b.from_mm;
  const double length = axis.norm();
  if (b.shape == BodyShape::Cylinder)
    s.geometry = std::make_shared<fcl::Cylinderd>(b.radius_mm, length);
  else
    s.geometry = std::make_shared<fcl::Coned>(b.radius_mm, length);  // apex at +length/2
  s.hull = sim_round_hull(b.radius_mm, b.shape == BodyShape::Cylinder ? b.radius_mm : 0, length, &s.hull_gap);
  s.local.linear() = sim_z_to(axis / length);
  s.local.translation() = 0.5 * (b.from_mm + b.to_mm) + offset;
  s.shape.radius_mm = b.radius_mm;
  s.shape.length_mm = length;
  return s;
}

// The distance of two placed bodies; a contact comes back as minus its
// penetration depth. A mesh is asked only up to `seed`: where nothing lies
// nearer, the seed comes back (a lower bound) with *bounded set — FCL
// prunes every bounding volume farther. Nearest points (machine frame)
// when asked.
double sim_pair_distance(const SimBody& a, const Eigen::Isometry3d& pa, const SimBody& b, const Eigen::Isometry3d& pb,
                         double seed = kSimInf, bool* bounded = nullptr, Vec3* near_a = nullptr,
                         Vec3* near_b = nullptr, std::array<int, 2>* triangles = nullptr) {
  if (bounded) *bounded = false;
  if (triangles) *triangles = {-1, -1};
  // A mesh first: FCL's nearest points follow the argument order.
  const bool swap = b.mesh && !a.mesh;
  const SimBody& first = swap ? b : a;
  const SimBody& second = swap ? a : b;
  const fcl::Transform3d t1 = (swap ? pb : pa) * first.local, t2 = (swap ? pa : pb) * second.local;
  const double margin = a.margin + b.margin;
  // The meshes' nearest triangles (FCL's b1 / b2 follow the argument order).
  auto record = [&](intptr_t b1, intptr_t b2) {
    if (!triangles) return;
    (*triangles)[swap ? 1 : 0] = first.mesh ? static_cast<int>(b1) : -1;
    (*triangles)[swap ? 0 : 1] = second.mesh ? static_cast<int>(b2) : -1;
  };
  fcl::DistanceRequestd request;
  request.gjk_solver_type = fcl::GST_LIBCCD;
  request.enable_nearest_points = near_a != nullptr;
  fcl::DistanceResultd result;
  const bool seeded = first.mesh && std::isfinite(seed);
  if (seeded) result.min_distance = seed + margin;
  if (first.mesh && second.hull) {
    // The primitive's hull first (SimBody::hull): apart from it, its
    // distance less the hull's gap is the pair's, as a lower bound within
    // that gap; touching it, the primitive itself is asked below.
    fcl::DistanceResultd hull_result = result;
    fcl::distance(first.geometry.get(), t1, second.hull.get(), t2, request, hull_result);
    if (seeded && !(hull_result.min_distance < seed + margin)) {
      if (bounded) *bounded = true;
      return seed;
    }
    if (hull_result.min_distance > 0) {
      record(hull_result.b1, -1);
      if (near_a) {
        *near_a = swap ? hull_result.nearest_points[1] : hull_result.nearest_points[0];
        *near_b = swap ? hull_result.nearest_points[0] : hull_result.nearest_points[1];
      }
      return hull_result.min_distance - margin - second.hull_gap;
    }
  }
  fcl::distance(first.geometry.get(), t1, second.geometry.get(), t2, request, result);
  if (seeded && !(result.min_distance < seed + margin)) {
    if (bounded) *bounded = true;
    return seed;
  }
  auto nearest = [&](const Vec3& p1, const Vec3& p2) {
    if (!near_a) return;
    *near_a = swap ? p2 : p1;
    *near_b = swap ? p1 : p2;
  };
  record(result.b1, result.b2);
  if (result.min_distance > 0) {
    nearest(result.nearest_points[0], result.nearest_points[1]);
    return result.min_distance - margin;
  }
  fcl::CollisionRequestd creq(first.mesh ? 64 : 1, true);
  creq.gjk_solver_type = fcl::GST_LIBCCD;
  fcl::CollisionResultd cres;
  fcl::collide(first.geometry.get(), t1, second.geometry.get(), t2, creq, cres);
  if (!cres.isCollision()) {
    nearest(result.nearest_points[0], result.nearest_points[1]);
    return -margin;
  }
  double depth = 0;
  for (size_t i = 0; i < cres.numContacts(); ++i) depth = std::max(depth, cres.getContact(i).penetration_depth);
  if (cres.numContacts() > 0) {
    nearest(cres.getContact(0).pos, cres.getContact(0).pos);
    record(cres.getContact(0).b1, cres.getContact(0).b2);
  }
  return -depth - margin;
}

// A lower bound on the distance of a mesh body to another: from its box
// (and the other's, when a mesh too); 0 where they overlap.
double sim_coarse_distance(const SimBody& a, const Eigen::Isometry3d& pa, const SimBody& b, const Eigen::Isometry3d& pb) {
  const fcl::Transform3d ta = pa * (a.mesh ? a.coarse_local : a.local), tb = pb * (b.mesh ? b.coarse_local : b.local);
  fcl::DistanceRequestd request;
  request.gjk_solver_type = fcl::GST_LIBCCD;
  fcl::DistanceResultd result;
  fcl::distance((a.mesh ? a.coarse : a.geometry).get(), ta, (b.mesh ? b.coarse : b.geometry).get(), tb, request, result);
  return std::max(0.0, result.min_distance);
}

// A mesh is never asked whether it lies nearer than this (mm), nor its box
// taken for a bound below it: FCL cannot prune by a bound of 0 or less
// (overlapping bounding volumes are 0 apart).
constexpr double kSeedFloor = 1e-3;

struct SimPairState {
  int a = 0, b = 0;
  double last = std::numeric_limits<double>::quiet_NaN();  // distance (or lower bound) at the last sample
  double used = 0;  // motion bound summed since
  BodyApproach best;
};

// Every body of a simulation and the chain each tool's length gives.
struct SimWorld {
  std::vector<Kinematics> kins;
  std::vector<MachineChain> chains;
  std::vector<SimBody> bodies;
  std::vector<std::string> unchecked;  // tools without a body
};

SimWorld sim_world(const MachineDefinition& machine, const std::vector<SimTool>& tools,
                   const MachineSetupBodies& setup) {
  if (tools.empty()) throw ParameterError("tools", "expected at least one tool");
  validate(machine);
  const std::vector<std::string> frames = body_frames(machine);
  validate_bodies(setup.fixture, frames, "fixture");
  validate_bodies(setup.stock, frames, "stock");
  validate_bodies(setup.part, frames, "part");
  SimWorld w;
  // One chain and kinematics per tool (the tool length places the head).
  w.kins.reserve(tools.size());
  w.chains.reserve(tools.size());
  for (const SimTool& t : tools) {
    w.kins.emplace_back(machine, t.length_mm);
    w.chains.emplace_back(w.kins.back().machine(), t.length_mm);
  }
  const MachineChain& chain0 = w.chains.front();
  // Part-frame coordinates are the part side's home coordinates less
  // part_origin.
  auto add = [&](const std::vector<MachineBody>& list, SimBody::Role role) {
    for (const MachineBody& b : list) {
      const int link = chain0.link_of(b.frame);
      const Vec3 offset = b.frame == "part" ? machine.part_origin_mm : Vec3::Zero();
      w.bodies.push_back(sim_body(b, link, role, offset));
    }
  };
  add(machine.bodies, PlacedBody::Machine);
  add(setup.fixture, PlacedBody::Fixture);
  add(setup.stock, PlacedBody::Stock);
  add(setup.part, PlacedBody::Part);
  for (size_t k = 0; k < tools.size(); ++k) {
    if (!tools[k].body) {
      w.unchecked.push_back("T" + std::to_string(tools[k].number));
      continue;
    }
    // Each part of the tool as cylinders over six slices of its length,
    // each of the slice's largest radius (sampled at nine heights and the
    // ends, plus 0.01 mm), neighbouring slices of one radius joined: they
    // enclose a profile that is monotone or barrel-like over a slice
    // (cutters, shanks, holders), and FCL measures a cylinder against a
    // box in microseconds, where the tool's mesh took ~0.6 ms.
    static const char* kPart[] = {"cutter", "shank", "holder"};
    constexpr int kSlices = 6, kSamples = 9;
    for (ToolPartId id : {ToolPartId::Cutter, ToolPartId::Shank, ToolPartId::Holder}) {
      if (!tools[k].body->has(id)) continue;
      const Profile& profile = tools[k].body->profile(id);
      const double length = profile.z_max() - profile.z_min();
      if (!(length > 0) || !(profile.max_radius() > 0)) continue;
      std::vector<std::array<double, 3>> slices;  // z0, z1, radius
      for (int slice = 0; slice < kSlices; ++slice) {
        const double z0 = profile.z_min() + length * slice / kSlices, z1 = profile.z_min() + length * (slice + 1) / kSlices;
        double radius = 0;
        for (int j = 0; j <= kSamples; ++j)
          radius = std::max(radius, profile.radius_at(std::min(z1, z0 + (z1 - z0) * j / kSamples)));
        radius += 0.01;
        if (!slices.empty() && std::abs(slices.back()[2] - radius) < 1e-9)
          slices.back()[1] = z1;
        else
          slices.push_back({z0, z1, radius});
      }
      for (const auto& [z0, z1, radius] : slices) {
        SimBody s;
        s.name = "T" + std::to_string(tools[k].number) + " " + kPart[static_cast<int>(id)];
        s.link = chain0.spindle_link();
        s.role = PlacedBody::Tool;
        s.tool = static_cast<int>(k);
        s.tool_part = id;
        s.geometry = std::make_shared<fcl::Cylinderd>(radius, z1 - z0);
        // Tool frame: tip at the origin, axis +Z; the tip sits the tool
        // length below the gauge point along the spindle.
        const Vec3 middle = (0.5 * (z0 + z1) - tools[k].length_mm) * machine.spindle;
        s.local.linear() = sim_z_to(machine.spindle);
        s.local.translation() = middle;
        s.centre = middle;
        s.radius = std::hypot(0.5 * (z1 - z0), radius);
        s.shape.name = s.name;
        s.shape.role = PlacedBody::Tool;
        s.shape.shape = BodyShape::Cylinder;
        s.shape.radius_mm = radius;
        s.shape.length_mm = z1 - z0;
        w.bodies.push_back(s);
      }
    }
  }
  return w;
}

VectorTurnBound vector_rate_bound(const Kinematics& kin, const Vec3& axis_from, const Vec3& axis_to, int steps);

// Whether a pair can meet and is checked (machine_sim.h, "Which pairs").
bool checked_pair(const SimBody& a, const SimBody& b, const MachineChain& chain) {
  if (a.link == b.link) return false;
  if (a.role == PlacedBody::Machine && b.role == PlacedBody::Machine && chain.adjacent(a.link, b.link)) return false;
  const bool a_tool = a.role == PlacedBody::Tool, b_tool = b.role == PlacedBody::Tool;
  if (a_tool && b_tool) return false;
  const SimBody* tool = a_tool ? &a : b_tool ? &b : nullptr;
  if (!tool) return true;
  const SimBody& other = a_tool ? b : a;
  if (other.role == PlacedBody::Stock) return false;
  if (other.role == PlacedBody::Part && tool->tool_part == ToolPartId::Cutter) return false;
  return true;
}

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

bool MachineChain::carries(int a, int b) const {
  for (int k = b; k >= 0; k = links_[static_cast<size_t>(k)].parent)
    if (k == a) return true;
  return false;
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

VectorTurnBound vector_turn_bound(const Kinematics& kin, const MachineAxes& from, const MachineAxes& to,
                                  const Vec3& tip_from, const Vec3& tip_to, int steps) {
  if (steps < 1) throw ParameterError("steps", "expected at least one sub-step");
  VectorTurnBound out = vector_rate_bound(kin, kin.tool_axis(from.rotary_rad), kin.tool_axis(to.rotary_rad), steps);
  // The model's rotaries at the sub-steps' ends: each the continuation of
  // the last (the solution nearest it) and within its sub-step's bound.
  MachineAxes q0 = from;
  for (int j = 1; j <= steps; ++j) {
    const double t = double(j) / steps;
    const MachineAxes q1 = controller_axes(kin, ControllerMotion::TcpVector, from, to, tip_from, tip_to, t);
    const Vec3 axis = kin.tool_axis(q1.rotary_rad);
    double nearest = kSimInf;
    std::array<double, 2> next = q1.rotary_rad;
    for (const RotarySolution& s : kin.rotary_solutions(axis, q0.rotary_rad)) {
      const double d = std::abs(s.rotary_rad[0] - q0.rotary_rad[0]) + std::abs(s.rotary_rad[1] - q0.rotary_rad[1]);
      if (d < nearest) {
        nearest = d;
        next = s.rotary_rad;
      }
    }
    for (int r = 0; r < 2; ++r) {
      const size_t k = static_cast<size_t>(r);
      const double d = std::abs(q1.rotary_rad[k] - q0.rotary_rad[k]);
      out.sampled_rad[k] += d;
      if (std::abs(next[k] - q1.rotary_rad[k]) > 1e-9 || d > out.step_rad[static_cast<size_t>(j - 1)][k] * (1 + 1e-9) + 1e-12)
        out.bounded = false;
    }
    q0 = q1;
  }
  if (!out.bounded) out.turn_rad = {kSimInf, kSimInf};
  return out;
}

// The rates' part of vector_turn_bound: per sub-step, from the range of
// c = d1.k over it (machine_sim.h, "Vector orientation").
VectorTurnBound machine_sim_detail::vector_rate_bound(const Kinematics& kin, const Vec3& axis_from, const Vec3& axis_to, int steps) {
  VectorTurnBound out;
  out.step_rad.assign(static_cast<size_t>(steps), {0.0, 0.0});
  const Vec3 ka = axis_from.normalized(), kb = axis_to.normalized();
  const Vec3 n = ka.cross(kb);
  const double theta = std::atan2(n.norm(), ka.dot(kb));
  if (n.norm() < 1e-12) return out;  // the axis stands still (interpolate_pose)
  const MachineDefinition& m = kin.machine();
  const int p = kin.primary_axis(), s = kin.secondary_axis();
  const Vec3 d1 = m.rotary[static_cast<size_t>(p)].direction.normalized();
  const Vec3 d2 = m.rotary[static_cast<size_t>(s)].direction.normalized();
  const double c12 = d1.dot(d2), cb = d2.dot(m.spindle.normalized());
  // G(c) = A0 + 2 B c - c^2; h(c) = (1 - c^2) / G(c), the square of |t2'| / Theta.
  const double a0 = 1 - c12 * c12 - cb * cb, bq = c12 * cb;
  auto g_of = [&](double c) { return a0 + 2 * bq * c - c * c; };
  // Where h' = 0: B c^2 + (A0 - 1) c + B = 0.
  std::vector<double> h_critical;
  if (std::abs(bq) > 1e-15) {
    const double disc = (a0 - 1) * (a0 - 1) - 4 * bq * bq;
    if (disc >= 0) {
      h_critical.push_back((-(a0 - 1) + std::sqrt(disc)) / (2 * bq));
      h_critical.push_back((-(a0 - 1) - std::sqrt(disc)) / (2 * bq));
    }
  } else if (std::abs(a0 - 1) > 1e-15) {
    h_critical.push_back(0);
  }
  // Along the arc k(x) = cos x ka + sin x u, x in [0, Theta]:
  // c(x) = d1.k(x) = R cos(x - x0).
  const Vec3 u = n.normalized().cross(ka);
  const double ca = d1.dot(ka), cu = d1.dot(u);
  const double amplitude = std::hypot(ca, cu), x0 = std::atan2(cu, ca);
  auto c_at = [&](double x) { return ca * std::cos(x) + cu * std::sin(x); };
  constexpr double kTiny = 1e-12;
  for (int j = 0; j < steps; ++j) {
    const double x_lo = theta * j / steps, x_hi = theta * (j + 1) / steps;
    double lo = std::min(c_at(x_lo), c_at(x_hi)), hi = std::max(c_at(x_lo), c_at(x_hi));
    for (int q = -2; q <= 3; ++q) {
      const double x = x0 + q * kPi;
      if (x > x_lo && x < x_hi) {
        const double v = (q % 2 == 0) ? amplitude : -amplitude;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    }
    lo = std::max(lo, -1.0);
    hi = std::min(hi, 1.0);
    const double s_min = std::sqrt(std::max(0.0, 1 - std::max(lo * lo, hi * hi)));
    const double g_min = std::min(g_of(lo), g_of(hi));  // G is concave
    if (s_min < kTiny || g_min < kTiny) {
      out.bounded = false;
      out.turn_rad = {kSimInf, kSimInf};
      out.step_rad[static_cast<size_t>(j)] = {kSimInf, kSimInf};
      continue;
    }
    double h_max = std::max((1 - lo * lo) / g_of(lo), (1 - hi * hi) / g_of(hi));
    for (double c : h_critical)
      if (c > lo && c < hi) h_max = std::max(h_max, (1 - c * c) / g_of(c));
    const double lever = std::max(std::abs(c12 - cb * lo), std::abs(c12 - cb * hi));
    const double rate2 = theta * std::sqrt(h_max);
    const double rate1 = theta / s_min + rate2 * lever / (s_min * s_min);
    auto& step = out.step_rad[static_cast<size_t>(j)];
    step[static_cast<size_t>(p)] = rate1 / steps;
    step[static_cast<size_t>(s)] = rate2 / steps;
    if (out.bounded)
      for (int r = 0; r < 2; ++r) out.turn_rad[static_cast<size_t>(r)] += step[static_cast<size_t>(r)];
  }
  return out;
}

MachineSimReport simulate_machine(const std::vector<ProgramMove>& blocks, const MachineDefinition& machine,
                                  const std::vector<SimTool>& tools, const MachineSetupBodies& setup,
                                  const MachineSimOptions& options) {
  if (!(options.clearance_mm > 0)) throw ParameterError("clearance", "expected a clearance > 0 mm");
  if (!(options.near_zone_mm >= options.clearance_mm))
    throw ParameterError("near_zone", "expected a near-miss zone at least the clearance (" +
                                          std::to_string(options.clearance_mm) + " mm)");
  SimWorld world = sim_world(machine, tools, setup);
  const std::vector<SimBody>& bodies = world.bodies;
  const std::vector<Kinematics>& kins = world.kins;
  const std::vector<MachineChain>& chains = world.chains;
  const MachineChain& chain0 = chains.front();
  MachineSimReport report;
  report.clearance_mm = options.clearance_mm;
  report.near_zone_mm = options.near_zone_mm;
  report.unchecked = world.unchecked;
  const double c = options.clearance_mm;

  // The pairs that can meet (see machine_sim.h).
  std::vector<SimPairState> pairs;
  for (int i = 0; i < static_cast<int>(bodies.size()); ++i)
    for (int j = i + 1; j < static_cast<int>(bodies.size()); ++j) {
      const SimBody &a = bodies[static_cast<size_t>(i)], &b = bodies[static_cast<size_t>(j)];
      if (!checked_pair(a, b, chain0)) continue;
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
  // Each body's speed split by joint: the slides' term, each rotary's.
  std::vector<double> slide_term(bodies.size());
  std::vector<std::array<double, 2>> rotary_term(bodies.size());
  // Under TCP: a spindle-link body's speed relative to the part's link
  // (machine_sim.h, "The bound"); negative where that does not apply.
  std::vector<double> relative(bodies.size(), -1);
  std::vector<Eigen::Isometry3d> link_pose(static_cast<size_t>(chain0.links()));
  report.blocks = static_cast<long>(blocks.size());

  // How far below the closest approach so far a pair may stray unmeasured
  // (machine_sim.h): the clearance, or a tenth of a distance far above it,
  // or down to the near-miss zone.
  const double zone = options.near_zone_mm;
  const auto allowance = [c, zone](double m) { return std::max({c, 0.1 * m, m - zone}); };
  // How near a mesh is asked to be (machine_sim.h, "The bound"): m less
  // half of what its allowance e exceeds the clearance by. Not m itself
  // where e is large: FCL prunes the hierarchy by the bound asked, and a
  // pair hovering just beyond its closest approach (a shank 20-30 mm off a
  // blade all program long, e ~ 10 mm) has nearly every bounding volume of
  // the blade's near side within m — the HECC impeller job's post spent
  // 98 % of its time in those queries. A sample not measured exactly is
  // then at least m - e/2 (the same guarantee: never reported further
  // above the truth than e) and steps on by at least (e + c)/2; a pair
  // near the part (e = c) is still measured exactly whenever it comes
  // nearer than m.
  const auto mesh_seed = [&allowance, c](double m) { return m - 0.5 * (allowance(m) - c); };
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
    double relative_turn = 0;  // the tool's turn relative to the part (TCP)
    const bool tcp = swept && motion != ControllerMotion::JointLinear;
    if (swept) {
      if (motion == ControllerMotion::TcpVector) {
        // The proved bound, where the model follows one branch (see
        // "Vector orientation").
        const VectorTurnBound bound = vector_turn_bound(kin, from.axes, to.axes, from.tip, to.tip);
        if (bound.bounded) {
          turn = bound.turn_rad;
        } else {
          turn = bound.sampled_rad;
          if (report.unbounded_blocks++ == 0) report.first_unbounded_line = got.line;
        }
        relative_turn = turn[0] + turn[1];
      } else {
        for (int r = 0; r < 2; ++r)
          turn[static_cast<size_t>(r)] = std::abs(to.axes.rotary_rad[static_cast<size_t>(r)] - from.axes.rotary_rad[static_cast<size_t>(r)]);
        // Turning at constant rates about axes at a fixed angle
        // (Kinematics::rotary_axes_cos).
        relative_turn = std::sqrt(turn[0] * turn[0] + turn[1] * turn[1] + 2 * turn[0] * turn[1] * kin.rotary_axes_cos());
      }
      double slides = (to.axes.linear_mm - from.axes.linear_mm).norm();
      const Vec3 tip_local = -kin.tool_length_mm() * machine.spindle;
      if (motion != ControllerMotion::JointLinear) {
        // The slides follow the tip and swing with the rotaries: the tip's
        // reach from each pivot, over the segment (part side: it moves on a
        // straight line, so its ends bound it) or fixed (tool side).
        const Vec3 mid = machine.part_origin_mm + 0.5 * (from.tip + to.tip);
        const double half = 0.5 * (to.tip - from.tip).norm();
        slides = 2 * half;
        for (int r = 0; r < 2; ++r) {
          const bool head = machine.rotary[static_cast<size_t>(r)].carrier == AxisCarrier::Tool;
          const int link = head ? chain.spindle_link() : chain.part_link();
          slides += turn[static_cast<size_t>(r)] * (head ? chain.reach(link, r, tip_local, 0) : chain.reach(link, r, mid, half));
        }
      }
      // The tip's speed in the part frame: under TCP its straight line;
      // joint-linear, the chord's plus what its curvature adds (|tip''| <=
      // 2 W^2 rho + 2 W v, motion.h move_deviation, so |tip'| strays at most
      // half that from the chord's slope), rho the tip's reach from the
      // pivots over the block: it grows at most at v + 3 W rho (the tip
      // swings about the head pivots, the table pivots about each other),
      // so by Gronwall rho <= (rho0 + v / 3W) e^(3W) - v / 3W.
      double tip_speed = (to.tip - from.tip).norm();
      if (!tcp) {
        const double w = turn[0] + turn[1], v = (to.axes.linear_mm - from.axes.linear_mm).norm();
        const double rho0 = kin.pivot_reach_mm(from.axes);
        const double rho = w > 0 ? (rho0 + v / (3 * w)) * std::exp(3 * w) - v / (3 * w) : rho0;
        tip_speed += w * w * rho + w * v;
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
        slide_term[b] = v;
        rotary_term[b] = {0.0, 0.0};
        for (int r : chain.rotaries(body.link)) {
          rotary_term[b][static_cast<size_t>(r)] = turn[static_cast<size_t>(r)] * chain.reach(body.link, r, body.centre, body.radius);
          v += rotary_term[b][static_cast<size_t>(r)];
        }
        speed[b] = v;
        relative[b] = body.link == chain.spindle_link()
                          ? tip_speed + relative_turn * ((body.centre - tip_local).norm() + body.radius)
                          : -1;
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
      if ((a.role == PlacedBody::Tool && a.tool != k) || (b.role == PlacedBody::Tool && b.tool != k)) continue;
      double v = 0;
      if (swept && (chain.carries(a.link, b.link) || chain.carries(b.link, a.link))) {
        // One carries the other: the joints between them alone.
        const bool a_carries = chain.carries(a.link, b.link);
        const SimBody& outer = a_carries ? b : a;
        const size_t o = static_cast<size_t>(a_carries ? p.b : p.a);
        const int inner = a_carries ? a.link : b.link;
        const std::vector<int>& outer_slides = chain.slides(outer.link);
        if (outer_slides.size() > chain.slides(inner).size()) v += slide_term[o];
        for (int r : chain.rotaries(outer.link)) {
          const std::vector<int>& held = chain.rotaries(inner);
          if (std::find(held.begin(), held.end(), r) == held.end()) v += rotary_term[o][static_cast<size_t>(r)];
        }
      } else if (swept) {
        v = speed[static_cast<size_t>(p.a)] + speed[static_cast<size_t>(p.b)];
      }
      // The spindle's link against the part's: their relative motion.
      if (swept && relative[static_cast<size_t>(p.a)] >= 0 && b.link == chain.part_link())
        v = std::min(v, relative[static_cast<size_t>(p.a)]);
      else if (swept && relative[static_cast<size_t>(p.b)] >= 0 && a.link == chain.part_link())
        v = std::min(v, relative[static_cast<size_t>(p.b)]);
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
        // A mesh (see "The bound"): once the pair has a closest approach m,
        // its box first — where that lies no nearer than m less a quarter
        // of the allowance, it is the sample (a lower bound stepping on by
        // at least 3/4 of the allowance) — then the mesh, asked only
        // whether it lies nearer than mesh_seed(m): a sample nearer is
        // measured exactly, else that is its lower bound.
        const Eigen::Isometry3d& pa = link_pose[static_cast<size_t>(a.link)];
        const Eigen::Isometry3d& pb = link_pose[static_cast<size_t>(b.link)];
        const double best = p.best.distance_mm;
        bool bounded = false;
        double d = 0;
        std::array<int, 2> triangles{-1, -1};
        if ((a.mesh || b.mesh) && std::isfinite(best)) {
          // A box overlapping (0 apart) says nothing: the mesh is asked.
          const double floor = std::max(best - 0.25 * allowance(best), kSeedFloor);
          d = sim_coarse_distance(a, pa, b, pb);
          bounded = true;
          if (d < floor)
            d = sim_pair_distance(a, pa, b, pb, std::max(mesh_seed(best), kSeedFloor), &bounded, nullptr, nullptr,
                                  &triangles);
        } else {
          d = sim_pair_distance(a, pa, b, pb, kSimInf, nullptr, nullptr, nullptr, &triangles);
        }
        ++report.queries;
        ++p.best.queries;
        if (!bounded && d < p.best.distance_mm) {
          p.best.a = sim_name_at(a, triangles[0]);
          p.best.b = sim_name_at(b, triangles[1]);
          p.best.distance_mm = d;
          p.best.block = static_cast<long>(i);
          p.best.line = got.line;
          p.best.t = t;
          p.best.axes = posed_q;
          p.best.tool = got.tool;
        }
        if (!bounded && d <= 0) {
          block_collided = true;
          const BodyApproach& f = report.first_collision;
          if (!report.collided || (static_cast<long>(i) == f.block && t < f.t)) {
            report.first_collision = p.best;
            report.first_collision.distance_mm = d;
            report.first_collision.t = t;
            report.first_collision.axes = posed_q;
            report.first_collision.block = static_cast<long>(i);
            report.first_collision.line = got.line;
            report.first_collision.tool = got.tool;
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
  // One entry per pair of names: a tool part's slices are one body to the
  // reader (its nearest slice's approach; the slices' queries summed; beyond
  // the zone only if every slice stayed beyond it).
  for (SimPairState& p : pairs) {
    if (!std::isfinite(p.best.distance_mm)) continue;
    const double m = p.best.distance_mm;
    p.best.beyond_zone = m - zone > std::max(c, 0.1 * m);
    auto same = std::find_if(report.closest.begin(), report.closest.end(),
                             [&](const BodyApproach& x) { return x.a == p.best.a && x.b == p.best.b; });
    if (same == report.closest.end()) {
      report.closest.push_back(p.best);
      continue;
    }
    const long queries = same->queries + p.best.queries;
    const bool beyond = same->beyond_zone && p.best.beyond_zone;
    if (m < same->distance_mm) *same = p.best;
    same->queries = queries;
    same->beyond_zone = beyond;
  }
  std::sort(report.closest.begin(), report.closest.end(),
            [](const BodyApproach& x, const BodyApproach& y) { return x.distance_mm < y.distance_mm; });
  return report;
}

MachineScene machine_scene(const MachineDefinition& machine, const std::vector<SimTool>& tools,
                           const MachineSetupBodies& setup, const BodyApproach& at) {
  const SimWorld world = sim_world(machine, tools, setup);
  int k = 0;
  for (size_t j = 0; j < tools.size(); ++j)
    if (tools[j].number == at.tool) k = static_cast<int>(j);
  const MachineChain& chain = world.chains[static_cast<size_t>(k)];
  std::vector<Eigen::Isometry3d> link_pose;
  for (int l = 0; l < chain.links(); ++l) link_pose.push_back(chain.pose(l, at.axes));
  MachineScene scene;
  scene.at = at;
  std::vector<size_t> of_a, of_b;  // the bodies (tool slices: several) the pair names
  for (size_t i = 0; i < world.bodies.size(); ++i) {
    const SimBody& b = world.bodies[i];
    if (b.role == PlacedBody::Tool && b.tool != k) continue;
    PlacedBody placed = b.shape;
    placed.pose = link_pose[static_cast<size_t>(b.link)] * b.local;
    const bool is_a = sim_answers_to(b, at.a), is_b = sim_answers_to(b, at.b);
    placed.highlighted = is_a || is_b;
    if (is_a) of_a.push_back(i);
    if (is_b) of_b.push_back(i);
    scene.bodies.push_back(placed);
  }
  if (of_a.empty() || of_b.empty())
    throw ParameterError("at", "'" + at.a + "' / '" + at.b + "' is no pair of this machine's and setup's bodies");
  double best = kSimInf;
  for (size_t i : of_a)
    for (size_t j : of_b) {
      const SimBody &a = world.bodies[i], &b = world.bodies[j];
      Vec3 na = Vec3::Zero(), nb = Vec3::Zero();
      const double d = sim_pair_distance(a, link_pose[static_cast<size_t>(a.link)], b,
                                         link_pose[static_cast<size_t>(b.link)], kSimInf, nullptr, &na, &nb);
      if (d < best) {
        best = d;
        scene.nearest_a = na;
        scene.nearest_b = nb;
      }
    }
  return scene;
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
    if (n.beyond_zone)
      out << "PASS: no pair within the " << r.near_zone_mm << " mm near-miss zone (nearest sampled " << n.distance_mm
          << " mm: " << n.a << " / " << n.b << ", line " << n.line << ")";
    else
      out << "PASS: closest approach " << n.distance_mm << " mm (" << n.a << " / " << n.b << ", line " << n.line << ")";
  }
  out << ", clearance " << r.clearance_mm << " mm";
  if (r.unbounded_blocks > 0)
    out << ", " << r.unbounded_blocks << " vector-orientation blocks not bounded (first at line "
        << r.first_unbounded_line << ": sampled)";
  return out.str();
}

}  // namespace bliskrun
