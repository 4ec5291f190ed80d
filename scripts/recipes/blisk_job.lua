-- The built-in blisk's blades finished as one job and posted as one verified
-- program per machine (issue 18): drum-wheel finishing of both flanks of the
-- chosen blades with the extended wheel of Table 2 (each flank planned and
-- proved as in blisk_drum_finish.lua), then both edges of each blade with
-- the bottom of a flat-end mill (as in blade_edges.lua: the window between
-- hub and casing, partial rows where tilted poses cut narrow strips); the
-- operations and blades linked through a clearance can outside the casing
-- and in front of / behind the hub (every link motion proved clear of every
-- blade and the hub, whole tool), then posted for an A/C trunnion (Fanuc)
-- and a B/C head-table (Heidenhain TCPM), each program read back and
-- replayed through the machine. Every blade is blade 1 turned: blade 1 is
-- planned and simulated, the others get its paths turned by the pitch.
--
--   bliskrun scripts/recipes/blisk_job.lua --out out [--set blades=2] [--set sides=both|pressure|suction]
--            [--set edges=false] [--set edge_span=0.1,0.9] [--set periodic=false]
--            [--set samples_u=100 --set samples_v=500]   (simulation samples per flank)
--            [--set edge_samples_u=200 --set edge_samples_v=400]   (per edge region)
--            [--set tool_life=MM]   (blades grouped per wheel by cutting length; sister wheels T15, T25, ...)
--            [--set blade_map=lean|false]   (blade 1's one map: coarse samples, or none)
--            [--set hub_top=MM]   (the root strip's top; default 0.5 mm over the edges' first rows)
--            [--set seam_spacing=MM]   (samples of the seams between operations, default 0.1)
-- Outputs: the two programs, blisk_job.json, blisk_job_undercut_*.png (the first flanks),
-- blisk_job_blade1_map.png (blade 1's whole surface after the job),
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

-- --set edges=false: the flanks only. --set edge_span=a,b: the edge
-- window in edge-region v (default 0.1,0.9, narrowed to hub and casing).
local with_edges = args.edges ~= false and args.edges ~= "false"
-- --set hub=false: no hub and root finishing.
local with_hub = args.hub ~= false and args.hub ~= "false"
local edge_span = {0.1, 0.9}
if args.edge_span then
  local a, b = tostring(args.edge_span):match("^%s*([%d.]+)%s*,%s*([%d.]+)%s*$")
  assert(a, "--set edge_span= expects two numbers a,b with 0 <= a < b <= 1")
  edge_span = {tonumber(a), tonumber(b)}
end
-- Every blade is blade 1 turned: plan the first, turn it for the others
-- (--set periodic=false plans each blade).
local periodic = args.periodic ~= false and args.periodic ~= "false"

local wheel = finish.design_wheels(blisk, {c_range = 30}).wheels.extended
-- The edge mill (blade_edges.lua): R 3, r 0.5, shank d 6.
local mill = bliskrun.flat_end_mill{radius = 3, corner_radius = 0.5, flute_length = 9,
                                    shank = {diameter = 6, length = 50}, holder = {diameter = 12, length = 40}}
-- The hub and root ball (blisk_hub_finish.lua): r 1.5, taper 2.5 deg, 40 mm
-- of flute to reach the hub from outside the casing.
local ball = bliskrun.tapered_ball_end_mill{tip_radius = 1.5, half_angle = 2.5, flute_length = 40,
                                            shank = {diameter = 8, length = 30}, holder = {diameter = 32, length = 40}}
local operations = {
  job.drum_finish{tool = "wheel", blades = blades, sides = sides, residual = 0.014, chord_tol = 0.002, feed = 600,
                  periodic = periodic},
}
if with_edges then
  -- The trailing edges with the flanks; the leading edges last, in a second
  -- setup with the part turned over (they face the table: see the posting).
  -- Every axis within 118 deg of the table's axis in its setup (the A
  -- cradle and the B head tilt to 120).
  operations[#operations + 1] = job.edge_finish{tool = "mill", blades = blades, edges = {"trailing"}, span = edge_span,
                                                feed = 400, periodic = periodic, reach = {axis = {0, 0, 1}, max = 118}}
end
if with_hub then
  -- The root strip all around each blade (above the drum's and the edges'
  -- strips: its top 0.5 mm over the edges' first rows, job.hub_finish —
  -- at 4 mm the LE kept 48-60 um between the two) and the channel floor to
  -- the next blade, from above.
  -- (--set hub_top=MM: the strip's top given instead.)
  operations[#operations + 1] = job.hub_finish{tool = "ball", blades = blades, scallop = 0.005, feed = 800,
                                               periodic = periodic, top = args.hub_top and tonumber(args.hub_top)}
end
if with_edges then
  operations[#operations + 1] = job.edge_finish{tool = "mill", blades = blades, edges = {"leading"}, span = edge_span,
                                                feed = 400, periodic = periodic,
                                                reach = {axis = {0, 0, -1}, min = 35, max = 118}}
end
local j = job.new{
  name = "blisk blades" .. (with_edges and ", edges" or "") .. (with_hub and ", hub and roots" or ""),
  part = blisk,
  clearance_radius = 110,
  -- --set tool_life=mm: whole blades per wheel up to that cutting length,
  -- then the next sister wheel (T15, T25, ...), as the impeller paper groups
  -- blades per tool.
  tools = {wheel = {number = 5, length = 110, spindle_rpm = 8000, tool = wheel, life_mm = args.tool_life,
                    sisters = args.tool_life and {15, 25, 35, 45, 55, 65, 75} or nil},
           mill = {number = 7, length = 100, spindle_rpm = 12000, tool = mill},
           ball = {number = 9, length = 130, spindle_rpm = 15000, tool = ball}},
  operations = operations,
}
local planned = j:plan()

local report = {flanks = {}, links = planned.links, moves = #planned.moves, programs = {}}
print(string.format("Job '%s': %d plans, %d moves, %d links through %s, each proved clear",
                    j.name, #planned.flanks, #planned.moves, planned.links, j.clearance_surface.description))
report.tool_groups = planned.tool_groups
for _, g in ipairs(planned.tool_groups) do
  print(string.format("  tool T%d: blades %d-%d, cutting length %.0f mm", g.tool, g.blades[1], g.blades[#g.blades],
                      g.cutting_length_mm))
end
for _, f in ipairs(planned.flanks) do
  if not f.turned_from or f.blade <= 2 or f.blade == blisk:blade_count() then
    print(string.format("  blade %2d %-14s  rows %3d%s  poses %5d  refused 0%s", f.blade, f.side, f.report.row_count,
                        f.report.infill_rows and string.format(" (+%d partial)", f.report.infill_rows) or "",
                        f.report.poses, f.turned_from and string.format("  (blade %d's, turned)", f.turned_from) or ""))
  elseif f.blade == 3 and f.side ~= "suction" then
    print("  ...")
  end
  report.flanks[#report.flanks + 1] = {blade = f.blade, side = f.side, operation = f.kind, rows = f.report.row_count,
                                       partial_rows = f.report.infill_rows, poses = f.report.poses, moves = f.moves,
                                       turned_from = f.turned_from}
end
-- Every flank simulated after the moves that machine it (core/sim).
local sim = j:simulate{samples_u = args.samples_u or 100, samples_v = args.samples_v or 500,
                       edge_samples_u = args.edge_samples_u, edge_samples_v = args.edge_samples_v,
                       seam_spacing = args.seam_spacing}
report.simulation = {undercut_max_mm = sim.undercut_max, overcut_mm = sim.overcut, flanks = {}}
for _, f in ipairs(sim.flanks) do
  report.simulation.flanks[#report.simulation.flanks + 1] = {blade = f.blade, side = f.side, operation = f.kind,
    undercut_max_mm = f.undercut_max, undercut_mean_mm = f.undercut_mean, overcut_mm = f.overcut,
    overcut_move = f.overcut_move, overcut_motion = f.overcut_motion, turned_from = f.turned_from,
    unreached = f.unreached, fillet_left_max_mm = f.fillet_left_max}
end
for _, f in ipairs(sim.flanks) do
  if f.kind == "edge_finish" and not f.turned_from then
    print(string.format("  simulated blade %d %s: material left up to %.2f um (e2 20 um), overcut %.2f um (edge and flanks)",
                        f.blade, f.side, 1e3 * f.undercut_max, 1e3 * f.overcut))
  elseif f.kind == "hub_finish" and not f.turned_from then
    print(string.format("  simulated blade %d root strip and channel floor: material left up to %.2f um, %d samples "
                        .. "unreached, overcut %.2f um; the fillet (the ball's radius in the sharp corner) up to %.3f mm",
                        f.blade, 1e3 * f.undercut_max, f.unreached, 1e3 * f.overcut, f.fillet_left_max))
  end
end
print(string.format("  simulated: undercut max %.2f um, overcut %.2f um%s", 1e3 * sim.undercut_max, 1e3 * sim.overcut,
                    sim.overcut_at and sim.overcut_at.overcut_move and string.format(" (job move %d, %s, blade %d %s)",
                      sim.overcut_at.overcut_move, sim.overcut_at.overcut_motion, sim.overcut_at.blade,
                      sim.overcut_at.side) or ""))
-- Seams between operations on blade 1 (issue 34 item 8, j:simulate_seams):
-- every boundary between two operations' regions — root strip / edges,
-- the edges' window tops, edges / flanks, root strip / flanks, channel
-- floor / fillet — simulated under every operation's moves that reach it,
-- each with its own tool, against the two operations' promises. A seam
-- beyond them fails the run after the report (non-zero exit; a gouge there
-- posts nothing).
report.seams = {}
for _, s in ipairs(sim.seams or {}) do
  report.seams[#report.seams + 1] = {seam = s.name, surface = s.surface, operations = s.operations,
    heights_mm = s.heights_mm, samples = s.samples, unreached = s.unreached, material_left_max_mm = s.material_left_max_mm,
    material_left_min_mm = s.material_left_min_mm, material_left_at = s.material_left_at, overcut_mm = s.overcut_mm,
    overcut_move = s.overcut_move, overcut_at = s.overcut_at, tolerance = s.tolerance, ok = s.ok, reason = s.reason}
  print(string.format("  seam, blade 1 %-34s %s, heights %s mm: material left %s, unreached %d of %d, deepest cut %.2f um "
                      .. "(within %.1f / %.1f um): %s", s.name .. ",", s.surface,
                      s.heights_mm and string.format("%.2f-%.2f", s.heights_mm[1], s.heights_mm[2]) or "-",
                      s.material_left_max_mm and string.format("up to %.2f um at %.2f mm", 1e3 * s.material_left_max_mm,
                        s.material_left_at.height_mm) or "none reached", s.unreached, s.samples, 1e3 * s.overcut_mm,
                      1e3 * s.tolerance.material_left_mm, -1e3 * s.tolerance.overcut_mm,
                      s.ok and "ok" or "FAIL (" .. s.reason .. ")"))
end
local seam_failures = {}
for _, s in ipairs(sim.seams or {}) do
  if not s.ok then seam_failures[#seam_failures + 1] = string.format("%s: %s", s.name, s.reason) end
end
report.seam_failures = #seam_failures

-- One map of blade 1 (issue 18 item 4): every surface of the blade — both
-- flanks, both edges, the root strip and the fillet below it, the channel
-- floor to blade 2 — swept by every operation's moves with their own tools
-- (j:simulate_blade), as one picture and one summary per region.
-- --set blade_map=false skips it; --set blade_map=lean samples coarsely.
if with_edges and with_hub and args.blade_map ~= false and args.blade_map ~= "false" then
  local lean = args.blade_map == "lean"
  local t_map = os.clock()
  local bm = j:simulate_blade(lean and {flank_samples = {16, 60}, edge_samples = {40, 12}, root_samples = {12, 160},
                                        floor_samples = {40, 30}} or {})
  print(string.format("  blade 1 map: %.1f s CPU", os.clock() - t_map))
  report.blade_map = {material_left_max_mm = bm.material_left_max_mm, overcut_mm = bm.overcut_mm,
                      unreached = bm.unreached, picture = "blisk_job_blade1_map.png", regions = {}}
  for _, r in ipairs(bm.regions) do
    report.blade_map.regions[#report.blade_map.regions + 1] = {name = r.name,
      material_left_max_mm = r.material_left_max_mm, material_left_min_mm = r.material_left_min_mm,
      overcut_mm = r.overcut_mm, overcut_move = r.overcut_move, unreached = r.unreached, samples = r.samples}
    print(string.format("  blade 1 map, %-14s material left %s, overcut %.2f um%s, unreached %d of %d (%.1f s)", r.name .. ":",
                        r.material_left_max_mm and string.format("%.2f..%.2f um", 1e3 * r.material_left_min_mm,
                          1e3 * r.material_left_max_mm) or "none reached", 1e3 * r.overcut_mm,
                        r.overcut_move and string.format(" (job move %d)", r.overcut_move) or "", r.unreached, r.samples,
                        r.seconds))
  end
  -- The scale: twice the drum finish's residual (the fillet's ball radius is clamped to it).
  bm.map:write_png("blisk_job_blade1_map.png", {title = "Blade 1 after the job: material left (mm; red above the design, "
                                                         .. "blue below), every operation's moves", scale = 0.03,
                                                width = 1200, height = 480})
end

local chord_tol = 0.002
if sim.overcut < -chord_tol - 1e-4 then
  bliskrun.write_json("blisk_job.json", report)
  error(string.format("the simulation finds an overcut of %.2f um, beyond the %.0f um chord tolerance; nothing posted",
                      -1e3 * sim.overcut, 1e3 * chord_tol), 0)
end
for _, s in ipairs(sim.seams or {}) do
  if s.overcut_mm < s.tolerance.overcut_mm - 0.0005 then
    bliskrun.write_json("blisk_job.json", report)
    error(string.format("seam %s: %s; nothing posted", s.name, s.reason), 0)
  end
end

-- Setups: the blisk's axis on the table's C axis, its inlet face down. The
-- leading edges face the table (their tool axes point up to 90 deg below
-- the table plane, beyond the A cradle's -120 deg and the head's reach), so
-- they are cut in a second setup with the part turned over; everything
-- else in the first.
local setups = {{name = "inlet down", first = 1, last = #planned.moves}}
for i, f in ipairs(planned.flanks) do
  if f.side == "leading edge" then
    local before = planned.flanks[i - 1]
    setups = {{name = "inlet down", first = 1, last = before.first_move + before.moves - 1},
              {name = "turned over (inlet up)", first = f.first_move, last = #planned.moves, flip = true}}
    break
  end
end
-- Turned over, the leading edges' axes are kept 35-118 deg off the table's
-- axis (job.edge_finish reach): within the A cradle's and the B head's 120,
-- and clear of the cone where the A/C cradle reaches an axis on either side
-- of A = 0 (up to its +30) — a path through it would have to change sides
-- between two moves, which no motion along the planned path does
-- (core/machine/motion.h refuses it).
-- The four programs are independent: posted at once on --threads (each
-- read back and replayed as one posted alone).
local programs = {}
for _, m in ipairs({{machine = "dmg_like_ac_trunnion", post = "fanuc", file = "blisk_job_ac_fanuc", ext = ".nc"},
                    {machine = "monoblock_like_head_table", post = "heidenhain", file = "blisk_job_bc_heidenhain",
                     ext = ".h"}}) do
  for k, setup in ipairs(setups) do
    programs[#programs + 1] = {machine = m.machine, post = m.post, setup = setup,
                               file = m.file .. (#setups > 1 and string.format("_setup%d", k) or "") .. m.ext}
  end
end
report.programs = j:post_programs(programs)
-- One budget: what the programs can cut below the design is the plan's
-- deepest cut (the simulation) plus how far the program's cutter leaves
-- the proved motion as its controller moves (the sweep: the split
-- tolerance and the output resolution's rounding).
for _, p in ipairs(report.programs) do
  p.overcut_bound_mm = sim.overcut - p.swept_cutter_mm
  print(string.format("  %s: overcut at most %.2f um (plan %.2f um, program off the plan by at most %.2f um)", p.file,
                      -1e3 * p.overcut_bound_mm, -1e3 * sim.overcut, 1e3 * p.swept_cutter_mm))
end
bliskrun.write_json("blisk_job.json", report)

-- The run's page and the ParaView collection: every flank painted with its
-- undercut (the first few), the whole job's toolpath with its links.
local flank_rows, blocks, pictures = {}, {{name = "job toolpath", moves = planned.moves}}, {}
for i, f in ipairs(sim.flanks) do
  flank_rows[i] = {f.blade, f.side, planned.flanks[i].report.row_count, planned.flanks[i].report.poses,
                   1e3 * f.undercut_max, 1e3 * f.undercut_mean, 1e3 * f.overcut}
  if i <= 4 and f.map then
    local picture = string.format("blisk_job_undercut_blade%d_%s.png", f.blade, f.side)
    f.map:write_png(picture, {title = string.format("Undercut after the job, blade %d %s flank (mm)", f.blade, f.side)})
    pictures[#pictures + 1] = {title = string.format("Undercut, blade %d %s", f.blade, f.side), image = picture}
    blocks[#blocks + 1] = {name = string.format("blade %d %s, undercut", f.blade, f.side),
                           surface = planned.flanks[i].plan:trimmed(), map = f.map, samples_u = 60, samples_v = 150}
  end
end
local program_rows = {}
for i, p in ipairs(report.programs) do
  program_rows[i] = {p.file, p.machine, p.post, p.blocks, p.positioning, 1e3 * p.max_position_mm,
                     1e3 * p.swept_cutter_mm, 1e3 * p.swept_tool_mm, -1e3 * p.overcut_bound_mm}
end
local sections = {
  {title = "Operations", text = string.format("%d moves, %d links through %s.", #planned.moves, planned.links,
                                              j.clearance_surface.description),
   table = {columns = {"blade", "flank, edge or root", "rows", "poses", "material left max (um)", "mean (um)",
                       "overcut (um)"},
            rows = flank_rows}},
  {title = "Programs, read back and swept as each controller moves", table = {columns = {"file", "machine", "post",
    "blocks", "positioning moves", "tip deviation (um)", "cutter off the proved motion (um)",
    "tool off the proved motion (um)", "overcut at most (um)"}, rows = program_rows}}}
if report.blade_map then
  pictures[#pictures + 1] = {title = "Blade 1 after the job, one map (flanks, edges, root strip, fillet, channel floor)",
                             image = report.blade_map.picture}
end
for _, p in ipairs(pictures) do sections[#sections + 1] = p end
require("run_report").write{title = "Job: " .. j.name, settings = {blades = count, sides = args.sides or "both",
  edges = with_edges, edge_span = string.format("%g, %g", edge_span[1], edge_span[2]), periodic = periodic,
  tool_life_mm = args.tool_life or "none", samples_u = args.samples_u or 100, samples_v = args.samples_v or 500},
  sections = sections, vtk = {path = "blisk_job.pvd", blocks = blocks},
  files = {{"blisk_job.json", "the report"},
           {"blisk_job_ac_fanuc*.nc", "Fanuc programs, A/C trunnion (one per setup)"},
           {"blisk_job_bc_heidenhain*.h", "Heidenhain programs, B/C head-table (one per setup)"},
           {"blisk_job_undercut_*.png", "the undercut maps above"},
           {"blisk_job_blade1_map.png", "blade 1's whole surface after the job, one map"}}}
-- Material left beyond a seam's tolerance: the programs are proved safe and
-- written, the part is not finished within tolerance — the run says so and
-- fails (the report has each seam's reason).
if #seam_failures > 0 then
  error(string.format("%d seam%s between operations beyond tolerance (blisk_job.json, seams): %s", #seam_failures,
                      #seam_failures > 1 and "s" or "", table.concat(seam_failures, "; ")), 0)
end
