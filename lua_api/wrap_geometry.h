#pragma once
// Lua handles of geometry values, shared by the wrappers of other subsystems
// (parts, analysis, planning) that take or return surfaces and grids.
#include <memory>
#include <string>

#include "core/geometry/curve.h"
#include "core/geometry/mesh.h"
#include "core/geometry/point_grid.h"
#include "core/geometry/revolution.h"
#include "core/geometry/surface.h"
#include "lua_api/luax.h"

namespace bliskrun::lua_api {

struct SurfaceHandle {
  std::shared_ptr<const Surface> surface;
};
struct CurveHandle {
  std::shared_ptr<const Curve> curve;
};
struct GridHandle {
  std::shared_ptr<const PointGrid> grid;
};
struct MeshHandle {
  std::shared_ptr<const TriangleMesh> mesh;
};

// Push a new handle of each kind.
void push_surface(lua_State* L, std::shared_ptr<const Surface> s);
void push_grid(lua_State* L, std::shared_ptr<const PointGrid> g);
void push_mesh(lua_State* L, std::shared_ptr<const TriangleMesh> m);
// A meridian line as {{z, r}, ...}.
void push_meridian(lua_State* L, const std::vector<Vec2>& meridian);
// The option `key` of `o`, when given, as a parameter window {lo, hi} with
// 0 <= lo < hi <= 1 (a surface's u or v range); errors name `what` and key.
void read_unit_window(lua_State* L, const luax::Options& o, const std::string& what, const char* key, double& lo,
                      double& hi);
// The option `key` of `o` as a surface of revolution (a hub or casing);
// errors name `what` and key.
std::shared_ptr<const SurfaceOfRevolution> revolution_option(lua_State* L, const luax::Options& o,
                                                             const std::string& key, const std::string& what);

}  // namespace bliskrun::lua_api

namespace bliskrun::luax {
template <> struct TypeName<lua_api::SurfaceHandle> { static constexpr const char* name = "bliskrun.Surface"; };
template <> struct TypeName<lua_api::CurveHandle> { static constexpr const char* name = "bliskrun.Curve"; };
template <> struct TypeName<lua_api::GridHandle> { static constexpr const char* name = "bliskrun.PointGrid"; };
template <> struct TypeName<lua_api::MeshHandle> { static constexpr const char* name = "bliskrun.Mesh"; };
}  // namespace bliskrun::luax
