-- Curvature analysis and drum-wheel design of the built-in 22-blade blisk,
-- as in the blisk paper (papers/blisk-drum-wheel-variable-chord §1–2):
--   1. each flank of blade 1 is rebuilt from a 100 x 500 point grid (eq. 4–8),
--   2. its curvature is analysed over the K < 0 region (eq. 9–11, 14; Table 1,
--      Fig. 11), with the tool axis restricted to the C-axis range (Fig. 3–4),
--   3. the drum wheel is sized by the traditional and the extended rule
--      (eq. 12, 13, 15; Table 2).
-- Outputs in the out folder: blisk_wheel_design.json (keys documented in
-- docs/lua_api.md, "The demo recipe"), gaussian_curvature_<side>.svg.
--
--   bliskrun scripts/recipes/blisk_wheel_design.lua --out out/
--   options: --set blades=22 --set c_range=30 --set rows=100 --set cols=500

local blades = args.blades or 22
local c_range = args.c_range or 30 * deg
local rows, cols = args.rows or 100, args.cols or 500

local blisk = bliskrun.blisk{blade_count = blades, grid_rows = rows, grid_cols = cols}
bliskrun.log(tostring(blisk))

local d_min = blisk:narrowest_passage()
local height = blisk:casing_radius(0) - blisk:hub_radius(0)

-- Table 1 per flank; the blade's figures are the larger of its two flanks.
local table1, flanks = require("blade_wheel_design").analyse(
  {pressure = bliskrun.interpolate_grid(blisk:flank_grid(1, "pressure")),
   suction = bliskrun.interpolate_grid(blisk:flank_grid(1, "suction"))},
  {samples_u = rows, samples_v = cols, c_range = c_range,
   picture = function(side) return string.format("gaussian_curvature_%s.svg", side) end,
   title = function(side) return string.format("Gaussian curvature K, %s flank of blade 1 (1/mm^2)", side) end})

local wheel = bliskrun.design_drum_wheel{k1_max = table1.k1_max, ke_max = table1.ke_max, d_min = d_min}

print(string.format("Built-in blisk: %d blades, blade height %.1f mm, narrowest passage d_min = %.2f mm",
                    blisk:blade_count(), height, d_min))
print("")
print("Table 1  curvature of the blade surfaces over K < 0 (1/mm)")
print(string.format("  k1 max  %.4f   (%s flank)", table1.k1_max, table1.k1_max_flank))
print(string.format("  k2 max  %.4f   (%s flank)", table1.k2_max, table1.k2_max_flank))
print(string.format("  ke max  %.4f   (%s flank)   within C in [-%g, +%g] deg", table1.ke_max, table1.ke_max_flank,
                    c_range, c_range))
print("")
print("Table 2  drum-wheel head design (mm)")
print("  wheel  rule         constraint          1/k1max  1/ke max   R_c    D_t")
print(string.format("  1      traditional  -                   %6.1f        -   %4g   %4.1f",
                    wheel.traditional.radius_limit, wheel.traditional.barrel_radius, wheel.traditional.max_diameter))
print(string.format("  2      extended     C in [-%g, %g] deg       -   %6.1f   %4g   %4.1f", c_range, c_range,
                    wheel.extended.radius_limit, wheel.extended.barrel_radius, wheel.extended.max_diameter))

bliskrun.write_json("blisk_wheel_design.json", {
  part = {kind = "built-in blisk", blades = blisk:blade_count(), blade_height_mm = height,
          narrowest_passage_mm = d_min, grid = {rows = rows, cols = cols}},
  c_range_deg = c_range,
  table1 = table1,
  flanks = flanks,
  table2 = {
    traditional = wheel.traditional,
    extended = wheel.extended,
  },
})
