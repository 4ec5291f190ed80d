-- Blisk flank finishing with a drum wheel, end to end, on the built-in
-- 22-blade blisk (blisk paper §3-4, SPEC §6.1 and §8):
--   1. the wheel is designed as in blisk_wheel_design.lua (Tables 1-3);
--   2. each flank of the blade is trimmed between hub and casing (§3.1,
--      Fig. 5), its rows spaced by the wheel's cut width at the allowed
--      residual height (Fig. 6), stepped along each row by the variable chord
--      height (eq. 18-19) with every segment's measured chord deviation within
--      the tolerance (§3.2);
--   3. the axis comes from the contact frame and is tilted until the wheel,
--      shank and holder clear the neighbouring blades and the hub, within the
--      C-axis range (§3.3-3.4); the motion between poses and the links between
--      rows are proved clear too; nothing unproven is emitted;
--   4. an independent simulation samples the design flank 200 x 1000 and
--      measures the material left (undercut) and any gouge (overcut) after
--      the swept tool (§4, Table 5, Fig. 15) - every move of the program,
--      rows and links, in the motion the checks assume; the worst overcut is
--      reported with the move that cut it.
-- Links leave the flank along its normal (a drum wheel's axis lies along the
-- span, nearly tangent to the flank: retracting along it drags the barrel
-- into a concave flank) and are proved against the finished flank itself.
-- Outputs: blisk_drum_finish.json (report and toolpath), blade<k>_<side>.apt (APT/CL: tool tip and
-- axis per move), undercut_blade<k>_<side>.png, blisk_drum_finish.pvd (+ .vtp: flanks
-- coloured by undercut and toolpaths, for ParaView), report.html, opening with the verdict (PASS or
-- FAIL per requirement: refusals, chord error, overcut, material left, unreached samples). The
-- run fails (exit 1, after writing the report) when a requirement fails.
--
--   bliskrun scripts/recipes/blisk_drum_finish.lua --out out/
--   bliskrun scripts/recipes/blisk_drum_finish.lua --data DIR --set part=cad --set cad=blade.step \
--     --set blade_count=22: your own blisk from its blade's STEP or IGES file (one closed airfoil
--     face or the two flank faces; the file's two curves or cad_hub/cad_casing as hub and casing;
--     scripts/lib/cad_part.lua, bliskrun.cad_blisk);
--   bliskrun scripts/recipes/blisk_drum_finish.lua --help lists the options (--set NAME=VALUE);
--   link=normal|axis and link_overcut: how links leave the flank, and how far below it they may
--   dip (docs/lua_api.md "Links"); all_blades=true also plans and simulates both flanks of every
--   blade, on --threads.

local cad_part = require("cad_part")
local opt = require("recipe_options")(cad_part.with_blisk_options{
  blade = {type = "integer", default = 1, range = {1, 1000}, help = "the blade to finish"},
  wheel = {type = "string", default = "extended", choices = {"extended", "traditional"},
           help = "wheel of Table 2: by 1/k_e within the C range (extended) or by 1/k1 (traditional)"},
  wheel_diameter = {type = "number", unit = "mm", range = {0.5, 100}, default_text = "Table 2's",
                    help = "the wheel's largest diameter D_t instead of the designed one"},
  residual = {type = "number", unit = "mm", default = 0.014, range = {0.0005, 0.5},
              help = "residual (scallop) height between rows"},
  map_scale_um = {type = "number", unit = "um", range = {0.1, 10000}, default_text = "2 x (residual + chord_tol)",
                  help = "colour scale of both flanks' maps, +- um (one scale, so they compare)"},
  chord_tol = {type = "number", unit = "mm", default = 0.002, range = {1e-5, 0.1},
               help = "chord deviation allowed between steps along a row"},
  steps = {type = "string", default = "variable", choices = {"variable", "constant"}, help = "step rule along a row"},
  c_range = {type = "number", unit = "deg", default = 30, range = {1, 90}, help = "C-axis range of the extended wheel"},
  shank_clearance = {type = "number", unit = "mm", default = 0.1, range = {0, 5}, help = "clearance of the shank"},
  link = {type = "string", choices = {"normal", "axis"}, default_text = "normal",
          help = "links leave along the flank normal or the wheel's axis"},
  link_overcut = {type = "number", unit = "mm", range = {0, 0.1}, default_text = "chord_tol",
                  help = "how far below the flank a link may dip"},
  samples_u = {type = "integer", default = 200, range = {2, 5000}, help = "simulation samples along the span"},
  samples_v = {type = "integer", default = 1000, range = {2, 20000}, help = "simulation samples along the chord"},
  all_blades = {type = "boolean", default = false, help = "also plan and simulate both flanks of every blade"},
  all_samples_u = {type = "integer", default = 100, range = {2, 5000}, help = "all_blades: samples along the span"},
  all_samples_v = {type = "integer", default = 500, range = {2, 20000}, help = "all_blades: samples along the chord"},
})
cad_part.check_unused(opt)
local finish = require("blisk_finish")
local blisk_world = require("blisk_world")
local run_report = require("run_report")

