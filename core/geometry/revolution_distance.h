#pragma once
// Distance from points to a surface of revolution about Z, in its meridian
// plane: the surface is the meridian turned about the axis, so the nearest
// point of it to q lies in q's own meridian half-plane, and the 3-D
// distance is the 2-D distance from (z, |q_xy|) to the meridian curve.
//
// What it is for: proving a ball that runs along a hub clear of the hub
// without a mesh. A hub tessellated finely enough for the proof has
// hundreds of thousands of triangles, and every conservative-advancement
// step of a motion along it is an FCL traversal of them; here a step is a
// descent of a small box tree over the meridian's segments.
//
// The meridian is held as a polyline within chord_tol_mm of the curve, and
// that tolerance is taken off every distance: a distance returned is never
// larger than the distance to the true surface. Like a mesh of the
// surface, the polyline ends where the meridian does: a point beyond an end
// is measured to the end's circle.
#include <vector>

#include "core/common/types.h"
#include "core/geometry/revolution.h"

namespace bliskrun {

class RevolutionDistance {
 public:
  // The meridian of `surface` sampled until the polyline lies within
  // chord_tol_mm of it (measured between samples). Throws
  // ParameterError("chord_tol") unless 0 < chord_tol_mm.
  RevolutionDistance(const SurfaceOfRevolution& surface, double chord_tol_mm);
  // A meridian polyline of (z, r) points (r >= 0, at least 2) taken as the
  // surface itself, within chord_tol_mm (>= 0) of the true one.
  RevolutionDistance(std::vector<Vec2> meridian_zr, double chord_tol_mm);

  double chord_tol_mm() const { return chord_tol_mm_; }
  int segment_count() const { return static_cast<int>(zr_.size()) - 1; }

  // Distance from q to the surface less the polyline's tolerance (never
  // below 0), resolved only up to `bound`: a point farther returns `bound`
  // itself, quickly. `nearest`, when given and resolved, receives the
  // nearest point of the polyline's surface.
  double distance(const Vec3& q, double bound, Vec3* nearest = nullptr) const;

 private:
  struct Node {
    Vec2 lo = Vec2::Zero(), hi = Vec2::Zero();  // box of the segments below, (z, r)
    int first = 0, count = 0;  // segments [first, first + count)
    int left = -1, right = -1;
  };
  int build(int first, int count);

  std::vector<Vec2> zr_;
  double chord_tol_mm_ = 0;
  std::vector<Node> nodes_;
};

}  // namespace bliskrun
