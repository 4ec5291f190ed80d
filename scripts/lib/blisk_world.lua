-- Collision worlds of the built-in blisk, for the interference loop
-- (blisk paper §3.4): the check surfaces around one blade are the flanks of
-- its two neighbours and the hub. The blade being machined is not a check
-- surface: the tool is meant to touch it.
--
--   local blisk_world = require("blisk_world")
--   local world = blisk_world.around_blade(blisk, 1, {chord_tol = 0.01})
--   local worlds = blisk_world.all_blades(blisk)   -- worlds[k] around blade k

local M = {}

-- blisk: a bliskrun.blisk{...}; k: blade number (1..N).
-- opts.chord_tol: tessellation tolerance of the check surfaces, mm (0.01).
-- opts.hub: include the hub (true).
-- opts.analytic_hub: measure the hub as a surface of revolution (each tool
--   piece's sphere cover against its meridian) instead of a mesh (false).
--   The edge finish's cutter runs along the hub near the root, and there a
--   mesh was its dearest FCL query (a third of the world checks' time on the
--   built-in LE). Not the default: the cover stands up to 0.01 mm outside
--   the tool, and the drum wheel, which runs that close to the hub, then
--   had 194 poses of a suction flank refused.
function M.around_blade(blisk, k, opts)
  opts = opts or {}
  local n = blisk:blade_count()
  assert(math.type(k) == "integer" and k >= 1 and k <= n,
         string.format("blade %s does not exist; blades are 1..%d", tostring(k), n))
  local tol = opts.chord_tol or 0.01
  local before, after = (k - 2) % n + 1, k % n + 1
  local surfaces = {}
  for _, b in ipairs{before, after} do
    for _, side in ipairs{"pressure", "suction"} do
      surfaces[#surfaces + 1] = {name = string.format("blade %d %s", b, side),
                                 surface = blisk:flank(b, side), chord_tol = tol}
    end
  end
  if opts.hub ~= false then
    surfaces[#surfaces + 1] = opts.analytic_hub and {name = "hub", revolution = blisk:hub(), chord_tol = tol}
                              or {name = "hub", surface = blisk:hub(), chord_tol = tol}
  end
  if opts.own ~= false then
    -- The blade being machined, for the shank and holder only (the cutter
    -- touches it by design). The shank runs along it a fraction of a mm
    -- away, FCL's slowest case, so its mesh is coarser (0.05 mm) and that
    -- tolerance is added to the clearance against it.
    local own_tol = opts.own_chord_tol or 0.05
    for _, side in ipairs{"pressure", "suction"} do
      surfaces[#surfaces + 1] = {name = string.format("blade %d %s (own)", k, side), surface = blisk:flank(k, side),
                                 chord_tol = own_tol, margin = own_tol, parts = {"shank", "holder"}}
    end
  end
  return bliskrun.collision_world{surfaces = surfaces}
end

-- The worlds around every blade (k = 1..N), each flank and the hub
-- tessellated once and shared; the same check surfaces as around_blade
-- (neighbours, hub, the blade itself for the shank). opts as for around_blade.
function M.all_blades(blisk, opts)
  opts = opts or {}
  local n = blisk:blade_count()
  local tol = opts.chord_tol or 0.01
  local meshes = {}
  for b = 1, n do
    meshes[b] = {}
    for _, side in ipairs{"pressure", "suction"} do meshes[b][side] = blisk:flank(b, side):tessellate(tol) end
  end
  local hub = opts.hub ~= false and blisk:hub():tessellate(tol) or nil
  local own_tol = opts.own_chord_tol or 0.05
  local own = {}
  if opts.own ~= false then
    for b = 1, n do
      own[b] = {}
      for _, side in ipairs{"pressure", "suction"} do own[b][side] = blisk:flank(b, side):tessellate(own_tol) end
    end
  end
  local worlds = {}
  for k = 1, n do
    local surfaces = {}
    for _, b in ipairs{(k - 2) % n + 1, k % n + 1} do
      for _, side in ipairs{"pressure", "suction"} do
        surfaces[#surfaces + 1] = {name = string.format("blade %d %s", b, side), mesh = meshes[b][side]}
      end
    end
    if hub then surfaces[#surfaces + 1] = {name = "hub", mesh = hub} end
    if own[k] then
      for _, side in ipairs{"pressure", "suction"} do
        surfaces[#surfaces + 1] = {name = string.format("blade %d %s (own)", k, side), mesh = own[k][side],
                                   margin = own_tol, parts = {"shank", "holder"}}
      end
    end
    worlds[k] = bliskrun.collision_world{surfaces = surfaces}
  end
  return worlds
end

return M
