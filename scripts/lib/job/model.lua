-- The job model (scripts/lib/job.lua is the entry): a job is data — one
-- part, a tool table and an ordered list of operations — and planning it is
-- a function of that data: every operation planned (job/blisk_ops.lua,
-- job/impeller_ops.lua), the units (flanks, edges, channels, faces) joined
-- in order by links proved clear (job/links.lua) into one toolpath whose
-- every move carries its operation, tool, blade and flank. Then it is
-- simulated (job/simulate.lua, job/seams.lua), posted (job/post.lua) and
-- reported (job/report.lua, job/run.lua).
local options = require("job.options")
local clearance = require("job.clearance")

local check_options, positive = options.check, options.positive

local M = {}

-- The Job type: its methods live in the job/*.lua modules of what they do.
local Job = {}
Job.__index = Job
M.Job = Job

-- job.new{name=, part=, clearance_radius= | clearance=, tools=, operations=,
-- link_clearance=}: the job's data, every option checked at the recipe's
-- line before anything is planned (docs/lua_api.md, Jobs).
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
    blank = {type = "table"},  -- the stock (job/stock.lua): {profile = {{r, z}, ...}, resolution = 0.5}
    tools = {type = "table", required = true},
    operations = {type = "table", required = true, check = function(v) if #v == 0 then return "expected at least one operation" end end},
  }, 2)
  if spec.blank then require("job.stock").check_blank(spec.blank, 2) end
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
    clearance_surface = clearance.cylinder(spec.clearance_radius, zmin - axial, zmax + axial)
  else
    if not spec.clearance then error("job.new: missing option 'clearance' (an impeller's links run this many mm "
                                     .. "over its outline)", 2) end
    clearance_surface = clearance.over_impeller(spec.part, spec.clearance)
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
  local blisk_ops = {rough_channels = true, drum_finish = true, edge_finish = true, hub_finish = true}
  local impeller_ops = {notch = true, widen = true, flank_finish = true, point_mill = true}
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
    if (impeller_ops[op.kind] and op.kind ~= "widen" or op.kind == "rough_channels") and not t.ball_radius then
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
                       tools = spec.tools, operations = spec.operations, worlds = {}, blank = spec.blank}, Job)
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

-- The tools-table entry of a tool number, sisters included (a sister has
-- its tool's form, length and speed).
function Job:tool_entry(n)
  for _, t in pairs(self.tools) do
    for _, k in ipairs({t.number, table.unpack(t.sisters or {})}) do
      if k == n then return t end
    end
  end
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
      if (op.kind == "hub_finish") == (pass == 2) then
        if self.on_plan_step then self.on_plan_step(op) end  -- j:run's progress line
        planned_of[i] = op:plan_flanks(self, i, planned_of)
      end
    end
  end
  -- A point mill that took faces over from a flank finish (job.point_mill's
  -- instead_of_flank): the flank finish's units of those faces are dropped.
  for i, op in ipairs(self.operations) do
    if op.kind == "point_mill" and op.instead_of_flank then
      local taken = {}
      for _, f in ipairs(op.chosen or {}) do taken[f] = true end
      for k, other in ipairs(self.operations) do
        if other.kind == "flank_finish" and planned_of[k] then
          local kept = {}
          for _, u in ipairs(planned_of[k]) do if not taken[u.side] then kept[#kept + 1] = u end end
          planned_of[k] = kept
        end
      end
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
        -- A roughing unit's end and start lie in its channel, over the stock
        -- it leaves: the legs there keep its cutter clearance (a rapid
        -- through the stock would cut it).
        local link = self:link(last.pose, {tip = first.tip, axis = first.axis}, t.tool, "link to " .. what,
                               last.blade, f.blade, last.link_cutter, f.link_cutter, last.tool_body)
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
              tool = number, tool_body = t.tool, link_cutter = f.link_cutter}
      flanks[#flanks + 1] = {operation = i, kind = op.kind, blade = f.blade, side = f.side, plan = f.plan,
                             report = f.report, moves = #plan_moves, first_move = first_move,
                             turned_from = f.turned_from, design_flanks = f.flanks, surface = f.surface}
    end
  end
  self.planned = {moves = moves, flanks = flanks, links = links, tool_groups = groups}
  if self.blank then
    -- Every move, in order, with its tool, through the stock (job/stock.lua).
    if self.on_plan_step then self.on_plan_step({kind = "stock_cut_by_every_move"}) end
    self.planned.stock = self:cut_stock(self.planned)
  end
  return self.planned
end

-- The independent simulation (core/sim) of every flank after all the moves
-- that machine it: o = {samples_u = 200, samples_v = 1000}. Returns per flank
-- {operation, blade, side, undercut_max, undercut_mean, overcut, overcut_move
-- (index in the job's moves), overcut_motion} and the totals (undercut_max,
-- overcut, where), and for a blisk the seams between the operations'

return M
