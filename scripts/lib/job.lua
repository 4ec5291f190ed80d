-- A machining job (issue 13 item 1, issue 18 item 3): one part, a tool
-- table and an ordered list of operations, planned into one toolpath that
-- carries the operation, tool, blade and flank (or channel) of every move,
-- linked safely from one operation (or flank) to the next through a
-- clearance surface, and posted as one program per machine.
--
-- Parts: a blisk (bliskrun.blisk: drum_finish) or an impeller
-- (bliskrun.impeller: notch, widen, flank_finish). The clearance surface is
-- a cylinder of radius clearance_radius about Z for a blisk (outside the
-- casing); for an impeller, the surface of revolution `clearance` mm above
-- its meridional outline (impeller_world.envelope): its channels open upward
-- and outward, so a tool backed out along its axis meets it just above the
-- channel.
--
--   local job = require("job")
--   local j = job.new{
--     name = "blisk flanks", part = blisk, clearance_radius = 150,
--     tools = {wheel = {number = 5, length = 110, spindle_rpm = 8000, tool = wheel}},
--     operations = {
--       job.drum_finish{tool = "wheel", blades = {1, 2}, residual = 0.014},
--     },
--   }
--   local planned = j:plan()
--   j:post{machine = "dmg_like_ac_trunnion", post = "fanuc", file = "blisk.nc"}
--
-- Every option table is checked where the recipe writes it: an unknown key,
-- a wrong type or an impossible value is an error at that recipe line.
-- Nothing is emitted that was not proved: a flank plan with a refused pose or
-- link stops the job, and every link move is proved clear of every blade and
-- the hub (world:check_motion, the whole tool) before it joins the path.

local M = {}

-- ---- option tables ---------------------------------------------------------

-- spec: key -> {type = "number"|"string"|"table"|"boolean"|"userdata"|"any",
-- required = bool, check = function(v) -> message or nil}. `level` is the
-- error level of the recipe line (2: the caller of the function that checks).
local function check_options(what, t, spec, level)
  level = level + 1
  if type(t) ~= "table" then error(what .. ": expected an option table, got " .. type(t), level) end
  for k in pairs(t) do
    if not spec[k] then
      local names = {}
      for name in pairs(spec) do names[#names + 1] = name end
      table.sort(names)
      error(string.format("%s: unknown option '%s', expected one of: %s", what, tostring(k),
                          table.concat(names, ", ")), level)
    end
  end
  for k, s in pairs(spec) do
    local v = t[k]
    if v == nil then
      if s.required then error(string.format("%s: missing option '%s'", what, k), level) end
    else
      if s.type ~= "any" and type(v) ~= s.type then
        error(string.format("%s: option '%s': expected a %s, got %s", what, k, s.type, type(v)), level)
      end
      local problem = s.check and s.check(v)
      if problem then error(string.format("%s: option '%s': %s", what, k, problem), level) end
    end
  end
end

local function positive(v) if not (v > 0) or v ~= v or v == math.huge then return "expected a finite value > 0" end end

local function add(a, b, s) return {a[1] + s * b[1], a[2] + s * b[2], a[3] + s * b[3]} end
local function dot(a, b) return a[1] * b[1] + a[2] * b[2] + a[3] * b[3] end
local function unit(a)
  local n = math.sqrt(dot(a, a))
  return {a[1] / n, a[2] / n, a[3] / n}
end

-- ---- operations ------------------------------------------------------------

-- Drum-wheel flank finishing (blisk paper §3) of the given blades' flanks,
-- one plan per flank with the shared settings of scripts/lib/blisk_finish.lua.
-- A plan's moves turned about Z by `angle` (rad): a blisk's blades are one
-- blade turned by the pitch, so blade k's path is blade 1's turned.
local function turned_moves(list, angle)
  local c, s = math.cos(angle), math.sin(angle)
  local function rot(v) return {c * v[1] - s * v[2], s * v[1] + c * v[2], v[3]} end
  local out = {}
  for i, m in ipairs(list) do
    local t = {}
    for key, value in pairs(m) do t[key] = value end
    t.tip, t.axis = rot(m.tip), rot(m.axis)
    out[i] = t
  end
  return out
end
M.turned_moves = turned_moves

-- Heights over a meridian ({{z, r}, ...}, a polyline about Z): the signed
-- distance of p from it in p's meridian plane, + away from the axis — the
-- hub's radial offset, as the hub plan measures its rows' heights.
local function meridian_height(meridian, p)
  local r, z = math.sqrt(p.x * p.x + p.y * p.y), p.z
  local best, sign = math.huge, 1
  for i = 2, #meridian do
    local z0, r0, z1, r1 = meridian[i - 1][1], meridian[i - 1][2], meridian[i][1], meridian[i][2]
    local dz, dr = z1 - z0, r1 - r0
    local t = math.max(0, math.min(1, ((z - z0) * dz + (r - r0) * dr) / (dz * dz + dr * dr)))
    local ez, er = z - (z0 + t * dz), r - (r0 + t * dr)
    local d = math.sqrt(ez * ez + er * er)
    if d < best then
      -- The segment's normal away from the axis: (-dr, dz) or its opposite.
      local nz, nr = -dr, dz
      if nr < 0 then nz, nr = -nz, -nr end
      best, sign = d, (ez * nz + er * nr >= 0) and 1 or -1
    end
  end
  return sign * best
end

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
                    surface = u.surface, moves_list = turned_moves(u.moves_list, 2 * math.pi * (k - base_k) / n)}
      end
    else
      units = plan_blade(k)
      base, base_k = units, k
    end
    for _, u in ipairs(units) do
      flanks[#flanks + 1] = {blade = k, side = u.side, plan = u.plan, report = u.report, feed = self.feed,
                             moves_list = u.moves_list, turned_from = u.turned_from, flanks = u.flanks,
                             surface = u.surface}
    end
  end
  return flanks
end

