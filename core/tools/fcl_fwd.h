#pragma once
// Forward declarations of the two FCL types that bliskrun's headers name
// (tool_fcl.h, collision_world.h hold meshes by shared_ptr). <fcl/fcl.h>
// is FCL's whole library of templates — ~3 s of parsing per translation
// unit, and 60-odd units reached it through planner headers — so only the
// .cpp files that call FCL (tool_fcl.cpp, collision_world.cpp,
// mesh_distance.cpp, machine_sim.cpp) include it. Must match
// fcl/math/bv/OBBRSS.h and fcl/geometry/bvh/BVH_model.h (FCL 0.7); a
// mismatch is a compile error in those files, not a silent one.
namespace fcl {
template <typename S_>
class OBBRSS;
using OBBRSSd = OBBRSS<double>;
template <typename BV>
class BVHModel;
}  // namespace fcl
