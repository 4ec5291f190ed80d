#include "core/collision/collision_world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <unordered_map>
#include <vector>

#include <fcl/fcl.h>

#include "core/collision/mesh_distance.h"
#include "core/common/exact_point.h"
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

ToolBody::ToolBody(Tool tool, double tol_mm) : tool_(std::move(tool)), parts_(fcl_parts(tool_, tol_mm)) {}

double ToolBody::overestimate_mm() const {
  double e = 0;
  for (const FclToolPart& p : parts_) e = std::max(e, p.overestimate_mm);
  return e;
}

namespace {

// One vertex of every connected piece of the mesh (triangles sharing a
// vertex index are connected).
std::vector<Vec3> piece_vertices(const TriangleMesh& mesh) {
  std::vector<int> parent(mesh.vertices.size());
  for (size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int k = 1; k < 3; ++k) parent[find(t[k])] = find(t[0]);
  }
  std::vector<Vec3> out;
  std::vector<bool> seen(parent.size(), false);
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const int root = find(t[0]);
    if (!seen[root]) {
      seen[root] = true;
      out.push_back(mesh.vertices[t[0]]);
    }
  }
  return out;
}

// Distance of a tool piece (its sphere cover, placed by `frame`) from a
// surface of revolution, resolved below `bound` (returned when farther).
// Groups whose bounding sphere is beyond the bound are skipped whole.
double cover_distance(const RevolutionDistance& surface, const SphereCover& cover, const Eigen::Isometry3d& frame,
                      double bound, Vec3* on_object, Vec3* on_tool) {
  const Vec3 origin = frame.translation();
  const Vec3 axis = frame.linear().col(2);
  double best = bound;
  for (const SphereCover::Group& g : cover.groups) {
    const double r = g.bound.radius;
    if (surface.distance(origin + g.bound.z * axis, best + r) - r >= best) continue;
    for (int j = g.first; j < g.first + g.count; ++j) {
      const AxisSphere& s = cover.spheres[static_cast<size_t>(j)];
      const Vec3 c = origin + s.z * axis;
      Vec3 foot;
      // Unresolved, the query returns its bound, and (best + r) - r can
      // round one unit below best: that must not pass as a nearer point
      // (its foot is unset; the part's nearest surface was misnamed).
      const double bound_here = best + s.radius;
      const double raw = surface.distance(c, bound_here, &foot);
      const double d = raw - s.radius;
      if (raw < bound_here && d < best) {
        best = d;
        *on_object = foot;
        const Vec3 to = foot - c;
        *on_tool = to.norm() > 0 ? Vec3(c + to.normalized() * s.radius) : c;
      }
    }
  }
  return best;
}

}  // namespace

bool PartMask::has(ToolPartId part) const {
  switch (part) {
    case ToolPartId::Cutter: return cutter;
    case ToolPartId::Shank: return shank;
    case ToolPartId::Holder: return holder;
  }
  return true;
}

void CollisionWorld::check_name(const std::string& name, const CheckSurfaceOptions& options) const {
  const PartMask& parts = options.parts;
  if (!parts.cutter && !parts.shank && !parts.holder)
    throw ParameterError(name, "a check surface must be checked against at least one tool part");
  if (!(options.margin_mm >= 0) || !std::isfinite(options.margin_mm))
    throw ParameterError(name, "the margin of a check surface must be a non-negative length");
  if (name.empty()) throw ParameterError("name", "a check surface needs a name");
  for (const Object& o : objects_) {
    if (o.name == name) throw ParameterError("name", "check surface '" + name + "' is already in the world");
  }
}

void CollisionWorld::add(const std::string& name, std::shared_ptr<const RevolutionDistance> surface,
                         CheckSurfaceOptions options) {
  check_name(name, options);
  if (!surface) throw ParameterError(name, "no surface of revolution given");
  Object o;
  o.name = name;
  o.revolution = std::move(surface);
  o.options = options;
  objects_.push_back(std::move(o));
}

struct CollisionWorld::PreparedSurface::Built {
  Object object;
  bool added = false;  // moved into a world (copies of a PreparedSurface share it)
};

void CollisionWorld::add(const std::string& name, const TriangleMesh& mesh, CheckSurfaceOptions options) {
  check_name(name, options);  // before the BVH is built for a name already taken
  add(prepare(name, mesh, options));
}

void CollisionWorld::add(PreparedSurface prepared) {
  if (!prepared.built_) throw ParameterError("surface", "not prepared (CollisionWorld::prepare)");
  if (prepared.built_->added) throw ParameterError(prepared.built_->object.name, "already added to a world");
  Object& o = prepared.built_->object;
  check_name(o.name, o.options);
  objects_.push_back(std::move(o));
  prepared.built_->added = true;
}

