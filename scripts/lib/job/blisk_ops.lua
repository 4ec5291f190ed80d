-- The blisk operations of a job (scripts/lib/job.lua is the entry): drum-
-- wheel flank finishing, edge finishing with a flat-end mill, the hub and
-- blade roots with a ball end. Each is its option table, checked at the
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
  }, 2)
  local op = {kind = "edge_finish", tool = o.tool, blades = o.blades, edges = o.edges or {"leading", "trailing"},
              e1 = o.e1 or -0.001, e2 = o.e2 or 0.02, overlap = o.overlap or 0.3, span = o.span or {0, 1},
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

return M