function M.drum_finish(o)
  check_options("job.drum_finish", o, {
    tool = {type = "string", required = true},
    blades = {type = "table", required = true, check = function(v)
      if #v == 0 then return "expected a list of blade numbers" end
      for _, b in ipairs(v) do if math.type(b) ~= "integer" or b < 1 then return "expected blade numbers 1, 2, ..." end end
    end},
    sides = {type = "table", check = function(v)
      for _, s in ipairs(v) do if s ~= "pressure" and s ~= "suction" then return "expected 'pressure' and/or 'suction'" end end
    end},
    residual = {type = "number", check = positive},
    chord_tol = {type = "number", check = positive},
    c_range = {type = "number", check = function(v) if not (v > 0 and v <= 90) then return "expected 0 < c_range <= 90 deg" end end},
    shank_clearance = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
    feed = {type = "number", check = positive},
    periodic = {type = "boolean"},
  }, 2)
  local op = {kind = "drum_finish", tool = o.tool, blades = o.blades, sides = o.sides or {"pressure", "suction"},
              residual = o.residual or 0.014, chord_tol = o.chord_tol or 0.002, c_range = o.c_range or 30,
              shank_clearance = o.shank_clearance or 0.1, feed = o.feed or 600, periodic = o.periodic == true}
  -- The plans of this operation, flank by flank, in cutting order: all
  -- flanks planned at once on the run's --threads (bliskrun.drum_finish_all;
  -- the plans do not depend on the thread count).
  function op.plan_flanks(self, j)
    local finish = require("blisk_finish")
    local blisk = j.part
    local common = finish.settings(blisk, j.tools[self.tool].tool,
                                   {residual = self.residual, chord_tol = self.chord_tol,
                                    shank_clearance = self.shank_clearance})
    common.jobs = {}
    local which = {}
    -- Periodic: the first blade planned, the others its plan turned.
    local planned_blades = self.periodic and {self.blades[1]} or self.blades
    for _, k in ipairs(planned_blades) do
      if k > blisk:blade_count() then
        error(string.format("job.drum_finish: blade %d does not exist; the part has %d", k, blisk:blade_count()), 0)
      end
      for _, side in ipairs(self.sides) do
        common.jobs[#common.jobs + 1] = {flank = finish.flank(blisk, k, side), world = j:world_around(k),
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
    blades = {type = "table", required = true, check = function(v)
      if #v == 0 then return "expected a list of blade numbers" end
      for _, b in ipairs(v) do if math.type(b) ~= "integer" or b < 1 then return "expected blade numbers 1, 2, ..." end end
    end},
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
  }, 2)
  local op = {kind = "edge_finish", tool = o.tool, blades = o.blades, edges = o.edges or {"leading", "trailing"},
              e1 = o.e1 or -0.001, e2 = o.e2 or 0.02, overlap = o.overlap or 0.3, span = o.span or {0.1, 0.9},
              periodic = o.periodic ~= false, feed = o.feed or 400, reach = o.reach}
  function op.plan_flanks(self, j)
    local blisk = j.part
    local tool = j.tools[self.tool].tool
    return blades_of(self, j, function(k)
      local units = {}
      for _, edge in ipairs(self.edges) do
        -- The flank whose edge end is at v = 0 first (bliskrun.edge_region).
        local first, second = blisk:flank(k, "pressure"), blisk:flank(k, "suction")
        if edge == "trailing" then first, second = second, first end
        local region = bliskrun.edge_region{first = first, second = second, overlap = self.overlap}
        local plan = bliskrun.edge_finish{edge = region.surface, flanks = {first, second}, tool = tool,
                                          world = j:world_around(k), name = string.format("blade %d %s edge", k, edge),
                                          span = self.span, hub = blisk:hub(), casing = blisk:casing(),
                                          e1 = self.e1, e2 = self.e2, reach = self.reach}
        local r = plan:report()
        if r.refusals > 0 or r.refused_links > 0 then
          error(string.format("job.edge_finish: blade %d %s edge: %d contacts and %d links refused; nothing of it is "
                              .. "emitted (see plan:report().refusal_reasons)", k, edge, r.refusals, r.refused_links), 0)
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
    blades = {type = "table", required = true, check = function(v)
      if #v == 0 then return "expected a list of blade numbers" end
      for _, b in ipairs(v) do if math.type(b) ~= "integer" or b < 1 then return "expected blade numbers 1, 2, ..." end end
    end},
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
    local function faces(k) return {pressure = blisk:flank(k, "pressure"), suction = blisk:flank(k, "suction")} end
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

-- ---- impeller operations (impeller paper §4) -------------------------------

local function blade_list(v)
  if #v == 0 then return "expected a list of blade numbers" end
  for _, b in ipairs(v) do if math.type(b) ~= "integer" or b < 1 then return "expected blade numbers 1, 2, ..." end end
end

local function require_impeller(j, what)
  if j.part_kind ~= "impeller" then error(what .. ": this operation machines an impeller; the job's part is a blisk", 0) end
end

-- Blade 1's units turned onto each blade of the operation: the model is
-- symmetric under turns of the blade pitch about Z, so the proofs carry over.
local function per_blade(j, units, blades)
  local iw = require("impeller_world")
  local out = {}
  for _, k in ipairs(blades) do
    local angle = iw.pitch_angle(j.part, k)
    for _, u in ipairs(units) do
      local moves = {}
      for i, m in ipairs(u.moves) do
        local p = iw.turn(m, angle)
        moves[i] = {kind = m.kind, tip = p.tip, axis = p.axis, row = m.row, motion = m.motion,
                    operation = m.operation}
      end
      out[#out + 1] = {blade = k, side = u.name, moves_list = moves, report = u.report}
    end
  end
  return out
end

-- A recipe's --set blades=N as the blade list {1, ..., N} (all the part's
-- blades when N is nil); an error names the range.
function M.first_blades(part, count)
  local n = part:blade_count()
  count = count or n
  if math.type(count) ~= "integer" or count < 1 or count > n then
    error(string.format("--set blades= expects 1..%d", n), 0)
  end
  local blades = {}
  for k = 1, count do blades[k] = k end
  return blades
end

-- A recipe's comma-separated --set value as a list ("left,right"); nil stays nil.
function M.split_list(text)
  if not text then return nil end
  local out = {}
  for item in tostring(text):gmatch("[^,]+") do out[#out + 1] = item end
  return out
end

-- Notching (§4.1): the channel's middle opened in depth levels from the
-- shroud contour to the stock above the hub (bliskrun.channel_rough). When a
-- job.widen follows it (same tool, same blades), each channel is notched and
-- widened in one plan, its passes linked inside the channel.
function M.notch(o)
  check_options("job.notch", o, {
    tool = {type = "string", required = true},
    blades = {type = "table", required = true, check = blade_list},
    stock = {type = "number", check = function(v) if not (v > 0 and v < 10) then return "expected 0 < stock < 10 mm" end end},
    min_stock = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
    depth_step = {type = "number", check = positive},
    stations = {type = "number", check = function(v) if math.type(v) ~= "integer" or v < 2 then return "expected an integer >= 2" end end},
    splitter_gap = {type = "number", check = positive},
    channels = {type = "table", check = function(v)
      if #v == 0 then return "expected a list of channel names" end
      for _, c in ipairs(v) do
        if c ~= "inlet" and c ~= "left" and c ~= "right" and c ~= "channel" then
          return "expected 'inlet', 'left', 'right' (with splitters) or 'channel' (without)"
        end
      end
    end},
    mesh_tol = {type = "number", check = positive},
    feed = {type = "number", check = positive},
  }, 2)
  local op = {kind = "notch", channels = o.channels, tool = o.tool, blades = o.blades, stock = o.stock or 0.5, depth_step = o.depth_step or 5,
              stations = o.stations or 41, splitter_gap = o.splitter_gap or 20, mesh_tol = o.mesh_tol or 0.05,
              feed = o.feed or 800}
  op.min_stock = o.min_stock or math.min(0.2, op.stock / 2)
  if op.min_stock > op.stock then error("job.notch: option 'min_stock': expected at most the stock", 2) end
  function op.plan_flanks(self, j, index)
    require_impeller(j, "job.notch")
    local iw = require("impeller_world")
    local widen = self.widen_op
    local meshes = j:impeller_meshes(self.mesh_tol)
    -- Where the widening leaves less on the hub than the cutter's clearance
    -- (the paper finishes it), the ball is meant to touch the hub.
    local hub_stock = widen and widen.hub_stock or self.stock
    local world = iw.channel_world(j.part, meshes, hub_stock < self.min_stock
                                   and {hub_finish = {cutter_clearance = self.min_stock - hub_stock}} or nil)
    local tool = j.tools[self.tool]
    local wanted, chosen, requests = {}, {}, {}
    for _, name in ipairs(self.channels or {}) do wanted[name] = true end
    for _, c in ipairs(iw.channels(j.part, {gap = self.splitter_gap})) do
      if not self.channels or wanted[c.name] then
        chosen[#chosen + 1] = c
        requests[#requests + 1] = {left = c.left, left_v = c.left_v, right = c.right, right_v = c.right_v,
                                   hub = j.part:hub(), tool = tool.tool, ball_radius = tool.ball_radius,
                                   world = world, stations = self.stations, stock = self.stock, hub_stock = hub_stock,
                                   scallop = widen and widen.scallop or nil, widen = widen ~= nil,
                                   depth_step = self.depth_step, cutter_clearance = self.min_stock}
      end
    end
    if #chosen == 0 then error("job.notch: none of the channels asked for is in this impeller", 0) end
    -- The channels are independent: planned side by side on --threads.
    local plans = bliskrun.channel_rough_all{channels = requests}
    local units = {}
    for k, c in ipairs(chosen) do
      local plan = plans[k]
      if #plan.refusals > 0 or not plan.complete then
        local first = plan.refusals[1]
        error(string.format("job.notch: channel %s: %d poses refused%s%s; nothing of it is emitted", c.name,
                            #plan.refusals, first and string.format(" (first: %s %d at t = %.3f: %s)", first.kind,
                                                                     first.index, first.t, first.reason) or "",
                            plan.complete and "" or ", stopped: " .. plan.stopped), 0)
      end
      -- A move belongs to the widening operation where its pass widens.
      local moves = {}
      for i, m in ipairs(plan.moves) do
        moves[i] = {kind = m.kind, tip = m.tip, axis = m.axis, row = m.row, motion = m.motion,
                    operation = widen and plan.passes[m.row].kind ~= "notch" and index + 1 or index}
      end
      units[#units + 1] = {name = c.name, moves = moves,
                           report = {notch_levels = plan.notch_levels, widen_left = plan.widen_left,
                                     widen_right = plan.widen_right, step_over = plan.step_over,
                                     scallop_max = plan.scallop_max, paths_added = plan.paths_added,
                                     poses = plan.poses, passes = #plan.passes, turned = plan.turned,
                                     inserted = plan.inserted, hub_stock = plan.hub_stock}}
    end
    return per_blade(j, units, self.blades)
  end
  return op
end

-- Widening with hub finishing (§4.2, eq. 12–14): from the notch towards both
-- faces along the hub, paths f = 2 sqrt(2rh - h^2) apart for the scallop h,
-- the last on each side the finishing pose of the cutter grown by the
-- faces' stock. As in the paper the widening finishes the hub in the same
-- passes: hub_stock (default 0) is what it leaves there, the faces keep the
-- notch's stock for flank finishing. Planned with the job.notch it must
-- directly follow (same tool and blades).
function M.widen(o)
  check_options("job.widen", o, {
    tool = {type = "string", required = true},
    blades = {type = "table", required = true, check = blade_list},
    scallop = {type = "number", check = positive},
    hub_stock = {type = "number", check = function(v) if not (v >= 0 and v < 10) then return "expected 0 <= hub_stock < 10 mm" end end},
    feed = {type = "number", check = positive},
  }, 2)
  return {kind = "widen", tool = o.tool, blades = o.blades, scallop = o.scallop or 0.01, hub_stock = o.hub_stock or 0,
          feed = o.feed or 1000, plan_flanks = function() return {} end}  -- its moves come with the notch's plan
end

-- Flank finishing (§4.3) of blade faces with the side of a (tapered)
-- ball-end mill (bliskrun.flank_mill): faces = list of "main plus", "main
-- minus", "splitter plus", "splitter minus" (default all four).
function M.flank_finish(o)
  local face_names = {["main plus"] = true, ["main minus"] = true, ["splitter plus"] = true,
                      ["splitter minus"] = true}
  check_options("job.flank_finish", o, {
    tool = {type = "string", required = true},
    blades = {type = "table", required = true, check = blade_list},
    faces = {type = "table", check = function(v)
      if #v == 0 then return "expected a list of faces" end
      for _, f in ipairs(v) do
        if not face_names[f] then return "expected 'main plus', 'main minus', 'splitter plus', 'splitter minus'" end
      end
    end},
    chord_tol = {type = "number", check = positive},
    clearance = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
    mesh_tol = {type = "number", check = positive},
    balance = {type = "boolean"},
    feed = {type = "number", check = positive},
  }, 2)
  local op = {kind = "flank_finish", tool = o.tool, blades = o.blades,
              faces = o.faces or {"main plus", "main minus", "splitter plus", "splitter minus"},
              chord_tol = o.chord_tol or 0.005, clearance = o.clearance or 0.5, mesh_tol = o.mesh_tol or 0.05,
              balance = o.balance ~= false, feed = o.feed or 600, lift = 5}
  function op.plan_flanks(self, j, index)
    require_impeller(j, "job.flank_finish")
    local iw = require("impeller_world")
    local meshes = j:impeller_meshes(self.mesh_tol)
    local tool = j.tools[self.tool]
    local units = {}
    for _, name in ipairs(self.faces) do
      local kind, side = name:match("^(%a+) (%a+)$")
      if kind == "splitter" and not j.part:has_splitter() then
        error("job.flank_finish: the impeller has no splitters; faces = {'" .. name .. "'}", 0)
      end
      local world = iw.face_world(j.part, meshes, kind, side)
      local plan = bliskrun.flank_mill{face = j.part:face(1, side, kind), design = iw.design_face(j.part, 1, side, kind),
                                       hub = j.part:hub(), tool = tool.tool,
                                       ball_radius = tool.ball_radius, world = world,
                                       chord_tol = self.chord_tol, clearance = self.clearance, balance = self.balance,
                                       residual_points = 10}
      if #plan.refusals > 0 or not plan.lead_in.clear or not plan.lead_out.clear then
        error(string.format("job.flank_finish: %s face: %d poses refused%s; nothing of it is emitted", name,
                            #plan.refusals, (plan.lead_in.clear and plan.lead_out.clear) and ""
                              or ", lead not clear: " .. (plan.lead_in.reason or "") .. (plan.lead_out.reason or "")), 0)
      end
      -- The plan's leads slide the ball along the hub, off the face; the
      -- unit starts and ends up the tool axis from there, off the hub, so
      -- the job's links never touch the finished surfaces. Those two motions
      -- are proved here like the plan's own.
      local function lifted(pose) return {tip = add(pose.tip, pose.axis, self.lift), axis = pose.axis} end
      local start, finish = lifted(plan.lead_in.away), lifted(plan.lead_out.away)
      for _, leg in ipairs{{start, plan.lead_in.away}, {plan.lead_out.away, finish}} do
        local m = world:check_motion(tool.tool, leg[1], leg[2],
                                     {clearance = {cutter = 0, shank = self.clearance, holder = self.clearance}})
        if not m.clear then
          error(string.format("job.flank_finish: %s face: the lift of %.1f mm off the hub at the %s is not clear "
                              .. "(margin %.3f mm)", name, self.lift, leg[1] == start and "lead-in" or "lead-out",
                              m.min_margin or 0 / 0), 0)
        end
      end
      local moves = {{kind = "rapid", tip = start.tip, axis = start.axis, row = 1, motion = "start", operation = index},
                     {kind = "feed", tip = plan.lead_in.away.tip, axis = plan.lead_in.away.axis, row = 1,
                      motion = "approach", operation = index}}
      for _, p in ipairs(plan.poses) do
        moves[#moves + 1] = {kind = "feed", tip = p.tip, axis = p.axis, row = 1,
                             motion = #moves == 2 and "approach" or "cut", operation = index}
      end
      moves[#moves + 1] = {kind = "feed", tip = plan.lead_out.away.tip, axis = plan.lead_out.away.axis, row = 1,
                           motion = "retract", operation = index}
      moves[#moves + 1] = {kind = "feed", tip = finish.tip, axis = finish.axis, row = 1, motion = "retract",
                           operation = index}
      units[#units + 1] = {name = name, moves = moves,
                           report = {poses = #plan.poses, stations = plan.stations, tilted = plan.tilted,
                                     residual_max = plan.residual.max, residual_min = plan.residual.min}}
    end
    return per_blade(j, units, self.blades)
  end
  return op
end

-- The blisk's clearance surface: the cylinder of radius R about Z.
--   back_out(pose) -> the tool backed out along its axis until the tip is on
--   the cylinder (nil when the axis points along Z); travel(out, into) ->
--   points round the cylinder, into last, in steps short enough that every
--   chord stays within 0.5 mm of it.
-- The clearance surface of a blisk: the cylinder of radius R about Z and,
-- when z0 < z1 are given, its end planes z = z0 and z = z1 in front of and
-- behind the part (a can). A tool backs out along its axis to the can's
-- first wall: the cylinder, or the end plane it points at when it meets
-- that first (an edge tool's axis is nearly axial; without the planes such
-- an axis would meet the cylinder far beyond the machine's travel); it
-- travels out on the plane to the cylinder's rim, round the cylinder, and in
-- on the other's plane.
function M.cylinder(R, z0, z1)
  local can = z0 and z1
  local c = {description = can and string.format("the clearance can (r = %g mm, z %g .. %g mm)", R, z0, z1)
                               or string.format("the clearance cylinder (r = %g mm)", R)}
  -- Whether a point lies inside the clearance surface (strictly).
  function c.contains(p)
    return p[1] ^ 2 + p[2] ^ 2 < R * R - 1e-9 and (not can or (p[3] > z0 + 1e-9 and p[3] < z1 - 1e-9))
  end
  function c.back_out(pose)
    local p, a = pose.tip, pose.axis
    -- |xy(p + t a)| = R: (a.a) t^2 + 2 (p.a) t + (p.p - R^2) = 0 in xy.
    local A, B, C = a[1] ^ 2 + a[2] ^ 2, p[1] * a[1] + p[2] * a[2], p[1] ^ 2 + p[2] ^ 2 - R * R
    local disc = B * B - A * C
    local t = A >= 0.04 and disc >= 0 and math.max(0, (-B + math.sqrt(disc)) / A) or nil
    if can and math.abs(a[3]) >= 1e-6 then
      -- The can's first wall along the axis: an end plane before the cylinder.
      local tz = math.max(0, ((a[3] < 0 and z0 or z1) - p[3]) / a[3])
      local q = add(p, a, tz)
      if q[1] ^ 2 + q[2] ^ 2 <= R * R and (not t or tz < t) then t = tz end
    end
    if not t then return nil end
    return {tip = add(p, a, t), axis = a}
  end
  -- The point on the rim (radius R) a point on an end plane travels out
  -- to, or the point itself when it is on the cylinder.
  local function rim(q)
    local r = math.sqrt(q[1] ^ 2 + q[2] ^ 2)
    if r >= R - 1e-6 then return q, false end
    if r < 1e-9 then return {R, 0, q[3]}, true end
    return {R * q[1] / r, R * q[2] / r, q[3]}, true
  end
  function c.travel(out, into)
    local from, out_plane = rim(out.tip)
    local to, into_plane = rim(into.tip)
    local points = {}
    if out_plane then points[#points + 1] = from end
    local t1, t2 = math.atan(from[2], from[1]), math.atan(to[2], to[1])
    local dt = t2 - t1
    while dt > math.pi do dt = dt - 2 * math.pi end
    while dt < -math.pi do dt = dt + 2 * math.pi end
    local n = math.max(1, math.ceil(math.abs(dt) / (2 * math.acos((R - 0.5) / R))))
    for i = 1, n do
      local s, t = i / n, t1 + i / n * dt
      points[#points + 1] = i == n and to or {R * math.cos(t), R * math.sin(t), from[3] + s * (to[3] - from[3])}
    end
    if into_plane then points[#points + 1] = into.tip end
    return points
  end
  return c
end

-- ---- the job -------------------------------------------------------------

local Job = {}
Job.__index = Job

function M.new(spec)
  check_options("job.new", spec, {
    name = {type = "string", required = true},
    part = {type = "any", required = true, check = function(v)
      if type(v) ~= "userdata" and type(v) ~= "table" then return "expected a part (bliskrun.blisk, bliskrun.impeller, ...)" end
    end},
    clearance_radius = {type = "number", check = positive},
    clearance_axial = {type = "number", check = positive},
    clearance = {type = "number", check = positive},
    link_clearance = {type = "table"},
    tools = {type = "table", required = true},
    operations = {type = "table", required = true, check = function(v) if #v == 0 then return "expected at least one operation" end end},
  }, 2)
  local part_kind = spec.part.face and "impeller" or "blisk"
  local clearance_surface
  if part_kind == "blisk" then
    if not spec.clearance_radius then error("job.new: missing option 'clearance_radius' (a blisk's links run on a "
                                            .. "cylinder about its axis outside the casing)", 2) end
    local casing = 0
    for _, p in ipairs(spec.part:casing_meridian()) do casing = math.max(casing, p[2]) end
    if spec.clearance_radius <= casing + 1 then
      error(string.format("job.new: option 'clearance_radius': %.3f mm is not outside the casing (radius up to %.3f mm) "
                          .. "by at least 1 mm", spec.clearance_radius, casing), 2)
    end
    -- End planes 10 mm (clearance_axial) in front of and behind the hub:
    -- a tool on a blade's edge backs out along its nearly axial axis.
    local zmin, zmax = math.huge, -math.huge
    for _, p in ipairs(spec.part:hub_meridian()) do zmin, zmax = math.min(zmin, p[1]), math.max(zmax, p[1]) end
    local axial = spec.clearance_axial or 10
    clearance_surface = M.cylinder(spec.clearance_radius, zmin - axial, zmax + axial)
  else
    if not spec.clearance then error("job.new: missing option 'clearance' (an impeller's links run this many mm "
                                     .. "over its outline)", 2) end
    clearance_surface = require("impeller_world").envelope(spec.part, spec.clearance)
    clearance_surface.description = string.format("the clearance surface %g mm over the impeller", spec.clearance)
  end
  local numbers = {}
  for name, t in pairs(spec.tools) do
    check_options("job.new tools." .. tostring(name), t, {
      number = {type = "number", required = true, check = function(v) if math.type(v) ~= "integer" or v < 0 then return "expected a tool number" end end},
      length = {type = "number", required = true, check = positive},
      spindle_rpm = {type = "number"},
      tool = {type = "userdata", required = true},
      ball_radius = {type = "number", check = positive},
      life_mm = {type = "number", check = positive},
      sisters = {type = "table", check = function(v)
        for _, n in ipairs(v) do if math.type(n) ~= "integer" or n < 0 then return "expected a list of tool numbers" end end
      end},
    }, 2)
    for _, n in ipairs({t.number, table.unpack(t.sisters or {})}) do
      if numbers[n] then error(string.format("job.new: tools '%s' and '%s' share number %d", numbers[n], name, n), 2) end
      numbers[n] = name
    end
  end
  local blisk_ops = {drum_finish = true, edge_finish = true, hub_finish = true}
  local impeller_ops = {notch = true, widen = true, flank_finish = true}
  for i, op in ipairs(spec.operations) do
    if type(op) ~= "table" or not op.kind then
      error(string.format("job.new: operations[%d]: expected an operation (job.drum_finish{...}, job.notch{...}, ...)",
                          i), 2)
    end
    if not (part_kind == "blisk" and blisk_ops or impeller_ops)[op.kind] then
      error(string.format("job.new: operations[%d] (%s) does not machine a%s %s", i, op.kind,
                          part_kind == "impeller" and "n" or "", part_kind), 2)
    end
    local t = spec.tools[op.tool]
    if not t then
      error(string.format("job.new: operations[%d] (%s) uses tool '%s', which the tools table does not list", i, op.kind,
                          tostring(op.tool)), 2)
    end
    for _, k in ipairs(op.blades or {}) do
      if k > spec.part:blade_count() then
        error(string.format("job.new: operations[%d] (%s): blade %d does not exist; the part has %d", i, op.kind, k,
                            spec.part:blade_count()), 2)
      end
    end
    if impeller_ops[op.kind] and op.kind ~= "widen" and not t.ball_radius then
      error(string.format("job.new: operations[%d] (%s): tool '%s' needs ball_radius (the radius of its tip ball, mm)",
                          i, op.kind, op.tool), 2)
    end
    if op.kind == "widen" then
      -- Widening starts from the notch: it is planned with the notch it
      -- follows, each channel's passes linked inside the channel.
      local notch = spec.operations[i - 1]
      local same = notch and notch.kind == "notch" and notch.tool == op.tool and #notch.blades == #op.blades
      for b = 1, same and #op.blades or 0 do same = same and notch.blades[b] == op.blades[b] end
      if not same then
        error(string.format("job.new: operations[%d] (widen) must directly follow the job.notch it widens, with the "
                            .. "same tool and blades: widening starts from the notch", i), 2)
      end
      if op.hub_stock > notch.stock then
        error(string.format("job.new: operations[%d] (widen): option 'hub_stock': expected at most the notch's "
                            .. "stock (%g mm)", i, notch.stock), 2)
      end
      notch.widen_op = op
    end
  end
  return setmetatable({name = spec.name, part = spec.part, part_kind = part_kind,
                       clearance_radius = spec.clearance_radius, clearance_surface = clearance_surface,
                       link_clearance = spec.link_clearance or {cutter = 0, shank = 0.1, holder = 1},
                       tools = spec.tools, operations = spec.operations, worlds = {}}, Job)
end

-- The impeller's faces and hub tessellated once per tolerance, shared by
-- every operation and the links.
function Job:impeller_meshes(tol)
  self.meshes = self.meshes or {}
  if not self.meshes[tol] then self.meshes[tol] = require("impeller_world").meshes(self.part, tol) end
  return self.meshes[tol]
end

-- The check surfaces around blade k (neighbours, hub, the blade itself for
-- the shank), built once per blade.
function Job:world_around(k)
  if not self.worlds[k] then
    -- Beyond a few blades, tessellate every flank once and share the meshes.
    local blisk_world = require("blisk_world")
    if self.part:blade_count() > 4 and self:blade_count_used() > 3 then
      self.worlds = blisk_world.all_blades(self.part)
    else
      self.worlds[k] = blisk_world.around_blade(self.part, k)
    end
  end
  return self.worlds[k]
end

-- How many distinct blades the operations machine.
function Job:blade_count_used()
  local seen, n = {}, 0
  for _, op in ipairs(self.operations) do
    for _, b in ipairs(op.blades or {}) do
      if not seen[b] then seen[b] = true; n = n + 1 end
    end
  end
  return n
end

-- What a link's back-out from, or approach to, blade k's flanks is proved
-- against: the neighbours and the hub as the plans see them (0.01 mm), and
-- blade k itself for every tool part, the cutter included (0.01 mm, added as
-- margin): the back-out and approach slide the wheel along its own blade,
-- where the plan's lead-in/out left it, and must not touch it.
function Job:link_world(k)
  self.link_worlds = self.link_worlds or {}
  if not self.link_worlds[k] then
    local n, tol = self.part:blade_count(), 0.01
    local surfaces = {}
    for _, b in ipairs{(k - 2) % n + 1, k % n + 1} do
      for _, side in ipairs{"pressure", "suction"} do
        surfaces[#surfaces + 1] = {name = string.format("blade %d %s", b, side), surface = self.part:flank(b, side),
                                   chord_tol = tol}
      end
    end
    surfaces[#surfaces + 1] = {name = "hub", surface = self.part:hub(), chord_tol = tol}
    for _, side in ipairs{"pressure", "suction"} do
      surfaces[#surfaces + 1] = {name = string.format("blade %d %s (own)", k, side), surface = self.part:flank(k, side),
                                 chord_tol = tol, margin = tol}
    end
    self.link_worlds[k] = bliskrun.collision_world{surfaces = surfaces}
  end
  return self.link_worlds[k]
end

-- Every blade and the hub, coarser (0.05 mm, added as margin): what a link
-- between two flanks, which may pass any blade, is proved against. With the
-- margin, clearance 0 for the cutter still keeps it 0.05 mm off every
-- surface: a link never cuts.
function Job:part_world()
  if not self.whole then
    local surfaces = {}
    for b = 1, self.part:blade_count() do
      for _, side in ipairs{"pressure", "suction"} do
        surfaces[#surfaces + 1] = {name = string.format("blade %d %s", b, side), surface = self.part:flank(b, side),
                                   chord_tol = 0.05, margin = 0.05}
      end
    end
    surfaces[#surfaces + 1] = {name = "hub", surface = self.part:hub(), chord_tol = 0.05, margin = 0.05}
    self.whole = bliskrun.collision_world{surfaces = surfaces}
  end
  return self.whole
end


-- Where a link leg is proved, and the turn that brings it there: the first
-- leg leaves blade a, the last reaches blade b, the ones between travel over
-- the part. An impeller's legs near blade k are turned back onto blade 1
-- (its model is symmetric under the blade pitch) and proved against blade
-- 1's neighbourhood.
function Job:leg_world(leg, legs, blade_a, blade_b)
  if self.part_kind == "blisk" then
    return leg == 1 and blade_a and self:link_world(blade_a) or leg == legs and blade_b and self:link_world(blade_b)
               or self:part_world(), 0
  end
  local iw = require("impeller_world")
  if (leg == 1 and blade_a) or (leg == legs and blade_b) then
    self.neighbourhood = self.neighbourhood or iw.neighbourhood(self.part, self:impeller_meshes(0.05))
    return self.neighbourhood, -iw.pitch_angle(self.part, leg == 1 and blade_a or blade_b)
  end
  self.impeller_whole = self.impeller_whole or iw.whole(self.part, self:impeller_meshes(0.5))
  return self.impeller_whole, 0
end

-- Link from pose `a` to pose `b` through the clearance surface: back out
-- along a's axis, travel over the surface (the axis turning from a's to
-- b's), then in along b's axis. Each motion is proved clear of the part with
-- the whole tool.
function Job:link(a, b, tool, what, blade_a, blade_b)
  local surface = self.clearance_surface
  local function back_out(pose, which)
    local p = surface.back_out(pose)
    if not p then
      error(string.format("job: %s (%s): backed out along its axis (%.3f, %.3f, %.3f) the tool does not reach %s",
                          what, which, pose.axis[1], pose.axis[2], pose.axis[3], surface.description), 0)
    end
    return p
  end
  local out, into = back_out(a, "back out"), back_out(b, "approach")
  local travel = surface.travel(out, into)
  local poses = {out}
  for i, tip in ipairs(travel) do
    local s = i / #travel
    local axis = unit(add(out.axis, {into.axis[1] - out.axis[1], into.axis[2] - out.axis[2], into.axis[3] - out.axis[3]}, s))
    poses[#poses + 1] = {tip = tip, axis = i == #travel and into.axis or axis}
  end
  poses[#poses + 1] = b
  local from = a
  for i, to in ipairs(poses) do
    self:prove_motion(from, to, tool, i, #poses, blade_a, blade_b,
                      string.format("%s: link motion %d of %d", what, i, #poses))
    from = to
  end
  table.remove(poses)  -- b itself is the next plan's first move
  return poses
end

-- Proves the motion from pose `a` to pose `b` clear of the part with the
-- whole tool, in the world of link leg `leg` of `legs` (Job:leg_world);
-- an error naming `what` otherwise.
function Job:prove_motion(a, b, tool, leg, legs, blade_a, blade_b, what)
  a, b = {tip = a.tip, axis = a.axis}, {tip = b.tip, axis = b.axis}
  local world, angle = self:leg_world(leg, legs, blade_a, blade_b)
  if angle ~= 0 then
    local iw = require("impeller_world")
    a, b = iw.turn(a, angle), iw.turn(b, angle)
  end
  local m = world:check_motion(tool, a, b, {clearance = self.link_clearance})
  if not m.clear then
    error(string.format("job: %s is not proved clear of the part (margin %.3f mm at t = %.3f)", what,
                        m.min_margin or 0 / 0, m.t or 0 / 0), 0)
  end
end

-- How far out along the tool axis a program's way in and out is proved
-- clear of the part (mm): beyond the clearance surface up to the machine's
-- safe height (core/machine/motion.h SafeMove; the post refuses a longer
-- way than was proved).
M.approach_length = 2000

-- A program's ends on the clearance surface: the way in to its first move
-- (backed out along its axis to the clearance surface, a rapid, then in to
-- it) unless it is a link move there already, and the way out from its last
-- one; and for the first and last move of each tool, the line out along
-- the tool axis to approach_length, proved clear (the machine comes down
-- and goes up along it). `moves` are the job's moves of the program (part
-- frame, before any flip); returns the moves to post.
function Job:program_ends(moves, up)
  if #moves == 0 then return moves end
  local surface = self.clearance_surface
  local out = {}
  local function entry(m, which)
    local p = surface.back_out(m)
    if not p then
      error(string.format("job: the program's %s (job move of operation %d, blade %d): backed out along its axis the "
                          .. "tool does not reach %s", which, m.operation or 0, m.blade or 0, surface.description), 0)
    end
    local e = {}
    for key, value in pairs(m) do e[key] = value end
    e.kind, e.tip, e.axis, e.motion, e.row, e.feed = "rapid", p.tip, p.axis, "link", nil, nil
    e.operation_kind = "link"
    return e
  end
  local first, last = moves[1], moves[#moves]
  local function inside(m) return not surface.contains or surface.contains(m.tip) end
  if first.motion ~= "link" and inside(first) then
    local e = entry(first, "first move")
    self:prove_motion(e, first, self:tool_entry(first.tool).tool, 1, 2, first.blade, first.blade,
                      "the way in to the program's first move")
    out[1] = e
  end
  for _, m in ipairs(moves) do out[#out + 1] = m end
  if last.motion ~= "link" and inside(last) then
    local e = entry(last, "last move")
    self:prove_motion(last, e, self:tool_entry(last.tool).tool, 1, 2, last.blade, last.blade,
                      "the way out from the program's last move")
    out[#out + 1] = e
  end
  -- The lines out at each tool's first and last move: along the tool axis
  -- and up the program's +Z (`up`: the job frame's -Z when the part is
  -- turned over), whichever the machine's Z slide moves it along.
  for i, m in ipairs(out) do
    local starts = i == 1 or out[i - 1].tool ~= m.tool
    local ends = i == #out or out[i + 1].tool ~= m.tool
    if starts or ends then
      for _, line in ipairs{{m.axis, "the tool axis"}, {up, "the program's +Z"}} do
        local far = {tip = add(m.tip, line[1], M.approach_length), axis = m.axis}
        self:prove_motion(m, far, self:tool_entry(m.tool).tool, 2, 3, m.blade, m.blade,
                          string.format("the line out along %s (%g mm) at the %s move of tool %d", line[2],
                                        M.approach_length, starts and "first" or "last", m.tool))
      end
    end
  end
  return out
end

-- Tool life (the impeller paper's grouping of blades per tool, §4): whole
-- blades in order, each tool's group within its life, the next group on the
-- next sister tool. As few tools as whole blades allow (filled greedily),
-- then the blades spread evenly over them, larger groups first — 17 blades
-- on 4 tools are 5, 4, 4, 4 as in the paper, not 5, 5, 5, 2 — where the
-- even spread keeps every group within the life (blades of unequal length
-- may not: then the greedy groups stand). lengths[i] = cutting length of the
-- i-th blade (mm); numbers = the tool and its sisters. Returns the tool
-- number of each blade and the groups {{tool =, first =, last =, length_mm
-- =}, ...}; an error when one blade alone outlasts the life or the sisters
-- run out.
function M.group_by_life(lengths, life_mm, numbers, what)
  local sizes = {}  -- greedy
  local used = 0
  for i, length in ipairs(lengths) do
    if life_mm and length > life_mm then
      error(string.format("%s: one blade cuts %.0f mm, more than the tool's life of %.0f mm", what, length, life_mm), 0)
    end
    if #sizes == 0 or (life_mm and used + length > life_mm) then
      if #sizes > 0 and not numbers[#sizes + 1] then
        error(string.format("%s: the tool's life of %.0f mm is used up after blade %d of %d and no sister tool is left "
                            .. "(tools.<name>.sisters)", what, life_mm, i - 1, #lengths), 0)
      end
      sizes[#sizes + 1], used = 0, 0
    end
    sizes[#sizes] = sizes[#sizes] + 1
    used = used + length
  end
  local g, n = #sizes, #lengths
  if g > 1 then
    local even, first, fits = {}, 1, true
    for k = 1, g do
      even[k] = n // g + (k <= n % g and 1 or 0)
      local sum = 0
      for i = first, first + even[k] - 1 do sum = sum + lengths[i] end
      fits = fits and sum <= life_mm
      first = first + even[k]
    end
    if fits then sizes = even end
  end
  local of, groups, first = {}, {}, 1
  for k, size in ipairs(sizes) do
    local group = {tool = numbers[k], first = first, last = first + size - 1, length_mm = 0}
    for i = group.first, group.last do
      of[i] = numbers[k]
      group.length_mm = group.length_mm + lengths[i]
    end
    groups[k], first = group, first + size
  end
  return of, groups
end

-- The cutting length of a plan's moves (mm): the tip's path over the cuts.
local function cutting_length(plan_moves)
  local total = 0
  for i = 2, #plan_moves do
    local m, p = plan_moves[i], plan_moves[i - 1]
    if m.kind == "feed" and m.motion == "cut" then
      total = total + math.sqrt((m.tip[1] - p.tip[1]) ^ 2 + (m.tip[2] - p.tip[2]) ^ 2 + (m.tip[3] - p.tip[3]) ^ 2)
    end
  end
  return total
end

-- Plans every operation and links them: returns {moves = {...}, flanks =
-- {...}, links = n}. A move: {kind, tip, axis, feed, row, tool (number),
-- operation (index), kind_of (operation kind), blade, side, motion}.
function Job:plan()
  local moves, flanks, links = {}, {}, 0
  local last = nil
  local groups = {}
  -- The hub finish after the others: its root strip's top reaches over
  -- the edge finishes' first rows (job.hub_finish). Planned in that order,
  -- emitted and linked in the job's.
  self.edge_first_rows = nil
  local planned_of = {}
  for pass = 1, 2 do
    for i, op in ipairs(self.operations) do
      if (op.kind == "hub_finish") == (pass == 2) then planned_of[i] = op:plan_flanks(self, i) end
    end
  end
  for i, op in ipairs(self.operations) do
    local t = self.tools[op.tool]
    local planned_flanks = planned_of[i]
    -- Blades in order with their cutting length, then the tool of each.
    local blade_order, blade_length, index_of = {}, {}, {}
    for _, f in ipairs(planned_flanks) do
      if not index_of[f.blade] then
        blade_order[#blade_order + 1] = f.blade
        index_of[f.blade] = #blade_order
        blade_length[#blade_order] = 0
      end
      blade_length[index_of[f.blade]] = blade_length[index_of[f.blade]] + cutting_length(f.moves_list)
    end
    local tool_of, op_groups = M.group_by_life(blade_length, t.life_mm, {t.number, table.unpack(t.sisters or {})},
                                               string.format("operation %d (%s), tool %d", i, op.kind, t.number))
    for _, g in ipairs(op_groups) do
      groups[#groups + 1] = {operation = i, tool = g.tool, blades = {table.unpack(blade_order, g.first, g.last)},
                             cutting_length_mm = g.length_mm}
    end
    for _, f in ipairs(planned_flanks) do
      local number = tool_of[index_of[f.blade]]
      local what = string.format("operation %d (%s) blade %d %s", i, op.kind, f.blade, f.side)
      local plan_moves = f.moves_list
      if last then
        local first = plan_moves[1]
        local link = self:link(last.pose, {tip = first.tip, axis = first.axis}, t.tool, "link to " .. what,
                               last.blade, f.blade)
        links = links + 1
        for k, p in ipairs(link) do
          -- The back-out to the clearance cylinder is the old tool's last
          -- move: a tool change happens out there, never at the part.
          moves[#moves + 1] = {kind = "rapid", tip = p.tip, axis = p.axis, tool = k == 1 and last.tool or number,
                               operation = i, operation_kind = "link", blade = f.blade, side = f.side, motion = "link"}
        end
      end
      local first_move = #moves + 1
      for _, m in ipairs(plan_moves) do
        -- A notch's plan carries the widening that follows it: its moves
        -- say which operation they belong to.
        local o = m.operation or i
        moves[#moves + 1] = {kind = m.kind, tip = m.tip, axis = m.axis, row = m.row, motion = m.motion,
                             feed = m.kind == "feed" and self.operations[o].feed or nil, tool = number, operation = o,
                             operation_kind = self.operations[o].kind, blade = f.blade, side = f.side}
      end
      last = {pose = {tip = plan_moves[#plan_moves].tip, axis = plan_moves[#plan_moves].axis}, blade = f.blade,
              tool = number}
      flanks[#flanks + 1] = {operation = i, kind = op.kind, blade = f.blade, side = f.side, plan = f.plan,
                             report = f.report, moves = #plan_moves, first_move = first_move,
                             turned_from = f.turned_from, design_flanks = f.flanks, surface = f.surface}
    end
  end
  self.planned = {moves = moves, flanks = flanks, links = links, tool_groups = groups}
  return self.planned
end

-- The independent simulation (core/sim) of every flank after all the moves
-- that machine it: o = {samples_u = 200, samples_v = 1000}. Returns per flank
-- {operation, blade, side, undercut_max, undercut_mean, overcut, overcut_move
-- (index in the job's moves), overcut_motion} and the totals (undercut_max,
-- overcut, where), and for a blisk the seams between the operations'
-- windows (simulate_seams; o.seams = false skips them, o.seam_spacing its
-- spacing): out.seams, out.seam_failures. Link moves stay 0.05 mm or more
-- off every surface (proved in plan()), so they remove nothing and need no
-- sweep. An
-- impeller job is simulated on its surfaces instead (simulate_impeller;
-- sweep_step, search_above and search_below apply there).
function Job:simulate(o)
  o = o or {}
  check_options("job:simulate", o, {
    samples_u = {type = "number", check = function(v) if math.type(v) ~= "integer" or v < 2 then return "expected an integer >= 2" end end},
    samples_v = {type = "number", check = function(v) if math.type(v) ~= "integer" or v < 2 then return "expected an integer >= 2" end end},
    edge_samples_u = {type = "number", check = function(v) if math.type(v) ~= "integer" or v < 2 then return "expected an integer >= 2" end end},
    edge_samples_v = {type = "number", check = function(v) if math.type(v) ~= "integer" or v < 2 then return "expected an integer >= 2" end end},
    sweep_step = {type = "number", check = positive},
    search_above = {type = "number", check = positive},
    search_below = {type = "number", check = positive},
    seams = {type = "boolean"},
    seam_spacing = {type = "number", check = positive},
  }, 2)
  if not self.planned then error("job:simulate: plan the job first (j:plan())", 2) end
  if self.part_kind == "impeller" then return self:simulate_impeller(o) end
  local out = {flanks = {}, undercut_max = 0, overcut = 0}
  -- A turned plan (a periodic operation's other blades) is its first
  -- blade's path turned with the blade: simulated once.
  local done = {}
  for _, f in ipairs(self.planned.flanks) do
    local sim = done[f.plan]
    if not sim then
      if f.kind == "edge_finish" then
        sim = f.plan:simulate{samples_u = o.edge_samples_u or 200, samples_v = o.edge_samples_v or 400,
                              flanks = f.design_flanks}
      elseif f.kind == "hub_finish" then
        -- The root strip above the fillet row and the channel floor; the
        -- fillet itself (the ball's radius in the sharp corner) apart.
        local h = f.plan:simulate{}
        sim = {undercut_max = math.max(h.strip.left_max, h.floor.left_max),
               undercut_mean = 0.5 * (h.strip.left_mean + h.floor.left_mean),
               overcut = math.min(h.root_overcut, h.floor_overcut), unreached = h.strip.unreached + h.floor.unreached,
               fillet_left_max = h.fillet.left_max}
      else
        sim = f.plan:simulate{samples_u = o.samples_u or 200, samples_v = o.samples_v or 1000}
      end
      done[f.plan] = sim
    end
    local r = {operation = f.operation, kind = f.kind, blade = f.blade, side = f.side, undercut_max = sim.undercut_max,
               undercut_mean = sim.undercut_mean, overcut = sim.overcut, overcut_motion = sim.overcut_motion,
               overcut_move = sim.overcut_move and f.first_move + sim.overcut_move - 1 or nil, map = sim.map,
               flank_overcut = sim.flank_overcut, turned_from = f.turned_from, unreached = sim.unreached,
               fillet_left_max = sim.fillet_left_max}
    if sim.flank_overcut and sim.flank_overcut < r.overcut then r.overcut = sim.flank_overcut end
    out.flanks[#out.flanks + 1] = r
    if sim.undercut_max > out.undercut_max then out.undercut_max = sim.undercut_max end
    if sim.overcut < out.overcut then
      out.overcut = sim.overcut
      out.overcut_at = r
    end
  end
  -- And across the boundaries between operations (simulate_seams): each
  -- plan above is measured over its own window only.
  if o.seams ~= false then
    local s = self:simulate_seams{spacing = o.seam_spacing}
    out.seams, out.seam_failures = s.seams, s.failures
  end
  return out
end

-- Blade 1's passes (simulate_blade, simulate_seams): each operation's moves
-- on a blade, in job order, each with its tool — blade 1's drum, edge and
-- hub moves and the neighbours' hub moves (blade N's channel ends on blade
-- 1's pressure root, blade 2's root rows border blade 1's channel floor).
-- moves_of[pass][pose] is the pose's index in the job's moves.
local function blade_passes(self)
  local n = self.part:blade_count()
  local passes, last, moves_of = {}, nil, {}
  for i, m in ipairs(self.planned.moves) do
    local key = m.operation_kind ~= "link" and (m.blade == 1 or (m.operation_kind == "hub_finish" and
                (m.blade == n or m.blade == 2))) and (m.operation .. ":" .. m.blade) or nil
    if key then
      if key ~= last then
        passes[#passes + 1] = {tool = self:tool_entry(m.tool).tool, poses = {}}
        moves_of[#passes] = {}
      end
      local poses = passes[#passes].poses
      poses[#poses + 1] = m
      moves_of[#passes][#poses] = i
    end
    last = key
  end
  return passes, moves_of
end

-- Only what can reach a window (spec = {surface, u, v, search_above}): the
-- stretches of each pass whose poses come within the tool's reach of the
-- window's box, with the pose before and after (a motion from or to a far
-- pose can still cut) — as the hub plan's own simulation does; most of a
-- job's moves are far from any one surface of blade 1. `reach` caches each
-- tool's reach. Returns the passes and their poses' job move indices.
local function passes_near(passes, moves_of, spec, reach)
  local lo, hi = {math.huge, math.huge, math.huge}, {-math.huge, -math.huge, -math.huge}
  for i = 0, 16 do
    for k = 0, 64 do
      local p = spec.surface:point(spec.u[1] + (spec.u[2] - spec.u[1]) * i / 16,
                                   spec.v[1] + (spec.v[2] - spec.v[1]) * k / 64)
      local x = {p.x, p.y, p.z}
      for c = 1, 3 do lo[c], hi[c] = math.min(lo[c], x[c]), math.max(hi[c], x[c]) end
    end
  end
  local out, out_moves = {}, {}
  for pi, pass in ipairs(passes) do
    reach[pass.tool] = reach[pass.tool] or pass.tool:reach()
    local r2 = (reach[pass.tool] + (spec.search_above or 0.5) + 1) ^ 2
    local inside = {}
    for k, m in ipairs(pass.poses) do
      local d2 = 0
      for c = 1, 3 do
        local x = m.tip[c]
        local e = x < lo[c] and lo[c] - x or (x > hi[c] and x - hi[c] or 0)
        d2 = d2 + e * e
      end
      inside[k] = d2 < r2
    end
    local cur, cur_moves = nil, nil
    for k, m in ipairs(pass.poses) do
      if inside[k] or inside[k - 1] or inside[k + 1] then
        if not cur then
          cur, cur_moves = {tool = pass.tool, poses = {}}, {}
          out[#out + 1], out_moves[#out + 1] = cur, cur_moves
        end
        cur.poses[#cur.poses + 1] = m
        cur_moves[#cur.poses] = moves_of[pi][k]
      else
        cur = nil
      end
    end
  end
  return out, out_moves
end

-- One map of blade 1 (issue 18 item 4): the material left and the gouges
-- over the whole blade, each surface swept by every operation's moves that
-- can reach it, each move with its own tool (bliskrun.simulate, core/sim):
-- blade 1's drum, edge and hub moves, and the neighbours' hub moves (blade
-- N's channel ends on blade 1's pressure root, blade 2's root rows border
-- blade 1's channel floor). The regions: both flanks (the drum finish's
-- trimmed flanks, from 0.1 mm above the ball's fillet to the casing, edge to
-- edge), both edges (each edge region over its machined span window, 0.3 mm
-- onto the flanks), the root strip all around the blade up to the hub
-- operation's top and the fillet below it (the ball's radius in the design's
-- sharp corner: material is tracked up to 2 mm there, more counts unreached), and the channel
-- floor to blade 2 — the last three the hub plan's own windows and regions
-- (plan:regions). o = {flank_samples = {u, v}, edge_samples = {around, span},
-- root_samples = {span, around}, floor_samples = {meridian, around}}.
-- Returns {regions = {{name, surface, material_left_max_mm,
-- material_left_min_mm, overcut_mm, overcut_move, unreached, samples, map,
-- tile = {map =, transpose =}}, ...}, material_left_max_mm and unreached
-- (the fillet apart), overcut_mm (all regions), map} — `map` all regions as one
-- picture (bliskrun.map_mosaic: the flanks and edges around the blade, span
-- up; under them the root strip, the fillet and the channel floor).
function Job:simulate_blade(o)
  o = o or {}
  local function pair(v) return type(v) == "table" and #v == 2 and math.type(v[1]) == "integer" and
                                math.type(v[2]) == "integer" and v[1] >= 2 and v[2] >= 2 end
  check_options("job:simulate_blade", o, {
    flank_samples = {type = "table", check = function(v) if not pair(v) then return "expected {u, v} integers >= 2" end end},
    edge_samples = {type = "table", check = function(v) if not pair(v) then return "expected {u, v} integers >= 2" end end},
    root_samples = {type = "table", check = function(v) if not pair(v) then return "expected {u, v} integers >= 2" end end},
    floor_samples = {type = "table", check = function(v) if not pair(v) then return "expected {u, v} integers >= 2" end end},
  }, 2)
  if not self.planned then error("job:simulate_blade: plan the job first (j:plan())", 2) end
  if self.part_kind == "impeller" then error("job:simulate_blade: a blisk job's blade (impellers: j:simulate)", 2) end
  local fs, es = o.flank_samples or {40, 200}, o.edge_samples or {80, 40}
  local rs, ls = o.root_samples or {40, 400}, o.floor_samples or {100, 80}
  local passes, moves_of = blade_passes(self)
  local reach = {}
  local function near(spec) return passes_near(passes, moves_of, spec, reach) end
  local regions = {}
  local function simulate(name, spec, keep)
    local near_passes, near_moves = near(spec)
    if #near_passes == 0 then near_passes, near_moves = {passes[1]}, {moves_of[1]} end
    local r = bliskrun.simulate{surface = spec.surface, passes = near_passes, u = spec.u, v = spec.v,
                                samples_u = spec.samples_u, samples_v = spec.samples_v, flip_normal = spec.flip_normal,
                                search_above = spec.search_above or 0.5, sweep_step = spec.sweep_step, keep = keep}
    local samples = spec.samples_u * spec.samples_v
    if keep then
      samples = 0
      for _, k in ipairs(keep) do if k then samples = samples + 1 end end
    end
    local at = r.overcut_pass and near_moves[r.overcut_pass]
    local region = {name = name, material_left_max_mm = r.residual_max, material_left_min_mm = r.residual_min,
                    overcut_mm = r.overcut, unreached = r.untouched, samples = samples, map = r.map, seconds = r.seconds,
                    overcut_move = at and at[r.overcut_pose] or nil,
                    tile = {map = r.map, transpose = spec.transpose}}
    regions[#regions + 1] = region
    return region
  end
  local hub_plan, fillet_top
  for _, f in ipairs(self.planned.flanks) do
    if f.kind == "hub_finish" and f.blade == 1 then hub_plan, fillet_top = f.plan, f.report.fillet.contact_max end
  end
  local function dist(a, b) return math.sqrt((a.x - b.x) ^ 2 + (a.y - b.y) ^ 2 + (a.z - b.z) ^ 2) end
  local top, around = {}, {}
  for _, side in ipairs({"pressure", "trailing edge", "suction", "leading edge"}) do
    for _, f in ipairs(self.planned.flanks) do
      if f.blade == 1 and f.side == side and f.kind == "drum_finish" then
        local ts = f.plan:trimmed()
        local span = dist(ts:point(0, 0.5), ts:point(1, 0.5))
        local u0 = fillet_top and math.min(0.5, (fillet_top + 0.1) / span) or 0
        top[#top + 1] = simulate(side .. " flank", {surface = ts, u = {u0, 1}, v = {0, 1}, samples_u = fs[1],
                                                    samples_v = fs[2]}).tile
      elseif f.blade == 1 and f.side == side and f.kind == "edge_finish" then
        top[#top + 1] = simulate(side, {surface = f.surface, u = {0, 1}, v = {f.report.span_v0, f.report.span_v1},
                                        samples_u = es[1], samples_v = es[2], transpose = true}).tile
      end
    end
  end
  if hub_plan then
    -- The ball's regions at the hub plan's own sweep step (0.1 mm).
    local w = hub_plan:regions{root_samples = rs, floor_samples = ls}
    if w.floor then w.floor.sweep_step = 0.1 end
    if w.root then
      w.root.sweep_step = 0.1
      around[#around + 1] = simulate("root strip", w.root, w.root.strip).tile
      local fillet = {}
      for k, v in pairs(w.root) do fillet[k] = v end
      fillet.search_above = 2
      around[#around + 1] = simulate("fillet", fillet, w.root.fillet).tile
    end
    if w.floor then around[#around + 1] = simulate("channel floor", w.floor, w.floor.floor).tile end
  end
  local out = {regions = regions, material_left_max_mm = 0, overcut_mm = 0, unreached = 0}
  for _, r in ipairs(regions) do
    if r.name ~= "fillet" then
      if r.material_left_max_mm then out.material_left_max_mm = math.max(out.material_left_max_mm, r.material_left_max_mm) end
      out.unreached = out.unreached + r.unreached
    end
    out.overcut_mm = math.min(out.overcut_mm, r.overcut_mm)
  end
  local rows = {top}
  if #around > 0 then rows[2] = around end
  out.map = bliskrun.map_mosaic{rows = rows, footer = string.format(
    "blade 1: flanks and edges around (span up), under them the root strip, the fillet and the channel floor; "
    .. "left up to %.1f um, %d unreached (fillet apart), overcut %.1f um", 1e3 * out.material_left_max_mm,
    out.unreached, 1e3 * out.overcut_mm)}
  return out
end

-- What an operation promises where it finishes (material left, deepest
-- cut; mm), from its own options: the drum finish its residual (scallop)
-- plus the chord tolerance and the chord as overcut; the edge finish its
-- band e2 / e1; the hub finish its scallop plus the chord of the ball
-- centre's path twice (where a floor row ends on the fillet row, the row
-- and the step along the fillet to the next both pass a sample, each up to
-- its chord off on the concave corner) and the planner's allowed overcut
-- (2 um, HubFinishRequest::allowed_overcut_mm).
local function promise(op)
  if op.kind == "drum_finish" then return {left = op.residual + op.chord_tol, cut = -op.chord_tol} end
  if op.kind == "edge_finish" then return {left = op.e2, cut = op.e1} end
  if op.kind == "hub_finish" then return {left = op.scallop + 2 * op.chord_tol, cut = -0.002} end
  return {left = 0, cut = 0}
end

-- Seams between operations on blade 1 (issue 34 item 8): each operation
-- reports the window it machines, so a band between two windows — or a
-- window's end that borders nothing — is measured by none of them (the
-- built-in LE kept 48.6 um in a band 4.2-4.5 mm above the hub, between the
-- root strip and the edge rows, beyond e2). Here every boundary between two
-- operations' regions is a band a margin either side of both boundaries,
-- simulated (bliskrun.simulate, core/sim) under every pass of every
-- operation that can reach it, each with its own tool and moves:
--   - root strip / edge: on each edge region, from the root strip's top
--     and the edge window's first row, `margin` below the lower to `margin`
--     above the higher (above the ball's fillet);
--   - edge window top: on each edge region, from `margin` below the window's
--     last row to the casing (what lies past the window is nobody's unless
--     the window reaches the blade's tip);
--   - edge / flank: on each drum-finished flank, the edge region's overlap
--     and `margin` more onto the flank at that edge's end, hub to casing;
--   - root strip / flank: on each flank, from above the ball's fillet to
--     `margin` above the root strip's top, edge to edge;
--   - channel floor / fillet (the hub by the blade's root): the floor's
--     samples within 1 mm of its rows' ends, where the floor rows meet the
--     fillet row (plan:regions: floor minus middle).
-- Tolerances: material left at most the looser of the two operations'
-- promises (the band is finished by either), the deepest cut at least the
-- promise of the operation whose move cut it, less `slack` (the sweep's
-- sampling); a sample no tool reaches within search_above (0.5 mm) is
-- unfinished. A seam beyond any of these is a FAIL with its reason — in the
-- result, never an error: the caller reports it.
-- o = {spacing = 0.1 (mm between samples), margin = 1 (mm), slack = 0.0005
-- (mm), only = {names} (those seams alone)}. Returns {seams = {{name,
-- surface, operations, u, v, heights_mm = {lo, hi} (above the hub),
-- samples, unreached, material_left_max_mm,
-- material_left_min_mm, material_left_at = {x, y, z, height_mm, u, v},
-- overcut_mm, overcut_move, overcut_operation, overcut_at, tolerance =
-- {material_left_mm, overcut_mm}, ok, reason, seconds}, ...}, failures,
-- seconds}.
function Job:simulate_seams(o)
  o = o or {}
  check_options("job:simulate_seams", o, {
    spacing = {type = "number", check = positive},
    margin = {type = "number", check = positive},
    slack = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
    only = {type = "table"},
  }, 2)
  if not self.planned then error("job:simulate_seams: plan the job first (j:plan())", 2) end
  local wanted
  if o.only then
    wanted = {}
    for _, name in ipairs(o.only) do wanted[name] = true end
  end
  if self.part_kind == "impeller" then error("job:simulate_seams: a blisk job's seams (impellers: j:simulate)", 2) end
  local t0 = os.clock()
  local spacing, margin, slack = o.spacing or 0.1, o.margin or 1, o.slack or 0.0005
  local hub_m, casing_m = self.part:hub_meridian(), self.part:casing_meridian()
  local function height(p) return meridian_height(hub_m, p) end
  local function below_casing(p) return -meridian_height(casing_m, p) end
  local function dist(a, b) return math.sqrt((a.x - b.x) ^ 2 + (a.y - b.y) ^ 2 + (a.z - b.z) ^ 2) end
  local function count(len) return math.max(4, math.min(600, math.ceil(len / spacing) + 1)) end
  local passes, moves_of = blade_passes(self)
  local reach = {}
  local hub, edges, flanks = nil, {}, {}
  for _, f in ipairs(self.planned.flanks) do
    if f.blade == 1 and not f.turned_from then
      if f.kind == "hub_finish" then hub = f
      elseif f.kind == "edge_finish" then edges[#edges + 1] = f
      elseif f.kind == "drum_finish" then flanks[#flanks + 1] = f end
    end
  end
  local floor_h = hub and hub.report.fillet.contact_max + 0.1 or 0.05
  local function op_name(f) return string.format("%s (operation %d)", f.kind, f.operation) end
  local seams, failures = {}, 0
  -- One band: spec = {name, surface, surface_name, owners = {f, ...}, u, v,
  -- samples_u, samples_v, keep (a function of the point, or a list), flip_normal}.
  local known = {}
  local function seam(spec)
    known[#known + 1] = spec.name
    if wanted and not wanted[spec.name] then return end
    local t = os.clock()
    local su, sv = spec.samples_u, spec.samples_v
    local keep, kept, lo_h, hi_h = nil, 0, math.huge, -math.huge
    if type(spec.keep) == "table" then keep = spec.keep end
    local tested = type(spec.keep) == "function"
    if tested then keep = {} end
    for i = 0, su - 1 do
      for k = 0, sv - 1 do
        local idx = i * sv + k + 1
        local p = spec.surface:point(spec.u[1] + (spec.u[2] - spec.u[1]) * i / (su - 1),
                                     spec.v[1] + (spec.v[2] - spec.v[1]) * k / (sv - 1))
        local ok = true
        if tested then ok = spec.keep(p); keep[idx] = ok elseif keep then ok = keep[idx] end
        if ok then
          kept = kept + 1
          local h = height(p)
          lo_h, hi_h = math.min(lo_h, h), math.max(hi_h, h)
        end
      end
    end
    local tol = {left = 0, cut = 0}
    local names = {}
    for _, f in ipairs(spec.owners) do
      local p = promise(self.operations[f.operation])
      tol.left, tol.cut = math.max(tol.left, p.left), math.min(tol.cut, p.cut)
      names[#names + 1] = op_name(f)
    end
    local out = {name = spec.name, surface = spec.surface_name, operations = names, u = spec.u, v = spec.v,
                 samples = kept, heights_mm = kept > 0 and {lo_h, hi_h} or nil,
                 tolerance = {material_left_mm = tol.left, overcut_mm = tol.cut}}
    if kept == 0 then
      out.ok, out.unreached, out.overcut_mm, out.seconds = true, 0, 0, os.clock() - t
      out.reason = "no sample of the band lies on the part"
      seams[#seams + 1] = out
      return out
    end
    local near, near_moves = passes_near(passes, moves_of, spec, reach)
    local r
    if #near > 0 then
      r = bliskrun.simulate{surface = spec.surface, passes = near, u = spec.u, v = spec.v, samples_u = su,
                            samples_v = sv, flip_normal = spec.flip_normal, search_above = 0.5,
                            sweep_step = spec.sweep_step, keep = keep}
    else
      r = {untouched = kept, overcut = 0}
    end
    out.unreached, out.overcut_mm = r.untouched, r.overcut
    out.material_left_max_mm, out.material_left_min_mm = r.residual_max, r.residual_min
    if r.residual_max_point then
      local p = r.residual_max_point
      out.material_left_at = {x = p.x, y = p.y, z = p.z, height_mm = height(p), u = r.residual_max_u,
                              v = r.residual_max_v}
    end
    -- The deepest cut against the promise of the operation that cut it
    -- (the looser of the owners' when the sweep's deepest sample lies
    -- outside the band and the band's deepest motion is not known).
    local cut_limit = tol.cut
    if r.overcut_pass then
      local move = near_moves[r.overcut_pass][r.overcut_pose]
      local m = self.planned.moves[move]
      out.overcut_move, out.overcut_operation = move, m.operation
      cut_limit = promise(self.operations[m.operation]).cut
    end
    if r.overcut_point then
      local p = r.overcut_point
      out.overcut_at = {x = p.x, y = p.y, z = p.z, height_mm = height(p), u = r.overcut_u, v = r.overcut_v}
    end
    out.tolerance.overcut_mm = cut_limit
    local reasons = {}
    if r.untouched > 0 then
      reasons[#reasons + 1] = string.format("%d of %d samples never reached (no tool within 0.5 mm: unfinished)",
                                            r.untouched, kept)
    end
    if r.residual_max and r.residual_max > tol.left then
      local at = out.material_left_at
      reasons[#reasons + 1] = string.format("%.1f um left, beyond %.1f um, %.2f mm above the hub", 1e3 * r.residual_max,
                                            1e3 * tol.left, at.height_mm)
    end
    if r.overcut < cut_limit - slack then
      reasons[#reasons + 1] = string.format("cut %.2f um deep (job move %s), beyond %.2f um", -1e3 * r.overcut,
                                            tostring(out.overcut_move), -1e3 * cut_limit)
    end
    out.ok = #reasons == 0
    out.reason = #reasons > 0 and table.concat(reasons, "; ") or nil
    if not out.ok then failures = failures + 1 end
    out.seconds = os.clock() - t
    seams[#seams + 1] = out
    return out
  end
  local function on_part(p) local h = height(p) return h >= floor_h and below_casing(p) >= 0 end
  -- The height range of an edge region's row v (over u around).
  local function row_heights(surface, v)
    local lo, hi = math.huge, -math.huge
    for i = 0, 20 do
      local h = height(surface:point(i / 20, v))
      lo, hi = math.min(lo, h), math.max(hi, h)
    end
    return lo, hi
  end
  -- The edge-region v where the row's lowest (highest) point is at height h.
  local function v_at(surface, h, highest)
    local a, b = 0, 1
    for _ = 1, 40 do
      local m = 0.5 * (a + b)
      local lo, hi = row_heights(surface, m)
      if (highest and hi or lo) < h then a = m else b = m end
    end
    return 0.5 * (a + b)
  end
  for _, e in ipairs(edges) do
    local surf, rep = e.surface, e.report
    local around = 0
    for i = 1, 20 do around = around + dist(surf:point((i - 1) / 20, 0.5), surf:point(i / 20, 0.5)) end
    local span = dist(surf:point(0.5, 0), surf:point(0.5, 1))
    local owners = {e}
    local first_lo, first_hi = row_heights(surf, rep.span_v0)
    local lo_h, hi_h = first_lo, first_hi
    if hub then
      lo_h, hi_h = math.min(lo_h, hub.report.heights[2]), math.max(hi_h, hub.report.heights[2])
      owners = {e, hub}
    end
    local v0 = v_at(surf, math.max(floor_h, lo_h - margin), true)
    local v1 = v_at(surf, hi_h + margin, false)
    seam{name = (hub and "root strip / " or "") .. e.side .. (hub and "" or ", window bottom"), surface = surf,
         surface_name = e.side .. " region", owners = owners, u = {0, 1}, v = {v0, v1}, samples_u = count(around),
         samples_v = count((v1 - v0) * span), keep = on_part}
    -- The top: past the window's last row up to the casing.
    local top_v = v_at(surf, select(2, row_heights(surf, rep.span_v1)) - margin, true)
    local casing_v = 1
    seam{name = e.side .. ", window top", surface = surf, surface_name = e.side .. " region", owners = {e},
         u = {0, 1}, v = {math.min(top_v, rep.span_v1), casing_v}, samples_u = count(around),
         samples_v = count((casing_v - math.min(top_v, rep.span_v1)) * span), keep = on_part}
  end
  for _, f in ipairs(flanks) do
    local ts = f.plan:trimmed()
    local span = dist(ts:point(0, 0.5), ts:point(1, 0.5))
    local chord = 0
    for i = 1, 40 do chord = chord + dist(ts:point(0.5, (i - 1) / 40), ts:point(0.5, i / 40)) end
    for _, e in ipairs(edges) do
      -- Pressure flank v: LE -> TE; suction: TE -> LE.
      local at_start = (f.side == "pressure") == (e.side == "leading edge")
      local w = math.min(0.5, (self.operations[e.operation].overlap + margin) / chord)
      local v = at_start and {0, w} or {1 - w, 1}
      seam{name = e.side .. " / " .. f.side .. " flank", surface = ts, surface_name = f.side .. " flank (trimmed)",
           owners = {e, f}, u = {0, 1}, v = v, samples_u = count(span), samples_v = count(w * chord), keep = on_part}
    end
    if hub then
      local u1 = math.min(1, (hub.report.heights[2] + margin) / span)
      seam{name = "root strip / " .. f.side .. " flank", surface = ts, surface_name = f.side .. " flank (trimmed)",
           owners = {hub, f}, u = {0, u1}, v = {0, 1}, samples_u = count(u1 * span), samples_v = count(chord),
           keep = on_part}
    end
  end
  if hub then known[#known + 1] = "channel floor / fillet" end
  for name in pairs(wanted or {}) do
    local found = false
    for _, k in ipairs(known) do found = found or k == name end
    if not found then
      error(string.format("job:simulate_seams: option 'only': no seam '%s' in this job, expected one of: %s", name,
                          table.concat(known, ", ")), 2)
    end
  end
  if hub and (not wanted or wanted["channel floor / fillet"]) then
    -- The channel floor where its rows end on the fillet row (the floor's
    -- samples within 1 mm of the rows' ends); the ball's regions at the hub
    -- plan's own sweep step (0.1 mm).
    local w = hub.plan:regions{root_samples = {4, 4}, floor_samples = {count(20), count(10)}}
    local f = w.floor
    if f then
      local keep = {}
      for i, k in ipairs(f.floor) do keep[i] = k and not f.middle[i] end
      seam{name = "channel floor / fillet", surface = f.surface, surface_name = "hub", owners = {hub}, u = f.u, v = f.v,
           samples_u = f.samples_u, samples_v = f.samples_v, flip_normal = f.flip_normal, keep = keep}
    end
  end
  return {seams = seams, failures = failures, seconds = os.clock() - t0}
end

-- The tools-table entry of a tool number, sisters included (a sister has
-- its tool's form, length and speed).
function Job:tool_entry(n)
  for _, t in pairs(self.tools) do
    for _, k in ipairs({t.number, table.unpack(t.sisters or {})}) do
      if k == n then return t end
    end
  end
end

-- An impeller job simulated (core/sim, bliskrun.simulate) on blade 1's faces
-- (as designed: impeller_world.design_face) and one pitch of the hub — every other blade's moves are blade 1's turned,
-- so blade 1's surfaces see what every blade sees — under the moves of each
-- operation alone, of the links, and of the whole job in order (the material
-- left after everything; a motion between two moves of different tools, the
-- tool change on the clearance surface, is not a cut). Motions that never
-- come within the cutter's reach of a surface are left out of its sweep.
-- Returns {surfaces = {{name, groups = {{name, operation, undercut_max,
-- residual_min, residual_max, overcut, overcut_move, overcut_operation,
-- untouched, seconds, map}, ...}, total = <the "job" group>}, ...},
-- overcut, overcut_at = {surface, move, operation}, seconds}.
function Job:simulate_impeller(o)
  local imp, moves = self.part, self.planned.moves
  local surfaces = {}
  for _, kind in ipairs(imp:has_splitter() and {"main", "splitter"} or {"main"}) do
    for _, side in ipairs({"plus", "minus"}) do
      surfaces[#surfaces + 1] = {name = kind .. " " .. side,
                                 surface = require("impeller_world").design_face(imp, 1, side, kind)}
    end
  end
  -- One pitch of the hub: every channel's floor once (blade feet untouched).
  local hub = imp:hub()
  local d = hub:eval(0.5, 0)
  local radial = {d.point.x, d.point.y, 0}
  local out = d.normal.x * radial[1] + d.normal.y * radial[2] + d.normal.z * math.sqrt(radial[1] ^ 2 + radial[2] ^ 2)
  surfaces[#surfaces + 1] = {name = "hub", surface = hub, v = {0, 1 / imp:blade_count()}, flip = out < 0,
                             search_above = 2}
  -- The cutter's reach per tool number (the sweep only uses the cutter).
  local reach = {}
  local function cutter_reach(n)
    if not reach[n] then
      local r = 0
      for _, seg in ipairs(self:tool_entry(n).tool:profile("cutter")) do
        for _, q in ipairs({seg.from, seg.to}) do r = math.max(r, math.sqrt(q[1] ^ 2 + q[2] ^ 2)) end
      end
      reach[n] = r
    end
    return reach[n]
  end
  local function group_of(i)
    local a, b = moves[i - 1], moves[i]
    if a.tool ~= b.tool then return nil end  -- the tool change, off the part
    if a.operation_kind == "link" or b.operation_kind == "link" then return "links" end
    return b.operation
  end
  local function segment_distance(c, p, q)
    local d = {q[1] - p[1], q[2] - p[2], q[3] - p[3]}
    local dd = d[1] ^ 2 + d[2] ^ 2 + d[3] ^ 2
    local t = dd > 0 and math.max(0, math.min(1, ((c[1] - p[1]) * d[1] + (c[2] - p[2]) * d[2] + (c[3] - p[3]) * d[3]) / dd)) or 0
    return math.sqrt((p[1] + t * d[1] - c[1]) ^ 2 + (p[2] + t * d[2] - c[2]) ^ 2 + (p[3] + t * d[3] - c[3]) ^ 2)
  end
  local result = {surfaces = {}, overcut = 0}
  local t0 = os.clock()
  for _, sfc in ipairs(surfaces) do
    -- Bounding sphere of the sampled window.
    local pts, c = {}, {0, 0, 0}
    local v0, v1 = sfc.v and sfc.v[1] or 0, sfc.v and sfc.v[2] or 1
    for a = 0, 10 do
      for b = 0, 10 do
        local p = sfc.surface:point(a / 10, v0 + (v1 - v0) * b / 10)
        pts[#pts + 1] = {p.x, p.y, p.z}
        c = {c[1] + p.x, c[2] + p.y, c[3] + p.z}
      end
    end
    c = {c[1] / #pts, c[2] / #pts, c[3] / #pts}
    local radius = 0
    for _, p in ipairs(pts) do
      radius = math.max(radius, math.sqrt((p[1] - c[1]) ^ 2 + (p[2] - c[2]) ^ 2 + (p[3] - c[3]) ^ 2))
    end
    -- 11 x 11 samples can miss a little of the window's extent: 2 % and 5 mm more.
    radius = 1.02 * radius + 5
    -- o.search_above: deeper stock than the default window (1 mm over a
    -- face, 2 over the hub) is tracked, not counted untouched; o.search_below
    -- (0.5 mm): how deep an overcut is measured (a deeper one reads as that).
    local search_above = math.max(sfc.search_above or 1, o.search_above or 0)
    -- Passes: runs of consecutive motions of one group (an operation, or the
    -- links) near the surface. One sweep per group; the job's is the lowest
    -- of them (every motion is in one group), computed by bliskrun.simulate.
    local passes, first, names, last = {}, {}, {}, {}
    for i = 2, #moves do
      local key = group_of(i)
      if key and segment_distance(c, moves[i - 1].tip, moves[i].tip) <= radius + cutter_reach(moves[i].tool) + search_above then
        local name = key == "links" and "links" or tostring(key)
        if last[name] ~= i - 1 then
          passes[#passes + 1] = {tool = self:tool_entry(moves[i].tool).tool, poses = {moves[i - 1]}, group = name}
          first[#passes] = i - 1
          names[name] = #passes
        end
        local pass = passes[names[name]]
        pass.poses[#pass.poses + 1] = moves[i]
        last[name] = i
      end
    end
    local rs = {name = sfc.name, groups = {}}
    if #passes > 0 then
      local sim = bliskrun.simulate{surface = sfc.surface, passes = passes, samples_u = o.samples_u or 60,
                                    samples_v = o.samples_v or 300, v = sfc.v, flip_normal = sfc.flip,
                                    search_above = search_above, search_below = o.search_below or 0.5, sweep_step = o.sweep_step or 0.1}
      local function entry(r, key)
        local e = {name = key == "job" and "job" or key == "links" and "links" or self.operations[tonumber(key)].kind,
                   operation = tonumber(key), undercut_max = r.undercut_max, undercut_mean = r.undercut_mean,
                   residual_min = r.residual_min, residual_max = r.residual_max, overcut = r.overcut,
                   untouched = r.untouched, samples = r.samples, seconds = r.seconds, map = r.map}
        if r.overcut_pass then
          e.overcut_move = first[r.overcut_pass] + r.overcut_pose - 1
          e.overcut_operation = moves[e.overcut_move].operation_kind
          e.overcut_point = r.overcut_point
        end
        return e
      end
      local order = {}
      for k, g in ipairs(sim.groups) do order[k] = g end
      table.sort(order, function(a, b)
        local ka, kb = a.name == "links" and 1e9 or tonumber(a.name), b.name == "links" and 1e9 or tonumber(b.name)
        return ka < kb
      end)
      for _, g in ipairs(order) do rs.groups[#rs.groups + 1] = entry(g, g.name) end
      rs.total = entry(sim, "job")
      rs.groups[#rs.groups + 1] = rs.total
      if rs.total.overcut < result.overcut then
        result.overcut = rs.total.overcut
        result.overcut_at = {surface = sfc.name, move = rs.total.overcut_move, operation = rs.total.overcut_operation}
      end
    end
    result.surfaces[#result.surfaces + 1] = rs
  end
  result.seconds = os.clock() - t0
  return result
end

-- An impeller job's simulation (j:simulate) for a run's report: prints each
-- surface's state after the job, writes its map (o.pictures .. name ..
-- ".png") and returns {json = {surfaces, seconds}, rows = (the report
-- table's rows), pictures = {{title, image}, ...}}. o.search_below: the
-- depth an overcut was measured to — one reaching it is printed "AT LEAST"
-- and flagged overcut_at_window_depth.
function Job:report_simulation(sim, o)
  local out = {json = {surfaces = {}, seconds = sim.seconds}, rows = {}, pictures = {}}
  for _, s in ipairs(sim.surfaces) do
    local entry = {name = s.name, groups = {}}
    for _, g in ipairs(s.groups) do
      entry.groups[#entry.groups + 1] = {name = g.name, operation = g.operation, residual_min_mm = g.residual_min,
        residual_max_mm = g.residual_max, undercut_mean_mm = g.undercut_mean, overcut_mm = g.overcut,
        overcut_move = g.overcut_move, overcut_operation = g.overcut_operation, untouched = g.untouched,
        samples = g.samples, seconds = g.seconds}
      out.rows[#out.rows + 1] = {s.name, g.name, g.residual_min and 1e3 * g.residual_min or "-",
                                 g.residual_max and 1e3 * g.residual_max or "-", 1e3 * g.undercut_mean, 1e3 * g.overcut,
                                 g.overcut_move or "-", g.untouched}
    end
    out.json.surfaces[#out.json.surfaces + 1] = entry
    local t = s.total
    if t then
      entry.overcut_at_window_depth = o.search_below and t.overcut <= -o.search_below + 1e-9 or nil
      print(string.format("  simulated %-14s after the job: %s, overcut %s%.1f um%s", s.name,
                          t.residual_min and string.format("material left %.3f..%.3f mm", t.residual_min, t.residual_max)
                            or "not reached by this job", entry.overcut_at_window_depth and "AT LEAST " or "",
                          -1e3 * t.overcut,
                          t.overcut_move and string.format(" (job move %d, %s)", t.overcut_move, t.overcut_operation) or ""))
      local picture = o.pictures .. s.name:gsub(" ", "_") .. ".png"
      t.map:write_png(picture, {title = "Material left after the job, blade 1 " .. s.name .. " (mm)"})
      out.pictures[#out.pictures + 1] = {title = "Material left, " .. s.name, image = picture}
    end
  end
  return out
end

-- The stop after an impeller job's simulation (j:simulate): a face may be
-- overcut by its own flank finish's planned residual (units: the plan's
-- {operation, name, report} of blade 1, `slack` mm for the simulation's
-- sampling), nothing else anywhere beyond the sweep's 2 um. An error names
-- the surface, the depth and the job move that cut it.
function Job:check_overcut(sim, units, slack)
  local allowed = {}
  for _, u in ipairs(units) do
    if u.operation == "flank_finish" then allowed[u.name] = math.min(0, u.report.residual_min) - slack end
  end
  for _, s in ipairs(sim.surfaces) do
    local t, floor = s.total, allowed[s.name] or -0.002
    if t and t.overcut < floor then
      error(string.format("simulation: blade 1 %s is overcut %.1f um at job move %d (%s), beyond the %.1f um its "
                          .. "operations allow; nothing is posted", s.name, -1e3 * t.overcut, t.overcut_move or -1,
                          t.overcut_operation or "?", -1e3 * floor), 0)
    end
  end
end

-- The one-line summary of a posted program (post.write's report) and its
-- entry for a run's JSON report. m = {machine =, name =, post =, file =, setup =}.
local function program_entry(m, r)
  local s = r.seconds
  print(string.format("  %s: %d blocks (%d positioning moves), tip within %.4f mm of the plan; %.1f s (path %.1f, "
                      .. "machine motion %.1f, post %.1f, read back and sweep %.1f, write %.1f)", m.file, r.moves,
                      r.positioning, r.max_position, s.read + s.motion + s.post + s.verify + s.write, s.read, s.motion,
                      s.post, s.verify, s.write))
  print(string.format("    swept as the controller moves (%s): cutter within %.2f um, tool within %.1f um of the proved "
                      .. "motion (tolerances %.1f / %.0f um); %d blocks slowed for the cutter or a rotary axis (cutter "
                      .. "at most %.2f x the feed; feed moves %.1f min, %.1f min at the planned tip feed); %d rotary "
                      .. "resets, largest rotary word %.1f deg", r.controller, 1e3 * r.swept_cutter, 1e3 * r.swept_tool,
                      1e3 * r.chord_tol, 1e3 * r.body_tol, r.slowed, r.cutter_speed_ratio, r.feed_minutes,
                      r.tip_feed_minutes, r.rotary_resets, r.rotary_largest))
  return {file = m.file, machine = m.name or m.machine, post = m.post, blocks = r.moves, positioning = r.positioning,
          max_position_mm = r.max_position, max_angle_deg = r.max_angle, setup = m.setup and m.setup.name or nil,
          controller = r.controller, swept_cutter_mm = r.swept_cutter, swept_tool_mm = r.swept_tool,
          swept_blocks = r.swept, unswept_blocks = r.unswept, safe_blocks = r.safe_moves, slowed_blocks = r.slowed,
          cutter_speed_ratio = r.cutter_speed_ratio, rotary_speed_deg_per_min = r.rotary_speed,
          rotary_resets = r.rotary_resets, rotary_largest_deg = r.rotary_largest, inserted_blocks = r.inserted,
          feed_minutes = r.feed_minutes, tip_feed_minutes = r.tip_feed_minutes}
end

-- Posts for one machine (j:post) and prints the one-line summary; returns
-- the program's entry for a run's JSON report. m = {machine = name or
-- Machine, name = (how the report calls a Machine), post =, file =}.
function Job:post_program(m)
  return program_entry(m, self:post{machine = m.machine, post = m.post, file = m.file, setup = m.setup, start = m.start,
                                    work_offset = m.work_offset, notes = m.notes})
end

-- Posts several programs at once (bliskrun.post.write_all: on the run's
-- threads, the longest first; each read back and replayed as j:post does)
-- and prints their summaries in list order; returns their entries. list =
-- {m, ...} as j:post_program takes. A setup's path is made once for all
-- the machines that take it.
function Job:post_programs(list)
  local options, offsets, paths = {}, {}, {}
  for i, m in ipairs(list) do
    local o = {machine = m.machine, post = m.post, file = m.file, setup = m.setup, start = m.start,
               work_offset = m.work_offset, notes = m.notes}
    local key = m.setup or "whole"
    paths[key] = paths[key] or {self:program_path(o, 3)}
    options[i], offsets[i] = self:post_options(o, paths[key][1], 3), paths[key][2]
  end
  local ok, result = pcall(bliskrun.post.write_all, options)
  if not ok then
    local message = tostring(result)
    local k = tonumber(message:match("programs%[(%d+)%]"))
    self:raise_post_error(message, k and offsets[k] or 0, 3)
  end
  local entries = {}
  for i, m in ipairs(list) do entries[i] = program_entry(m, result[i]) end
  return entries
end

-- `level`: the error level of the recipe line, seen from the function
-- that takes it (as error() counts).
local function check_post_options(o, level)
  check_options("job:post", o, {
    machine = {type = "any", required = true}, post = {type = "any", required = true},
    file = {type = "string", required = true}, chord_tol = {type = "number", check = positive},
    setup = {type = "table"},
    start = {type = "table"},  -- the machine's axes before the first move (picks the rotary branch)
    work_offset = {type = "number"},  -- G54 = 1 / the TNC's preset (post.write checks it)
    notes = {type = "table"},         -- header lines of the recipe's own
  }, level)
end

-- The moves of a program and the job move before its first: o.setup =
-- {name =, first =, last =, flip = bool, clocking_deg = 0}: the job's moves
-- first..last as one program, with the part turned over (180 deg about X: the
-- side of the part that faced the table faces the spindle) when flip, then
-- turned clocking_deg about Z (how it is clocked on the fixture). A blisk's
-- leading edges face the table with its axis on C: no tool direction the A
-- cradle reaches cuts them in the first setup. The program's header states
-- both (post.write's setup).
function Job:program_path(o, level)
  check_post_options(o, level + 1)
  if not self.planned then error("job:post: plan the job first (j:plan())", level) end
  local first, last = 1, #self.planned.moves
  if o.setup then first, last = o.setup.first or 1, o.setup.last or #self.planned.moves end
  local moves = {}
  for i = first, last do moves[#moves + 1] = self.planned.moves[i] end
  local up = o.setup and o.setup.flip and {0, 0, -1} or {0, 0, 1}
  local ok, ends = pcall(self.program_ends, self, moves, up)
  if not ok then error(tostring(ends), level) end
  -- Job move numbers in messages count the program's moves from `first`;
  -- a way in put before them shifts them by one.
  local shift = #ends > 0 and ends[1] ~= moves[1] and 1 or 0
  if not o.setup then return ends, first - 1 - shift end
  local clocking = o.setup.clocking_deg or 0
  if type(clocking) ~= "number" then error("job:post: setup.clocking_deg: expected a number (degrees)", level) end
  local clock = clocking ~= 0 and {c = math.cos(math.rad(clocking)), s = math.sin(math.rad(clocking))} or nil
  local path = {}
  for _, m in ipairs(ends) do
    if o.setup.flip or clock then
      local t = {}
      for key, value in pairs(m) do t[key] = value end
      local tip, axis = m.tip, m.axis
      if o.setup.flip then
        tip, axis = {tip[1], -tip[2], -tip[3]}, {axis[1], -axis[2], -axis[3]}
      end
      if clock then
        tip = {clock.c * tip[1] - clock.s * tip[2], clock.s * tip[1] + clock.c * tip[2], tip[3]}
        axis = {clock.c * axis[1] - clock.s * axis[2], clock.s * axis[1] + clock.c * axis[2], axis[3]}
      end
      t.tip, t.axis = tip, axis
      m = t
    end
    path[#path + 1] = m
  end
  return path, first - 1 - shift
end

-- post.write's options for a program of `path`: the program's tools in the
-- order they are first used (a sister tool has its tool's length and speed).
function Job:post_options(o, path, level)
  check_post_options(o, level + 1)
  local tools, order, bottom_only = {}, {}, {}
  for _, m in ipairs(path) do
    if not order[m.tool] then
      order[m.tool] = true
      local t = self:tool_entry(m.tool)
      tools[#tools + 1] = {number = m.tool, length = t.length, spindle_rpm = t.spindle_rpm, body = t.tool}
      bottom_only[m.tool] = true
    end
    if m.operation_kind ~= "edge_finish" and m.operation_kind ~= "link" then bottom_only[m.tool] = false end
  end
  -- The feed at the cutter is measured on the part of it that cuts: the
  -- edge finish cuts with a flat-end mill's bottom and corner (the profile
  -- up to the end of its first arc), not its flutes.
  for _, t in ipairs(tools) do
    if bottom_only[t.number] and t.body:kind() == "flat-end mill" then
      local reach = 0
      for _, e in ipairs(t.body:profile()) do
        for _, rz in ipairs{e.from, e.to} do reach = math.max(reach, math.sqrt(rz[1] ^ 2 + rz[2] ^ 2)) end
        if e.kind == "arc" then break end
      end
      t.active_reach = reach
    end
  end
  local machine = type(o.machine) == "string" and bliskrun.machine.load(o.machine) or o.machine
  -- The header states the setup: which one, turned over or not, clocking.
  local setup = o.setup and {name = o.setup.name, flip = o.setup.flip or false, clocking_deg = o.setup.clocking_deg or 0}
  return {machine = machine, post = o.post, path = path, file = o.file, tools = tools, name = self.name,
          chord_tol = o.chord_tol or 0.002, start = o.start, approach = {proved = M.approach_length, proved_up = M.approach_length},
          setup = setup,
          work_offset = o.work_offset, notes = o.notes}
end

-- A move out of travel (or out of reach) names the job's move: say which
-- operation, blade and flank it belongs to. `offset`: the job move before
-- the program's first.
function Job:raise_post_error(message, offset, level)
  local start = tonumber(message:match("moves start at move (%d+)")) or 1
  local n = tonumber(message:match("%):.-move (%d+)") or message:match("move (%d+)"))
  local m = n and self.planned.moves[offset + start + n - 1]
  if m then
    error(string.format("job:post: job move %d (operation %d %s, blade %d %s flank, %s): %s", offset + start + n - 1,
                        m.operation, m.operation_kind, m.blade, m.side, m.motion or m.kind, message), level)
  end
  error(message, level)
end

-- Posts the planned job for one machine: o = {machine = name or Machine,
-- post = name or post table, file =, chord_tol = 0.002, setup =, start =}.
-- Returns the post.write report (the program read back and replayed).
function Job:post(o)
  local path, offset = self:program_path(o, 3)
  local ok, result = pcall(bliskrun.post.write, self:post_options(o, path, 3))
  if ok then return result end
  self:raise_post_error(tostring(result), offset, 3)
end

return M
