#include "core/collision/mesh_distance.h"

#include <limits>

#include <fcl/fcl.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>
#include <fcl/narrowphase/detail/traversal/distance/mesh_distance_traversal_node.h>

namespace bliskrun {

MeshDistanceBound mesh_distance_lower_bound(const fcl::BVHModel<fcl::OBBRSSd>& a,
                                            const fcl::BVHModel<fcl::OBBRSSd>& b, const Eigen::Isometry3d& b_to_a,
                                            double seed, double rel_err) {
  fcl::DistanceRequestd request;
  request.enable_nearest_points = true;
  fcl::DistanceResultd result;
  // What lies beyond seed (1 + rel_err) is not sought: nothing found means
  // nothing within seed.
  const double sought = seed * (1 + rel_err);
  result.min_distance = sought;
  fcl::detail::MeshDistanceTraversalNodeOBBRSS<double> node;
  fcl::detail::initialize(node, a, fcl::Transform3d::Identity(), b, b_to_a, request, result);
  node.rel_err = rel_err;
  node.abs_err = std::numeric_limits<double>::infinity();  // the relative test alone prunes
  fcl::detail::distance(&node, nullptr, 2);
  MeshDistanceBound out;
  out.found = result.min_distance < sought;
  out.distance_mm = out.found ? result.min_distance / (1 + rel_err) : seed;
  if (out.found) {
    out.on_a = result.nearest_points[0];
    out.on_b = result.nearest_points[1];
  }
  return out;
}

}  // namespace bliskrun
