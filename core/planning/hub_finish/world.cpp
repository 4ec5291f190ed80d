// What the hub finish proves against: the collision world (the neighbours
// with the whole tool, blade k and k+1 and the hub with the shank and
// holder, the hub inset for the cutter), the gouge guards over the design
// surfaces, and the flute above the ball against both closed blades.
#include <algorithm>
#include <memory>
#include <string>

#include "core/common/parallel.h"
#include "core/geometry/mesh.h"
#include "core/geometry/revolution_distance.h"
#include "core/planning/hub_finish/internal.h"

namespace bliskrun {

using hub_detail::hub_offset_out;

CollisionWorld hub_finish_world(const HubFinishRequest& rq, const std::vector<NamedMesh>& extra) {
  if (!rq.hub) throw ParameterError("hub", "the hub (a surface of revolution) is required");
  CollisionWorld w;
  auto add_faces = [&](const BladeFaces& f, const std::string& name, bool cutter) {
    if (!f.pressure || !f.suction) return;
    PartMask parts;
    parts.cutter = cutter;
    const double tol = cutter ? rq.mesh_tol_mm : 0.05;
    const CheckSurfaceOptions opt{parts, cutter ? 0.0 : tol};
    w.add(name + " pressure", tessellate(*f.pressure, tol), opt);
    w.add(name + " suction", tessellate(*f.suction, tol), opt);
    if (f.leading) w.add(name + " leading edge", tessellate(*f.leading, tol), opt);
    if (f.trailing) w.add(name + " trailing edge", tessellate(*f.trailing, tol), opt);
  };
  add_faces(rq.previous, "blade k-1", true);
  add_faces(rq.blade, "blade k (shank)", false);
  add_faces(rq.next, "blade k+1 (shank)", false);
  PartMask no_cutter;
  no_cutter.cutter = false;
  w.add("hub (shank)", std::make_shared<const RevolutionDistance>(*rq.hub, 1e-4), CheckSurfaceOptions{no_cutter, 0});
  PartMask cutter_only;
  cutter_only.shank = cutter_only.holder = false;
  // The cutter meets the hub by design: checked against the hub 0.2 mm
  // inside it, a guard against gross errors (the gouge guard measures what
  // it cuts). Closer, a motion along the hub would be proved in steps of a
  // few um (conservative advancement steps by the distance).
  const SurfaceOfRevolution inset = hub_offset_out(*rq.hub, -0.2);
  w.add("hub (cutter)", std::make_shared<const RevolutionDistance>(inset, 1e-5), CheckSurfaceOptions{cutter_only, 0});
  for (const NamedMesh& m : extra) w.add(m.name, m.mesh);
  return w;
}

namespace hub_detail {

void make_guards(const HubFinishRequest& rq, const ClosedRoot& blade, const ClosedRoot& next, const Surface& sector,
                 bool sector_flip, Guards& guards, CollisionWorld& own_world) {
  parallel_for_index(4, rq.threads, [&](size_t i) {
    if (i == 0)
      guards.blade = std::make_unique<GougeGuard>(*blade.surface, link_guard_sampling(*blade.surface, rq.guard_spacing_mm, false));
    else if (i == 1)
      guards.next = std::make_unique<GougeGuard>(*next.surface, link_guard_sampling(*next.surface, rq.guard_spacing_mm, false));
    else if (i == 2)
      guards.hub = std::make_unique<GougeGuard>(sector, link_guard_sampling(sector, rq.guard_spacing_mm, sector_flip));
    else if (!rq.world)
      own_world = hub_finish_world(rq);
  });
}

// A conical drum wheel of a barrel radius so large that it bulges outward
// by < 0.01 um: it encloses the cone.
std::unique_ptr<ToolBody> flute_body_of(const Tool& tool, double flute_from, const ClosedRoot& blade,
                                        const ClosedRoot& next, CollisionWorld& flute_world) {
  const double flute_top = tool.cutter().z_max();
  std::unique_ptr<ToolBody> flute_body;
  if (flute_top > flute_from + 0.1) {
    const double rf0 = tool.cutter().radius_at(flute_from), rf1 = tool.cutter().radius_at(flute_top - 1e-9);
    const Tool flute_tool =
        Tool::conical_drum_wheel({2 * rf0 + 2e-5, 2 * rf1 + 2e-5, 1e7, flute_top - flute_from, {}, {}});
    flute_body = std::make_unique<ToolBody>(flute_tool, 0.005);
    constexpr double kFluteMeshMm = 0.05;  // with that as margin: the flute keeps off the blades
    flute_world.add("blade k", tessellate(*blade.surface, kFluteMeshMm), {PartMask{}, kFluteMeshMm});
    flute_world.add("blade k+1", tessellate(*next.surface, kFluteMeshMm), {PartMask{}, kFluteMeshMm});
  }
  return flute_body;
}

}  // namespace hub_detail
}  // namespace bliskrun