local blade = opt.blade
local wheel_rule = opt.wheel
local c_range = opt.c_range
local settings = {residual = opt.residual, chord_tol = opt.chord_tol,
                  steps = opt.steps, shank_clearance = opt.shank_clearance,
                  link = opt.link, link_overcut = opt.link_overcut}

local blisk = opt.part == "cad" and cad_part.blisk(opt) or bliskrun.blisk{}
assert(math.type(blade) == "integer" and blade >= 1 and blade <= blisk:blade_count(),
       string.format("--set blade= expects 1..%d", blisk:blade_count()))
local design = finish.design_wheels(blisk, {c_range = c_range})
local tool = design.wheels[wheel_rule]
if opt.wheel_diameter then
  tool = bliskrun.drum_wheel{max_diameter = opt.wheel_diameter, barrel_radius = design.table2[wheel_rule].barrel_radius,
                             head_length = 4, shank = {diameter = 6, length = 96}}
end
finish.check_wheel_fits(blisk, tool)  -- before planning: a wheel must enter the passage
-- The extended wheel is only valid within the C range it was designed for.
if wheel_rule == "extended" then settings.c_range = c_range end
bliskrun.log(string.format("wheel %s: %s", wheel_rule, tool:description()))

local world = blisk_world.around_blade(blisk, blade)
local report = {
  part = {kind = opt.part == "cad" and "blisk from CAD" or "built-in blisk", file = opt.cad,
          blades = blisk:blade_count(), narrowest_passage_mm = design.d_min},
  wheel = {rule = wheel_rule, description = tool:description(), table2 = design.table2[wheel_rule]},
  settings = {residual_mm = settings.residual, chord_tol_mm = settings.chord_tol, steps = settings.steps,
              c_range_deg = settings.c_range, shank_clearance_mm = settings.shank_clearance},
  flanks = {},
}
local ok = true
local vtk_blocks = {}  -- for ParaView: each flank with its undercut, each toolpath
local flank_rows, pictures = {}, {}  -- for report.html
print(string.format("Drum-wheel finish of blade %d, %s", blade, tool:description()))
print("  flank     rows  width mm      poses  refused  max chord um  undercut max/mean/median/std um  overcut um")
for _, side in ipairs{"pressure", "suction"} do
  local plan = finish.plan(blisk, blade, side, tool, world, settings)
  local r = plan:report()
  local apt = string.format("blade%d_%s.apt", blade, side)
  plan:write_apt(apt)
  local sim = plan:simulate{samples_u = opt.samples_u, samples_v = opt.samples_v}
  local picture = string.format("undercut_blade%d_%s.png", blade, side)
  sim.map:write_png(picture, {title = string.format("Material left on blade %d %s flank by its drum-wheel moves (µm)",
                                                    blade, side),
                              scale_um = opt.map_scale_um or 2e3 * (settings.residual + settings.chord_tol)})
  table.insert(vtk_blocks, {name = side .. " flank, undercut", surface = plan:trimmed(), map = sim.map,
                            samples_u = 100, samples_v = 250})
  table.insert(vtk_blocks, {name = side .. " toolpath", moves = plan:moves()})
  local verified = r.refusals == 0 and r.refused_links == 0 and sim.overcut >= -settings.chord_tol - 1e-4
  if sim.overcut_move then
    bliskrun.log(string.format("%s: deepest overcut %.2f um by move %d (%s, row %d)", side, 1e3 * sim.overcut,
                               sim.overcut_move, sim.overcut_motion, sim.overcut_row))
  end
  ok = ok and verified
  print(string.format("  %-8s  %4d  %4.2f-%4.2f  %6d  %7d  %12.2f  %6.2f / %5.2f / %5.2f / %5.2f  %10.2f",
                      side, r.row_count, r.width_min, r.width_max, r.poses, r.refusals + r.refused_links,
                      1e3 * r.max_deviation, 1e3 * sim.undercut_max, 1e3 * sim.undercut_mean,
                      1e3 * sim.undercut_median, 1e3 * sim.undercut_std, 1e3 * sim.overcut))
  flank_rows[#flank_rows + 1] = {side, r.row_count, r.poses, r.refusals + r.refused_links, 1e3 * r.max_deviation,
                                 1e3 * sim.undercut_max, 1e3 * sim.undercut_mean, 1e3 * sim.overcut}
  pictures[#pictures + 1] = {title = "Undercut, " .. side .. " flank", image = picture,
                             caption = "Material left over (u', v) of the trimmed flank, µm: red above the design, "
                                       .. "blue below, grey never reached."}
  -- Timings go to the log, not the report: same inputs, same bytes.
  bliskrun.log(string.format("%s: trim %.2f s, rows %.2f s, tilt %.2f s, links %.2f s, simulation %.2f s", side,
                             r.seconds.trim, r.seconds.rows, r.seconds.tilt, r.seconds.links, sim.seconds))
  r.seconds = nil
  r.apt = apt
  r.toolpath = {}
  for i, m in ipairs(plan:moves()) do
    r.toolpath[i] = {kind = m.kind, motion = m.motion, row = m.row, tip = {m.tip[1], m.tip[2], m.tip[3]},
                     axis = {m.axis[1], m.axis[2], m.axis[3]}}
  end
  r.simulation = {undercut_max_mm = sim.undercut_max, undercut_mean_mm = sim.undercut_mean,
                  undercut_median_mm = sim.undercut_median, undercut_std_mm = sim.undercut_std,
                  overcut_mm = sim.overcut, overcut_move = sim.overcut_move, overcut_motion = sim.overcut_motion,
                  overcut_row = sim.overcut_row, untouched = sim.untouched, samples = sim.samples,
                  first_machined_row = sim.first_machined_row, tool_positions = sim.tool_positions, u0 = sim.u0,
                  picture = picture}
  r.verified = verified
  report.flanks[side] = r
