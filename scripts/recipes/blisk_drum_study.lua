-- The blisk paper's planning study (§4, Tables 4-5, Fig. 12, 13, 15) on the
-- built-in blisk: wheel 1 (traditional rule) and wheel 2 (extended rule,
-- planned within the C-axis range) each plan the same flank with constant
-- chord height (eq. 17 as written, no measurement: group a / c) and with the
-- variable chord height (eq. 18-19, every segment measured: b / d) at the
-- same residual height; all four are simulated at 200 x 1000 samples.
-- Outputs: blisk_drum_study.json (Tables 4-5, per-row points and chord
-- errors of every group), fig12_points_per_row.svg, fig13_chord_error.svg,
-- fig15_undercut_<group>.png, blisk_drum_study.pvd (the flank painted with each
-- group's undercut, the four toolpaths), report.html.
--
--   bliskrun scripts/recipes/blisk_drum_study.lua --out out/
--   (--help lists the options, --set NAME=VALUE)

local opt = require("recipe_options"){
  side = {type = "string", default = "pressure", choices = {"pressure", "suction"}, help = "the flank studied"},
  blade = {type = "integer", default = 1, range = {1, 1000}, help = "the blade studied"},
  residual = {type = "number", unit = "mm", default = 0.014, range = {0.0005, 0.5},
              help = "residual (scallop) height between rows"},
  chord_tol = {type = "number", unit = "mm", default = 0.002, range = {1e-5, 0.1},
               help = "chord deviation allowed between steps along a row"},
  c_range = {type = "number", unit = "deg", default = 30, range = {1, 90}, help = "C-axis range of wheel 2"},
  row_u = {type = "number", default = 0.93, range = {0, 1}, help = "span fraction of the row of Fig. 13"},
  samples_u = {type = "integer", default = 200, range = {2, 5000}, help = "simulation samples along the span"},
  samples_v = {type = "integer", default = 1000, range = {2, 20000}, help = "simulation samples along the chord"},
  shank_clearance = {type = "number", unit = "mm", default = 0.1, range = {0, 5}, help = "clearance of the shank"},
}
local finish = require("blisk_finish")
local blisk_world = require("blisk_world")
local chart = require("svg_chart")

local side = opt.side
local blade = opt.blade
local residual, chord_tol = opt.residual, opt.chord_tol
local c_range = opt.c_range
local row_u = opt.row_u  -- the row of Fig. 13
local shank_clearance = opt.shank_clearance

local blisk = bliskrun.blisk{}
local design = finish.design_wheels(blisk, {c_range = c_range})
local world = blisk_world.around_blade(blisk, blade)

local groups = {
  {id = "a", wheel = 1, rule = "traditional", steps = "constant"},
  {id = "b", wheel = 1, rule = "traditional", steps = "variable"},
  {id = "c", wheel = 2, rule = "extended", steps = "constant"},
  {id = "d", wheel = 2, rule = "extended", steps = "variable"},
}

local results = {}
for _, g in ipairs(groups) do
  bliskrun.log(string.format("group %s: wheel %d (%s), %s chord height", g.id, g.wheel, g.rule, g.steps))
  local plan = finish.plan(blisk, blade, side, design.wheels[g.rule], world, {
    residual = residual, chord_tol = chord_tol, steps = g.steps, shank_clearance = shank_clearance,
    -- Eq. 17 as the paper applies it: the step from the local curvature,
    -- not measured. The variable method is always measured (ours).
    guarantee = g.steps == "variable",
    c_range = g.rule == "extended" and c_range or nil,
  })
  local r = plan:report()
  local sim = plan:simulate{samples_u = opt.samples_u, samples_v = opt.samples_v}
  local picture = "fig15_undercut_" .. g.id .. ".png"
  -- One colour scale for all four maps, so they compare.
  sim.map:write_png(picture, {title = string.format("Fig. 15 (%s): undercut, wheel %d, %s chord height (µm)", g.id,
                                                    g.wheel, g.steps), scale_um = 2e3 * residual})
  -- Rows over chord tolerance: eq. 17 underestimates where curvature rises.
  local over = 0
  for _, row in ipairs(r.rows) do if row.max_deviation > chord_tol * (1 + 1e-9) then over = over + 1 end end
  local closest, best = 1, math.huge
  for i, row in ipairs(r.rows) do
    if math.abs(row.u - row_u) < best then closest, best = i, math.abs(row.u - row_u) end
  end
  results[#results + 1] = {group = g, plan = plan, report = r, sim = sim, picture = picture,
                           rows_over_tolerance = over, fig13_row = plan:row(closest)}
end

print(string.format("Built-in blisk, blade %d %s flank: residual %.0f um, chord tolerance %.0f um", blade, side,
                    residual * 1e3, chord_tol * 1e3))
print("Table 4  simulation results")
print("  wheel  group  method     rows  poses  max chord um  rows > tol  max undercut um  overcut um")
for _, x in ipairs(results) do
  print(string.format("  %d      %s      %-9s  %4d  %5d  %12.2f  %10d  %15.2f  %10.2f", x.group.wheel, x.group.id,
                      x.group.steps, x.report.row_count, x.report.poses, 1e3 * x.report.max_deviation,
                      x.rows_over_tolerance, 1e3 * x.sim.undercut_max, 1e3 * x.sim.overcut))
end
print("Table 5  undercut analysis (µm)")
print("  wheel  group  max     mean    median  std")
for _, x in ipairs(results) do
  print(string.format("  %d      %s      %6.2f  %6.2f  %6.2f  %6.2f", x.group.wheel, x.group.id, 1e3 * x.sim.undercut_max,
                      1e3 * x.sim.undercut_mean, 1e3 * x.sim.undercut_median, 1e3 * x.sim.undercut_std))
end

-- Fig. 12: contact points per row, each group.
local series12 = {}
for _, x in ipairs(results) do
  local pts = {}
  for i, row in ipairs(x.report.rows) do pts[i] = {i, row.contacts} end
  series12[#series12 + 1] = {name = string.format("%s: wheel %d, %s", x.group.id, x.group.wheel, x.group.steps),
                             points = pts}
end
bliskrun.write_text("fig12_points_per_row.svg", chart.lines{
  title = "Fig. 12: contact points per row", x_label = "row (hub to tip)", y_label = "points", series = series12})

-- Fig. 13: measured chord error along the row nearest u' = row_u, wheel 1
-- and wheel 2, constant vs variable.
local series13 = {}
for _, x in ipairs(results) do
  local row, pts = x.fig13_row, {}
  for k, dev in ipairs(row.deviation) do pts[k] = {0.5 * (row.v[k] + row.v[k + 1]), 1e3 * dev} end
  series13[#series13 + 1] = {name = string.format("%s: u' %.3f", x.group.id, row.u), points = pts}
end
bliskrun.write_text("fig13_chord_error.svg", chart.lines{
  title = string.format("Fig. 13: chord error along the row at u' ~ %.2f", row_u), x_label = "v (chord)",
  y_label = "chord error (µm)", series = series13, limit = {y = 1e3 * chord_tol, name = "tolerance"}})

local json = {part = {kind = "built-in blisk", blade = blade, flank = side}, residual_mm = residual,
              chord_tol_mm = chord_tol, c_range_deg = c_range, shank_clearance_mm = shank_clearance, table1 = design.table1, table2 = design.table2,
              groups = {}}
for _, x in ipairs(results) do
  local rows = {}
  for i, row in ipairs(x.report.rows) do
    rows[i] = {u = row.u, width_mm = row.width, points = row.contacts, max_chord_error_mm = row.max_deviation}
  end
  json.groups[x.group.id] = {
    wheel = x.group.wheel, rule = x.group.rule, tool = x.report.tool, steps = x.group.steps,
    guarantee = x.report.guarantee, rows = x.report.row_count, poses = x.report.poses,
    refusals = x.report.refusals + x.report.refused_links, max_chord_error_mm = x.report.max_deviation,
    rows_over_tolerance = x.rows_over_tolerance,
    table5 = {undercut_max_mm = x.sim.undercut_max, undercut_mean_mm = x.sim.undercut_mean,
              undercut_median_mm = x.sim.undercut_median, undercut_std_mm = x.sim.undercut_std,
              overcut_mm = x.sim.overcut, untouched = x.sim.untouched},
    per_row = rows, fig13_row = {u = x.fig13_row.u, v = x.fig13_row.v, chord_error_mm = x.fig13_row.deviation},
    picture = x.picture,
  }
end
-- A design or study run states no tolerance: its verdict says so (issue 37).
json.verdict = require("run_report").verdict({})
bliskrun.write_json("blisk_drum_study.json", json)

-- The run's page and the ParaView collection.
local table4, sections, blocks = {}, {}, {}
for _, x in ipairs(results) do
  table4[#table4 + 1] = {x.group.id, x.group.wheel, x.group.steps, x.report.row_count, x.report.poses,
                         1e3 * x.report.max_deviation, x.rows_over_tolerance, 1e3 * x.sim.undercut_max,
                         1e3 * x.sim.undercut_mean, 1e3 * x.sim.undercut_median, 1e3 * x.sim.undercut_std,
                         1e3 * x.sim.overcut}
  sections[#sections + 1] = {title = "Fig. 15 (" .. x.group.id .. ")", image = x.picture,
                             caption = "Undercut over the trimmed flank, mm (one colour scale for all four)."}
  blocks[#blocks + 1] = {name = "flank, undercut " .. x.group.id, surface = x.plan:trimmed(), map = x.sim.map,
                         samples_u = 100, samples_v = 250}
  blocks[#blocks + 1] = {name = "toolpath " .. x.group.id, moves = x.plan:moves()}
end
table.insert(sections, 1, {title = "Tables 4 and 5", table = {columns = {"group", "wheel", "chord height", "rows",
  "poses", "max chord (µm)", "rows > tol", "undercut max (µm)", "mean (µm)", "median (µm)", "std (µm)",
  "overcut (µm)"}, rows = table4}})
table.insert(sections, 2, {title = "Fig. 12: contact points per row", svg = bliskrun.read_text("fig12_points_per_row.svg")})
table.insert(sections, 3, {title = "Fig. 13: chord error along a row", svg = bliskrun.read_text("fig13_chord_error.svg")})
require("run_report").write{title = string.format("Drum-finish planning study, blade %d %s flank", blade, side),
  settings = {residual_mm = residual, chord_tol_mm = chord_tol, c_range_deg = c_range, row_u = row_u,
              shank_clearance_mm = shank_clearance},
  sections = sections, vtk = {path = "blisk_drum_study.pvd", blocks = blocks},
  files = {{"blisk_drum_study.json", "Tables 4-5, per-row points and chord errors"},
           {"fig12_points_per_row.svg, fig13_chord_error.svg", "the line charts above"},
           {"fig15_undercut_*.png", "the undercut maps above"}}}
