-- The NASA HECC impeller (15 main + 15 splitter blades) machined as one job
-- (issue 13), as scripts/recipes/impeller_job.lua machines the built-in one:
-- every channel notched and widened (the widening finishing the hub, which is
-- a true surface of revolution here, as in the paper), both faces of every
-- main blade and splitter flank-finished, the cutters grouped by tool life,
-- linked over a clearance surface 10 mm above the part, simulated, posted for
-- two B/C trunnions (Heidenhain TCPM, Fanuc) and read back.
--
--   bliskrun scripts/recipes/hecc_impeller_job.lua --data ../shared/data --out out [--set blades=15]
--            [--set stations=41] [--set stock=MM] [--set min_stock=0.2] [--set depth_step=5]
--            [--set scallop=0.01] [--set hub_stock=0] [--set chord_tol=0.005] [--set finish_life=MM] [--set rough_life=MM]
--            [--set channels=inlet,left,right] [--set "faces=main plus,main minus,splitter plus,splitter minus"]
--            [--set sim_u=60] [--set sim_v=300] [--set simulate=false] [--set tolerance=0.05] [--set set=design|cold]
--
-- The part (scripts/lib/hecc_impeller_part.lua): the lofted faces of
-- bliskrun.read_hecc, turned so the channels open upward like the built-in
-- impeller's, each face planned on its ruled fit (bliskrun.fit_ruled) and
-- proved against, simulated on and measured against the lofted face.
--
-- The HECC blades are not ruled: the ruled fits are 0.7-1 mm off the
-- lofted faces. What that means here, stated in the output, not hidden:
--   * roughing is planned on the fits, so it leaves the stock on the fit; the
--     default stock is the largest fit error + 0.5 mm (rounded up to 0.1 mm),
--     so the widening's last pass stays off the real face (every pose is
--     proved against the lofted faces with min_stock for the cutter);
--   * flank finishing with a ruled cutter cannot follow a face that is not
--     ruled: its residual against the lofted face (flank_mill{design=},
--     balanced per axis) is the fit error spread over + and -, i.e. it
--     overcuts and undercuts the design by several tenths of a mm, far
--     beyond a 0.05 mm thickness tolerance. The JSON says so per face
--     (finish.within_tolerance = false) and the run prints it; these faces
--     need point milling (a ball end along the face) to finish to size.
-- Outputs: hecc_impeller_job_bc_heidenhain.h, hecc_impeller_job_bc_fanuc.nc, hecc_impeller_job.json,
-- hecc_impeller_job_left_*.png (maps), hecc_impeller_job.pvd (toolpath), report.html.
local job = require("job")
local hecc = require("hecc_impeller_part")

local part = hecc.load{set = args.set or "design"}
local n = part:blade_count()
local blades = job.first_blades(part, args.blades)
local count = #blades
local tolerance = args.tolerance or 0.05

-- The ruled fits, blade 1 (every blade is blade 1 turned).
local fit_max, fits = 0, {}
for _, kind in ipairs{"main", "splitter"} do
  for _, side in ipairs{"plus", "minus"} do
    local f = part:ruled_fit(kind, side)
    fits[kind .. " " .. side] = {max_mm = f.max, rms_mm = f.rms, worst_row = f.worst_row, worst_col = f.worst_col}
    fit_max = math.max(fit_max, f.max)
  end
end
local min_stock = args.min_stock or 0.2
local stock = args.stock or math.max(0.5, math.ceil((fit_max + 0.5) * 10 - 1e-9) / 10)
print(string.format("HECC impeller: %d main + %d splitter blades; ruled fits of the lofted faces %.3f mm at worst; "
                    .. "roughing stock %.2f mm (min %.2f)", n, n, fit_max, stock, min_stock))

-- Tapered ball-end mills of the HECC flank recipe's form (the channels are
-- narrower at the inlet than the built-in impeller's): rougher and finisher.
local cutter = bliskrun.tapered_ball_end_mill{tip_radius = 2, half_angle = 2, flute_length = 90,
                                              shank = {diameter = 12, length = 60},
                                              holder = {diameter = 40, length = 60}}
