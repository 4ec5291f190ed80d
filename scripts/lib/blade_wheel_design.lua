-- Tables 1 and 2 of the blisk paper (§2.2: curvature over K < 0 with the
-- C-axis range, the narrowest passage, the traditional and the extended
-- drum wheel) for a blade read from real data, shared by the Rotor 37 and
-- Rotor 67 recipes.
--
--   local wheel_design = require("blade_wheel_design")
--   wheel_design.run(part, {name = "NASA Rotor 37", prefix = "rotor37", c_range = 30
--                           [, passage = wheel_design.narrowest_passage(part)]})
--
-- part: a blade model table (bliskrun.read_rotor37 / read_rotor67 / ...),
-- read with span_extension = 0 so that the analysis covers the blade between
-- its hub and tip sections and the passage is not measured below the hub.
-- Prints the tables, writes <prefix>_gaussian_curvature_{pressure,suction}.png,
-- <prefix>_wheel_design.json (keys as the demo recipe's, plus the fit), the
-- flanks for ParaView (<prefix>_wheel_design.pvd) and report.html, and
-- returns the report table.

local M = {}

-- Table 1 of a blade from its two flanks (§2.2): curvature statistics of
-- each flank over K < 0 with k_e within ±c_range, a Gaussian-curvature
-- picture per flank, and the blade's figures as the larger of the two.
-- surfaces = {pressure = Surface, suction = Surface}; opts: c_range (deg,
-- 30), samples_u (100), samples_v (500), picture = function(side) -> file
-- name (nil: no pictures), title = function(side) -> picture title.
-- Returns table1 ({k1_max, k2_max, ke_max, <key>_flank}) and flanks (per
-- side: k1_max/k2_max/ke_max = {value, u, v, angle_deg},
-- negative_K_fraction, K_min, K_max, picture).
function M.analyse(surfaces, opts)
  opts = opts or {}
  local flanks, table1 = {}, {k1_max = 0, k2_max = 0, ke_max = 0}
  for _, side in ipairs{"pressure", "suction"} do
    local st = bliskrun.curvature_stats(surfaces[side], {samples_u = opts.samples_u or 100,
                                                         samples_v = opts.samples_v or 500,
                                                         c_range = opts.c_range or 30})
    local picture = opts.picture and opts.picture(side)
    if picture then st.map:write_png(picture, {title = opts.title(side)}) end
    local function where(e) return {value = e.value, u = e.u, v = e.v, angle_deg = e.angle} end
    flanks[side] = {k1_max = where(st.k1_max), k2_max = where(st.k2_max), ke_max = where(st.ke_max),
                    negative_K_fraction = st.negative_K_fraction, K_min = st.K_min, K_max = st.K_max,
                    picture = picture}
    for _, key in ipairs{"k1_max", "k2_max", "ke_max"} do
      if st[key].value > table1[key] then
        table1[key] = st[key].value
        table1[key .. "_flank"] = side
      end
    end
  end
  return table1, flanks
end

-- The narrowest passage (blisk paper eq. 13, d_min): suction flank of
-- blade 1 to the pressure flank of blade 2 (blade 1 turned one pitch in the
-- direction the suction side faces). Returns bliskrun.narrowest_passage's
-- table (distance in mm, and where).
function M.narrowest_passage(part, suction)
  local pitch = -part.rotation * 360 / part.blades
  local next_pressure = part.pressure:rotated(pitch):surface()
  return bliskrun.narrowest_passage(suction or part.suction:surface(), next_pressure)
end

function M.run(part, opts)
  local c_range = opts.c_range or 30
  local prefix, name = opts.prefix, opts.name
  local surfaces = {pressure = part.pressure:surface(), suction = part.suction:surface()}
  local table1, flanks = M.analyse(surfaces, {
    c_range = c_range,
    picture = function(side) return prefix .. "_gaussian_curvature_" .. side .. ".png" end,
    title = function(side) return name .. ", " .. side .. " flank: Gaussian curvature K (1/mm^2)" end,
  })
  for _, side in ipairs{"pressure", "suction"} do
    local rows, cols = part[side]:size()
    flanks[side].grid = {rows = rows, cols = cols}
  end

  local passage = opts.passage or M.narrowest_passage(part, surfaces.suction)
  local wheel = bliskrun.design_drum_wheel{k1_max = table1.k1_max, ke_max = table1.ke_max, d_min = passage.distance}

  print(string.format("%s: %d blades, %d sections, narrowest passage d_min = %.2f mm", name, part.blades,
                      part.sections, passage.distance))
  print(string.format("Loft fit of the given section points: max %.2f um, RMS %.2f um (%d points)",
                      part.fit.max_mm * 1000, part.fit.rms_mm * 1000, part.fit.points))
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

  local report = {
    part = {kind = name, blades = part.blades, sections = part.sections, narrowest_passage_mm = passage.distance,
            rotation = part.rotation, rotation_from = part.rotation_from},
    fit = {max_mm = part.fit.max_mm, rms_mm = part.fit.rms_mm, points = part.fit.points},
    c_range_deg = c_range, table1 = table1, flanks = flanks,
    table2 = {traditional = wheel.traditional, extended = wheel.extended},
  }
  -- A design or study run states no tolerance: its verdict says so (issue 37).
  report.verdict = require("run_report").verdict({})
  bliskrun.write_json(prefix .. "_wheel_design.json", report)
  M.write_report(name, prefix, report, surfaces, c_range)
  return report
end

-- report.html (Tables 1 and 2, the curvature pictures, every number) and the
-- flanks as a ParaView collection, for the demo and the real-blade recipes.
function M.write_report(name, prefix, report, surfaces, c_range)
  local t1, t2 = report.table1, report.table2
  local rows = {}
  for _, key in ipairs{"k1_max", "k2_max", "ke_max"} do rows[#rows + 1] = {key, t1[key], t1[key .. "_flank"]} end
  local sections = {
    {title = "Table 1: curvature over K < 0", text = string.format("k_e within C in [-%g, %g] deg.", c_range, c_range),
     table = {columns = {"figure", "value (1/mm)", "flank"}, rows = rows}},
    {title = "Table 2: drum-wheel head", table = {columns = {"rule", "radius limit (mm)", "R_c (mm)", "D_t (mm)"},
      rows = {{"traditional", t2.traditional.radius_limit, t2.traditional.barrel_radius, t2.traditional.max_diameter},
              {"extended", t2.extended.radius_limit, t2.extended.barrel_radius, t2.extended.max_diameter}}}},
  }
  local blocks = {}
  for _, side in ipairs{"pressure", "suction"} do
    local picture = report.flanks[side].picture
    if picture then
      sections[#sections + 1] = {title = "Gaussian curvature, " .. side .. " flank", image = picture,
                                 caption = "K over (u, v) of the flank, 1/mm^2 (Fig. 11)."}
    end
    blocks[#blocks + 1] = {name = side .. " flank", surface = surfaces[side], samples_u = 60, samples_v = 200}
  end
  require("run_report").write{title = name .. ": curvature and drum-wheel design",
    settings = {c_range_deg = c_range}, sections = sections, numbers = report,
    vtk = {path = prefix .. "_wheel_design.pvd", blocks = blocks},
    files = {{prefix .. "_wheel_design.json", "the report"},
             {prefix .. "_gaussian_curvature_*.png", "the curvature pictures above"}}}
end

return M
