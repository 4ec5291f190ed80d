-- The blisk operations of a job (scripts/lib/job.lua is the entry): channel
-- roughing in levels, drum-wheel flank finishing, edge finishing with a
-- flat-end mill, the hub and blade roots with a ball end. Each is its option table, checked at the
-- recipe's line, and a plan_flanks(self, j) that plans its units (one per
-- flank, edge or root) and refuses to emit anything unproved. A blisk's
-- blades are one blade turned: with `periodic` the first blade is planned
-- and the others get its path turned by the pitch.
local options = require("job.options")
local geometry = require("job.geometry")

local check_options, positive, blade_list = options.check, options.positive, options.blade_list
local turned_moves, meridian_height = geometry.turned_moves, geometry.meridian_height

local M = {}

-- The blades of an operation planned once and turned (periodic) or each
-- planned: plan_blade(k) -> {{side =, plan =, report =, moves_list =}, ...}.
-- Returns the job's flank entries in blade order.
local function blades_of(self, j, plan_blade)
  local flanks, base, base_k = {}, nil, nil
  local n = j.part:blade_count()
  for _, k in ipairs(self.blades) do
    local units
    if self.periodic and base then
      units = {}
      for i, u in ipairs(base) do
        units[i] = {side = u.side, plan = u.plan, report = u.report, turned_from = base_k, flanks = u.flanks,
                    surface = u.surface, link_cutter = u.link_cutter,
                    moves_list = turned_moves(u.moves_list, 2 * math.pi * (k - base_k) / n)}
      end
    else
      units = plan_blade(k)
      base, base_k = units, k
    end
    for _, u in ipairs(units) do
      flanks[#flanks + 1] = {blade = k, side = u.side, plan = u.plan, report = u.report, feed = self.feed,
                             moves_list = u.moves_list, turned_from = u.turned_from, flanks = u.flanks,
                             surface = u.surface, link_cutter = u.link_cutter}
    end
  end
  return flanks
end

