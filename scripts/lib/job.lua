-- A machining job (issue 13 item 1, issue 18 item 3): one part, a tool
-- table and an ordered list of operations, planned into one toolpath that
-- carries the operation, tool, blade and flank of every move, linked safely
-- from one operation (or flank) to the next through a clearance cylinder
-- about the part axis, and posted as one program per machine.
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

-- ---- operations ------------------------------------------------------------

-- Drum-wheel flank finishing (blisk paper §3) of the given blades' flanks,
-- one plan per flank with the shared settings of scripts/lib/blisk_finish.lua.
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
  }, 2)
  local op = {kind = "drum_finish", tool = o.tool, blades = o.blades, sides = o.sides or {"pressure", "suction"},
              residual = o.residual or 0.014, chord_tol = o.chord_tol or 0.002, c_range = o.c_range or 30,
              shank_clearance = o.shank_clearance or 0.1, feed = o.feed or 600}
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
    for _, k in ipairs(self.blades) do
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
      flanks[#flanks + 1] = {blade = k, side = side, plan = plan, report = r, feed = self.feed}
    end
    return flanks
  end
  return op
end

-- ---- the job -------------------------------------------------------------

local Job = {}
Job.__index = Job

function M.new(spec)
  check_options("job.new", spec, {
    name = {type = "string", required = true},
    part = {type = "userdata", required = true},
    clearance_radius = {type = "number", required = true, check = positive},
    link_clearance = {type = "table"},
    tools = {type = "table", required = true},
    operations = {type = "table", required = true, check = function(v) if #v == 0 then return "expected at least one operation" end end},
  }, 2)
  local casing = 0
  for _, p in ipairs(spec.part:casing_meridian()) do casing = math.max(casing, p[2]) end
  if spec.clearance_radius <= casing + 1 then
    error(string.format("job.new: option 'clearance_radius': %.3f mm is not outside the casing (radius up to %.3f mm) "
                        .. "by at least 1 mm", spec.clearance_radius, casing), 2)
  end
  local numbers = {}
  for name, t in pairs(spec.tools) do
    check_options("job.new tools." .. tostring(name), t, {
      number = {type = "number", required = true, check = function(v) if math.type(v) ~= "integer" or v < 0 then return "expected a tool number" end end},
      length = {type = "number", required = true, check = positive},
      spindle_rpm = {type = "number"},
      tool = {type = "userdata", required = true},
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
  for i, op in ipairs(spec.operations) do
    if type(op) ~= "table" or not op.kind then
      error(string.format("job.new: operations[%d]: expected an operation (job.drum_finish{...})", i), 2)
    end
    if not spec.tools[op.tool] then
      error(string.format("job.new: operations[%d] (%s) uses tool '%s', which the tools table does not list", i, op.kind,
                          tostring(op.tool)), 2)
    end
  end
  return setmetatable({name = spec.name, part = spec.part, clearance_radius = spec.clearance_radius,
                       link_clearance = spec.link_clearance or {cutter = 0, shank = 0.1, holder = 1},
                       tools = spec.tools, operations = spec.operations, worlds = {}}, Job)
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

local function radius(p) return math.sqrt(p[1] ^ 2 + p[2] ^ 2) end
local function add(a, b, s) return {a[1] + s * b[1], a[2] + s * b[2], a[3] + s * b[3]} end
local function unit(a)
  local n = math.sqrt(a[1] ^ 2 + a[2] ^ 2 + a[3] ^ 2)
  return {a[1] / n, a[2] / n, a[3] / n}
end

-- The point where the tool, backed out along its axis from `pose`, has its
-- tip on the clearance cylinder (radius R about Z).
local function backed_out(pose, R, what)
  local p, a = pose.tip, pose.axis
  -- |xy(p + t a)| = R: (a.a) t^2 + 2 (p.a) t + (p.p - R^2) = 0 in xy.
  local A = a[1] ^ 2 + a[2] ^ 2
  local B = p[1] * a[1] + p[2] * a[2]
  local C = p[1] ^ 2 + p[2] ^ 2 - R * R
  local disc = B * B - A * C
  if A < 0.04 or disc < 0 then
    error(string.format("job: %s: the tool axis (%.3f, %.3f, %.3f) points along the part axis; backing out along it "
                        .. "does not reach the clearance radius", what, a[1], a[2], a[3]), 0)
  end
  local t = (-B + math.sqrt(disc)) / A
  if t < 0 then t = 0 end
  return {tip = add(p, a, t), axis = a}
end

-- Link from pose `a` to pose `b` through the clearance cylinder: back out
-- along a's axis, travel round the cylinder in steps short enough that every
-- chord stays within 0.5 mm of it (axis turning from a's to b's), then in
-- along b's axis. Each motion is proved clear of the whole part.
function Job:link(a, b, tool, what, blade_a, blade_b)
  local R = self.clearance_radius
  local out, into = backed_out(a, R, what .. " (back out)"), backed_out(b, R, what .. " (approach)")
  local t1, t2 = math.atan(out.tip[2], out.tip[1]), math.atan(into.tip[2], into.tip[1])
  local dt = t2 - t1
  while dt > math.pi do dt = dt - 2 * math.pi end
  while dt < -math.pi do dt = dt + 2 * math.pi end
  local step = 2 * math.acos((R - 0.5) / R)
  local n = math.max(1, math.ceil(math.abs(dt) / step))
  local poses = {out}
  for i = 1, n do
    local s = i / n
    local t = t1 + s * dt
    local z = out.tip[3] + s * (into.tip[3] - out.tip[3])
    local axis = unit(add(out.axis, {into.axis[1] - out.axis[1], into.axis[2] - out.axis[2], into.axis[3] - out.axis[3]}, s))
    poses[#poses + 1] = {tip = {R * math.cos(t), R * math.sin(t), z}, axis = i == n and into.axis or axis}
  end
  poses[#poses + 1] = b
  local from = a
  for i, to in ipairs(poses) do
    -- The first motion leaves blade a, the last reaches blade b; the ones
    -- between run on the clearance cylinder, past any blade.
    local world = i == 1 and self:link_world(blade_a) or i == #poses and self:link_world(blade_b) or self:part_world()
    local m = world:check_motion(tool, from, to, {clearance = self.link_clearance})
    if not m.clear then
      error(string.format("job: %s: link motion %d of %d is not proved clear of the part (margin %.3f mm at t = %.3f)",
                          what, i, #poses, m.min_margin or 0 / 0, m.t or 0 / 0), 0)
    end
    from = to
  end
  table.remove(poses)  -- b itself is the next plan's first move
  return poses
end

-- Tool life (the impeller paper's grouping of blades per tool, §4): whole
-- blades in order, as many per tool as its life allows, the next group on the
-- next sister tool. lengths[i] = cutting length of the i-th blade (mm);
-- numbers = the tool and its sisters. Returns the tool number of each blade
-- and the groups {{tool =, first =, last =, length_mm =}, ...}; an error when
-- one blade alone outlasts the life or the sisters run out.
function M.group_by_life(lengths, life_mm, numbers, what)
  local of, groups = {}, {}
  local current, used = 1, 0
  for i, length in ipairs(lengths) do
    if life_mm and length > life_mm then
      error(string.format("%s: one blade cuts %.0f mm, more than the tool's life of %.0f mm", what, length, life_mm), 0)
    end
    if life_mm and used + length > life_mm and used > 0 then
      current, used = current + 1, 0
      if not numbers[current] then
        error(string.format("%s: the tool's life of %.0f mm is used up after blade %d of %d and no sister tool is left "
                            .. "(tools.<name>.sisters)", what, life_mm, i - 1, #lengths), 0)
      end
    end
    used = used + length
    of[i] = numbers[current]
    local g = groups[#groups]
    if not g or g.tool ~= numbers[current] then
      g = {tool = numbers[current], first = i, last = i, length_mm = 0}
      groups[#groups + 1] = g
    end
    g.last = i
    g.length_mm = g.length_mm + length
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
  for i, op in ipairs(self.operations) do
    local t = self.tools[op.tool]
    local planned_flanks = op:plan_flanks(self)
    -- Blades in order with their cutting length, then the tool of each.
    local blade_order, blade_length, index_of = {}, {}, {}
    for _, f in ipairs(planned_flanks) do
      f.moves_list = f.plan:moves()
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
        moves[#moves + 1] = {kind = m.kind, tip = m.tip, axis = m.axis, row = m.row, motion = m.motion,
                             feed = m.kind == "feed" and f.feed or nil, tool = number, operation = i,
                             operation_kind = op.kind, blade = f.blade, side = f.side}
      end
      last = {pose = {tip = plan_moves[#plan_moves].tip, axis = plan_moves[#plan_moves].axis}, blade = f.blade,
              tool = number}
      flanks[#flanks + 1] = {operation = i, kind = op.kind, blade = f.blade, side = f.side, plan = f.plan,
                             report = f.report, moves = #plan_moves, first_move = first_move}
    end
  end
  self.planned = {moves = moves, flanks = flanks, links = links, tool_groups = groups}
  return self.planned
end

-- The independent simulation (core/sim) of every flank after all the moves
-- that machine it: o = {samples_u = 200, samples_v = 1000}. Returns per flank
-- {operation, blade, side, undercut_max, undercut_mean, overcut, overcut_move
-- (index in the job's moves), overcut_motion} and the totals (undercut_max,
-- overcut, where). Link moves stay 0.05 mm or more off every surface
-- (proved in plan()), so they remove nothing and need no sweep.
function Job:simulate(o)
  o = o or {}
  check_options("job:simulate", o, {
    samples_u = {type = "number", check = function(v) if math.type(v) ~= "integer" or v < 2 then return "expected an integer >= 2" end end},
    samples_v = {type = "number", check = function(v) if math.type(v) ~= "integer" or v < 2 then return "expected an integer >= 2" end end},
  }, 2)
  if not self.planned then error("job:simulate: plan the job first (j:plan())", 2) end
  local out = {flanks = {}, undercut_max = 0, overcut = 0}
  for _, f in ipairs(self.planned.flanks) do
    local sim = f.plan:simulate{samples_u = o.samples_u or 200, samples_v = o.samples_v or 1000}
    local r = {operation = f.operation, kind = f.kind, blade = f.blade, side = f.side, undercut_max = sim.undercut_max,
               undercut_mean = sim.undercut_mean, overcut = sim.overcut, overcut_motion = sim.overcut_motion,
               overcut_move = sim.overcut_move and f.first_move + sim.overcut_move - 1 or nil, map = sim.map}
    out.flanks[#out.flanks + 1] = r
    if sim.undercut_max > out.undercut_max then out.undercut_max = sim.undercut_max end
    if sim.overcut < out.overcut then
      out.overcut = sim.overcut
      out.overcut_at = r
    end
  end
  return out
end

-- Posts the planned job for one machine: o = {machine = name or Machine,
-- post = name or post table, file =, chord_tol = 0.002}. Returns the
-- post.write report (the program read back and replayed).
function Job:post(o)
  check_options("job:post", o, {
    machine = {type = "any", required = true}, post = {type = "any", required = true},
    file = {type = "string", required = true}, chord_tol = {type = "number", check = positive},
  }, 2)
  if not self.planned then error("job:post: plan the job first (j:plan())", 2) end
  -- The program's tools in the order they are first used; a sister tool
  -- has its tool's length and speed.
  local tools, order = {}, {}
  for _, m in ipairs(self.planned.moves) do
    if not order[m.tool] then
      order[m.tool] = true
      for _, t in pairs(self.tools) do
        for _, n in ipairs({t.number, table.unpack(t.sisters or {})}) do
          if n == m.tool then tools[#tools + 1] = {number = n, length = t.length, spindle_rpm = t.spindle_rpm} end
        end
      end
    end
  end
  local machine = type(o.machine) == "string" and bliskrun.machine.load(o.machine) or o.machine
  local ok, result = pcall(bliskrun.post.write, {machine = machine, post = o.post, path = self.planned.moves,
                                                 file = o.file, tools = tools, name = self.name,
                                                 chord_tol = o.chord_tol or 0.002})
  if ok then return result end
  -- A move out of travel (or out of reach) names the job's move: say which
  -- operation, blade and flank it belongs to.
  local message = tostring(result)
  local offset = tonumber(message:match("moves start at move (%d+)")) or 1
  local n = tonumber(message:match("%):.-move (%d+)") or message:match("move (%d+)"))
  local m = n and self.planned.moves[offset + n - 1]
  if m then
    error(string.format("job:post: job move %d (operation %d %s, blade %d %s flank, %s): %s", offset + n - 1,
                        m.operation, m.operation_kind, m.blade, m.side, m.motion or m.kind, message), 2)
  end
  error(message, 2)
end

return M
