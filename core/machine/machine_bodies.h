#pragma once
// The solids a machine is made of, for the machine simulation (machine_sim.h):
// each a simple primitive fixed to one link of the kinematic chain.
//
// Frames a body is fixed to (MachineBody::frame):
//   "base"       the machine bed: never moves;
//   "X" "Y" "Z"  a linear slide (MachineDefinition::tool_slides / part_slides
//                say which side each slide carries and in which order);
//   "A" "B" "C"  a rotary axis' carrier (the cradle, the table, the fork, the
//                head), as MachineDefinition::rotary names them;
//   "spindle"    the outermost link of the tool side (what the tool turns in);
//   "part"       the outermost link of the part side (fixture and stock).
// Coordinates are those of the kinematics with all axes at zero (home):
// links the Z slide carries (the Z slide itself, the head axes, "spindle")
// relative to the spindle gauge point at home — as head pivots are, so that
// the tool length lifts them in tip mode; "part" in the part frame
// (MachineDefinition::part_origin); every other link (the base, the other
// slides, the table axes) in the machine frame (program zero).
//
// Meshes. The part itself (a blisk's or an impeller's blades) comes in as
// triangle meshes — the tessellations the collision worlds check the tool
// against — placed in the part frame. A mesh is a surface, not a solid:
// a body wholly between two faces of a blade, crossing neither, is not
// seen; the blades are a few mm thick and no machine body is that thin.
#include <memory>
#include <string>
#include <vector>

#include "core/common/types.h"
#include "core/geometry/mesh.h"

namespace bliskrun {

enum class BodyShape { Box, Cylinder, Cone, Mesh };

struct MachineBody {
  std::string name;             // unique within the machine, for reports
  std::string frame = "base";   // see above
  BodyShape shape = BodyShape::Box;
  // Box: its two corners at home (edges along the frame's axes).
  Vec3 min_mm = Vec3::Zero(), max_mm = Vec3::Zero();
  // Cylinder: the axis' end centres `from` and `to`; cone: base centre `from`,
  // apex `to`. radius_mm: the cylinder's, the cone's base.
  Vec3 from_mm = Vec3::Zero(), to_mm = Vec3::Zero();
  double radius_mm = 0;
  // Mesh: its triangles (shared, not copied; several meshes make one body,
  // e.g. a blade's two flanks), placed by `placement` (frame coordinates
  // from the meshes'), and how far the true surface may lie from them
  // (mm; the tessellation's chord tolerance): the body counts that much
  // nearer than its triangles, so a distance is never above the truth.
  std::vector<std::shared_ptr<const TriangleMesh>> meshes;
  Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();
  double margin_mm = 0;
  // Mesh, optional: one name per mesh, the one a report gives where the
  // body's nearest point lies on that mesh. A part of many blades is one
  // body (one pair per machine body or tool part, not one per blade: the
  // HECC impeller's 30 blades made 579 pairs, each sampled on its own)
  // whose approaches still name the blade.
  std::vector<std::string> mesh_names;
};

// Centre and radius of a sphere holding the body (home coordinates; a
// mesh's placed, its margin included).
void bounding_sphere(const MachineBody& body, Vec3& centre_mm, double& radius_mm);

// Checks names (non-empty, unique), frames (one of `frames`), shapes
// (min < max on each box axis, from != to, radius > 0, all finite; a mesh
// with triangles, indices in range, finite vertices, margin >= 0). Throws
// ParameterError naming "<where>[i].<field>" ("bodies[3].radius").
void validate_bodies(const std::vector<MachineBody>& bodies, const std::vector<std::string>& frames,
                     const std::string& where);

}  // namespace bliskrun