-- Channel roughing in levels (issue 41; bliskrun.channel_levels,
-- core/planning/channel_levels.h): channel k — between blade k's suction
-- flank and blade k+1's pressure flank — cleared from the blank's top (the
-- casing, or `top`, a surface of revolution) down to the hub in levels of
-- at most `step_down` mm, paths at most `step_over` mm apart, leaving
-- `stock` on both flanks and `hub_stock` on the hub within `scallop`; every
-- pose, motion and link proved against both blades and the hub with the
-- whole tool, the cutter kept the stock (less `allowance`) off them.
-- `blades` lists the channels by their first blade. Periodic by default:
-- the first channel planned, the others its path turned by the pitch.
function M.rough_channels(o)
  local function non_negative(v) if not (v >= 0) then return "expected >= 0 mm" end end
  check_options("job.rough_channels", o, {
    tool = {type = "string", required = true},
    blades = {type = "table", required = true, check = blade_list},
    stock = {type = "number", check = function(v) if not (v > 0 and v < 10) then return "expected 0 < stock < 10 mm" end end},
    hub_stock = {type = "number", check = function(v) if not (v > 0 and v < 10) then return "expected 0 < hub_stock < 10 mm" end end},
    step_down = {type = "number", check = positive},
    step_over = {type = "number", check = positive},
    scallop = {type = "number", check = positive},
    stations = {type = "number", check = function(v) if math.type(v) ~= "integer" or v < 2 then return "expected an integer >= 2" end end},
    chord_tol = {type = "number", check = positive},
    tilt = {type = "number", check = function(v) if not (v >= 0 and v < 45) then return "expected 0 <= tilt < 45 deg" end end},
    clearance = {type = "number", check = non_negative},
    allowance = {type = "number", check = non_negative},
    tolerance = {type = "number", check = positive},
    mesh_tol = {type = "number", check = positive},
    top = {type = "table", check = function(v)
      if #v < 2 then return "expected the top's meridian, {{z, r}, ...} (at least 2 points)" end
      for _, q in ipairs(v) do
        if type(q) ~= "table" or type(q[1]) ~= "number" or type(q[2]) ~= "number" or q[2] < 0 then
          return "expected the top's meridian, {{z, r}, ...} with r >= 0"
        end
      end
    end},
    periodic = {type = "boolean"},
    feed = {type = "number", check = positive},
    samples = {type = "table", check = function(v)
      if not (math.type(v[1]) == "integer" and math.type(v[2]) == "integer" and v[1] >= 2 and v[2] >= 2) then
        return "expected {span, chord} integers >= 2"
      end
    end},
  }, 2)
  local op = {kind = "rough_channels", tool = o.tool, blades = o.blades, stock = o.stock or 0.5,
              step_down = o.step_down or 1.0, step_over = o.step_over or 2.0, scallop = o.scallop or 0.03,
              stations = o.stations or 41, chord_tol = o.chord_tol or 0.005, tilt = o.tilt or 3,
              clearance = o.clearance or 0.5, allowance = o.allowance or 0.035, tolerance = o.tolerance or 0.05,
              mesh_tol = o.mesh_tol or 0.01, top = o.top, periodic = o.periodic ~= false, feed = o.feed or 1000,
              samples = o.samples or {60, 300}}
  op.hub_stock = o.hub_stock or op.stock
  if op.hub_stock > op.stock then error("job.rough_channels: option 'hub_stock': expected at most the stock", 2) end
  if op.allowance + op.mesh_tol + 0.005 > op.tolerance then
    error(string.format("job.rough_channels: option 'allowance': %g mm plus the world's tessellation (%g mm) must "
                        .. "stay inside the tolerance (%g mm) with 5 um to spare", op.allowance, op.mesh_tol,
                        op.tolerance), 2)
  end
  function op.plan_flanks(self, j)
    local blisk = j.part
    local n = blisk:blade_count()
    local entry = j.tools[self.tool]
    -- The blank's top over the channels: the casing unless given (a blank
    -- turned to the casing contour before the channels are roughed).
    local top_meridian = self.top or blisk:casing_meridian()
    local top = self.top and bliskrun.surface_of_revolution{meridian = self.top} or blisk:casing()
    j.channel_meshes = j.channel_meshes or {}
    j.channel_meshes[self.mesh_tol] = j.channel_meshes[self.mesh_tol] or {}
    return blades_of(self, j, function(k)
      local left, right = blisk:flank(k, "suction"), blisk:flank(k % n + 1, "pressure")
      -- The rest of each blade (its rounds up to the top, its other flank):
      -- a ball passing a flank's end keeps the stock off them too.
      local bw = require("blisk_world")
      local function rest(b, other)
        return {bw.edge_round(blisk, b, "leading", top).surface, bw.edge_round(blisk, b, "trailing", top).surface,
                blisk:flank(b, other)}
      end
      local world = require("blisk_world").around_channel(blisk, k, {chord_tol = self.mesh_tol, top = top,
        face_margin = self.stock - self.hub_stock, meshes = j.channel_meshes[self.mesh_tol]})
      local plan = bliskrun.channel_levels{left = left, right = right, left_v = {1, 0}, right_v = {0, 1},
                                           left_blade = rest(k, "pressure"), right_blade = rest(k % n + 1, "suction"),
                                           hub = blisk:hub(), top = top, tool = entry.tool,
                                           ball_radius = entry.ball_radius, world = world, stations = self.stations,
                                           stock = self.stock, hub_stock = self.hub_stock, step_down = self.step_down,
                                           step_over = self.step_over, scallop = self.scallop,
                                           chord_tol = self.chord_tol, tilt = self.tilt, clearance = self.clearance,
                                           allowance = self.allowance}
      if #plan.refusals > 0 or not plan.complete then
        local first = plan.refusals[1]
        error(string.format("job.rough_channels: channel %d (blade %d suction to blade %d pressure): %d poses refused%s%s; "
                            .. "nothing of it is emitted", k, k, k % n + 1, #plan.refusals,
                            first and string.format(" (first: level %d %s %d at t = %.3f: %s)", first.level or 0,
                                                    first.kind, first.index, first.t, first.reason) or "",
                            plan.complete and "" or ", stopped: " .. plan.stopped), 0)
      end
      local report = {row_count = #plan.passes, poses = plan.poses, levels = plan.levels,
                      levels_added = plan.levels_added, paths_added = plan.paths_added,
                      steps = plan.steps, links = plan.links - plan.steps,
                      turned = plan.turned, inserted = plan.inserted, level_step_max = plan.level_step_max,
                      step_over_max = plan.step_over_max, axial_engagement_max = plan.axial_engagement_max,
                      slot_width = plan.slot_width, face_cusp_max = plan.face_cusp_max,
                      hub_cusp_max = plan.hub_cusp_max, top_height = {plan.top_height_min, plan.top_height_max},
                      corner = plan.corner, stock = self.stock, hub_stock = plan.hub_stock,
                      cutter_clearance = plan.cutter_clearance, step_down = self.step_down,
                      step_over = self.step_over, scallop = self.scallop}
      -- The stock it leaves, measured by the independent simulation (core/sim,
      -- bliskrun.simulate: the moves swept with the tool's exact distance)
      -- on both flanks and the hub where the roughing reaches them: each
      -- flank from the ball's corner with the hub (the hub level's highest
      -- contact) up to the top, the hub between the hub level's first and
      -- last stations and r + stock or more from both flanks (closer is the
      -- ball's corner).
      local function simulate(_, so)
        so = so or {}
        return M.rough_stock(self, {blisk = blisk, k = k, left = left, right = right, tool = entry.tool,
                                    ball_radius = entry.ball_radius, moves = plan.moves, plan = plan,
                                    top_meridian = top_meridian, samples = so.samples or self.samples})
      end
      -- The job's links leave and reach the channel over the stock: their
      -- legs there keep the cutter as far off as the plan's own.
      return {{side = "channel", plan = {simulate = simulate}, report = report, moves_list = plan.moves,
               link_cutter = plan.cutter_clearance}}
    end)
  end
  return op
end

-- The stock a channel's roughing leaves (job.rough_channels' unit
-- simulate): both flanks and the hub swept by the unit's moves
-- (bliskrun.simulate), each over the region the roughing reaches (above).
-- c = {blisk, k, left, right, tool, ball_radius, moves, plan, top_meridian,
-- samples = {span, chord}}. Returns {surfaces = {{name, stock_min_mm,
-- stock_max_mm, untouched, samples, map, seconds}, ...}, stock_min_mm,
-- stock_max_mm, untouched, and the job's fields: undercut_max (the largest
-- stock left), undercut_mean, overcut (0: nothing cut below the design)}.
function M.rough_stock(op, c)
  local su, sv = c.samples[1], c.samples[2]
  local g = c.ball_radius + op.stock
  local hub_m = c.blisk:hub_meridian()
  local faces = {{name = string.format("blade %d suction", c.k), surface = c.left, corner = c.plan.corner[1]},
                 {name = string.format("blade %d pressure", c.k % c.blisk:blade_count() + 1), surface = c.right,
                  corner = c.plan.corner[2]}}
  local search_above = op.stock + 1
  local out = {surfaces = {}, stock_min_mm = math.huge, stock_max_mm = -math.huge, untouched = 0,
               undercut_mean = 0, overcut = 0}
  local function add(name, r, samples)
    out.surfaces[#out.surfaces + 1] = {name = name, stock_min_mm = r.residual_min, stock_max_mm = r.residual_max,
                                       untouched = r.untouched, samples = samples, map = r.map, seconds = r.seconds,
                                       overcut_mm = r.overcut}
    if r.residual_min then
      out.stock_min_mm = math.min(out.stock_min_mm, r.residual_min)
      out.stock_max_mm = math.max(out.stock_max_mm, r.residual_max)
    end
    out.untouched = out.untouched + r.untouched
    out.overcut = math.min(out.overcut, r.overcut)
  end
  -- The flanks: from the corner to the top.
  for _, f in ipairs(faces) do
    local keep, kept = {}, 0
    for a = 0, su - 1 do
      for b = 0, sv - 1 do
        local p = f.surface:point(a / (su - 1), b / (sv - 1))
        local ok = meridian_height(hub_m, p) >= f.corner and meridian_height(c.top_meridian, p) <= 0
        keep[#keep + 1] = ok
        if ok then kept = kept + 1 end
      end
    end
    add(f.name, bliskrun.simulate{surface = f.surface, passes = {{tool = c.tool, poses = c.moves}}, samples_u = su,
                                  samples_v = sv, search_above = search_above, keep = keep}, kept)
  end
  -- The hub: its samples window (u over the hub level's stations, v round
  -- the channel) sampled with the moves turned by `turn` so the window lies
  -- inside v in (0, 1) whatever the channel's angle.
  local lo, hi, ref = math.huge, -math.huge, nil
  for _, m in ipairs(c.moves) do
    local x, y = m.tip[1] + c.ball_radius * m.axis[1], m.tip[2] + c.ball_radius * m.axis[2]
    local th = math.atan(y, x)
    ref = ref or th
    th = ref + math.atan(math.sin(th - ref), math.cos(th - ref))
    lo, hi = math.min(lo, th), math.max(hi, th)
  end
  local turn = math.pi - 0.5 * (lo + hi)
  local v0, v1 = (lo + turn) / (2 * math.pi), (hi + turn) / (2 * math.pi)
  local hub, hu, hv = c.blisk:hub(), su, sv
  local keep, kept = {}, 0
  local cs, sn = math.cos(-turn), math.sin(-turn)
  for a = 0, hu - 1 do
    for b = 0, hv - 1 do
      local q = hub:point(c.plan.hub_u_in + (c.plan.hub_u_out - c.plan.hub_u_in) * a / (hu - 1), v0 + (v1 - v0) * b / (hv - 1))
      local p = {x = cs * q.x - sn * q.y, y = sn * q.x + cs * q.y, z = q.z}
      local ok = true
      for _, f in ipairs(faces) do
        local foot = f.surface:project({p.x, p.y, p.z})
        if not foot or foot.v <= 1e-9 or foot.v >= 1 - 1e-9 then ok = false; break end
        local n = f.surface:eval(foot.u, foot.v).normal
        local d = (p.x - foot.point.x) * n.x + (p.y - foot.point.y) * n.y + (p.z - foot.point.z) * n.z
        if d < g then ok = false; break end
      end
      keep[#keep + 1] = ok
      if ok then kept = kept + 1 end
    end
  end
  local turned = require("job.geometry").turned_moves(c.moves, turn)
  -- The hub's normal out of its material points away from the axis.
  local e = hub:eval(0.5 * (c.plan.hub_u_in + c.plan.hub_u_out), 0)
  local flip = e.normal.x * e.point.x + e.normal.y * e.point.y < 0
  add("hub", bliskrun.simulate{surface = hub, passes = {{tool = c.tool, poses = turned}}, samples_u = hu, samples_v = hv,
                               u = {c.plan.hub_u_in, c.plan.hub_u_out}, v = {v0, v1}, search_above = search_above,
                               flip_normal = flip, keep = keep}, kept)
  if out.stock_min_mm == math.huge then out.stock_min_mm, out.stock_max_mm = nil, nil end
  out.undercut_max = out.stock_max_mm or 0
  return out
end

-- The stock still on the hub when operation `index` of job j runs: the hub
-- stock of the last channel roughing before it, unless a hub finish came
-- between; 0 without a roughing (the part already roughed is the job's
-- part, as far as any proof knows).
local function hub_stock_before(j, index)
  local left = 0
  for i = 1, (index or #j.operations + 1) - 1 do
    local op = j.operations[i]
    if op.kind == "rough_channels" then left = op.hub_stock
    elseif op.kind == "hub_finish" then left = 0 end
  end
  return left
end

-- The stock still on each blade face when operation `index` of job j
-- starts: left[b][face] = {stock = mm, top =, mesh_tol =, below =} (face:
-- "pressure", "suction", "leading", "trailing") — the stock the last
-- channel roughing before it left there (its `stock`, as for the hub: the
-- shank's clearance on top covers its scallops, 0.49-0.52 mm measured on
-- the built-in flanks; with stock + tolerance the built-in trailing edge's
-- plan changed so that one link turned the axis 0.002 deg past the C
-- table's pole, which the Heidenhain post cannot follow), its top (the
-- blank's, a meridian or nil for the casing) and its mesh tolerance; after
-- a drum finish of the flank only its strip up to `below` mm over the hub
-- (the plan's hub strip, under its first row) until a hub finish of the
-- blade; nil where an edge finish since has finished that edge, or no
-- roughing reached the face (the part already roughed is the job's part,
-- as far as any proof knows).
local function flank_stock_before(j, index)
  local n, left = j.part:blade_count(), {}
  local function set(b, face, e) left[b] = left[b] or {}; left[b][face] = e end
  for i = 1, (index or #j.operations + 1) - 1 do
    local op = j.operations[i]
    if op.kind == "rough_channels" then
      -- Channel c: blade c's suction flank and blade c+1's pressure flank,
      -- and both blades' edge rounds (the ball keeps the stock off them).
      local e = {stock = op.stock, top = op.top, mesh_tol = op.mesh_tol}
      for _, c in ipairs(op.blades) do
        set(c, "suction", e)
        set(c % n + 1, "pressure", e)
        for _, b in ipairs{c, c % n + 1} do
          set(b, "leading", e)
          set(b, "trailing", e)
        end
      end
    elseif op.kind == "drum_finish" then
      -- The strip under its first row keeps the stock until the hub finish.
      for _, b in ipairs(op.blades) do
        for _, side in ipairs(op.sides) do
          local e = left[b] and left[b][side]
          if e then
            set(b, side, op.hub_strip and op.hub_strip > 0 and {stock = e.stock, top = e.top, mesh_tol = e.mesh_tol,
                                                                 below = op.hub_strip} or nil)
          end
        end
      end
    elseif op.kind == "edge_finish" then
      for _, b in ipairs(op.blades) do
        for _, edge in ipairs(op.edges) do if left[b] then left[b][edge] = nil end end
      end
    elseif op.kind == "hub_finish" then
      -- Its root strip all round the blade, up to `top` (at least 4 mm):
      -- over the drum finish's strip.
      for _, b in ipairs(op.blades) do
        for _, side in ipairs{"pressure", "suction"} do
          if left[b] and left[b][side] and left[b][side].below then left[b][side] = nil end
        end
      end
    end
  end
  return left
end

-- The world blade k's units of operation `index` (self) are proved in, with
-- the stock still there as obstacles for the shank and holder: the hub's
-- (`hub_stock` mm, 0 for none) and the flanks' of blade k's neighbours and
-- of blade k itself, each as when the operation starts (flank_stock_before;
-- it only shrinks while the operation runs, so what is proved against it
-- holds throughout). A periodic operation's plan is turned onto every blade
-- of it, so each flank at a given place relative to blade k carries the
-- most stock that place carries for any of them. skip(side): blade k's own
-- flanks left out (the drum finish's own flank, cut from the tip down).
-- Without any stock, the job's world around blade k (j:world_around).
local function stock_world(self, j, index, k, hub_stock, skip)
  local blisk = j.part
  local n = blisk:blade_count()
  local left = flank_stock_before(j, index)
  local list, top, tol = {}, nil, nil
  for _, d in ipairs{-1, 0, 1} do
    for _, side in ipairs{"pressure", "suction", "leading", "trailing"} do
      if not (d == 0 and skip and skip(side)) then
        local most
        for _, b in ipairs(self.periodic and self.blades or {k}) do
          local e = left[(b + d - 1) % n + 1] and left[(b + d - 1) % n + 1][side]
          -- The whole flank over its strip under the drum's first row.
          if e and (not most or e.stock > most.stock or (most.below and not e.below)
                    or (e.below and most.below and e.below > most.below)) then most = e end
        end
        if most then
          list[#list + 1] = {blade = (k + d - 1) % n + 1, side = side, stock = most.stock, below = most.below}
          top, tol = most.top, most.mesh_tol
        end
      end
    end
  end
  if hub_stock <= 0 and #list == 0 then return j:world_around(k), nil end
  local key = string.format("%d:%g", k, hub_stock)
  for _, f in ipairs(list) do key = key .. string.format(":%d%s%g/%s", f.blade, f.side, f.stock, tostring(f.below)) end
  j.stock_worlds = j.stock_worlds or {}
  if not j.stock_worlds[key] then
    -- The flanks' meshes as the roughing's worlds tessellated them (trimmed
    -- to its top, at its mesh tolerance), shared with them.
    tol = tol or 0.01
    j.channel_meshes = j.channel_meshes or {}
    j.channel_meshes[tol] = j.channel_meshes[tol] or {}
    j.stock_worlds[key] = require("blisk_world").around_blade(blisk, k, {
      hub_stock = hub_stock, flank_stock = list, chord_tol = tol, meshes = j.channel_meshes[tol],
      top = top and bliskrun.surface_of_revolution{meridian = top} or nil})
  end
  return j.stock_worlds[key], list
end

-- Drum-wheel flank finishing (blisk paper §3) of the given blades' flanks,
-- one plan per flank with the shared settings of scripts/lib/blisk_finish.lua.
function M.drum_finish(o)
  check_options("job.drum_finish", o, {
    tool = {type = "string", required = true},
    blades = {type = "table", required = true, check = blade_list},
    sides = {type = "table", check = function(v)
      for _, s in ipairs(v) do if s ~= "pressure" and s ~= "suction" then return "expected 'pressure' and/or 'suction'" end end
    end},
    residual = {type = "number", check = positive},
    chord_tol = {type = "number", check = positive},
    c_range = {type = "number", check = function(v) if not (v > 0 and v <= 90) then return "expected 0 < c_range <= 90 deg" end end},
    shank_clearance = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
    feed = {type = "number", check = positive},
    periodic = {type = "boolean"},
    top_down = {type = "boolean"},
  }, 2)
  local op = {kind = "drum_finish", tool = o.tool, blades = o.blades, sides = o.sides or {"pressure", "suction"},
              residual = o.residual or 0.014, chord_tol = o.chord_tol or 0.002, c_range = o.c_range or 30,
              shank_clearance = o.shank_clearance or 0.1, feed = o.feed or 600, periodic = o.periodic == true,
              top_down = o.top_down}
  -- The plans of this operation, flank by flank, in cutting order: all
  -- flanks planned at once on the run's --threads (bliskrun.drum_finish_all;
  -- the plans do not depend on the thread count).
  function op.plan_flanks(self, j, index)
    local finish = require("blisk_finish")
    local blisk = j.part
    -- After a roughing the flank the wheel finishes still carries its stock
    -- above the row it cuts, where the shank runs along it (0.15-0.34 mm off
    -- the built-in pressure flank): its rows are then cut from the tip down
    -- (top_down, unless given), so the flank above is finished when the
    -- shank passes it; the stock still on the other flanks is an obstacle
    -- for the shank and holder (stock_world).
    local left = flank_stock_before(j, index)
    local top_down = self.top_down
    if top_down == nil then
      top_down = false
      for _, k in ipairs(self.blades) do
        for _, side in ipairs(self.sides) do if left[k] and left[k][side] then top_down = true end end
      end
    end
    self.top_down_used = top_down
    local common = finish.settings(blisk, j.tools[self.tool].tool,
                                   {residual = self.residual, chord_tol = self.chord_tol,
                                    shank_clearance = self.shank_clearance, top_down = top_down})
    common.jobs = {}
    local which = {}
    -- Periodic: the first blade planned, the others its plan turned.
    local planned_blades = self.periodic and {self.blades[1]} or self.blades
    local hub_stock = hub_stock_before(j, index)
    for _, k in ipairs(planned_blades) do
      if k > blisk:blade_count() then
        error(string.format("job.drum_finish: blade %d does not exist; the part has %d", k, blisk:blade_count()), 0)
      end
      for i, side in ipairs(self.sides) do
        -- Its own flank left out when cut from the tip down (the cutting
        -- part takes the stock below the row; the shank stands above it),
        -- and its other flank where this operation finished it before.
        local function skip(s)
          if s == side then return top_down end
          -- Its edge rounds stay in: the wheel runs past the flank's ends
          -- beside them, and left out the shank stood 0.19 mm off the built-in
          -- pressure flank's rounds, inside their 0.5 mm (the stock model's
          -- 1 mm rays met that graze on 8 of 22 blades only).
          for h = 1, i - 1 do if self.sides[h] == s then return true end end
          return false
        end
        common.jobs[#common.jobs + 1] = {flank = finish.flank(blisk, k, side),
                                         world = stock_world(self, j, index, k, hub_stock, skip),
                                         name = string.format("blade %d %s", k, side),
                                         axis_limit = finish.c_axis_limit(blisk, k, self.c_range)}
        which[#which + 1] = {blade = k, side = side}
      end
    end
    local flanks = {}
    for i, plan in ipairs(bliskrun.drum_finish_all(common)) do
      local k, side = which[i].blade, which[i].side
      local r = plan:report()
      if r.refusals > 0 or r.refused_links > 0 then
        error(string.format("job.drum_finish: blade %d %s flank: %d poses and %d links refused; nothing of it is "
                            .. "emitted (see plan:report().refusal_reasons)", k, side, r.refusals, r.refused_links), 0)
      end
      flanks[#flanks + 1] = {blade = k, side = side, plan = plan, report = r, feed = self.feed,
                             moves_list = plan:moves()}
      -- The strip under the first row keeps its stock (flank_stock_before).
      self.hub_strip = math.max(self.hub_strip or 0, r.hub_strip or 0)
    end
    if not self.periodic then return flanks end
    return blades_of(self, j, function() return flanks end)
  end
  return op
end

-- Blade edges finished with the bottom of a flat-end mill (edge paper §3,
-- bliskrun.edge_finish): each blade's leading and trailing edge regions
-- (bliskrun.edge_region, `overlap` mm onto the flanks) between hub and
-- casing (the strip above the hub is the hub-fillet operation's), every pose
-- and link proved against the blade's neighbours, the hub and itself. With
-- `periodic` (default) the first blade is planned and every other blade
-- gets its path turned by the pitch (the blisk's blades are one blade
-- turned, and so are their neighbours and the hub: what is proved for one
-- holds for all).
function M.edge_finish(o)
  check_options("job.edge_finish", o, {
    tool = {type = "string", required = true},
    blades = {type = "table", required = true, check = blade_list},
    edges = {type = "table", check = function(v)
      if #v == 0 then return "expected 'leading' and/or 'trailing'" end
      for _, e in ipairs(v) do if e ~= "leading" and e ~= "trailing" then return "expected 'leading' and/or 'trailing'" end end
    end},
    e1 = {type = "number", check = function(v) if not (v <= 0) then return "expected <= 0 mm (the overcut limit)" end end},
    e2 = {type = "number", check = positive},
    overlap = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
    span = {type = "table", check = function(v)
      if not (type(v[1]) == "number" and type(v[2]) == "number" and 0 <= v[1] and v[1] < v[2] and v[2] <= 1) then
        return "expected {from, to} with 0 <= from < to <= 1"
      end
    end},
    periodic = {type = "boolean"},
    feed = {type = "number", check = positive},
    reach = {type = "table"},
    hub_stock = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
    flank_stock = {type = "boolean"},
    short_lift = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
  }, 2)
  local op = {kind = "edge_finish", tool = o.tool, blades = o.blades, edges = o.edges or {"leading", "trailing"},
              e1 = o.e1 or -0.001, e2 = o.e2 or 0.02, overlap = o.overlap or 0.3, span = o.span or {0, 1},
              periodic = o.periodic ~= false, feed = o.feed or 400, reach = o.reach, hub_stock = o.hub_stock,
              flank_stock = o.flank_stock, short_lift = o.short_lift or 0}
  function op.plan_flanks(self, j, index)
    local blisk = j.part
    local tool = j.tools[self.tool].tool
    local hub_stock = self.hub_stock or hub_stock_before(j, index)
    return blades_of(self, j, function(k)
      local units = {}
      -- The shank and holder kept off the stock still on the hub (the first
      -- rows run along it with the axis nearly tangent to it: with the hub
      -- alone as the obstacle the shank stood 0.39 mm over the hub, inside
      -- the roughing's 0.5 mm) and on the flanks (flank_stock: by default
      -- what the roughing left on flanks no drum finish has finished since —
      -- the shank ran 0.18-0.56 mm off the neighbour's facing flank, in its
      -- stock, where the drum finish had finished blade 1 alone).
      local world
      if self.flank_stock == false then
        world = hub_stock > 0 and stock_world({periodic = false}, j, 1, k, hub_stock) or j:world_around(k)
      else
        -- Its own edges are the cutter's.
        world = stock_world(self, j, index, k, hub_stock, function(s)
          for _, e in ipairs(self.edges) do if e == s then return true end end
          return false
        end)
      end
      for _, edge in ipairs(self.edges) do
        -- The flank whose edge end is at v = 0 first (bliskrun.edge_region).
        local first, second = blisk:flank(k, "pressure"), blisk:flank(k, "suction")
        if edge == "trailing" then first, second = second, first end
        local region = bliskrun.edge_region{first = first, second = second, overlap = self.overlap}
        local plan = bliskrun.edge_finish{edge = region.surface, flanks = {first, second}, tool = tool,
                                          world = world, name = string.format("blade %d %s edge", k, edge),
                                          span = self.span, hub = blisk:hub(), casing = blisk:casing(),
                                          e1 = self.e1, e2 = self.e2, reach = self.reach,
                                          short_lift = self.short_lift}
        local r = plan:report()
        if r.refusals > 0 or r.refused_links > 0 then
          local first = r.refusal_reasons and r.refusal_reasons[1]
          error(string.format("job.edge_finish: blade %d %s edge: %d contacts and %d links refused; nothing of it is "
                              .. "emitted (the first: %s)", k, edge, r.refusals, r.refused_links,
                              first or "see plan:report().refusal_reasons"), 0)
        end
        -- Where the hub narrowed the window (its first row the lowest the
        -- hub allows), the first row's highest point above the hub: the hub
        -- finish's root strip reaches over it (job.hub_finish's top). A
        -- window the recipe starts higher borders nothing below: the job's
        -- seams report it.
        if r.span_v0 > self.span[1] + 1e-9 then
          local hub_m, first = blisk:hub_meridian(), -math.huge
          for i = 0, 40 do first = math.max(first, meridian_height(hub_m, region.surface:point(i / 40, r.span_v0))) end
          j.edge_first_rows = j.edge_first_rows or {}
          j.edge_first_rows[#j.edge_first_rows + 1] = {blade = k, edge = edge, height_mm = first}
        end
        units[#units + 1] = {side = edge .. " edge", plan = plan, report = r, moves_list = plan:moves(),
                             flanks = {first, second}, surface = region.surface}
      end
      return units
    end)
  end
  return op
end

-- The hub and the blade roots with a tapered ball end (bliskrun.hub_finish,
-- core/planning/hub_finish.h): blade k's root strip all around it — what the
-- drum finish and the edge finish leave above the hub, from the fillet row
-- (the ball on hub and blade at once) up to `top` mm (default: 4, or
-- top_over_edges above the edges' first rows), overlapping both — and
-- the channel floor from blade k to blade k+1. A refused contact or link
-- stops the job. Periodic by default (job.drum_finish).
function M.hub_finish(o)
  check_options("job.hub_finish", o, {
    tool = {type = "string", required = true},
    blades = {type = "table", required = true, check = blade_list},
    top = {type = "number", check = positive},
    top_over_edges = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
    scallop = {type = "number", check = positive},
    chord_tol = {type = "number", check = positive},
    periodic = {type = "boolean"},
    feed = {type = "number", check = positive},
  }, 2)
  local op = {kind = "hub_finish", tool = o.tool, blades = o.blades, top = o.top, top_over_edges = o.top_over_edges or 0.5,
              scallop = o.scallop or 0.005, chord_tol = o.chord_tol or 0.001, periodic = o.periodic ~= false,
              feed = o.feed or 800}
  function op.plan_flanks(self, j)
    local blisk = j.part
    local n = blisk:blade_count()
    -- The root strip's top (issue 34 item 8): given, or 4 mm, raised to
    -- top_over_edges above the highest point of any edge finish's first
    -- row in the job (Job:plan plans the edges first). Around a leading
    -- edge a row at constant edge-region span climbs the conical hub's
    -- slope: the built-in LE's first row lies 3.9-4.9 mm above the hub,
    -- and with the strip's top at 4 mm the band between (4.2-4.5 mm) kept
    -- 48-60 um, beyond the edges' e2, measured by neither operation.
    local top, top_from = self.top or 4, self.top and "given" or "default"
    if not self.top then
      for _, e in ipairs(j.edge_first_rows or {}) do
        if e.height_mm + self.top_over_edges > top then
          top = e.height_mm + self.top_over_edges
          top_from = string.format("blade %d %s edge's first row (%.2f mm) + %.2f mm", e.blade, e.edge, e.height_mm,
                                   self.top_over_edges)
        end
      end
    end
    self.top_used, self.top_from = top, top_from
    -- Each blade's flanks and edge rounds (blisk_world.blade_faces, up to
    -- the casing): the flanks end where the rounds begin and a round stands up
    -- to its radius in front of them, so a world of flanks alone checked
    -- nothing there. Blade k-1's for every tool part, k's and k+1's for the
    -- shank and holder (the cutter runs round them by design, proved by the
    -- gouge guards on the closed blades, whose half circles are the rounds).
    local function faces(k) return require("blisk_world").blade_faces(blisk, k) end
    return blades_of(self, j, function(k)
      local plan = bliskrun.hub_finish{blade = faces(k), next = faces(k % n + 1), previous = faces((k - 2) % n + 1),
                                       hub = blisk:hub(), tool = j.tools[self.tool].tool, top = top,
                                       scallop = self.scallop, chord_tol = self.chord_tol}
      local r = plan:report()
      local refused = r.root.refusals + r.channel.refusals
      local refused_links = r.root.refused_links + r.channel.refused_links
      if refused > 0 or refused_links > 0 then
        error(string.format("job.hub_finish: blade %d root and channel: %d contacts and %d links refused; nothing of "
                            .. "it is emitted (see plan:report().refusals)", k, refused, refused_links), 0)
      end
      r.row_count = r.root.rows + r.channel.rows
      r.top_from = top_from
      -- The root strip, then the channel: joined through the clearance can
      -- like any two plans (the channel's first pose is a plain "start"
      -- from the root's last: straight across, that rapid ran through the
      -- blade's suction flank, 0.24 mm deep where blade 1's map sampled it).
      -- The plan joins them itself (plan:moves() with no part, r.join:
      -- through the channel), but proved as its own links are: against
      -- blades k-1, k, k+1 and the hub, the cutter meeting k and k+1 through
      -- the gouge guards only (it may graze them within the allowance). The
      -- job's link is proved against more: every blade and the hub, the
      -- whole tool off all of them (blade k by 0.01 mm, the traverse by
      -- 0.05: link_world, part_world). So the job keeps its own link here.
      local moves, channel = plan:moves("root"), plan:moves("channel")
      if #moves > 0 and #channel > 0 then
        local a, b = moves[#moves], channel[1]
        local link = j:link({tip = a.tip, axis = a.axis}, {tip = b.tip, axis = b.axis}, j.tools[self.tool].tool,
                            string.format("link from blade %d's root strip to its channel", k), k, k)
        for _, p in ipairs(link) do moves[#moves + 1] = {kind = "rapid", tip = p.tip, axis = p.axis, motion = "link"} end
      end
      for _, m in ipairs(channel) do moves[#moves + 1] = m end
      return {{side = "root and channel", plan = plan, report = r, moves_list = moves}}
    end)
  end
  return op
end

return M
