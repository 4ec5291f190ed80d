-- Posts the real drum-wheel finishing plan of one flank of the built-in
-- blisk (the plan blisk_drum_finish.lua makes and proves) for two machines,
-- and proves both programs by read-back (issue 5, SPEC §7; issue 13 item 5):
--   the A/C trunnion (dmg_like_ac_trunnion) with the Fanuc post, in machine
--   axes (G93, moves split to the chord tolerance), and
--   the B head / C table (monoblock_like_head_table) with the Heidenhain post
--   (FUNCTION TCPM).
-- The plan's links (retract, traverse, approach) are rapids that turn the
-- rotary axes; a G0 would move each axis at its own rate and swing the tool
-- off the path the planner proved clear, so the post writes them as
-- positioning feed moves at the machine's rapid feed, split like cuts (see
-- docs/lua_api.md, post.write). Each header states where the work offset
-- must be set.
--
--   bliskrun scripts/recipes/blisk_post.lua --out out [--set NAME=VALUE]... (--help lists them)
-- Outputs: the two programs, blisk_post.json, blisk_post.pvd (flank and
-- toolpath for ParaView), report.html.
local opt = require("recipe_options"){
  blade = {type = "integer", default = 1, range = {1, 1000}, help = "the blade whose flank is posted"},
  side = {type = "string", default = "suction", choices = {"suction", "pressure"}, help = "the flank posted"},
  feed = {type = "number", unit = "mm/min", default = 600, range = {1, 100000}, help = "feed along the flank"},
}
local finish = require("blisk_finish")
local blisk_world = require("blisk_world")

local blade = opt.blade
local side = opt.side
local feed = opt.feed                  -- mm/min along the flank

local blisk = bliskrun.blisk{}
assert(math.type(blade) == "integer" and blade >= 1 and blade <= blisk:blade_count(),
       string.format("--set blade= expects 1..%d", blisk:blade_count()))
local design = finish.design_wheels(blisk, {c_range = 30})
local wheel = design.wheels.extended
local plan = finish.plan(blisk, blade, side, wheel, blisk_world.around_blade(blisk, blade),
                         {residual = 0.014, chord_tol = 0.002, steps = "variable", shank_clearance = 0.1,
                          c_range = 30})
local r = plan:report()
assert(r.refusals == 0 and r.refused_links == 0,
       string.format("the plan refused %d poses and %d links: nothing to post", r.refusals, r.refused_links))

local path = {}
for i, m in ipairs(plan:moves()) do
  path[i] = {kind = m.kind, tip = m.tip, axis = m.axis, row = m.row, feed = m.kind == "feed" and feed or nil}
end

-- Tool 5: the extended drum wheel, gauge length 110 mm (head 4 + shank 96 + 10 in the holder).
local tool = {number = 5, length = 110, spindle_rpm = 8000}
local name = string.format("blisk blade %d %s", blade, side)
local report = {planned_moves = #path, rows = r.row_count, blade = blade, side = side, programs = {}}
local setup_sheet = require("setup_sheet")
local requirements, sheets = {}, {}
for _, job in ipairs({
  {machine = "dmg_like_ac_trunnion", post = "fanuc", file = "blade_ac_fanuc.nc"},
  {machine = "monoblock_like_head_table", post = "heidenhain", file = "blade_bc_heidenhain.h"},
}) do
  local m = bliskrun.machine.load(job.machine)
  local w = bliskrun.post.write{machine = m, post = job.post, path = path, file = job.file,
                                tool = tool, name = name, chord_tol = 0.002}
  bliskrun.log(string.format("%s on %s: %d blocks (%d inserted, %d rapids as positioning moves), tip within "
                             .. "%.4f mm of the plan, axis within %.5f deg", job.file, m:name(), w.moves, w.inserted,
                             w.positioning, w.max_position, w.max_angle))
  report.programs[#report.programs + 1] = {
    file = job.file, machine = m:name(), post = job.post, blocks = w.moves, inserted = w.inserted,
    positioning = w.positioning, max_position_mm = w.max_position, max_angle_deg = w.max_angle,
    max_departure_mm = w.max_deviation}
  for _, q in ipairs(setup_sheet.requirements(job.file, w)) do requirements[#requirements + 1] = q end
  local sheet = setup_sheet.build{file = job.file, machine = job.machine, post = job.post, report = w,
    tools = {{number = tool.number, description = wheel:description(), stick_out_mm = tool.length,
              spindle_rpm = tool.spindle_rpm, feeds_mm_per_min = {feed}, sisters = {}}},
    operations = {[""] = "drum finish, " .. name}, work_offset = 1,
    origin = "the part frame's origin: on the blisk's axis at z = 0 of its model; the machine file's part_origin "
             .. "places it from the machine's zero (the header's setup notes)",
    fixture = "not modelled (the machine file's part_origin stands for it)", stock = "not stated"}
  setup_sheet.write(sheet)
  sheets[#sheets + 1] = sheet
  report.programs[#report.programs].cycle_time = sheet.cycle_time
end
report.verdict = require("run_report").verdict(requirements)
bliskrun.write_json("blisk_post.json", report)

local rows = {}
for i, p in ipairs(report.programs) do
  rows[i] = {p.file, p.machine, p.post, p.blocks, p.positioning, 1e3 * p.max_position_mm, p.max_angle_deg}
end
local sections = {{title = "Programs, read back and replayed", table = {columns = {"file", "machine", "post", "blocks",
  "positioning moves", "tip deviation (µm)", "axis deviation (deg)"}, rows = rows}}}
for _, section in ipairs(setup_sheet.sections(sheets)) do sections[#sections + 1] = section end
require("run_report").write{title = "Posting the drum finish of " .. name, verdict = report.verdict,
  settings = {blade = blade, side = side, feed_mm_min = feed, planned_moves = #path, rows = r.row_count},
  sections = sections,
  vtk = {path = "blisk_post.pvd", blocks = {{name = "flank", surface = plan:trimmed(), samples_u = 60,
                                            samples_v = 200}, {name = "toolpath", moves = plan:moves()}}},
  files = {{"blisk_post.json", "the figures above"}, {"blade_ac_fanuc.nc", "Fanuc program, A/C trunnion"},
           {"blade_bc_heidenhain.h", "Heidenhain program, B/C head-table"},
           {"blade_*_setup.html", "each program's setup sheet (and its .json)"}}}
