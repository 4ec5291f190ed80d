#include "core/collision/collision_world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/common/error.h"

namespace bliskrun {

double Clearances::of(ToolPartId part) const {
  switch (part) {
    case ToolPartId::Cutter: return cutter_mm;
    case ToolPartId::Shank: return shank_mm;
    case ToolPartId::Holder: return holder_mm;
  }
  return 0;
}

namespace {

void validate(const Clearances& c) {
  for (const auto& [name, v] : {std::pair<const char*, double>{"clearance.cutter", c.cutter_mm},
                                {"clearance.shank", c.shank_mm},
                                {"clearance.holder", c.holder_mm}}) {
    if (!std::isfinite(v) || v < 0) throw ParameterError(name, "must be a non-negative length in mm");
  }
}

}  // namespace

ToolBody::ToolBody(Tool tool, double tol_mm) : tool_(std::move(tool)), parts_(fcl_parts(tool_, tol_mm)) {
  for (FclToolPart& p : parts_) p.geometry->computeLocalAABB();
}

double ToolBody::overestimate_mm() const {
  double e = 0;
  for (const FclToolPart& p : parts_) e = std::max(e, p.overestimate_mm);
  return e;
}

void CollisionWorld::add(const std::string& name, const TriangleMesh& mesh) {
  if (name.empty()) throw ParameterError("name", "a check surface needs a name");
  for (const Object& o : objects_) {
    if (o.name == name) throw ParameterError("name", "check surface '" + name + "' is already in the world");
  }
  if (mesh.triangles.empty()) throw ParameterError(name, "check surface mesh has no triangles");
  const int n = static_cast<int>(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) {
    if (!v.allFinite()) throw ParameterError(name, "check surface mesh has a non-finite vertex");
  }
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  model->beginModel(static_cast<int>(mesh.triangles.size()), n);
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Eigen::Vector3i& t = mesh.triangles[i];
    if (t.minCoeff() < 0 || t.maxCoeff() >= n) {
      std::ostringstream os;
      os << "triangle " << i << " refers to a vertex outside 0.." << n - 1;
      throw ParameterError(name, os.str());
    }
    model->addTriangle(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
  }
  model->endModel();
  model->computeLocalAABB();
  objects_.push_back(Object{name, std::move(model), static_cast<int>(mesh.triangles.size())});
}

PoseCheck CollisionWorld::check(const ToolBody& body, const ToolPose& pose, const Clearances& clearances) const {
  return check(body, tool_to_part(pose), clearances);
}

PoseCheck CollisionWorld::check(const ToolBody& body, const Eigen::Isometry3d& frame,
                                const Clearances& clearances) const {
  validate(clearances);
  PoseCheck out;
  out.min_margin_mm = std::numeric_limits<double>::infinity();
  fcl::DistanceRequestd request;
  request.enable_nearest_points = true;
  const fcl::Transform3d identity = fcl::Transform3d::Identity();
  for (const FclToolPart& part : body.parts()) {
    PartClearance pc;
    pc.part = part.id;
    pc.distance_mm = std::numeric_limits<double>::infinity();
    const fcl::Transform3d tf = frame * part.in_tool;
    for (int i = 0; i < size(); ++i) {
      fcl::DistanceResultd result;
      // Mesh first: FCL's BVH-shape traversal then reports nearest_points
      // in argument order (the shape-first call swaps them in FCL 0.7).
      fcl::distance(objects_[i].model.get(), identity, part.geometry.get(), tf, request, result);
      double d = result.min_distance;
      if (d <= 0) {
        pc.collides = true;
        d = 0;
      }
      if (d < pc.distance_mm) {
        pc.distance_mm = d;
        pc.object = i;
        pc.on_object = result.nearest_points[0];
        pc.on_tool = result.nearest_points[1];
      }
      if (pc.collides) break;
    }
    const double margin = pc.distance_mm - clearances.of(part.id);
    // A touching part is never clear, even with clearance 0.
    if (margin < 0 || pc.collides) out.clear = false;
    if (margin < out.min_margin_mm || out.worst < 0) {
      out.min_margin_mm = margin;
      out.worst = static_cast<int>(out.parts.size());
    }
    out.parts.push_back(pc);
  }
  return out;
}

MotionCheck CollisionWorld::check_motion(const ToolBody& body, const ToolPose& from, const ToolPose& to,
                                         const Clearances& clearances, double tol_mm, int max_samples) const {
  if (!(tol_mm > 0) || !std::isfinite(tol_mm)) throw ParameterError("tol_mm", "must be a positive length");
  if (max_samples < 1) throw ParameterError("max_samples", "must be at least 1");
  const PoseMotion motion(from, to);
  MotionCheck out;
  out.min_margin_mm = std::numeric_limits<double>::infinity();
  double t = 0;
  while (true) {
    const PoseCheck here = check(body, motion.frame_at(t), clearances);
    ++out.samples;
    out.min_margin_mm = std::min(out.min_margin_mm, here.min_margin_mm);
    if (!here.clear) {
      out.clear = false;
      out.t = t;
      out.at = here;
      return out;
    }
    double step = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < here.parts.size(); ++i) {
      const PartClearance& pc = here.parts[i];
      const double speed = motion.max_point_speed(body.parts()[i].reach_mm);
      if (speed <= 0) continue;
      step = std::min(step, (pc.distance_mm - clearances.of(pc.part) + tol_mm) / speed);
    }
    if (t + step >= 1) return out;
    if (out.samples >= max_samples) {
      out.clear = false;
      out.undecided = true;
      out.t = t;
      out.at = here;
      return out;
    }
    t += step;
  }
}

}  // namespace bliskrun
