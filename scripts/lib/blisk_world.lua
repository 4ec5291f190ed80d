-- Collision worlds of the built-in blisk, for the interference loop
-- (blisk paper §3.4): the check surfaces around one blade are the flanks and
-- edge rounds of its two neighbours and the hub. The blade being machined (its flanks and
-- edge rounds) is a check surface for the shank and holder only: the cutter is meant to
-- touch it.
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
-- opts.hub_stock: the stock still on the hub, mm (0): the hub again (as a
--   surface of revolution), for the shank and holder only, with that margin — an operation that runs before
--   the hub is finished keeps its shank and holder off the stock there (the
--   cutter cuts it; job.edge_finish after job.rough_channels).
-- opts.flank_stock: the stock still on blades, {{blade =, side =, stock =
--   mm, below =}, ...}: side "pressure" or "suction" (the flank trimmed
--   between the hub and opts.top, a surface of revolution, the casing by
--   default: the blank's top the roughing started from; with `below`, only
--   its strip up to `below` mm over the hub) or "leading" / "trailing" (the
--   edge round up to opts.top), with the stock as its margin, for the shank
--   and holder only (the cutter cuts stock). Distance to the face below the
--   stock is inside it: no mesh of the stock itself, the face's mesh (at
--   opts.chord_tol, its tolerance added to the margin; opts.meshes: a cache
--   shared with around_channel) measured with that margin.
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
    for _, edge in ipairs{"leading", "trailing"} do
      surfaces[#surfaces + 1] = {name = string.format("blade %d %s edge", b, edge),
                                 mesh = M.edge_round_mesh(blisk, b, edge, tol)}
    end
  end
  if opts.hub ~= false then
    surfaces[#surfaces + 1] = opts.analytic_hub and {name = "hub", revolution = blisk:hub(), chord_tol = tol}
                              or {name = "hub", surface = blisk:hub(), chord_tol = tol}
    if (opts.hub_stock or 0) > 0 then
      -- Measured without a mesh (analytic_hub's sphere cover, at most 0.01
      -- mm pessimistic, nothing against a margin this size): a second hub
      -- mesh was ~100 MB more in the blisk job.
      surfaces[#surfaces + 1] = {name = "hub's stock", revolution = blisk:hub(), chord_tol = tol,
                                 margin = opts.hub_stock, parts = {"shank", "holder"}, stock = true}
    end
  end
  local cache = opts.meshes or {}
  for _, f in ipairs(opts.flank_stock or {}) do
    assert(({pressure = true, suction = true, leading = true, trailing = true})[f.side],
           "flank_stock: side must be 'pressure', 'suction', 'leading' or 'trailing'")
    assert(type(f.stock) == "number" and f.stock > 0, "flank_stock: stock must be a number > 0 (mm)")
    local mesh, name
    if f.side == "leading" or f.side == "trailing" then
      cache[f.blade] = cache[f.blade] or {}
      cache[f.blade][f.side] = cache[f.blade][f.side] or M.edge_round(blisk, f.blade, f.side, opts.top).surface:tessellate(tol)
      mesh, name = cache[f.blade][f.side], string.format("blade %d %s edge's stock", f.blade, f.side)
    elseif f.below then
      -- The strip a drum finish leaves over the hub: the flank up to the hub
      -- raised by `below` (radially, at least that far along the flank).
      local key = string.format("%s below %g", f.side, f.below)
      cache[f.blade] = cache[f.blade] or {}
      if not cache[f.blade][key] then
        local raised = {}
        for i, q in ipairs(blisk:hub_meridian()) do raised[i] = {q[1], q[2] + f.below} end
        cache[f.blade][key] = bliskrun.trim_flank{flank = blisk:flank(f.blade, f.side), hub = blisk:hub(),
          casing = bliskrun.surface_of_revolution{meridian = raised}}:tessellate(tol)
      end
      mesh, name = cache[f.blade][key], string.format("blade %d %s's stock below %g mm", f.blade, f.side, f.below)
    else
      mesh = M.trimmed_flank_mesh(blisk, f.blade, f.side, opts.top, tol, cache)
      name = string.format("blade %d %s's stock", f.blade, f.side)
    end
    surfaces[#surfaces + 1] = {name = name, mesh = mesh, margin = f.stock + tol, parts = {"shank", "holder"},
                               stock = true}
  end
  if opts.own ~= false then
    -- The blade being machined, for the shank and holder only (the cutter
    -- touches it by design). The shank runs along it a fraction of a mm
    -- away, FCL's slowest case, so its mesh is coarser (0.05 mm) and that
    -- tolerance is added to the clearance against it.
    local own_tol = opts.own_chord_tol or 0.05
    for _, s in ipairs(M.own_surfaces(blisk, k, own_tol)) do surfaces[#surfaces + 1] = s end
  end
  return bliskrun.collision_world{surfaces = surfaces}
end

-- The world a channel is roughed in (job.rough_channels, bliskrun.channel_levels):
-- channel k lies between blade k's suction flank and blade k+1's pressure
-- flank. Both flanks of both blades and the hub, for every tool part: the
-- roughing's cutter keeps the stock off all of them (its clearance, the
-- hub's stock less an allowance, is the planner's; opts.face_margin, the
-- faces' stock beyond the hub's, is added on the flanks). Blades farther
-- round cannot be reached from inside the channel: the holder stands ~75 mm
-- up the tool, far over their tips.
-- The flanks are trimmed between the hub and the top (the casing, or
-- opts.top, the blank's top as a surface of revolution).
-- opts.chord_tol (0.01 mm), opts.face_margin (0), opts.meshes: a cache
-- {[blade] = {pressure =, suction =, leading =, trailing =}} of tessellations at chord_tol,
-- filled as needed and shared between channels.
function M.around_channel(blisk, k, opts)
  opts = opts or {}
  local n = blisk:blade_count()
  assert(math.type(k) == "integer" and k >= 1 and k <= n,
         string.format("channel %s does not exist; channels are 1..%d", tostring(k), n))
  local tol, cache = opts.chord_tol or 0.01, opts.meshes or {}
  local top = opts.top or blisk:casing()
  local surfaces = {}
  for _, b in ipairs{k, k % n + 1} do
    cache[b] = cache[b] or {}
    for _, side in ipairs{"suction", "pressure"} do
      surfaces[#surfaces + 1] = {name = string.format("blade %d %s", b, side),
                                 mesh = M.trimmed_flank_mesh(blisk, b, side, top, tol, cache),
                                 margin = opts.face_margin or 0}
    end
  end
  for _, b in ipairs{k, k % n + 1} do
    for _, edge in ipairs{"leading", "trailing"} do
      cache[b][edge] = cache[b][edge] or M.edge_round(blisk, b, edge, top).surface:tessellate(tol)
      surfaces[#surfaces + 1] = {name = string.format("blade %d %s edge", b, edge), mesh = cache[b][edge],
                                 margin = opts.face_margin or 0}
    end
  end
  -- The hub measured as a surface of revolution (each tool piece's sphere
  -- cover against its meridian within 1 um, never above the true distance)
  -- rather than a mesh of the whole wheel at tol: every step of a motion
  -- proof asked that mesh's FCL hierarchy, 17 % of the channel's planning
  -- CPU (bench/RESULTS.md), for the same proved moves; and no hub mesh is
  -- built or kept.
  surfaces[#surfaces + 1] = {name = "hub", revolution = blisk:hub(), chord_tol = 1e-3}
  return bliskrun.collision_world{surfaces = surfaces}
end

-- Blade b's flank `side` as the blade is: from the hub to `top` (a surface
-- of revolution; the casing by default) — the flank's grid reaches past the
-- casing, up to 7 mm at the inlet, where no material is (the shank passes
-- there) — tessellated at tol mm. cache (optional): {[b] = {[side] = mesh}},
-- filled as needed (around_channel's `meshes`; one top per cache).
function M.trimmed_flank_mesh(blisk, b, side, top, tol, cache)
  cache = cache or {}
  cache[b] = cache[b] or {}
  cache[b][side] = cache[b][side] or bliskrun.trim_flank{flank = blisk:flank(b, side), hub = blisk:hub(),
                                                         casing = top or blisk:casing()}:tessellate(tol)
  return cache[b][side]
end

-- Blade b's leading or trailing edge round (bliskrun.edge_region, no
-- overlap onto the flanks) from the hub row up to the top (the casing, or a
-- surface of revolution `top`): the flank's grid reaches past the casing,
-- where no material is.
function M.edge_round(blisk, b, edge, top)
  local first, second = blisk:flank(b, "pressure"), blisk:flank(b, "suction")
  if edge == "trailing" then first, second = second, first end
  top = top or blisk:casing()
  -- The span where the edge end (first's v = 0) meets the top: its foot on
  -- the top's surface lies along the top's normal from it, outward there.
  local function above(u)
    local p = first:point(u, 0)
    local f = top:project(p)
    local n = top:eval(f.u, f.v).normal
    local d = (p.x - f.point.x) * n.x + (p.y - f.point.y) * n.y + (p.z - f.point.z) * n.z
    local out = n.x * p.x + n.y * p.y  -- the normal's sense away from the axis
    return (out >= 0) == (d >= 0) and f.distance > 0
  end
  local lo, hi = 0, 1
  if above(1) then
    for _ = 1, 40 do
      local m = 0.5 * (lo + hi)
      if above(m) then hi = m else lo = m end
    end
  else
    hi = 1
  end
  return bliskrun.edge_region{first = first, second = second, overlap = 0, span = {0, hi}}
end

-- Blade b's faces as bliskrun.hub_finish takes them (its blade, next and
-- previous): both flanks and both edge rounds (edge_round, up to the
-- casing; check surfaces of its world: the flanks end where the rounds
-- begin, and a round stands up to its radius in front of them).
function M.blade_faces(blisk, b)
  return {pressure = blisk:flank(b, "pressure"), suction = blisk:flank(b, "suction"),
          leading = M.edge_round(blisk, b, "leading").surface, trailing = M.edge_round(blisk, b, "trailing").surface}
end

-- One blade's face (a flank, "pressure" or "suction", or an edge round,
-- "leading" or "trailing") tessellated at `tol` (mm), once per blisk,
-- blade, face and tolerance, when first asked: a world around one blade
-- asks only its neighbours'. Shared by the worlds below and the part's
-- bodies in the machine simulation (part_bodies).
local face_cache = setmetatable({}, {__mode = "k"})
local function face_mesh(blisk, b, face, tol)
  local by_tol = face_cache[blisk] or {}
  face_cache[blisk] = by_tol
  by_tol[tol] = by_tol[tol] or {}
  local key = b .. " " .. face
  local mesh = by_tol[tol][key]
  if not mesh then
    local surface = (face == "leading" or face == "trailing") and M.edge_round(blisk, b, face).surface
                    or blisk:flank(b, face)
    mesh = surface:tessellate(tol)
    by_tol[tol][key] = mesh
  end
  return mesh
end

-- Blade k's own faces as check surfaces for the shank and holder only (the
-- cutter touches the blade by design; a planner's traverse world gives them
-- back to it, CollisionWorld::unchecked_pairs): both flanks and both edge
-- rounds, tessellated at `tol` with `tol` as their margin (a chord of the
-- convex blade lies up to tol inside it). The rounds too: the flanks end
-- where the rounds begin, and a round stands up to its radius (0.3-0.4 mm)
-- in front of the line between the flanks' ends, where a shank passing the
-- blade's own edge was checked against nothing.
function M.own_surfaces(blisk, k, tol)
  local out = {}
  for _, side in ipairs{"pressure", "suction"} do
    out[#out + 1] = {name = string.format("blade %d %s (own)", k, side), mesh = face_mesh(blisk, k, side, tol),
                     margin = tol, parts = {"shank", "holder"}}
  end
  for _, edge in ipairs{"leading", "trailing"} do
    out[#out + 1] = {name = string.format("blade %d %s edge (own)", k, edge), mesh = face_mesh(blisk, k, edge, tol),
                     margin = tol, parts = {"shank", "holder"}}
  end
  return out