CollisionWorld::PreparedSurface CollisionWorld::prepare(const std::string& name, const TriangleMesh& mesh,
                                                        CheckSurfaceOptions options) {
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
  PreparedSurface out;
  out.built_ = std::make_shared<PreparedSurface::Built>(PreparedSurface::Built{
      Object{name, std::move(model), nullptr, static_cast<int>(mesh.triangles.size()), piece_vertices(mesh), options},
      false});
  return out;
}

std::string describe(const PoseCheck& c, const CollisionWorld& world) {
  if (c.worst < 0) return "collides";
  const PartClearance& p = c.parts[static_cast<size_t>(c.worst)];
  std::string what = std::string(to_string(p.part)) + " ";
  what += p.object >= 0 ? "against " + world.name(p.object) : "against a check surface";
  return what + " (margin " + std::to_string(c.min_margin_mm) + " mm)";
}

PoseCheck CollisionWorld::check(const ToolBody& body, const ToolPose& pose, const Clearances& clearances,
                                double horizon_mm) const {
  validate(clearances);
  if (std::isnan(horizon_mm) || horizon_mm < 0) throw ParameterError("horizon", "must be a non-negative length");
  std::vector<std::vector<double>> bound;
  for (const FclToolPart& part : body.parts())
    bound.emplace_back(part.pieces.size(), clearances.of(part.id) + horizon_mm);
  return check_bounded(body, tool_to_part(pose), clearances, bound, nullptr);
}

std::shared_ptr<const CollisionWorld> CollisionWorld::unchecked_pairs() const {
  auto out = std::make_shared<CollisionWorld>();
  for (const Object& o : objects_) {
    const PartMask& m = o.options.parts;
    if ((m.cutter && m.shank && m.holder) || o.options.stock) continue;
    Object left = o;
    left.options.parts = PartMask{!m.cutter, !m.shank, !m.holder};
    out->objects_.push_back(std::move(left));
  }
  if (out->objects_.empty()) return nullptr;
  return out;
}

std::shared_ptr<const CollisionWorld> CollisionWorld::without_triangles(const TriangleFilter& drop) const {
  auto out = std::make_shared<CollisionWorld>();
  for (const Object& o : objects_) {
    if (!o.model) {
      out->objects_.push_back(o);
      continue;
    }
    // FCL keeps each triangle's corners apart (addTriangle); equal
    // coordinates are made one vertex again, so the connected pieces (the
    // containment test's) are what they were.
    const fcl::BVHModel<fcl::OBBRSSd>& m = *o.model;
    TriangleMesh kept;
    std::unordered_map<Vec3, int, ExactPointHash, ExactPointEqual> index;
    auto vertex = [&](const Vec3& p) {
      const auto [it, added] = index.emplace(p, static_cast<int>(kept.vertices.size()));
      if (added) kept.vertices.push_back(p);
      return it->second;
    };
    for (int t = 0; t < m.num_tris; ++t) {
      const fcl::Triangle& tri = m.tri_indices[t];
      const Vec3 a = m.vertices[tri[0]], b = m.vertices[tri[1]], c = m.vertices[tri[2]];
      if (!drop(a, b, c)) kept.triangles.emplace_back(vertex(a), vertex(b), vertex(c));
    }
    if (kept.triangles.size() == static_cast<size_t>(m.num_tris)) out->objects_.push_back(o);
    else if (!kept.triangles.empty()) out->objects_.push_back(prepare(o.name, kept, o.options).built_->object);
  }
  if (out->objects_.empty()) return nullptr;
  return out;
}

std::vector<int>& CollisionWorld::nearest_hints(size_t parts) const {
  // Per thread (queries run on many), per world. A world freed and another
  // made at its address inherits stale hints: harmless, they only order.
  thread_local std::unordered_map<const CollisionWorld*, std::vector<int>> hints;
  if (hints.size() > 64 && !hints.count(this)) hints.clear();
  std::vector<int>& mine = hints[this];
  if (mine.size() < parts * kHintPieces) mine.resize(parts * kHintPieces, 0);
  for (int& h : mine)
    if (h >= size()) h = 0;
  return mine;
}

