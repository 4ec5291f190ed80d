-- The built-in blisk's flanks finished as one job and posted as one verified
-- program per machine (issue 13 item 7, issue 18 item 3): drum-wheel
-- finishing of both flanks of the chosen blades with the extended wheel of
-- Table 2, each flank planned and proved as in blisk_drum_finish.lua, the
-- flanks linked through a clearance cylinder outside the casing (every link
-- motion proved clear of every blade and the hub, whole tool), then posted
-- for an A/C trunnion (Fanuc) and a B/C head-table (Heidenhain TCPM), each
-- program read back and replayed through the machine.
--
--   bliskrun scripts/recipes/blisk_job.lua --out out [--set blades=2] [--set sides=both|pressure|suction]
--            [--set samples_u=100 --set samples_v=500]   (simulation samples per flank)
--            [--set tool_life=MM]   (blades grouped per wheel by cutting length; sister wheels T15, T25, ...)
-- Outputs: the two programs, blisk_job.json, blisk_job_undercut_*.png (the first four flanks),
-- blisk_job.pvd (job toolpath, flanks with their undercut, for ParaView), report.html.
local job = require("job")
local finish = require("blisk_finish")

local blisk = bliskrun.blisk{}
local count = args.blades or 2
assert(math.type(count) == "integer" and count >= 1 and count <= blisk:blade_count(),
       string.format("--set blades= expects 1..%d", blisk:blade_count()))
local sides = ({both = {"pressure", "suction"}, pressure = {"pressure"}, suction = {"suction"}})[args.sides or "both"]
assert(sides, "--set sides= expects both, pressure or suction")
local blades = {}
for k = 1, count do blades[k] = k end

local wheel = finish.design_wheels(blisk, {c_range = 30}).wheels.extended
local j = job.new{
  name = "blisk flanks",
  part = blisk,
  clearance_radius = 110,
  -- --set tool_life=mm: whole blades per wheel up to that cutting length,
  -- then the next sister wheel (T15, T25, ...), as the impeller paper groups
  -- blades per tool.
  tools = {wheel = {number = 5, length = 110, spindle_rpm = 8000, tool = wheel, life_mm = args.tool_life,
                    sisters = args.tool_life and {15, 25, 35, 45, 55, 65, 75} or nil}},
  operations = {
    job.drum_finish{tool = "wheel", blades = blades, sides = sides, residual = 0.014, chord_tol = 0.002, feed = 600},
  },
}
local planned = j:plan()