end
print(string.format("  links leave along the flank %s, offset %.2f-%.2f mm (pressure), %.2f-%.2f mm (suction); "
                    .. "every move simulated", report.flanks.pressure.links.retract, report.flanks.pressure.links.offset_min,
                    report.flanks.pressure.links.offset_max, report.flanks.suction.links.offset_min,
                    report.flanks.suction.links.offset_max))
print(string.format("  first row raised above the hub by the wheel's hub clearance: strip %.2f mm (pressure), "
                    .. "%.2f mm (suction), left for the hub-fillet operation",
                    report.flanks.pressure.hub_strip, report.flanks.suction.hub_strip))

if opt.all_blades then
  local worlds = blisk_world.all_blades(blisk)
  local common = finish.settings(blisk, tool, settings)
  common.jobs = {}
  for k = 1, blisk:blade_count() do
    for _, side in ipairs{"pressure", "suction"} do
      local job = {flank = finish.flank(blisk, k, side), world = worlds[k], name = string.format("blade %d %s", k, side)}
      -- The extended wheel needs each blade's own C range.
      if settings.c_range then job.axis_limit = finish.c_axis_limit(blisk, k, c_range) end
      common.jobs[#common.jobs + 1] = job
    end
  end
  local plans = bliskrun.drum_finish_all(common)
  local all = {flanks = {}, poses = 0, refusals = 0, overcut_mm = 0}
  -- Every flank's whole program simulated too (coarser by default: 44 flanks).
  local su, sv = opt.all_samples_u, opt.all_samples_v
  for i, plan in ipairs(plans) do
    local r = plan:report()
    local apt = string.format("blade%02d_%s.apt", (i + 1) // 2, i % 2 == 1 and "pressure" or "suction")
    plan:write_apt(apt)
    local sim = plan:simulate{samples_u = su, samples_v = sv}
    all.flanks[i] = {name = r.name, rows = r.row_count, poses = r.poses, refusals = r.refusals + r.refused_links,
                     max_deviation_mm = r.max_deviation, apt = apt, undercut_max_mm = sim.undercut_max,
                     overcut_mm = sim.overcut, overcut_motion = sim.overcut_motion}
    all.poses = all.poses + r.poses
    all.refusals = all.refusals + r.refusals + r.refused_links
    all.overcut_mm = math.min(all.overcut_mm, sim.overcut)
  end
  ok = ok and all.refusals == 0 and all.overcut_mm >= -settings.chord_tol - 1e-4
  report.all_blades = all
  print(string.format("  all %d blades: %d flanks, %d poses, %d refused, deepest overcut %.2f um (every move, %d x %d "
                      .. "samples per flank)", blisk:blade_count(), #plans, all.poses, all.refusals,
                      1e3 * all.overcut_mm, su, sv))
end

report.verified = ok
-- The verdict: per flank no refusal, every chord within the tolerance, no
-- cut deeper than it (0.1 um for the sweep's sampling), material left
-- within the residual plus the chord tolerance, every sample reached.
local requirements = {}
for _, side in ipairs{"pressure", "suction"} do
  local f = report.flanks[side]
  local sim = f.simulation
  for _, q in ipairs{
    {name = side .. " flank: refused poses and links", unit = "count", measured = f.refusals + f.refused_links, at_most = 0},
    {name = side .. " flank: chord error (largest segment)", unit = "µm", measured = 1e3 * f.max_deviation,
     at_most = 1e3 * settings.chord_tol * (1 + 1e-9)},
    {name = side .. " flank: overcut (simulated)", unit = "µm", measured = math.max(0, -1e3 * sim.overcut_mm),
     at_most = 1e3 * settings.chord_tol + 0.1},
    {name = side .. " flank: material left (scallop, simulated)", unit = "µm", measured = 1e3 * sim.undercut_max_mm,
     at_most = 1e3 * (settings.residual + settings.chord_tol)},
    {name = side .. " flank: samples never reached", unit = "count", measured = sim.untouched, at_most = 0}} do
    requirements[#requirements + 1] = q
  end
end
if report.all_blades then
  requirements[#requirements + 1] = {name = "all blades: refused poses and links", unit = "count",
                                     measured = report.all_blades.refusals, at_most = 0}
  requirements[#requirements + 1] = {name = "all blades: overcut (simulated)", unit = "µm",
                                     measured = math.max(0, -1e3 * report.all_blades.overcut_mm),
                                     at_most = 1e3 * settings.chord_tol + 0.1}
end
report.verdict = run_report.verdict(requirements)
bliskrun.write_json("blisk_drum_finish.json", report)
bliskrun.write_vtk{path = "blisk_drum_finish.pvd", blocks = vtk_blocks}
local settings_shown = {blade = blade, wheel = wheel_rule .. ": " .. tool:description()}
for k, v in pairs(report.settings) do settings_shown[k] = v end
run_report.write{title = string.format("Drum-wheel finish of blade %d", blade), verdict = report.verdict,
  subtitle = ok and "verified: no pose refused, no overcut beyond the chord tolerance" or "NOT verified",
  settings = settings_shown,
  sections = {{title = "Flanks", table = {columns = {"flank", "rows", "poses", "refused", "max chord error (µm)",
                                                     "undercut max (µm)", "undercut mean (µm)", "overcut (µm)"},
                                          rows = flank_rows}},
              pictures[1], pictures[2]},
  files = {{"blisk_drum_finish.json", "report and toolpath"}, {"blade*_*.apt", "APT/CL per flank"},
           {"undercut_blade*_*.png", "the undercut maps above"},
           {"blisk_drum_finish.pvd", "ParaView: flanks coloured by undercut, toolpaths"}}}