end

-- Every blade's flanks at `tol`: meshes[b].pressure, meshes[b].suction.
function M.flank_meshes(blisk, tol)
  local meshes = {}
  for b = 1, blisk:blade_count() do
    meshes[b] = {pressure = face_mesh(blisk, b, "pressure", tol), suction = face_mesh(blisk, b, "suction", tol)}
  end
  return meshes
end

-- Blade b's leading or trailing edge round (edge_round, up to the casing)
-- at `tol`. The built-in blisk's flanks end where its rounds begin, and a
-- round stands up to its radius (0.3-0.4 mm) in front of the line between
-- the flanks' ends: without them a shank passing a neighbour's edge was
-- checked against nothing there (the blisk job's trailing-edge mill, 21 um
-- into blade 2's round, found by the machine simulation once the rounds
-- were bodies).
function M.edge_round_mesh(blisk, b, edge, tol)
  assert(edge == "leading" or edge == "trailing", "edge_round_mesh: edge must be 'leading' or 'trailing'")
  return face_mesh(blisk, b, edge, tol)
end

-- The blisk's blades as bodies of the machine simulation (post.write's
-- `part`): all blades as one mesh body "blades", each blade's two flanks
-- and two edge rounds named after it (mesh_names), in the part frame, the tolerance as margin
-- — the meshes the worlds check the shank and holder against (the own
-- blade's, 0.05 mm). One body, as for the impeller (impeller_world's
-- part_bodies): one pair per machine body or tool part, the far blades
-- pruned by one hierarchy. The disc under them is the recipe's stock.
function M.part_bodies(blisk, tol)
  tol = tol or 0.05
  local body = {name = "blades", meshes = {}, mesh_names = {}, margin = tol}
  for b, m in ipairs(M.flank_meshes(blisk, tol)) do
    for _, side in ipairs{"pressure", "suction"} do
      body.meshes[#body.meshes + 1] = m[side]
      body.mesh_names[#body.mesh_names + 1] = "blade " .. b
    end
    for _, edge in ipairs{"leading", "trailing"} do  -- and its edge rounds (edge_round_mesh)
      body.meshes[#body.meshes + 1] = M.edge_round_mesh(blisk, b, edge, tol)
      body.mesh_names[#body.mesh_names + 1] = "blade " .. b
    end
  end
  return {body}
end

-- The worlds around every blade (k = 1..N), each flank and the hub
-- tessellated once and shared; the same check surfaces as around_blade
-- (neighbours, hub, the blade itself, flanks and rounds, for the shank and
-- holder). opts as for around_blade.
function M.all_blades(blisk, opts)
  opts = opts or {}
  local n = blisk:blade_count()
  local tol = opts.chord_tol or 0.01
  local meshes = M.flank_meshes(blisk, tol)
  local hub = opts.hub ~= false and blisk:hub():tessellate(tol) or nil
  local own_tol = opts.own_chord_tol or 0.05
  local worlds = {}
  for k = 1, n do
    local surfaces = {}
    for _, b in ipairs{(k - 2) % n + 1, k % n + 1} do
      for _, side in ipairs{"pressure", "suction"} do
        surfaces[#surfaces + 1] = {name = string.format("blade %d %s", b, side), mesh = meshes[b][side]}
      end
      for _, edge in ipairs{"leading", "trailing"} do
        surfaces[#surfaces + 1] = {name = string.format("blade %d %s edge", b, edge),
                                   mesh = M.edge_round_mesh(blisk, b, edge, tol)}
      end
    end
    if hub then surfaces[#surfaces + 1] = {name = "hub", mesh = hub} end
    if opts.own ~= false then
      for _, s in ipairs(M.own_surfaces(blisk, k, own_tol)) do surfaces[#surfaces + 1] = s end
    end
    worlds[k] = bliskrun.collision_world{surfaces = surfaces}
  end
  return worlds
end

return M
