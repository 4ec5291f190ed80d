-- Posting a planned job (Job methods; scripts/lib/job.lua is the entry):
-- a program's ends on the clearance surface and its lines out to the safe
-- height, proved; its setup (the part turned over, clocked); post.write's
-- options; one or several programs posted, each read back and replayed; a
-- move out of travel named by its job move, operation, blade and flank.
local options = require("job.options")
local geometry = require("job.geometry")
local Job = require("job.model").Job
local setup_sheet = require("setup_sheet")

local check_options, positive, add = options.check, options.positive, geometry.add

local M = {}

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

-- The part itself as bodies of the machine simulation (post.write's
-- `part`): every blade of the blisk or impeller as a mesh in the part
-- frame, the meshes the collision worlds check the tool against (shared,
-- tessellated once), made once per job. post.write places them by the
-- program's setup (turned over, clocked) as the path is.
function Job:part_bodies()
  if not self.part_bodies_list then
    if not self.part then
      self.part_bodies_list = {}  -- a job of moves alone (no part to place)
    elseif self.part_kind == "blisk" then
      self.part_bodies_list = require("blisk_world").part_bodies(self.part)
    else
      self.part_bodies_list = require("impeller_world").part_bodies(self.part, self:impeller_meshes(0.05),
                                                                    self:impeller_meshes(0.2))
    end
  end
  return self.part_bodies_list
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
  local mc = r.machine_check
  if mc.verdict == "SKIPPED" then
    print("    WARNING: " .. mc.warning)
  else
    local near = {}
    for k = 1, math.min(3, #mc.closest) do
      local c = mc.closest[k]
      near[k] = require("run_report").approach_text(c, mc.near_zone)
    end
    print(string.format("    machine simulation %s: %d pairs, %d distance queries (%d pair-blocks cleared by the broad phase), "
                        .. "%.2f s (%.2f s CPU); nearest: %s", mc.verdict, mc.pairs, mc.queries, mc.skipped, mc.seconds,
                        mc.cpu_seconds, table.concat(near, ", ")))
    if mc.unbounded_blocks > 0 then print("    WARNING: " .. mc.summary) end
    if mc.picture_note then print("    " .. mc.picture_note) end
  end
  -- The nearest pairs (of up to a thousand with a blisk's blades).
  local closest = {}
  for k, c in ipairs(mc.closest or {}) do
    if k > 20 then break end
    closest[k] = {a = c.a, b = c.b, distance_mm = c.distance, line = c.line, block = c.block, tool = c.tool,
                  queries = c.queries, beyond_zone = c.beyond_zone}
  end
  return {machine_check = {verdict = mc.verdict, summary = mc.summary, warning = mc.warning, clearance_mm = mc.clearance,
                           near_zone_mm = mc.near_zone,
                           seconds = mc.seconds, cpu_seconds = mc.cpu_seconds, pairs = mc.pairs, queries = mc.queries,
                           skipped = mc.skipped, unbounded_blocks = mc.unbounded_blocks, picture = mc.picture,
                           picture_note = mc.picture_note, closest = closest},
          file = m.file, machine = m.name or m.machine, post = m.post, blocks = r.moves, positioning = r.positioning,
          max_position_mm = r.max_position, max_angle_deg = r.max_angle, setup = m.setup and m.setup.name or nil,
          controller = r.controller, swept_cutter_mm = r.swept_cutter, swept_tool_mm = r.swept_tool,
          chord_tol_mm = r.chord_tol, body_tol_mm = r.body_tol,
          swept_cutter_tightest_mm = r.swept_cutter_tightest, swept_tool_tightest_mm = r.swept_tool_tightest,
          swept_blocks = r.swept, unswept_blocks = r.unswept, safe_blocks = r.safe_moves, slowed_blocks = r.slowed,
          cutter_speed_ratio = r.cutter_speed_ratio, rotary_speed_deg_per_min = r.rotary_speed,
          rotary_resets = r.rotary_resets, rotary_largest_deg = r.rotary_largest, inserted_blocks = r.inserted,
          feed_minutes = r.feed_minutes, tip_feed_minutes = r.tip_feed_minutes}
end

-- The setup sheet of one posted program (setup_sheet.lua), written beside
-- it: m as program_entry takes, `tools` post.write's tools (in the order the
-- program calls them), r post.write's report.
function Job:setup_sheet(m, tools, r)
  local sheet_tools, names = {}, {}
  for i, t in ipairs(tools) do
    local entry = self:tool_entry(t.number)
    local feeds, sisters = {}, {}
    for _, op in ipairs(self.operations) do
      if self.tools[op.tool] == entry and op.feed then feeds[#feeds + 1] = op.feed end
    end
    for _, k in ipairs({entry.number, table.unpack(entry.sisters or {})}) do
      if k ~= t.number then sisters[#sisters + 1] = k end
    end
    sheet_tools[i] = {number = t.number, description = t.body and t.body:description() or nil,
                      stick_out_mm = t.length, spindle_rpm = t.spindle_rpm, feeds_mm_per_min = feeds,
                      sisters = sisters}
  end
  for k, op in ipairs(self.operations) do
    local entry = self.tools[op.tool]
    names["operation " .. k] = string.format("%d: %s%s", k, op.kind:gsub("_", " "),
                                             entry and string.format(", T%d", entry.number) or "")
  end
  local setup = m.setup and string.format("%s%s%s", m.setup.name or "", m.setup.flip and ", turned over" or "",
                                          (m.setup.clocking_deg or 0) ~= 0
                                            and string.format(", clocked %g deg", m.setup.clocking_deg) or "")
  local sheet = setup_sheet.build{file = m.file, machine = m.name or m.machine, post = m.post, report = r,
    tools = sheet_tools, operations = names, work_offset = m.work_offset, setup = setup,
    origin = "the part frame's origin: on the part's axis at z = 0 of its model" .. (m.setup and m.setup.flip
      and " (turned over: the part's +Z points down the machine's -Z)" or "")
      .. "; the machine file's part_origin places it from the machine's zero (the header's setup notes)",
    fixture = self.fixture or "not modelled by the job (the machine file's part_origin stands for it)",
    stock = self.stock or "not stated by the job"}
  setup_sheet.write(sheet)
  return sheet
end

-- Posts for one machine (j:post) and prints the one-line summary; returns
-- the program's entry for a run's JSON report. m = {machine = name or
-- Machine, name = (how the report calls a Machine), post =, file =}.
-- What a programs entry hands to j:post (check_post_options says what each is).
local program_keys = {"machine", "post", "file", "setup", "start", "work_offset", "coolant", "program_number", "notes",
                      "machine_check", "machine_clearance", "machine_near_zone", "fixture", "stock", "part",
                      "machine_picture"}
local function post_request_of(m)
  local o = {}
  for _, k in ipairs(program_keys) do o[k] = m[k] end
  return o
end

function Job:post_program(m)
  return program_entry(m, self:post(post_request_of(m)))
end

-- Posts several programs at once (bliskrun.post.write_all: on the run's
-- threads, the longest first; each read back and replayed as j:post does)
-- and prints their summaries in list order; returns their entries. list =
-- {m, ...} as j:post_program takes. A setup's path is made once for all
-- the machines that take it. `level`: the error level of the recipe line
-- (default 3: the caller's caller; j:run passes 4).
function Job:post_programs(list, level)
  level = level or 3
  local requests, offsets, paths = {}, {}, {}
  for i, m in ipairs(list) do
    local o = post_request_of(m)
    local key = m.setup or "whole"
    paths[key] = paths[key] or {self:program_path(o, level)}
    requests[i], offsets[i] = self:post_options(o, paths[key][1], level), {paths[key][2], paths[key][3]}
  end
  local ok, result = pcall(bliskrun.post.write_all, requests)
  if not ok then
    local message = tostring(result)
    local k = tonumber(message:match("programs%[(%d+)%]"))
    self:raise_post_error(message, k and offsets[k][1] or 0, level, k and offsets[k][2])
  end
  local entries = {}
  for i, m in ipairs(list) do
    entries[i] = program_entry(m, result[i])
    local sheet = self:setup_sheet(m, requests[i].tools, result[i])
    entries[i].cycle_time, entries[i].setup_sheet = sheet.cycle_time, sheet
    print(string.format("    estimated cycle time %.1f min (positioning %.0f s, cutting %.0f s, %d tool changes %.0f s); "
                        .. "setup sheet %s", sheet.cycle_time.total_s / 60, sheet.cycle_time.rapid_s,
                        sheet.cycle_time.cut_s, sheet.cycle_time.tool_changes, sheet.cycle_time.tool_change_s,
                        sheet.files.html))
  end
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
    coolant = {type = "string"},      -- flood, mist, through, off (post.write checks it)
    program_number = {type = "number"},  -- O-number / PGM name (post.write checks it)
    notes = {type = "table"},         -- header lines of the recipe's own
    -- The machine simulation (post.write): false skips it, with a warning
    -- in the report; the fixture's and the stock's bodies, part frame; the
    -- part's (default: its blades, j:part_bodies(); false: none); the
    -- machine's picture at the closest approach (default <file>_machine.png;
    -- false: none).
    machine_check = {type = "boolean"}, fixture = {type = "table"}, stock = {type = "table"},
    machine_clearance = {type = "number", check = positive},  -- mm (post.write: default 0.5)
    machine_near_zone = {type = "number", check = positive},  -- mm (post.write: default 10)
    part = {type = "any", check = function(v)
      if v ~= false and type(v) ~= "table" then return "expected a list of bodies or false" end
    end},
    machine_picture = {type = "any", check = function(v)
      if v ~= false and type(v) ~= "string" then return "expected a file name or false" end
    end},
  }, level)
end

-- The moves of a program, the job move before its first (offset) and
-- {first =, last =}, its job moves (for messages): o.setup =
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
  local moves, splits = {}, {}
  for i = first, last do
    local m = self.planned.moves[i]
    if m.rapid_to then
      splits[#splits + 1] = i
      -- A rapid through the stock fed from where it meets the stock
      -- (job/stock.lua): at the rapid rate up to there, in air.
      local air = {}
      for key, value in pairs(m) do air[key] = value end
      air.kind, air.feed, air.tip, air.axis, air.rapid_to, air.in_stock = "rapid", nil, m.rapid_to.tip, m.rapid_to.axis, nil, nil
      moves[#moves + 1] = air
    end
    moves[#moves + 1] = m
  end
  local up = o.setup and o.setup.flip and {0, 0, -1} or {0, 0, 1}
  local ok, ends = pcall(self.program_ends, self, moves, up)
  if not ok then error(tostring(ends), level) end
  -- Job move numbers in messages count the program's moves from `first`;
  -- a way in put before them shifts them by one.
  local shift = #ends > 0 and ends[1] ~= moves[1] and 1 or 0
  if not o.setup then return ends, first - 1 - shift, {first = first, last = last, splits = splits} end
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
  return path, first - 1 - shift, {first = first, last = last, splits = splits}
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
          work_offset = o.work_offset, coolant = o.coolant, program_number = o.program_number, notes = o.notes,
          machine_check = o.machine_check, machine_clearance = o.machine_clearance,
          machine_near_zone = o.machine_near_zone, fixture = o.fixture, stock = o.stock,
          part = o.part ~= false and (o.part or self:part_bodies()) or nil,
          machine_picture = o.machine_picture ~= false and (o.machine_picture or o.file:gsub("%.[^./]*$", "") .. "_machine.png")
                            or nil}
end

-- A move out of travel (or out of reach) names the job's move: say which
-- operation, blade and flank it belongs to. `offset`: the job move before
-- the program's first; `span` = {first, last, splits}: the program's job
-- moves and those split in two (j:program_path), so a move before or after them is named as the
-- program's way in to its first or out from its last.
-- The move is the first "move N" of the machine motion's own message:
-- after the tool's prefix where a program has several tools ("tool 2, whose
-- moves start at move S (move numbers below count from there): move N ..."),
-- else after post.write_all's "programs[k] (file): " — the program's file
-- name and the tool's prefix are no move of the message's (the first "):"
-- was taken for the prefix's end, and post.write_all's "(file): " comes
-- first: the tool's start S was read as N, naming job move 2 S - 1).
function Job:raise_post_error(message, offset, level, span)
  local start = tonumber(message:match("moves start at move (%d+)")) or 1
  local own = message:match("count from there%)(.*)$") or message:gsub("^.-programs%[%d+%] %b(): ", "", 1)
  local n = tonumber(own:match("move (%d+)"))
  local k, what = n and offset + start + n - 1, "job move %d"
  -- The program's moves count a split rapid's part in air apart
  -- (program_path): job move j stands at j + the splits up to j, its part
  -- in air just before it (named as j).
  if k and span and span.splits and #span.splits > 0 and k >= span.first then
    local c, split = 0, {}
    for _, x in ipairs(span.splits) do split[x] = true end
    for j = span.first, span.last do
      if split[j] then c = c + 1 end
      if j + c >= k then k = j break end
      if j == span.last then k = k - c end
    end
  end
  if k and span and k < span.first then k, what = span.first, "the way in to job move %d" end
  if k and span and k > span.last then k, what = span.last, "the way out from job move %d" end
  local m = k and self.planned.moves[k]
  if m then
    error(string.format("job:post: " .. what .. " (operation %d %s, blade %d %s flank, %s): %s", k, m.operation,
                        m.operation_kind, m.blade, m.side, m.motion or m.kind, message), level)
  end
  error(message, level)
end

-- Posts the planned job for one machine: o = {machine = name or Machine,
-- post = name or post table, file =, chord_tol = 0.002, setup =, start =}.
-- Returns the post.write report (the program read back and replayed).
function Job:post(o)
  local path, offset, span = self:program_path(o, 3)
  local ok, result = pcall(bliskrun.post.write, self:post_options(o, path, 3))
  if ok then return result end
  self:raise_post_error(tostring(result), offset, 3, span)
end

return M
