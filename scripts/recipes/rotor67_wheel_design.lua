-- NASA Rotor 67 (22-blade transonic fan, the blade count of the blisk paper):
-- the analogue of the paper's Tables 1 and 2 on a real blade.
--   bliskrun scripts/recipes/rotor67_wheel_design.lua --data ../shared/data --out out/
-- Reads nasa_rotor67/rotor67geometry.dat from a --data folder (feet,
-- converted to mm by the reader), rebuilds both flanks from the 14 stream
-- surfaces (edge circles left out), analyses their curvature over K < 0 with
-- the C-axis range, measures the narrowest passage to the next blade and
-- sizes the drum wheel by the traditional and the extended rule.
-- Options: --set c_range=30 --set cols=200

local c_range = args.c_range or 30 * deg
local rotor = bliskrun.read_rotor67("nasa_rotor67/rotor67geometry.dat", {cols = args.cols or 200})
bliskrun.log(string.format("Rotor 67: %d blades, %d stream surfaces", rotor.blades, rotor.sections))

local flanks, table1 = {}, {k1_max = 0, k2_max = 0, ke_max = 0}
local surfaces = {}
for _, side in ipairs{"pressure", "suction"} do
  local surface = rotor[side]:surface()
  surfaces[side] = surface
  local rows, cols = rotor[side]:size()
  local st = bliskrun.curvature_stats(surface, {samples_u = 100, samples_v = 500, c_range = c_range})
  local picture = "rotor67_gaussian_curvature_" .. side .. ".svg"
  st.map:write_svg(picture, {title = "Rotor 67, " .. side .. " flank: Gaussian curvature K (1/mm^2)"})
  local function where(e) return {value = e.value, u = e.u, v = e.v, angle_deg = e.angle} end
  flanks[side] = {k1_max = where(st.k1_max), k2_max = where(st.k2_max), ke_max = where(st.ke_max),
                  negative_K_fraction = st.negative_K_fraction, grid = {rows = rows, cols = cols},
                  picture = picture}
  for _, key in ipairs{"k1_max", "k2_max", "ke_max"} do
    if st[key].value > table1[key] then
      table1[key] = st[key].value
      table1[key .. "_flank"] = side
    end
  end
end

-- The passage: suction flank of blade 1 to the pressure flank of blade 2.
local next_pressure = rotor.pressure:rotated(360 / rotor.blades):surface()
local passage = bliskrun.narrowest_passage(surfaces.suction, next_pressure)
local wheel = bliskrun.design_drum_wheel{k1_max = table1.k1_max, ke_max = table1.ke_max, d_min = passage.distance}

print(string.format("NASA Rotor 67: %d blades, narrowest passage d_min = %.2f mm", rotor.blades, passage.distance))
print("Table 1  curvature over K < 0 (1/mm)")
for _, key in ipairs{"k1_max", "k2_max", "ke_max"} do
  print(string.format("  %-6s  %.4f   (%s flank)", key, table1[key], table1[key .. "_flank"]))
end
print(string.format("  k_e within C in [-%g, +%g] deg", c_range, c_range))
print("Table 2  drum-wheel head design (mm)")
print(string.format("  traditional: R_c < %.1f -> %g, D_t %.1f", wheel.traditional.radius_limit,
                    wheel.traditional.barrel_radius, wheel.traditional.max_diameter))
print(string.format("  extended:    R_c < %.1f -> %g, D_t %.1f", wheel.extended.radius_limit,
                    wheel.extended.barrel_radius, wheel.extended.max_diameter))

bliskrun.write_json("rotor67_wheel_design.json", {
  part = {kind = "NASA Rotor 67", blades = rotor.blades, sections = rotor.sections,
          narrowest_passage_mm = passage.distance},
  c_range_deg = c_range, table1 = table1, flanks = flanks,
  table2 = {traditional = wheel.traditional, extended = wheel.extended},
})