local finish_life = args.finish_life or 4000
local j = job.new{
  name = "hecc impeller",
  part = part,
  clearance = 10,
  tools = {
    rougher = {number = 1, length = 150, spindle_rpm = 15000, tool = cutter, ball_radius = 2,
               life_mm = args.rough_life, sisters = args.rough_life and {11, 21, 31, 41, 51, 61, 71} or nil},
    finisher = {number = 2, length = 150, spindle_rpm = 18000, tool = cutter, ball_radius = 2,
                life_mm = finish_life, sisters = {12, 22, 32, 42, 52, 62, 72}},
  },
  operations = {
    job.notch{tool = "rougher", blades = blades, stock = stock, min_stock = min_stock,
              depth_step = args.depth_step or 5, stations = args.stations or 41, channels = job.split_list(args.channels),
              feed = 800},
    job.widen{tool = "rougher", blades = blades, scallop = args.scallop or 0.01, hub_stock = args.hub_stock or 0,
              feed = 1000},
    job.flank_finish{tool = "finisher", blades = blades, chord_tol = args.chord_tol or 0.005, faces = job.split_list(args.faces),
                     feed = 600},
  },
}

local t0 = os.clock()
local planned = j:plan()
local report = {part = tostring(part), frame = part.frame, blades = count, moves = #planned.moves,
                links = planned.links, ruled_fit = fits, roughing_stock_mm = stock, min_stock_mm = min_stock,
                thickness_tolerance_mm = tolerance, units = {}, tool_groups = planned.tool_groups, programs = {},
                refusals = 0}
local poses = 0
for _, f in ipairs(planned.flanks) do poses = poses + (f.report.poses or 0) end
report.poses = poses
print(string.format("Job '%s': %d blades, %d channel and face plans (%d poses, none refused: a refusal stops the "
                    .. "job and names the channel or face), %d moves, %d links over %s, each proved clear; planned "
                    .. "in %.1f s CPU", j.name, count, #planned.flanks, poses, #planned.moves, planned.links,
                    j.clearance_surface.description, os.clock() - t0))