local report = {flanks = {}, links = planned.links, moves = #planned.moves, programs = {}}
print(string.format("Job '%s': %d flanks, %d moves, %d links through the clearance cylinder (r = %g mm), each proved clear",
                    j.name, #planned.flanks, #planned.moves, planned.links, j.clearance_radius))
report.tool_groups = planned.tool_groups
for _, g in ipairs(planned.tool_groups) do
  print(string.format("  tool T%d: blades %d-%d, cutting length %.0f mm", g.tool, g.blades[1], g.blades[#g.blades],
                      g.cutting_length_mm))
end
for _, f in ipairs(planned.flanks) do
  print(string.format("  blade %2d %-8s  rows %3d  poses %5d  refused 0", f.blade, f.side, f.report.row_count, f.report.poses))
  report.flanks[#report.flanks + 1] = {blade = f.blade, side = f.side, rows = f.report.row_count, poses = f.report.poses,
                                       moves = f.moves}
end
-- Every flank simulated after the moves that machine it (core/sim).
local sim = j:simulate{samples_u = args.samples_u or 100, samples_v = args.samples_v or 500}
report.simulation = {undercut_max_mm = sim.undercut_max, overcut_mm = sim.overcut, flanks = {}}
for _, f in ipairs(sim.flanks) do
  report.simulation.flanks[#report.simulation.flanks + 1] = {blade = f.blade, side = f.side,
    undercut_max_mm = f.undercut_max, undercut_mean_mm = f.undercut_mean, overcut_mm = f.overcut,
    overcut_move = f.overcut_move, overcut_motion = f.overcut_motion}
end
print(string.format("  simulated: undercut max %.2f um, overcut %.2f um%s", 1e3 * sim.undercut_max, 1e3 * sim.overcut,
                    sim.overcut_at and sim.overcut_at.overcut_move and string.format(" (job move %d, %s, blade %d %s)",
                      sim.overcut_at.overcut_move, sim.overcut_at.overcut_motion, sim.overcut_at.blade,
                      sim.overcut_at.side) or ""))
local chord_tol = 0.002
if sim.overcut < -chord_tol - 1e-4 then
  bliskrun.write_json("blisk_job.json", report)
  error(string.format("the simulation finds an overcut of %.2f um, beyond the %.0f um chord tolerance; nothing posted",
                      -1e3 * sim.overcut, 1e3 * chord_tol), 0)
end

for _, m in ipairs({{machine = "dmg_like_ac_trunnion", post = "fanuc", file = "blisk_job_ac_fanuc.nc"},
                    {machine = "monoblock_like_head_table", post = "heidenhain", file = "blisk_job_bc_heidenhain.h"}}) do
  report.programs[#report.programs + 1] = j:post_program(m)
end
bliskrun.write_json("blisk_job.json", report)

-- The run's page and the ParaView collection: every flank painted with its
-- undercut (the first few), the whole job's toolpath with its links.
local flank_rows, blocks, pictures = {}, {{name = "job toolpath", moves = planned.moves}}, {}
for i, f in ipairs(sim.flanks) do
  flank_rows[i] = {f.blade, f.side, planned.flanks[i].report.row_count, planned.flanks[i].report.poses,
                   1e3 * f.undercut_max, 1e3 * f.undercut_mean, 1e3 * f.overcut}
  if i <= 4 then
    local picture = string.format("blisk_job_undercut_blade%d_%s.png", f.blade, f.side)
    f.map:write_png(picture, {title = string.format("Undercut after the job, blade %d %s flank (mm)", f.blade, f.side)})
    pictures[#pictures + 1] = {title = string.format("Undercut, blade %d %s", f.blade, f.side), image = picture}
    blocks[#blocks + 1] = {name = string.format("blade %d %s, undercut", f.blade, f.side),
                           surface = planned.flanks[i].plan:trimmed(), map = f.map, samples_u = 60, samples_v = 150}
  end
end
local program_rows = {}
for i, p in ipairs(report.programs) do
  program_rows[i] = {p.file, p.machine, p.post, p.blocks, p.positioning, 1e3 * p.max_position_mm}
end
local sections = {
  {title = "Flanks", text = string.format("%d moves, %d links through the clearance cylinder (r = %g mm).",
                                          #planned.moves, planned.links, j.clearance_radius),
   table = {columns = {"blade", "flank", "rows", "poses", "undercut max (um)", "mean (um)", "overcut (um)"},
            rows = flank_rows}},
  {title = "Programs, read back and replayed", table = {columns = {"file", "machine", "post", "blocks",
    "positioning moves", "tip deviation (um)"}, rows = program_rows}}}
for _, p in ipairs(pictures) do sections[#sections + 1] = p end
require("run_report").write{title = "Job: " .. j.name, settings = {blades = count, sides = args.sides or "both",
  tool_life_mm = args.tool_life or "none", samples_u = args.samples_u or 100, samples_v = args.samples_v or 500},
  sections = sections, vtk = {path = "blisk_job.pvd", blocks = blocks},
  files = {{"blisk_job.json", "the report"}, {"blisk_job_ac_fanuc.nc", "Fanuc program, A/C trunnion"},
           {"blisk_job_bc_heidenhain.h", "Heidenhain program, B/C head-table"},
           {"blisk_job_undercut_*.png", "the undercut maps above"}}}
