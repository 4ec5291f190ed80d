-- Repair toolpaths of a welded-up blade (issue 16 item 5, repair paper §2,
-- SPEC §6.5), planned on the *design* surface of blade 1 of the built-in
-- blisk over two regions given here (blade_repair.lua plans the same on
-- the rebuilt blade over the region it extracts):
--   tip:  the whole way around the blade above `tip_span` of the span, with
--         `deposit` mm of weld: a ball-end spiral (§2.2) per offset layer;
--   edge: the leading edge, `edge_width` mm either side of its apex, over
--         the span range `edge_span`: a ball-end zigzag along iso-span lines
--         with arc lead-outs and bridges (§2.1) per offset layer.
-- Offset layers (§1.5/§2): roughing on the design offset outward by
-- stock + k·layer (outside first), finishing on the design. Every pose and
-- motion is proved against the blade itself (shank and holder) and a
-- fixture below the root (every part), and on the finishing layer against
-- the design surface (core/sim gouge guard). Then the independent
-- simulation (bliskrun.simulate) of each finishing layer on the design
-- over its region (material left) and over a band of the undamaged blade
-- around it (gouge), and the tip's finishing program posted for the A/C
-- trunnion with the Fanuc post and read back.
--
-- The blade: the built-in blisk's pressure and suction flanks of blade 1
-- between r = 63 mm (the mean hub radius: its root on the fixture, a
-- cylinder of that radius about Z) and r = 93 mm (the mean casing radius:
-- its tip), closed by its edge circles (bliskrun.close_blade).
--
--   bliskrun scripts/recipes/blade_repair_paths.lua --out out
--            [--set NAME=VALUE]... (--help lists them)
-- Outputs: blade_repair_paths.json, blade_repair_tip_fanuc.nc, the material-left maps,
-- blade_repair_paths.pvd (design blade and toolpaths), report.html.
local opt = require("recipe_options"){
  tip_span = {type = "number", default = 0.85, range = {0.05, 0.98}, help = "span fraction above which the tip is welded"},
  deposit = {type = "number", unit = "mm", default = 2.0, range = {0, 10}, help = "weld deposit"},
  layer = {type = "number", unit = "mm", default = 0.5, range = {0.05, 10}, help = "offset layer thickness"},
  stock = {type = "number", unit = "mm", default = 0.2, range = {0, 5}, help = "stock the roughing layers leave"},
  scallop = {type = "number", unit = "mm", default = 0.005, range = {1e-4, 0.5}, help = "scallop height between passes"},
  chord_tol = {type = "number", unit = "mm", default = 0.002, range = {1e-4, 0.1}, help = "chord deviation allowed between steps"},
  ball = {type = "number", unit = "mm", default = 3, range = {0.5, 10}, help = "ball radius"},
  edge_width = {type = "number", unit = "mm", default = 4, range = {0.5, 20}, help = "edge: width either side of the apex"},
  edge_span = {type = "string", default = "0.3:0.6", help = "edge: span range lo:hi, 0 <= lo < hi <= 1",
               check = function(v)
                 local a, b = v:match("^([%d.]+):([%d.]+)$")
                 a, b = tonumber(a), tonumber(b)
                 if not (a and b and 0 <= a and a < b and b <= 1) then return "expected lo:hi with 0 <= lo < hi <= 1" end
               end},
  regions = {type = "string", default = "tip,edge", help = "regions to repair, a comma list of tip and edge",
             check = function(v)
               for name in v:gmatch("[^,]+") do
                 if name ~= "tip" and name ~= "edge" then return "expected a list of tip and edge, got " .. name end
               end
             end},
}
local t_start = os.clock()
local tip_span, deposit, layer, stock = opt.tip_span, opt.deposit, opt.layer, opt.stock
local scallop, chord_tol, ball, edge_width = opt.scallop, opt.chord_tol, opt.ball, opt.edge_width
local a, b = opt.edge_span:match("^([%d.]+):([%d.]+)$")
local edge_span = {tonumber(a), tonumber(b)}
local regions = {}
for name in opt.regions:gmatch("[^,]+") do regions[#regions + 1] = name end

-- The design blade, root r = 63 to tip r = 93, closed around its section.
local blisk = bliskrun.blisk{}
local r_lo, r_hi = 60 - 1.5, 96 + 1.5           -- the flanks' radial range (u linear in r)
local r_root, r_tip = 63, 93
local function flank_u(r) return (r - r_lo) / (r_hi - r_lo) end
local sections = 31                              -- 1 mm apart
local blade, closed = bliskrun.close_blade{pressure = blisk:flank(1, "pressure"), suction = blisk:flank(1, "suction"),
                                           u = {flank_u(r_root), flank_u(r_tip)}, sections = sections}
-- The loft's u at a fraction of the span (its sections are equally spaced in r).
local function span_u(f)
  local x = f * (sections - 1)
  local i = math.min(math.floor(x), sections - 2)
  local a, b = closed.section_u[i + 1], closed.section_u[i + 2]
  return a + (b - a) * (x - i)
end

-- The fixture: a cylinder about Z at the root radius, under the whole blade.
local fixture = bliskrun.surface_of_revolution{meridian = {{-30, r_root}, {30, r_root}}}
local world = bliskrun.collision_world{surfaces = {
  -- The blade for the shank and holder (the cutter touches it by design; its
  -- gouge is the planner's guard), 0.05 mm mesh and that much margin.
  {name = "blade", surface = blade, chord_tol = 0.05, margin = 0.05, parts = {"shank", "holder"}},
  {name = "fixture", surface = fixture, chord_tol = 0.01}}}
local tool = bliskrun.ball_end_mill{radius = ball, flute_length = 4 * ball, shank = {diameter = 2 * ball, length = 60},
                                    holder = {diameter = 25, length = 50}}

local perimeter = closed.perimeter
local region_of = {
  tip = {pattern = "spiral", u = {span_u(tip_span), 1}, v = {0, 1},
         -- the band of undamaged blade below it: 1 mm of span (the ball,
         -- R 3, leaves the design 1 mm from its contact by 0.17 mm)
         band = {u = {span_u(math.max(0, tip_span - 1 / 30)), span_u(tip_span)}, v = {0, 1}}},
  edge = {pattern = "zigzag", u = {span_u(edge_span[1]), span_u(edge_span[2])},
          v = {closed.le_v - edge_width / perimeter, closed.le_v + edge_width / perimeter}},
}
do
  local e = region_of.edge
  assert(e.v[1] > 0 and e.v[2] < 1, "the edge region crosses the seam of the closed blade")
  -- The band around the edge region: 1 mm of span and 1.5 mm around on every side.
  local du, dv = span_u(1 / 30) - span_u(0), 1.5 / perimeter
  e.band = {u = {math.max(0, e.u[1] - du), math.min(1, e.u[2] + du)}, v = {e.v[1] - dv, e.v[2] + dv}}
end

local report = {blade = {root_radius_mm = r_root, tip_radius_mm = r_tip, perimeter_mm = perimeter, le_v = closed.le_v,
                         sections = sections},
                tool = tool:description(), deposit_mm = deposit, layer_mm = layer, stock_mm = stock,
                scallop_mm = scallop, chord_tol_mm = chord_tol, regions = {}}
local pictures, vtk_blocks, rows = {}, {{name = "design blade", surface = blade, samples_u = 60, samples_v = 400}}, {}
local setup_sheet = require("setup_sheet")
local requirements, sheets = {}, {}  -- the verdict; the posted program's setup sheet
local plans = {}

local repair = require("repair")

for _, name in ipairs(regions) do
  local region = region_of[name]
  local t0 = os.clock()
  local plan = bliskrun.repair_paths{design = blade, tool = tool, world = world, pattern = region.pattern,
                                     u = region.u, v = region.v, deposit = deposit, layer = layer, stock = stock,
                                     scallop = scallop, chord_tol = chord_tol, clearance = 0.5}
  local plan_s = os.clock() - t0
  bliskrun.log(string.format("  %s planned in %.1f s CPU (paths %.1f s, connections %.1f s)", name, plan_s,
                             plan.paths_seconds, plan.connect_seconds))
  plans[name] = plan
  for _, r in ipairs(plan.refusals) do
    bliskrun.log(string.format("  %s layer %d: refused at u = %.4f, v = %.4f: %s", name, r.layer, r.u, r.v, r.reason))
  end
  for _, why in ipairs(plan.refused) do bliskrun.log("  " .. name .. ": " .. why) end
  -- The independent simulation of the finishing layer on the design: over
  -- the region (material left) and over the band of undamaged blade next to
  -- it (gouge), samples about 0.05 mm apart.
  local passes = repair.finishing_passes(plan, tool)
  local function window_samples(w) return repair.window_samples(blade, w, closed.le_v) end
  -- The default sweep (0.05 mm of the fastest cutter point): at 0.15 mm
  -- the material left read 0.26 um higher on the tip (positions missed).
  local su, sv = window_samples(region)
  t0 = os.clock()
  local sim = bliskrun.simulate{surface = blade, passes = passes, u = region.u, v = region.v, samples_u = su,
                                samples_v = sv, search_above = 0.05, search_below = 0.05}
  local bu, bv = window_samples(region.band)
  local band = bliskrun.simulate{surface = blade, passes = passes, u = region.band.u, v = region.band.v,
                                 samples_u = bu, samples_v = bv, search_above = 0.05, search_below = 0.05}
  bliskrun.log(string.format("  %s simulated in %.1f s CPU", name, os.clock() - t0))
  local picture = "repair_" .. name .. "_material_left.png"
  sim.map:write_png(picture, {title = "Material left after the " .. name .. " finishing layer (µm)"})
  pictures[#pictures + 1] = {title = "Material left on the design after finishing, " .. name .. " region",
                             image = picture}
  local finish = plan.layers[#plan.layers]
  local entry = {
    pattern = plan.pattern, u = region.u, v = region.v, layers = plan.layers, passes = plan.passes,
    poses = plan.poses, moves = #plan.moves, tilted = plan.tilted, refusals = #plan.refusals,
    bridges = plan.bridges, links = plan.links, refused_connections = plan.refused_connections,
    gouge_refusals = plan.gouge_refusals, gouge_splits = plan.gouge_splits,
    chord_deviation_max_mm = plan.max_deviation, guard_spacing_mm = plan.guard_spacing,
    simulation = {samples = sim.samples, untouched = sim.untouched, residual_max_mm = sim.residual_max,
                  residual_min_mm = sim.residual_min, undercut_mean_mm = sim.undercut_mean, overcut_mm = sim.overcut,
                  band_overcut_mm = band.overcut, band_samples = band.samples,
                  allowed_undercut_mm = scallop + chord_tol},
  }
  report.regions[name] = entry
  print(string.format("%s (%s): %d layers, %d passes, %d poses, %d bridges, %d links, %d refused poses, "
                      .. "%d refused connections, %d tilted; finishing: chord <= %.2f um, step-over %.3f..%.3f mm",
                      name, plan.pattern, #plan.layers, plan.passes, plan.poses, plan.bridges, plan.links,
                      #plan.refusals, plan.refused_connections, plan.tilted, 1e3 * plan.max_deviation,
                      finish.step_over_min, finish.step_over_max))
  print(string.format("  simulated finishing on the design: material left %.2f..%.2f um (allowed %.1f), "
                      .. "untouched %d of %d; overcut %.2f um in the region, %.2f um in the band around it",
                      1e3 * (sim.residual_min or 0), 1e3 * (sim.residual_max or 0), 1e3 * (scallop + chord_tol),
                      sim.untouched, sim.samples, -1e3 * sim.overcut, -1e3 * band.overcut))
  -- The design restored within scallop + chord (the simulation's samples
  -- add nothing: they read the material at points), and no gouge beyond a
  -- few um into the region or the undamaged blade around it.
  for _, q in ipairs{
    {name = name .. ": refused connections", unit = "count", measured = #plan.refused, at_most = 0,
     note = #plan.refused > 0 and table.concat(plan.refused, "; ") or nil},
    {name = name .. ": material left on the design (simulated)", unit = "µm",
     measured = sim.residual_max and 1e3 * sim.residual_max, at_most = 1e3 * (scallop + chord_tol) + 0.1},
    {name = name .. ": samples never reached", unit = "count", measured = sim.untouched, at_most = 0},
    {name = name .. ": overcut in the region (simulated)", unit = "µm", measured = math.max(0, -1e3 * sim.overcut),
     at_most = 3},
    {name = name .. ": overcut in the band around it (simulated)", unit = "µm",
     measured = math.max(0, -1e3 * band.overcut), at_most = 3}} do
    requirements[#requirements + 1] = q
  end
  rows[#rows + 1] = {name, plan.pattern, #plan.layers, plan.passes, plan.poses, plan.bridges, plan.links,
                     #plan.refusals + plan.refused_connections, 1e3 * plan.max_deviation,
                     1e3 * (sim.residual_max or 0), 1e3 * math.min(sim.overcut, band.overcut)}
  vtk_blocks[#vtk_blocks + 1] = {name = name .. " toolpath", moves = plan.moves}
end

-- The tip's finishing program, posted for the A/C trunnion (Fanuc, machine
-- axes, G93) and read back. The blade stands on its fixture with its span
-- up: part frame = the blisk frame turned -90 deg about Y (x, y, z) ->
-- (-z, y, x), its root at z = 0.
if plans.tip then
  local plan = plans.tip
  local t_post = os.clock()
  assert(plan.refused_connections == 0, "the tip plan refused connections: nothing to post")
  local path = {}
  local function to_fixture(p) return {-p.z, p.y, p.x - r_root} end
  local function axis_to_fixture(a) return {-a.z, a.y, a.x} end
  for i = plan.first_finishing_move, #plan.moves do
    local m = plan.moves[i]
    path[#path + 1] = {kind = m.kind, tip = to_fixture(m.tip), axis = axis_to_fixture(m.axis), row = m.row,
                       feed = m.kind == "feed" and 800 or nil}
  end
  local machine = bliskrun.machine.load("dmg_like_ac_trunnion")
  local w = bliskrun.post.write{machine = machine, post = "fanuc", path = path, file = "blade_repair_tip_fanuc.nc",
                                tool = {number = 7, length = 4 * ball + 60 + 10, spindle_rpm = 12000},
                                name = "blade 1 tip repair, finishing", chord_tol = chord_tol}
  report.post = {file = "blade_repair_tip_fanuc.nc", machine = machine:name(), post = "fanuc", planned_moves = #path,
                 blocks = w.moves, inserted = w.inserted, positioning = w.positioning, max_position_mm = w.max_position,
                 max_angle_deg = w.max_angle}
  for _, q in ipairs(setup_sheet.requirements(report.post.file, w)) do requirements[#requirements + 1] = q end
  local sheet = setup_sheet.build{file = report.post.file, machine = "dmg_like_ac_trunnion", post = "fanuc", report = w,
    tools = {{number = 7, description = string.format("ball end mill r %g mm", ball), stick_out_mm = 4 * ball + 60 + 10,
              spindle_rpm = 12000, feeds_mm_per_min = {800}, sisters = {}}},
    operations = {[""] = "tip repair, finishing layer"}, work_offset = 1,
    origin = "the blade's fixture frame: its root at z = 0, span up (the blisk frame turned -90 deg about Y)",
    fixture = "a blade fixture holding the root, span up (not modelled)",
    stock = string.format("deposit %g mm over the damaged tip, %g mm stock left for the finishing layer", deposit, stock)}
  setup_sheet.write(sheet)
  sheets[#sheets + 1] = sheet
  report.post.cycle_time = sheet.cycle_time
  bliskrun.log(string.format("  posted in %.1f s CPU", os.clock() - t_post))
  print(string.format("posted %s on %s: %d blocks (%d inserted), read back within %.4f mm and %.5f deg",
                      report.post.file, report.post.machine, w.moves, w.inserted, w.max_position, w.max_angle))
end
bliskrun.log(string.format("recipe %.1f s CPU", os.clock() - t_start))
report.verdict = require("run_report").verdict(requirements)
bliskrun.write_json("blade_repair_paths.json", report)
for _, section in ipairs(setup_sheet.sections(sheets)) do pictures[#pictures + 1] = section end

require("run_report").write{
  title = "Repair toolpaths on blade 1 of the built-in blisk", verdict = report.verdict,
  settings = {tip_span = tip_span, deposit_mm = deposit, layer_mm = layer, stock_mm = stock, scallop_mm = scallop,
              chord_tol_mm = chord_tol, ball_radius_mm = ball, edge_width_mm = edge_width,
              edge_span = edge_span[1] .. ".." .. edge_span[2]},
  sections = {{title = "Regions, planned and simulated", table = {columns = {"region", "pattern", "layers", "passes",
    "poses", "bridges", "links", "refused", "chord max (µm)", "material left max (µm)", "overcut (µm)"}, rows = rows}},
    table.unpack(pictures)},
  numbers = report,
  vtk = {path = "blade_repair_paths.pvd", blocks = vtk_blocks},
  files = {{"blade_repair_paths.json", "the figures above"}, {"blade_repair_tip_fanuc.nc", "Fanuc program, A/C trunnion"},
           {"blade_repair_tip_fanuc_setup.html", "its setup sheet (and .json)"}}}
