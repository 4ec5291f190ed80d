-- The setup sheet of a posted program (issue 37 item 3): what the operator
-- needs to set the machine up from one page — the tools the program calls
-- (number, type and dimensions, stick-out, spindle speed, feeds, sister
-- tools), the work offset and where the part origin lies, fixture and
-- stock, the range each axis word takes, the operations in order, and the
-- estimated cycle time per operation and for the program (post.write's
-- cycle_time: positioning, cutting and tool changes apart). Written beside
-- the program as <program>_setup.json and <program>_setup.html.
--
--   local setup_sheet = require("setup_sheet")
--   local sheet = setup_sheet.build{file = "x.nc", machine = "name", post = "fanuc", report = post_report,
--     tools = {{number=, description=, stick_out_mm=, spindle_rpm=, feeds_mm_per_min = {...}, sisters = {...}}},
--     operations = {["operation 1"] = "1: drum finish, T5", ...} (names for the report's labels),
--     work_offset = 1, origin = "...", fixture = "...", stock = "...", setup = "..."}
--   setup_sheet.write(sheet)            -- the two files; returns their names
--   setup_sheet.sections(sheets)        -- report sections for a run's page
local M = {}

-- "x.nc" -> "x_setup"
local function stem(file) return (file:gsub("%.[^./]*$", "")) .. "_setup" end

-- The work offset as each controller family writes it.
local function offset_text(n)
  n = n or 1
  local iso = n <= 6 and string.format("G%d", 53 + n) or string.format("G54.1 P%d", n - 6)
  return string.format("%d (%s; Heidenhain preset %d)", n, iso, n)
end

function M.build(o)
  local c = o.report.cycle_time
  local per_operation = {}
  for i, p in ipairs(c.per_operation) do
    per_operation[i] = {operation = o.operations and o.operations[p.operation] or p.operation, total_s = p.total_s,
                        rapid_s = p.rapid_s, cut_s = p.cut_s, tool_change_s = p.tool_change_s}
  end
  local ranges = {}
  for axis, r in pairs(o.report.axis_ranges or {}) do
    ranges[#ranges + 1] = {axis = axis, unit = axis:match("^[XYZ]$") and "mm" or "deg", min = r[1], max = r[2]}
  end
  table.sort(ranges, function(a, b) return a.axis < b.axis end)
  return {program = o.file, machine = o.machine, post = o.post, setup = o.setup,
          work_offset = offset_text(o.work_offset), part_origin = o.origin, fixture = o.fixture, stock = o.stock,
          tools = o.tools, axis_ranges = ranges, operations = per_operation,
          cycle_time = {total_s = c.total_s, rapid_s = c.rapid_s, cut_s = c.cut_s, tool_change_s = c.tool_change_s,
                        tool_changes = c.tool_changes},
          files = {json = stem(o.file) .. ".json", html = stem(o.file) .. ".html"}}
end

local function minutes(s) return s / 60 end

-- The sheet's tables, for its own page and for a run's report.
local function tables(sheet)
  local tools = {}
  for i, t in ipairs(sheet.tools) do
    local feeds = {}
    for _, f in ipairs(t.feeds_mm_per_min or {}) do feeds[#feeds + 1] = string.format("%g", f) end
    local sisters = {}
    for _, s in ipairs(t.sisters or {}) do sisters[#sisters + 1] = "T" .. s end
    tools[i] = {"T" .. t.number, t.description or "", t.stick_out_mm or "", t.spindle_rpm or "",
                table.concat(feeds, ", "), #sisters > 0 and table.concat(sisters, ", ") or "none"}
  end
  local axes = {}
  for i, r in ipairs(sheet.axis_ranges) do axes[i] = {r.axis, r.unit, r.min, r.max} end
  local ops = {}
  for i, p in ipairs(sheet.operations) do
    ops[i] = {i, p.operation, p.rapid_s, p.cut_s, p.tool_change_s, minutes(p.total_s)}
  end
  local c = sheet.cycle_time
  ops[#ops + 1] = {"", "whole program", c.rapid_s, c.cut_s, c.tool_change_s, minutes(c.total_s)}
  return {
    tools = {columns = {"tool", "type, dimensions and holder", "stick-out (mm)", "spindle (1/min)", "feeds (mm/min)",
                        "sister tools"}, rows = tools},
    axes = {columns = {"axis", "unit", "min", "max"}, rows = axes},
    operations = {columns = {"#", "operation", "positioning (s)", "cutting (s)", "tool changes (s)", "total (min)"},
                  rows = ops},
    setup = {columns = {"item", "value"}, rows = {
      {"program", sheet.program}, {"machine", sheet.machine}, {"post", sheet.post},
      {"setup", sheet.setup or "one setup"}, {"work offset", sheet.work_offset},
      {"part origin (program zero)", sheet.part_origin or "not stated"},
      {"fixture", sheet.fixture or "not stated"}, {"stock", sheet.stock or "not stated"},
      {"estimated cycle time (min)", minutes(c.total_s)}, {"tool changes", c.tool_changes}}},
  }
end

local kModel = "Estimated from the blocks read back and the machine's axis limits (machine file `dynamics`; "
               .. "docs/lua_api/machines_and_posts.md): rapids axis by axis from rest to rest, feed runs with "
               .. "look-ahead at the programmed feed, a tool change at the machine's tool_change_s. Dwells, spindle "
               .. "run-up and M-codes are not counted."

-- Writes <program>_setup.json and <program>_setup.html; returns their names.
function M.write(sheet)
  bliskrun.write_json(sheet.files.json, sheet)
  local t = tables(sheet)
  bliskrun.report{path = sheet.files.html, title = "Setup sheet: " .. sheet.program,
    subtitle = string.format("%s, %s post; estimated cycle time %.1f min", sheet.machine, sheet.post,
                             minutes(sheet.cycle_time.total_s)),
    sections = {{title = "Setup", table = t.setup},
                {title = "Tools the program calls", table = t.tools},
                {title = "Operations in order, with their estimated times", text = kModel, table = t.operations},
                {title = "Axis ranges the program uses (words as written; with TCP, XYZ is the tip in the part frame)",
                 table = t.axes}}}
  return sheet.files.json, sheet.files.html
end

-- What a posted program is judged by (a run's verdict): the cutter and the
-- whole tool within the post's tolerances plus what the output resolution
-- explains, at the block nearest its allowance (post.write's *_tightest;
-- post.write itself fails beyond them, so these pass when there is a
-- program), and the tip at every block end within the read-back tolerance.
function M.requirements(file, r)
  return {
    {name = file .. ": cutter off the proved motion (read back, swept; tightest block)", unit = "µm",
     measured = 1e3 * r.swept_cutter_tightest[1], at_most = 1e3 * r.swept_cutter_tightest[2],
     note = string.format("largest %.3g µm; tolerance %.3g µm + output resolution", 1e3 * r.swept_cutter,
                          1e3 * r.chord_tol)},
    {name = file .. ": tool body off the proved motion (tightest block)", unit = "µm",
     measured = 1e3 * r.swept_tool_tightest[1], at_most = 1e3 * r.swept_tool_tightest[2]}}
end

-- A run's report: one section with every program's cycle time, then each
-- program's tools.
function M.sections(sheets)
  if #sheets == 0 then return {} end
  local rows = {}
  for i, s in ipairs(sheets) do
    local c = s.cycle_time
    local tools = {}
    for _, t in ipairs(s.tools) do tools[#tools + 1] = "T" .. t.number end
    rows[i] = {s.program, s.machine, table.concat(tools, " "), c.rapid_s, c.cut_s, c.tool_change_s,
               minutes(c.total_s), s.files.html}
  end
  local out = {{title = "Cycle time and setup sheets", text = kModel,
                table = {columns = {"program", "machine", "tools", "positioning (s)", "cutting (s)",
                                    "tool changes (s)", "total (min)", "setup sheet"}, rows = rows}}}
  for _, s in ipairs(sheets) do
    local t = tables(s)
    out[#out + 1] = {title = "Setup sheet " .. s.program .. ": tools and operations", table = t.tools}
    out[#out + 1] = {title = "Setup sheet " .. s.program .. ": operations", table = t.operations}
  end
  return out
end

-- A belt-grinding robot program's sheet: the robot programmer's page
-- instead of the machinist's — the cell and its station (belt, wheel,
-- belt speed), how the blade is gripped, the speeds, the range each joint
-- takes, and the estimated cycle time (plan:cycle_time,
-- core/machine/robot_cycle_time.h).
--   setup_sheet.robot{file =, robot =, cell_file =, post =, part =, grip =,
--     station = {name =, belt =, speed =, wheel = {radius =, width =}},
--     feed_mm_s =, link_feed_mm_s =, moves = plan:moves(), cycle = plan:cycle_time()}
function M.robot(o)
  local lo, hi = {}, {}
  for _, m in ipairs(o.moves) do
    for j = 1, 6 do
      lo[j] = math.min(lo[j] or math.huge, m.joints[j])
      hi[j] = math.max(hi[j] or -math.huge, m.joints[j])
    end
  end
  local ranges = {}
  for j = 1, 6 do ranges[j] = {axis = "A" .. j, unit = "deg", min = lo[j], max = hi[j]} end
  local st = o.station
  return {program = o.file, robot = o.robot, cell_file = o.cell_file, post = o.post, part = o.part, grip = o.grip,
          station = st, feed_mm_s = o.feed_mm_s, link_feed_mm_s = o.link_feed_mm_s, moves = #o.moves,
          axis_ranges = ranges, cycle_time = o.cycle,
          files = {json = stem(o.file) .. ".json", html = stem(o.file) .. ".html"}}
end

local kRobotModel = "Estimated from the plan the program is written from and the arm's joint speeds "
                    .. "(core/machine/robot_cycle_time.h): each path one motion at its contact speed with one "
                    .. "ramp at the TCP acceleration, slowed where a joint reaches its maximum speed; each link "
                    .. "move from rest to rest; home to the first target and back at full joint speed. The "
                    .. "controller's own path planner decides the real time."

local function robot_tables(sheet)
  local c, st = sheet.cycle_time, sheet.station
  local axes = {}
  for i, r in ipairs(sheet.axis_ranges) do axes[i] = {r.axis, r.unit, r.min, r.max} end
  return {
    setup = {columns = {"item", "value"}, rows = {
      {"program", sheet.program}, {"robot cell", sheet.robot}, {"cell file", sheet.cell_file or "not stated"},
      {"post", sheet.post}, {"part", sheet.part}, {"grip", sheet.grip},
      {"station", st.name}, {"belt", st.belt or "not stated"},
      {"belt speed (m/s)", st.speed or "not stated"},
      {"contact wheel radius / width (mm)", string.format("%g / %g", st.wheel.radius, st.wheel.width)},
      {"contact speed along the path (mm/s)", sheet.feed_mm_s},
      {"link speed off the wheel (mm/s)", sheet.link_feed_mm_s}, {"moves", sheet.moves},
      {"estimated cycle time (min)", minutes(c.total_s)}}},
    time = {columns = {"part of the program", "length (mm)", "time (s)"}, rows = {
      {string.format("grinding (%d paths)", c.paths), c.grinding_mm, c.grinding_s},
      {"links off the wheel (retract, traverse, approach)", c.link_mm, c.link_s},
      {"home to the first target and back", "", c.home_s},
      {"whole program", c.grinding_mm + c.link_mm, c.total_s}}},
    axes = {columns = {"joint", "unit", "min", "max"}, rows = axes},
  }
end

-- Writes a robot program's <program>_setup.json and .html; returns their names.
function M.write_robot(sheet)
  bliskrun.write_json(sheet.files.json, sheet)
  local t = robot_tables(sheet)
  local c = sheet.cycle_time
  bliskrun.report{path = sheet.files.html, title = "Setup sheet: " .. sheet.program,
    subtitle = string.format("%s, %s post, station %s; estimated cycle time %.1f min", sheet.robot, sheet.post,
                             sheet.station.name, minutes(c.total_s)),
    sections = {{title = "Setup", table = t.setup},
                {title = "Estimated cycle time", text = kRobotModel .. (c.joint_limited_steps > 0 and string.format(
                   " %d steps are slowed by a joint's speed limit.", c.joint_limited_steps) or ""), table = t.time},
                {title = "Joint ranges the program uses", table = t.axes}}}
  return sheet.files.json, sheet.files.html
end

-- A run's report: one table of every robot program's time and sheet.
function M.robot_sections(sheets)
  if #sheets == 0 then return {} end
  local rows = {}
  for i, s in ipairs(sheets) do
    local c = s.cycle_time
    rows[i] = {s.program, s.robot, s.station.name, c.grinding_s, c.link_s, c.home_s, minutes(c.total_s),
               s.files.html}
  end
  return {{title = "Cycle time and setup sheets", text = kRobotModel,
           table = {columns = {"program", "robot", "station", "grinding (s)", "links (s)", "home moves (s)",
                               "total (min)", "setup sheet"}, rows = rows}}}
end

return M