PoseCheck CollisionWorld::check_bounded(const ToolBody& body, const Eigen::Isometry3d& frame,
                                        const Clearances& clearances, const std::vector<std::vector<double>>& bound,
                                        std::vector<std::vector<double>>* piece_distance, bool coarse_far) const {
  PoseCheck out;
  out.min_margin_mm = std::numeric_limits<double>::infinity();
  fcl::DistanceRequestd request;
  request.enable_nearest_points = true;
  const fcl::Transform3d identity = fcl::Transform3d::Identity();
  const Eigen::Isometry3d to_tool = frame.inverse();
  if (piece_distance) piece_distance->assign(body.parts().size(), {});
  std::vector<int>& hints = nearest_hints(body.parts().size());
  for (size_t p = 0; p < body.parts().size(); ++p) {
    const FclToolPart& part = body.parts()[p];
    PartClearance pc;
    pc.part = part.id;
    pc.distance_mm = std::numeric_limits<double>::infinity();
    pc.resolved = false;
    // A piece wholly inside the part crosses no face: test one vertex each.
    for (int i = 0; i < size() && !pc.collides; ++i) {
      if (!objects_[i].options.parts.has(part.id)) continue;
      for (const Vec3& v : objects_[i].piece_vertices) {
        const Vec3 in_tool = to_tool * v;
        if (body.tool().signed_distance(in_tool, part.id) <
            part.overestimate_at(in_tool.z()) + objects_[i].options.margin_mm) {
          pc.collides = pc.resolved = true;
          pc.distance_mm = 0;
          pc.object = i;
          pc.on_tool = pc.on_object = v;
          break;
        }
      }
    }
    // Each piece resolved up to its own bound: a motion check steps by each
    // piece's distance over its own speed.
    for (size_t k = 0; k < part.pieces.size() && !pc.collides; ++k) {
      // Never seed FCL with 0: an overlap reports distance 0, which would
      // not beat a zero seed and would pass as "clear" (clearance 0,
      // horizon 0).
      double best = std::max(bound[p][k], 1e-6);
      bool resolved = false;
      // The object nearest this piece at its last query on this thread is
      // asked first: the others are then pruned by its distance, not by the
      // bound (beside a neighbouring blade, its far flank costs a fraction).
      // The order changes the cost only: the minimum is the same.
      int& hint = hints[p * kHintPieces + std::min(k, kHintPieces - 1)];
      const int first = hint;  // the order is fixed before the loop updates the hint
      for (int n = 0; n < size(); ++n) {
        const int i = n == 0 ? first : (n <= first ? n - 1 : n);
        if (!objects_[i].options.parts.has(part.id)) continue;
        // A surface with a margin counts as that much nearer than its mesh.
        const double margin = objects_[i].options.margin_mm;
        if (objects_[i].revolution) {
          const double seed = best + margin;
          Vec3 on_object = Vec3::Zero(), on_tool = Vec3::Zero();
          const double d = cover_distance(*objects_[i].revolution, part.pieces[k].cover, frame, seed, &on_object,
                                          &on_tool);
          if (d < seed) {
            resolved = true;
            best = std::max(0.0, d - margin);
            hint = i;
            if (best < pc.distance_mm) {
              pc.object = i;
              pc.on_object = on_object;
              pc.on_tool = on_tool;
            }
            if (best <= 0) break;
          }
          continue;
        }
        fcl::DistanceResultd result;
        // Seeded with the best bound so far: FCL prunes every bounding
        // volume farther than that.
        const double seed = best + margin;
        result.min_distance = seed;
        const FclPiece& piece = part.pieces[k];
        if (coarse_far) {
          // A motion proof: a lower bound is all a step needs. The coarse
          // body (where the piece has one) by the approximate traversal
          // answers first; the fine body, exactly, only where either's error
          // could be a sizeable part of the margin to the clearance (then
          // the step would be much shorter than the exact distance allows).
          const fcl::BVHModel<fcl::OBBRSSd>& first_body = piece.coarse ? *piece.coarse : *piece.geometry;
          const double over = piece.coarse ? piece.coarse_overestimate_mm : 0.0;
          const MeshDistanceBound first =
              mesh_distance_lower_bound(*objects_[i].model, first_body, frame, seed, kFarRelErr);
          if (!(first.distance_mm < seed)) continue;
          result.min_distance = first.distance_mm;
          result.nearest_points[0] = first.on_a;
          result.nearest_points[1] = first.on_b;
          const double far = first.distance_mm - margin - clearances.of(part.id);
          if (far < kCoarseFarFactor * over || far < kCoarseFarFactor * kFarRelErr * first.distance_mm) {
            // The fine body exactly, from what the first answer found (at
            // most its error and the coarse body's overestimate above it).
            const fcl::DistanceResultd kept = result;
            const double fine_seed = std::min(seed, first.distance_mm * (1 + kFarRelErr) + over + 1e-9);
            result = fcl::DistanceResultd();
            result.min_distance = fine_seed;
            fcl::distance(objects_[i].model.get(), identity, piece.geometry.get(), frame, request, result);
            if (!(result.min_distance < fine_seed)) {
              if (fine_seed >= seed) continue;  // the fine body is no nearer than the seed either
              result = kept;                    // only by rounding: the first answer still bounds it
            }
          }
        } else {
          // Mesh first, tool second: nearest_points follow the argument order.
          fcl::distance(objects_[i].model.get(), identity, piece.geometry.get(), frame, request, result);
        }
        // Compared with the seed itself: (d + m) - m can round below d.
        if (result.min_distance < seed) {
          resolved = true;
          best = std::max(0.0, result.min_distance - margin);
          hint = i;
          if (best < pc.distance_mm) {
            pc.object = i;
            pc.on_object = result.nearest_points[0];
            pc.on_tool = result.nearest_points[1];
          }
          if (best <= 0) break;
        }
      }
      if (piece_distance) (*piece_distance)[p].push_back(best);
      if (best < pc.distance_mm || (best == pc.distance_mm && resolved)) {
        pc.distance_mm = best;
        pc.resolved = resolved;
      }
      if (best <= 0) {
        pc.collides = true;
        pc.distance_mm = 0;
      }
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
  validate(clearances);
  if (!(tol_mm > 0) || !std::isfinite(tol_mm)) throw ParameterError("tol_mm", "must be a positive length");
  if (max_samples < 1) throw ParameterError("max_samples", "must be at least 1");
  const PoseMotion motion(from, to);
  std::vector<std::vector<double>> speed, bound, distance;
  for (const FclToolPart& part : body.parts()) {
    speed.emplace_back();
    for (const FclPiece& piece : part.pieces) speed.back().push_back(motion.max_point_speed(piece.reach_mm));
    bound.emplace_back(part.pieces.size(), 0.0);
  }
  MotionCheck out;
  out.min_margin_mm = std::numeric_limits<double>::infinity();
  double t = 0;
  while (true) {
    // Resolve each distance only as far as it could matter: up to what
    // would carry the proof to t = 1 in one step.
    for (size_t p = 0; p < bound.size(); ++p) {
      const double c = clearances.of(body.parts()[p].id);
      for (size_t k = 0; k < bound[p].size(); ++k) bound[p][k] = c + std::max(0.0, speed[p][k] * (1 - t) - tol_mm);
    }
    const PoseCheck here = check_bounded(body, motion.frame_at(t), clearances, bound, &distance, true);
    ++out.samples;
    out.min_margin_mm = std::min(out.min_margin_mm, here.min_margin_mm);
    if (!here.clear) {
      out.clear = false;
      out.t = t;
      out.at = here;
      return out;
    }
    // Every piece may advance until it could have come within its part's
    // clearance (less tol_mm): its distance over its speed.
    double step = std::numeric_limits<double>::infinity();
    for (size_t p = 0; p < distance.size(); ++p) {
      const double c = clearances.of(body.parts()[p].id);
      for (size_t k = 0; k < distance[p].size(); ++k) {
        if (speed[p][k] <= 0) continue;
        step = std::min(step, (distance[p][k] - c + tol_mm) / speed[p][k]);
      }
    }
    if (t + step >= 1 - 1e-12) return out;
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

double CollisionWorld::motion_min_margin(const ToolBody& body, const ToolPose& from, const ToolPose& to,
                                         const Clearances& clearances, double tol_mm) const {
  if (!(tol_mm > 0)) throw ParameterError("tol", "expected a positive tolerance in mm");
  const PoseMotion motion(from, to);
  const double speed = motion.max_point_speed(body.tool().reach());
  auto margin = [&](double t) { return check(body, motion.pose_at(t), clearances).min_margin_mm; };
  double best = std::numeric_limits<double>::infinity();
  // Depth-first halving; the stack holds (t0, g0, t1, g1).
  struct Piece { double t0, g0, t1, g1; };
  std::vector<Piece> stack;
  constexpr int kStart = 8;  // a first even sample finds the low region early
  std::vector<double> g(kStart + 1);
  for (int i = 0; i <= kStart; ++i) best = std::min(best, g[i] = margin(double(i) / kStart));
  for (int i = kStart; i > 0; --i) stack.push_back({double(i - 1) / kStart, g[i - 1], double(i) / kStart, g[i]});
  while (!stack.empty()) {
    const Piece p = stack.back();
    stack.pop_back();
    if (0.5 * (p.g0 + p.g1 - speed * (p.t1 - p.t0)) >= best - tol_mm) continue;
    const double tm = 0.5 * (p.t0 + p.t1), gm = margin(tm);
    best = std::min(best, gm);
    stack.push_back({tm, gm, p.t1, p.g1});
    stack.push_back({p.t0, p.g0, tm, gm});
  }
  return best - tol_mm;
}

}  // namespace bliskrun
