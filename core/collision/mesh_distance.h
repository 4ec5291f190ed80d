#pragma once
// FCL's distance between two triangle meshes as a lower bound, found
// approximately — what a conservative-advancement step needs, at a
// fraction of the exact traversal's cost where two long bodies run nearly
// parallel (a 120 mm shank beside a blade: thousands of box pairs lie
// within a few per cent of the nearest, and the exact traversal opens
// them all).
//
// With rel_err > 0 the traversal drops every pair of bounding volumes whose
// lower bound is within a factor (1 + rel_err) of the nearest pair found so
// far, so what it finds is at most (1 + rel_err) times the true distance;
// divided by (1 + rel_err), it bounds the true distance from below.
// fcl::distance cannot do this: FCL 0.7 copies DistanceRequest::rel_err
// into its traversal node before the request is set, so it is always 0.
#include "core/common/types.h"
#include "core/tools/fcl_fwd.h"

namespace bliskrun {

struct MeshDistanceBound {
  // At most the true distance and at least it over (1 + rel_err); `seed`
  // or more when nothing lies nearer than seed (found = false).
  double distance_mm = 0;
  bool found = false;
  // The pair of points found (in a's frame), when found: at distance
  // distance_mm * (1 + rel_err) of each other.
  Vec3 on_a = Vec3::Zero(), on_b = Vec3::Zero();
};

// a in its own frame, b placed in it by b_to_a. rel_err = 0 is the exact
// distance (within seed).
MeshDistanceBound mesh_distance_lower_bound(const fcl::BVHModel<fcl::OBBRSSd>& a,
                                            const fcl::BVHModel<fcl::OBBRSSd>& b, const Eigen::Isometry3d& b_to_a,
                                            double seed, double rel_err);

}  // namespace bliskrun