for _, g in ipairs(planned.tool_groups) do
  print(string.format("  operation %d, tool T%d: blades %d-%d, cutting length %.0f mm", g.operation, g.tool,
                      g.blades[1], g.blades[#g.blades], g.cutting_length_mm))
end
local by_op = {}
for _, m in ipairs(planned.moves) do by_op[m.operation_kind] = (by_op[m.operation_kind] or 0) + 1 end
report.moves_by_operation = by_op
print(string.format("  moves: notch %d, widen %d, flank finish %d, links %d", by_op.notch or 0, by_op.widen or 0,
                    by_op.flank_finish or 0, by_op.link or 0))

-- Flank finishing on the ruled fits against the design: the verdict per face.
report.finish = {}
for _, f in ipairs(planned.flanks) do
  if f.blade == 1 then
    report.units[#report.units + 1] = {operation = f.kind, name = f.side, moves = f.moves, report = f.report}
    if f.kind == "flank_finish" then
      local r = f.report
      local ok = r.residual_max <= tolerance and r.residual_min >= -tolerance
      report.finish[f.side] = {ruled_fit_max_mm = fits[f.side].max_mm, residual_max_mm = r.residual_max,
                               residual_min_mm = r.residual_min, within_tolerance = ok,
                               note = ok and "flank finishing holds the design within the tolerance"
                                 or "NOT within tolerance: the blade is not ruled; flank finishing on its ruled fit "
                                    .. "undercuts and overcuts the lofted face (point milling needed to finish it)"}
      print(string.format("  %s: flank finish on the ruled fit (fit %.3f mm) leaves %+.3f .. %+.3f mm against the "
                          .. "lofted face: %s", f.side, fits[f.side].max_mm, r.residual_min, r.residual_max,
                          ok and "within tolerance" or string.format("NOT within +-%.3f mm", tolerance)))
    end
  end
end

-- The material left (core/sim) on blade 1's lofted faces and one pitch of the hub.
-- The stock left on a face is up to the roughing stock plus the fit error:
-- tracked that high, so it is measured, not counted untouched. Flank
-- finishing on the fit cuts into the face (the plan says how far); an
-- overcut is measured down to half the thinnest blade (deeper, the sweep
-- would meet the cutter finishing the blade's other face), so one deeper
-- than that reads as that.
local thinnest = math.huge
for _, kind in ipairs{"main", "splitter"} do
  local a, b = part:design_face(1, "plus", kind), part:design_face(1, "minus", kind)
  for i = 0, 30 do
    for k = 0, 60 do
      local foot = b:project(a:point(i / 30, k / 60))
      if foot then thinnest = math.min(thinnest, foot.distance) end
    end
  end
end
local search_below = math.min(fit_max + 0.5, thinnest / 2)
report.blade_thickness_min_mm, report.simulation_search_below_mm = thinnest, search_below
local sim = args.simulate ~= false and j:simulate{samples_u = args.sim_u or 60, samples_v = args.sim_v or 300,
                                                  search_above = stock + fit_max + 0.5, search_below = search_below}
  or {surfaces = {}, seconds = 0}
local simulated = j:report_simulation(sim, {pictures = "hecc_impeller_job_left_", search_below = search_below})
report.simulation = simulated.json
local sim_rows, pictures = simulated.rows, simulated.pictures
print(string.format("  simulation: %.1f s CPU (overcut measured down to %.3f mm, half the thinnest blade, %.3f mm)",
                    sim.seconds, search_below, thinnest))
-- Nothing is posted after an overcut the operations do not allow: the hub
-- and the roughing must cut nothing; a face only what its flank finish's
-- plan says (its residual against the lofted face, 20 um for the sweep's
-- sampling of a residual of tenths of a mm).
j:check_overcut(sim, report.units, 0.02)

local fanuc_bc = bliskrun.machine.load("table_table_bc", {name = "B/C trunnion 600 (Fanuc)"})
for _, m in ipairs({{machine = "bc_trunnion_hermle_like", post = "heidenhain", file = "hecc_impeller_job_bc_heidenhain.h"},
                    {machine = fanuc_bc, name = "table_table_bc", post = "fanuc", file = "hecc_impeller_job_bc_fanuc.nc"}}) do
  report.programs[#report.programs + 1] = j:post_program(m)
end
bliskrun.write_json("hecc_impeller_job.json", report)

local fit_rows, finish_rows, unit_rows, program_rows = {}, {}, {}, {}
for _, name in ipairs{"main plus", "main minus", "splitter plus", "splitter minus"} do
  fit_rows[#fit_rows + 1] = {name, 1e3 * fits[name].max_mm, 1e3 * fits[name].rms_mm}
  local f = report.finish[name]
  if f then
    finish_rows[#finish_rows + 1] = {name, 1e3 * f.residual_min_mm, 1e3 * f.residual_max_mm,
                                     f.within_tolerance and "yes" or "NO"}
  end
end
for _, u in ipairs(report.units) do unit_rows[#unit_rows + 1] = {u.operation, u.name, u.moves, u.report.poses} end
for i, p in ipairs(report.programs) do
  program_rows[i] = {p.file, p.machine, p.post, p.blocks, p.positioning, 1e3 * p.max_position_mm}
end
require("run_report").write{title = "Job: NASA HECC impeller", settings = {blades = count,
  stations = args.stations or 41, roughing_stock_mm = stock, finish_life_mm = finish_life,
  thickness_tolerance_mm = tolerance, tool = cutter:description()},
  sections = {
    {title = "Ruled fits of the lofted faces (blade 1)", text = "The faces are planned on these fits; the "
       .. "roughing stock is the largest fit error + 0.5 mm.",
     table = {columns = {"face", "fit max (um)", "fit RMS (um)"}, rows = fit_rows}},
    {title = "Flank finishing against the lofted faces", text = string.format("Residual of the ruled cutter's "
       .. "axes (balanced) against the design; thickness tolerance %.3f mm. The HECC blades are not ruled: "
       .. "flank finishing does not finish them to size.", tolerance),
     table = {columns = {"face", "residual min (um)", "residual max (um)", "within tolerance"}, rows = finish_rows}},
    {title = "Blade 1's plans", text = string.format("%d moves in all, %d links over %s.", #planned.moves,
                                                     planned.links, j.clearance_surface.description),
     table = {columns = {"operation", "channel / face", "moves", "poses"}, rows = unit_rows}},
    {title = "Material left (simulated, blade 1's lofted faces and one pitch of the hub)",
     table = {columns = {"surface", "moves of", "left min (um)", "left max (um)", "undercut mean (um)",
                         "overcut (um)", "overcut at move", "untouched samples"}, rows = sim_rows}},
    {title = "Programs, read back and replayed", table = {columns = {"file", "machine", "post", "blocks",
      "positioning moves", "tip deviation (um)"}, rows = program_rows}},
    table.unpack(pictures)},
  vtk = {path = "hecc_impeller_job.pvd", blocks = {{name = "job toolpath", moves = planned.moves}}},
  files = {{"hecc_impeller_job.json", "the report"}, {"hecc_impeller_job_bc_heidenhain.h", "Heidenhain program, B/C trunnion"},
           {"hecc_impeller_job_bc_fanuc.nc", "Fanuc program, B/C trunnion"},
           {"hecc_impeller_job_left_*.png", "the maps of the material left above"}}}
