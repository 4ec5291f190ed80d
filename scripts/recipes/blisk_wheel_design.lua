-- Curvature analysis and drum-wheel design of the built-in 22-blade blisk,
-- as in the blisk paper (papers/blisk-drum-wheel-variable-chord §1–2):
--   1. each flank of blade 1 is rebuilt from a 100 x 500 point grid (eq. 4–8),
--   2. its curvature is analysed over the K < 0 region of the machined flank,
--      trimmed between hub and casing (eq. 9–11, 14, 16; Table 1, Fig. 11),
--      with the tool axis restricted to the C-axis range (Fig. 3–4), and over
--      the whole grid for comparison,
--   3. the drum wheel is sized by the traditional and the extended rule
--      (eq. 12, 13, 15; Table 2).
-- Outputs in the out folder: blisk_wheel_design.json (keys documented in
-- docs/lua_api.md, "The demo recipe"), gaussian_curvature_<side>.png,
-- blisk_wheel_design.pvd (the machined flanks, for ParaView), report.html.
--
--   bliskrun scripts/recipes/blisk_wheel_design.lua --out out/
--   (--help lists the options, --set NAME=VALUE)

local opt = require("recipe_options"){
  blades = {type = "integer", default = 22, range = {3, 200}, help = "blades of the built-in blisk"},
  c_range = {type = "number", unit = "deg", default = 30 * deg, range = {1, 90}, help = "C-axis range of the extended rule"},
  rows = {type = "integer", default = 100, range = {4, 2000}, help = "grid rows of each flank (span)"},
  cols = {type = "integer", default = 500, range = {4, 10000}, help = "grid columns of each flank (chord)"},
}
local blades = opt.blades
local c_range = opt.c_range
local rows, cols = opt.rows, opt.cols

local blisk = bliskrun.blisk{blade_count = blades, grid_rows = rows, grid_cols = cols}
bliskrun.log(tostring(blisk))

local d_min = blisk:narrowest_passage()
local height = blisk:casing_radius(0) - blisk:hub_radius(0)

-- Table 1 per flank over the machined flank: the flank rebuilt from its grid
-- (eq. 4-8), trimmed between hub and casing (eq. 16), so the grid's span
-- extension below the hub, which is never machined, does not set the wheel.
-- The blade's figures are the larger of its two flanks. For comparison, the
-- same over the whole grid.
local wheel_design = require("blade_wheel_design")
local whole, machined = {}, {}
for _, side in ipairs{"pressure", "suction"} do
  whole[side] = bliskrun.interpolate_grid(blisk:flank_grid(1, side))
  machined[side] = bliskrun.trim_flank{flank = whole[side], hub = blisk:hub(), casing = blisk:casing()}
end
local table1, flanks = wheel_design.analyse(machined,
  {samples_u = rows, samples_v = cols, c_range = c_range,
   picture = function(side) return string.format("gaussian_curvature_%s.png", side) end,
   title = function(side)
     return string.format("Gaussian curvature K, machined %s flank of blade 1 (1/mm^2)", side)
   end})
local table1_whole, flanks_whole = wheel_design.analyse(whole, {samples_u = rows, samples_v = cols, c_range = c_range})

local wheel = bliskrun.design_drum_wheel{k1_max = table1.k1_max, ke_max = table1.ke_max, d_min = d_min}

print(string.format("Built-in blisk: %d blades, blade height %.1f mm, narrowest passage d_min = %.2f mm",
                    blisk:blade_count(), height, d_min))
print("")
print("Table 1  curvature of the machined flanks (hub to casing, edges excluded) over K < 0 (1/mm);")
print("         where: span fraction from the hub curve, chord fraction from the leading edge")
print("                 machined flank                          whole grid (incl. below the hub)")
-- v runs LE -> TE on the pressure flank and TE -> LE on the suction flank.
local function chord(side, v) return side == "suction" and 1 - v or v end
for _, key in ipairs{"k1_max", "k2_max", "ke_max"} do
  local side, side_w = table1[key .. "_flank"], table1_whole[key .. "_flank"]
  local at, w = flanks[side][key], flanks_whole[side_w][key]
  print(string.format("  %s  %.4f  %-8s span %.2f chord %.2f    %.4f  %-8s span %.2f chord %.2f", key:sub(1, 2) .. " max",
                      table1[key], side, at.u, chord(side, at.v), table1_whole[key], side_w, w.u, chord(side_w, w.v)))
end
print(string.format("  (ke within C in [-%g, +%g] deg)", c_range, c_range))
print("")
print("Table 2  drum-wheel head design (mm)")
print("  wheel  rule         constraint          1/k1max  1/ke max   R_c    D_t")
print(string.format("  1      traditional  -                   %6.1f        -   %4g   %4.1f",
                    wheel.traditional.radius_limit, wheel.traditional.barrel_radius, wheel.traditional.max_diameter))
print(string.format("  2      extended     C in [-%g, %g] deg       -   %6.1f   %4g   %4.1f", c_range, c_range,
                    wheel.extended.radius_limit, wheel.extended.barrel_radius, wheel.extended.max_diameter))

local report = {
  part = {kind = "built-in blisk", blades = blisk:blade_count(), blade_height_mm = height,
          narrowest_passage_mm = d_min, grid = {rows = rows, cols = cols}},
  c_range_deg = c_range,
  region = "machined flank: between the hub and casing curves (eq. 16), edges excluded; u = span fraction from the hub, v = the flank's chord parameter (LE to TE on the pressure flank, TE to LE on the suction flank)",
  table1 = table1,
  flanks = flanks,
  table1_whole_grid = table1_whole,
  flanks_whole_grid = flanks_whole,
  table2 = {
    traditional = wheel.traditional,
    extended = wheel.extended,
  },
}
bliskrun.write_json("blisk_wheel_design.json", report)
wheel_design.write_report("Built-in blisk, blade 1 (machined flanks)", "blisk", report, machined, c_range)
