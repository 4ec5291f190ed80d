-- The built-in impeller machined as one job and posted as one verified
-- program per machine (impeller paper §4; issue 13): every channel notched
-- and widened, the widening finishing the hub as in the paper (the faces
-- keep the stock), then both faces of every main blade and
-- splitter flank-finished, the finishing cutters grouped per blade by tool
-- life as in the paper (17 blades: 5, 4, 4, 4 per cutter).
--
--   bliskrun scripts/recipes/impeller_job.lua --out out [--set blades=17] [--set stations=41]
--            [--set finish_life=MM] [--set rough_life=MM]   (cutting length per cutter; sisters follow)
--            [--set scallop=0.01] [--set depth_step=5] [--set stock=0.5] [--set chord_tol=0.005]
--            [--set hub_stock=0]   (left on the hub by the widening; the faces keep the stock)
--            [--set channels=inlet,left,right] [--set "faces=main plus,main minus,splitter plus,splitter minus"]
--            [--set sim_u=60] [--set sim_v=300] [--set simulate=false]   (samples of the simulated surfaces)
--
-- Blade 1's channel plans (three channels around the splitter) and face plans
-- are proved with the whole tool against the blades either side and the hub
-- (scripts/lib/impeller_world.lua); every other blade's are them turned by the
-- blade pitch (the model is symmetric). Operations and blades are linked
-- over a clearance surface 10 mm above the part, every link leg proved. Posted for
-- two B/C trunnions (Heidenhain TCPM, Fanuc), each program read back and
-- replayed through the machine with travel checked on every move.
-- The material each operation and the whole job leave on blade 1's faces
-- and one pitch of the hub is simulated (core/sim) and mapped.
-- Outputs: impeller_job_bc_heidenhain.h, impeller_job_bc_fanuc.nc, impeller_job.json,
-- impeller_job_left_*.png (maps), impeller_job.pvd (toolpath), report.html.
local job = require("job")

local imp = bliskrun.impeller{}
local blades = job.first_blades(imp, args.blades)
local count = #blades

-- The paper's tapered ball-end mill for roughing and finishing (two tools of
-- the same form: the rougher wears, the finisher holds the size).
local cutter = bliskrun.tapered_ball_end_mill{tip_radius = 3, half_angle = 2, flute_length = 90,
                                              shank = {diameter = 16, length = 60},
                                              holder = {diameter = 50, length = 60}}
-- Finishing cutting length per cutter: the default puts the 17 blades on 4
-- cutters (5, 4, 4, 4), as the paper did.
local finish_life = args.finish_life or 4000
local j = job.new{
  name = "impeller",
  part = imp,
  clearance = 10,  -- links run 10 mm over the impeller's outline (hub, shroud, blade ends)
  tools = {
    rougher = {number = 1, length = 150, spindle_rpm = 12000, tool = cutter, ball_radius = 3,
               life_mm = args.rough_life, sisters = args.rough_life and {11, 21, 31, 41, 51, 61, 71} or nil},
    finisher = {number = 2, length = 150, spindle_rpm = 15000, tool = cutter, ball_radius = 3,
                life_mm = finish_life, sisters = {12, 22, 32, 42, 52, 62, 72}},
  },
  operations = {
    job.notch{tool = "rougher", blades = blades, stock = args.stock or 0.5, depth_step = args.depth_step or 5,
              stations = args.stations or 41, channels = job.split_list(args.channels), feed = 800},
    job.widen{tool = "rougher", blades = blades, scallop = args.scallop or 0.01, hub_stock = args.hub_stock or 0,
              feed = 1000},
    job.flank_finish{tool = "finisher", blades = blades, chord_tol = args.chord_tol or 0.005, faces = job.split_list(args.faces),
                     feed = 600},
  },
}

local t0 = os.clock()
local planned = j:plan()
local report = {part = "built-in impeller", blades = count, moves = #planned.moves, links = planned.links,
                units = {}, tool_groups = planned.tool_groups, programs = {}}
print(string.format("Job '%s': %d blades, %d channel and face plans, %d moves, %d links over %s, each "
                    .. "proved clear; planned in %.1f s CPU", j.name, count, #planned.flanks, #planned.moves,
                    planned.links, j.clearance_surface.description, os.clock() - t0))
