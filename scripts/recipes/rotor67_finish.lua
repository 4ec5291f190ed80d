-- Drum-wheel finishing of one flank of one NASA Rotor 67 blade (blisk paper
-- §3-4 on a real 22-blade fan; issue 6 with issue 4's planner):
--   1. the blade is read and lofted from the 14 stream surfaces (feet -> mm),
--      its Tables 1-2 computed between hub and tip as in rotor67_wheel_design;
--   2. the drum wheel of the extended rule (D_t, R_c from Table 2; head
--      length D_t / 2) plans the flank: trimmed at the hub and casing, rows
--      by cut width at the residual height, variable chord height measured
--      within the tolerance, tilted until clear of the two neighbouring blades
--      and the hub within C +-c_range;
--   3. the undercut simulation measures what is left.
-- Outputs: rotor67_finish.json, rotor67_blade1_<side>.apt,
-- rotor67_undercut_<side>.png, rotor67_finish.pvd (flank with its undercut and the
-- toolpath, for ParaView), report.html, and the design's rotor67_finish_design_* files.
--
--   bliskrun scripts/recipes/rotor67_finish.lua --data ../shared/data --out out/
--   (--help lists the options, --set NAME=VALUE)

local opt = require("recipe_options"){
  side = {type = "string", default = "pressure", choices = {"pressure", "suction"}, help = "the flank to finish"},
  c_range = {type = "number", unit = "deg", default = 30, range = {1, 90}, help = "C-axis range of the extended wheel"},
  residual = {type = "number", unit = "mm", default = 0.014, range = {0.0005, 0.5},
              help = "residual (scallop) height between rows"},
  chord_tol = {type = "number", unit = "mm", default = 0.002, range = {1e-5, 0.1},
               help = "chord deviation allowed between steps along a row"},
  wheel = {type = "string", default = "extended", choices = {"extended", "traditional"}, help = "wheel of Table 2"},
  wheel_diameter = {type = "number", unit = "mm", range = {0.5, 100}, default_text = "Table 2's",
                    help = "the wheel's largest diameter D_t instead of the designed one"},
  shank_ratio = {type = "number", default = 0.4, range = {0.05, 1}, help = "shank diameter over the wheel's diameter"},
  link = {type = "string", choices = {"normal", "axis"}, default_text = "normal",
          help = "links leave along the flank normal or the wheel's axis"},
  link_overcut = {type = "number", unit = "mm", range = {0, 0.1}, default_text = "chord_tol",
                  help = "how far below the flank a link may dip"},
  samples_u = {type = "integer", default = 600, range = {2, 5000}, help = "simulation samples along the span"},
  samples_v = {type = "integer", default = 1000, range = {2, 20000}, help = "simulation samples along the chord"},
}
local wheel_design = require("blade_wheel_design")
local finish = require("blisk_finish")

local side = opt.side
local c_range = opt.c_range
local residual, chord_tol = opt.residual, opt.chord_tol
local file = "nasa_rotor67/rotor67geometry.dat"

-- A wheel of the recipe's own size must enter the channel: checked before
-- the design writes anything (Table 2's own wheel is checked below).
-- The passage is measured once and handed to the design.
local design_part = bliskrun.read_rotor67(file, {span_extension = 0})
local passage = wheel_design.narrowest_passage(design_part)
if opt.wheel_diameter then
  finish.check_wheel_fits(passage.distance, bliskrun.drum_wheel{max_diameter = opt.wheel_diameter, barrel_radius = 50,
                                                                head_length = opt.wheel_diameter / 2})
end

-- Tables 1-2 between hub and tip; the planning part extends past them (as
-- a CAD export does) so the trim finds the hub and casing on the flank.
local design = wheel_design.run(design_part,
                                {name = "NASA Rotor 67", prefix = "rotor67_finish_design", c_range = c_range,
                                 passage = passage})
local part = bliskrun.read_rotor67(file)
local rule = opt.wheel
local ext = design.table2[rule]
local d_t = opt.wheel_diameter or ext.max_diameter
local tool = bliskrun.drum_wheel{max_diameter = d_t, barrel_radius = ext.barrel_radius, head_length = d_t / 2,
                                 shank = {diameter = opt.shank_ratio * d_t, length = 120}}
bliskrun.log("wheel: " .. tool:description())
-- Table 2 sizes the wheel below d_min; checked all the same, before any
-- planning, as for the built-in blisk (a changed rule or shank must not
-- plan a wheel that cannot enter the channel).
finish.check_wheel_fits(passage.distance, tool)

-- Check surfaces: both flanks of the two neighbouring blades, the hub, and
-- the blade itself for the shank.
local pitch = 360 / part.blades
local surfaces = {}
for _, turn in ipairs{-pitch, pitch} do
  for _, s in ipairs{"pressure", "suction"} do
    surfaces[#surfaces + 1] = {name = string.format("blade at %+.2f deg %s", turn, s),
                               surface = part[s]:rotated(turn):surface(), chord_tol = 0.01}
  end
end
surfaces[#surfaces + 1] = {name = "hub", surface = part.hub, chord_tol = 0.01}
-- The blade itself, for the shank and holder (coarser mesh, its tolerance
-- added to the clearance against it).
for _, s in ipairs{"pressure", "suction"} do
  surfaces[#surfaces + 1] = {name = "blade 1 " .. s .. " (own)", surface = part[s]:surface(), chord_tol = 0.05,
                             margin = 0.05, parts = {"shank", "holder"}}
end
local world = bliskrun.collision_world{surfaces = surfaces}

local flank = part[side]:surface()
local settings = finish.settings(nil, tool, {residual = residual, chord_tol = chord_tol, link = opt.link,
                                             link_overcut = opt.link_overcut})
settings.hub, settings.casing = part.hub, part.casing
settings.flank, settings.world, settings.name = flank, world, "Rotor 67 blade 1 " .. side
settings.axis_limit = finish.c_axis_limit_at(flank, c_range)
local plan = bliskrun.drum_finish(settings)
local r = plan:report()
local apt = "rotor67_blade1_" .. side .. ".apt"
plan:write_apt(apt)
local sim = plan:simulate{samples_u = opt.samples_u, samples_v = opt.samples_v}
local picture = "rotor67_undercut_" .. side .. ".png"
sim.map:write_png(picture, {title = "NASA Rotor 67, blade 1 " .. side .. " flank: material left by the finishing moves (µm)"})
bliskrun.log(string.format("timings: trim %.2f s, rows %.2f s, tilt %.2f s, links %.2f s, simulation %.2f s",
                           r.seconds.trim, r.seconds.rows, r.seconds.tilt, r.seconds.links, sim.seconds))
r.seconds = nil

print(string.format("NASA Rotor 67 blade 1, %s flank, %s", side, tool:description()))
print(string.format("  rows %d (width %.2f-%.2f mm), poses %d, refused %d poses / %d links, max chord %.2f um",
                    r.row_count, r.width_min, r.width_max, r.poses, r.refusals, r.refused_links,
                    1e3 * r.max_deviation))
print(string.format("  first row %.2f mm above the hub curve (hub clearance rule)", r.hub_strip))
print(string.format("  undercut max %.2f / mean %.2f / median %.2f / std %.2f um, overcut %.2f um, untouched %d",
                    1e3 * sim.undercut_max, 1e3 * sim.undercut_mean, 1e3 * sim.undercut_median,
                    1e3 * sim.undercut_std, 1e3 * sim.overcut, sim.untouched))
for _, why in ipairs(r.refusal_reasons) do bliskrun.log("refused: " .. why) end

-- The chord tolerance bounds the contact's chord; where the axis turns
-- between two poses (the blade twists, the tilt loop leans it), a cutter
-- point at distance rho from the tip leaves that chord by up to
-- rho * dtheta^2 / 8 more. The planner halves the segments where that and
-- the chord together exceed the tolerance and proves the rest against the
-- finished flank, so the simulation is judged against the tolerance alone;
-- the term is still reported (here with rho the head's corner, an upper
-- bound).
local rho = math.sqrt((ext.max_diameter / 2) ^ 2 + (ext.max_diameter / 2) ^ 2)
local turn_dev = 0
local moves = plan:moves()
for i = 2, #moves do
  local a, b = moves[i - 1], moves[i]
  if a.kind == "feed" and b.kind == "feed" and a.row == b.row then
    local c = a.axis[1] * b.axis[1] + a.axis[2] * b.axis[2] + a.axis[3] * b.axis[3]
    local dtheta = math.acos(math.max(-1, math.min(1, c)))
    turn_dev = math.max(turn_dev, rho * dtheta * dtheta / 8)
  end
end
print(string.format("  axis turning between poses adds up to %.2f um to the chord tolerance", 1e3 * turn_dev))
print(string.format("  links leave along the flank %s, offset %.2f-%.2f mm; every move simulated%s", r.links.retract,
                    r.links.offset_min, r.links.offset_max,
                    sim.overcut_move and string.format(", deepest overcut by move %d (%s, row %d)", sim.overcut_move,
                                                       sim.overcut_motion, sim.overcut_row) or ""))
r.axis_turn_deviation_mm = turn_dev
r.apt = apt
r.simulation = {undercut_max_mm = sim.undercut_max, undercut_mean_mm = sim.undercut_mean,
                undercut_median_mm = sim.undercut_median, undercut_std_mm = sim.undercut_std,
                overcut_mm = sim.overcut, overcut_move = sim.overcut_move, overcut_motion = sim.overcut_motion,
                overcut_row = sim.overcut_row, untouched = sim.untouched, samples = sim.samples,
                first_machined_row = sim.first_machined_row, picture = picture}
r.verified = r.refusals == 0 and r.refused_links == 0 and sim.overcut >= -chord_tol - 1e-4
-- The verdict: no refusal, every chord within the tolerance, no cut deeper
-- than it (0.1 um for the sweep's sampling), material left within the
-- residual plus the chord tolerance, every sample reached.
local verdict = require("run_report").verdict{
  {name = "refused poses and links", unit = "count", measured = r.refusals + r.refused_links, at_most = 0},
  {name = "chord error (largest segment)", unit = "µm", measured = 1e3 * r.max_deviation,
   at_most = 1e3 * chord_tol * (1 + 1e-9)},
  {name = "overcut (simulated)", unit = "µm", measured = math.max(0, -1e3 * sim.overcut), at_most = 1e3 * chord_tol + 0.1},
  {name = "material left (scallop, simulated)", unit = "µm", measured = 1e3 * sim.undercut_max,
   at_most = 1e3 * (residual + chord_tol)},
  {name = "samples never reached", unit = "count", measured = sim.untouched, at_most = 0}}
bliskrun.write_json("rotor67_finish.json", {
  verdict = verdict,
  part = {kind = "NASA Rotor 67", blades = part.blades, fit = part.fit},
  wheel = {rule = "extended", description = tool:description(), table2 = ext, table1 = design.table1,
           narrowest_passage_mm = design.part.narrowest_passage_mm},
  settings = {residual_mm = residual, chord_tol_mm = chord_tol, c_range_deg = c_range},
  flank = r,
})
require("run_report").write{title = "NASA Rotor 67, blade 1 " .. side .. " flank: drum-wheel finish",
  subtitle = r.verified and "verified: no pose refused, no overcut beyond the chord tolerance" or "NOT verified",
  verdict = verdict,
  settings = {side = side, residual_mm = residual, chord_tol_mm = chord_tol, c_range_deg = c_range,
              wheel = tool:description()},
  sections = {{title = "Flank", table = {columns = {"rows", "poses", "refused", "max chord (µm)", "undercut max (µm)",
                "mean (µm)", "overcut (µm)"}, rows = {{r.row_count, r.poses, r.refusals + r.refused_links,
                1e3 * r.max_deviation, 1e3 * sim.undercut_max, 1e3 * sim.undercut_mean, 1e3 * sim.overcut}}}},
              {title = "Undercut", image = picture, caption = "Material left over the trimmed flank, mm."}},
  vtk = {path = "rotor67_finish.pvd", blocks = {{name = side .. " flank, undercut", surface = plan:trimmed(),
           map = sim.map, samples_u = 150, samples_v = 300}, {name = "toolpath", moves = moves}}},
  files = {{"rotor67_finish.json", "the report"}, {apt, "APT/CL"}, {picture, "the undercut map"},
           {"rotor67_finish_design_*", "Tables 1-2 of the blade (wheel design)"}}}