for _, g in ipairs(planned.tool_groups) do
  print(string.format("  operation %d, tool T%d: blades %d-%d, cutting length %.0f mm", g.operation, g.tool,
                      g.blades[1], g.blades[#g.blades], g.cutting_length_mm))
end
local by_op = {}
for _, m in ipairs(planned.moves) do by_op[m.operation_kind] = (by_op[m.operation_kind] or 0) + 1 end
report.moves_by_operation = by_op
print(string.format("  moves: notch %d, widen %d, flank finish %d, links %d", by_op.notch or 0, by_op.widen or 0,
                    by_op.flank_finish or 0, by_op.link or 0))
for _, f in ipairs(planned.flanks) do
  if f.blade == 1 then
    report.units[#report.units + 1] = {operation = f.kind, name = f.side, moves = f.moves, report = f.report}
  end
end

-- The material left (core/sim) on blade 1's faces and one pitch of the hub,
-- per operation and after the whole job; every other blade's moves are blade
-- 1's turned. Faces: the flank finish's residual of the ruled cutter
-- (eq. 33-36, about +-0.11 mm balanced) is the design's, so the run stops
-- only on an overcut deeper than that on a face, or any on the hub beyond
-- the sweep's resolution.
local sim = args.simulate ~= false and j:simulate{samples_u = args.sim_u or 60, samples_v = args.sim_v or 300}
  or {surfaces = {}, seconds = 0}
local simulated = j:report_simulation(sim, {pictures = "impeller_job_left_"})
report.simulation = simulated.json
local sim_rows, pictures = simulated.rows, simulated.pictures
print(string.format("  simulation: %.1f s CPU", sim.seconds))
-- Nothing is posted after a simulated overcut the operations do not allow.
j:check_overcut(sim, report.units, 0.005)

-- The machines: B/C trunnions, whose cradle swivels both ways. At the
-- outlet the finishing axis lies along the part axis, so widening passes
-- carry the tool axis over the pole of the table's C axis, and following the
-- planned motion there turns C half round and leaves the cradle on the other
-- side of zero: an A/C cradle that tilts only one way (-120..+30 deg, the
-- DMG-like trunnion) runs out of travel on the next path (the post names the
-- move). The Hermle-like machine with a TNC (TCPM), and a 600-class B/C
-- trunnion with a Fanuc (no TCP: moves split to the chord tolerance).
local fanuc_bc = bliskrun.machine.load("table_table_bc", {name = "B/C trunnion 600 (Fanuc)"})
for _, m in ipairs({{machine = "bc_trunnion_hermle_like", post = "heidenhain", file = "impeller_job_bc_heidenhain.h"},
                    {machine = fanuc_bc, name = "table_table_bc", post = "fanuc", file = "impeller_job_bc_fanuc.nc"}}) do
  report.programs[#report.programs + 1] = j:post_program(m)
end
bliskrun.write_json("impeller_job.json", report)

local unit_rows, program_rows = {}, {}
for _, u in ipairs(report.units) do
  unit_rows[#unit_rows + 1] = {u.operation, u.name, u.moves, u.report.poses}
end
for i, p in ipairs(report.programs) do
  program_rows[i] = {p.file, p.machine, p.post, p.blocks, p.positioning, 1e3 * p.max_position_mm}
end
require("run_report").write{title = "Job: " .. j.name, settings = {blades = count, stations = args.stations or 41,
  finish_life_mm = finish_life, tool = cutter:description()},
  sections = {
    {title = "Blade 1's plans", text = string.format("%d moves in all, %d links over %s.", #planned.moves,
                                                     planned.links, j.clearance_surface.description),
     table = {columns = {"operation", "channel / face", "moves", "poses"}, rows = unit_rows}},
    {title = "Material left (simulated, blade 1's faces and one pitch of the hub)",
     table = {columns = {"surface", "moves of", "left min (um)", "left max (um)", "undercut mean (um)",
                         "overcut (um)", "overcut at move", "untouched samples"}, rows = sim_rows}},
    {title = "Programs, read back and replayed", table = {columns = {"file", "machine", "post", "blocks",
      "positioning moves", "tip deviation (um)"}, rows = program_rows}},
    table.unpack(pictures)},
  vtk = {path = "impeller_job.pvd", blocks = {{name = "job toolpath", moves = planned.moves}}},
  files = {{"impeller_job.json", "the report"}, {"impeller_job_bc_heidenhain.h", "Heidenhain program, B/C trunnion"},
           {"impeller_job_bc_fanuc.nc", "Fanuc program, B/C trunnion"},
           {"impeller_job_left_*.png", "the maps of the material left above"}}}
