-- NASA HECC centrifugal impeller (15 main + 15 splitter blades): rebuilds
-- both blades from their section loops and exports them.
--   bliskrun scripts/recipes/hecc_impeller_model.lua --data ../shared/data --out out/
-- Reads nasa_hecc_impeller from a --data folder (inches, converted to mm by
-- the reader), lofts the pressure and suction flanks of the main and the
-- splitter blade (edge circles found and left out, flanks extended 3 % of the
-- span past hub and shroud as a CAD face would be), and writes
--   hecc_<blade>_{pressure,suction}.stl   the flanks, within chord_tol
--   hecc_hub.stl                          the hub, a surface of revolution
--   hecc_<blade>_section_fit.svg          fit of the given points per section
--   hecc_impeller_model.json              fit numbers, edge circles, files
-- Options: --set set=design|cold  --set cols=200  --set chord_tol=0.01

local set = args.set or "design"
local chord_tol = args.chord_tol or 0.01
local cols = args.cols or 200

-- A bar chart of the fit per section: max (dark) and RMS (light), in um.
local function fit_svg(path, title, sections)
  local w, h, left, bottom, top = 720, 360, 70, 50, 40
  local worst = 0
  for _, s in ipairs(sections) do worst = math.max(worst, s.max_mm * 1000) end
  local scale = worst > 0 and worst * 1.1 or 1
  local n = #sections
  local slot = (w - left - 20) / n
  local function y(v) return h - bottom - (h - bottom - top) * v / scale end
  local out = {string.format('<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">', w, h),
               string.format('<rect width="%d" height="%d" fill="white"/>', w, h),
               string.format('<text x="%d" y="22" font-size="14">%s</text>', left, title)}
  for k = 0, 4 do
    local v = scale * k / 4
    out[#out + 1] = string.format('<line x1="%d" x2="%d" y1="%.1f" y2="%.1f" stroke="#ddd"/>', left, w - 20, y(v), y(v))
    out[#out + 1] = string.format('<text x="%d" y="%.1f" text-anchor="end">%.2f</text>', left - 6, y(v) + 4, v)
  end
  for i, s in ipairs(sections) do
    local x = left + (i - 1) * slot
    out[#out + 1] = string.format('<rect x="%.1f" y="%.1f" width="%.1f" height="%.1f" fill="#1f4e79"><title>section %d: max %.3f um</title></rect>',
                                  x + slot * 0.15, y(s.max_mm * 1000), slot * 0.35, h - bottom - y(s.max_mm * 1000), i, s.max_mm * 1000)
    out[#out + 1] = string.format('<rect x="%.1f" y="%.1f" width="%.1f" height="%.1f" fill="#9dc3e6"><title>section %d: RMS %.3f um</title></rect>',
                                  x + slot * 0.5, y(s.rms_mm * 1000), slot * 0.35, h - bottom - y(s.rms_mm * 1000), i, s.rms_mm * 1000)
    out[#out + 1] = string.format('<text x="%.1f" y="%d" text-anchor="middle">%d</text>', x + slot / 2, h - bottom + 16, i)
  end
  out[#out + 1] = string.format('<line x1="%d" x2="%d" y1="%d" y2="%d" stroke="black"/>', left, w - 20, h - bottom, h - bottom)
  out[#out + 1] = string.format('<text x="%d" y="%d" text-anchor="middle">section (hub to shroud)</text>', (left + w) // 2, h - 12)
  out[#out + 1] = string.format('<text x="16" y="%d" transform="rotate(-90 16 %d)" text-anchor="middle">distance to the flank, um (max dark, RMS light)</text>', h // 2, h // 2)
  out[#out + 1] = "</svg>\n"
  bliskrun.write_text(path, table.concat(out, "\n"))
end

local report = {set = set, chord_tol_mm = chord_tol, blades = {}}
local hub_written = false
for _, blade in ipairs{"main", "splitter"} do
  local part = bliskrun.read_hecc("nasa_hecc_impeller", {blade = blade, set = set, cols = cols})
  local files = {}
  for _, side in ipairs{"pressure", "suction"} do
    local mesh = part[side]:surface():tessellate(chord_tol)
    local file = string.format("hecc_%s_%s.stl", blade, side)
    mesh:write_stl(file)
    local _, triangles = mesh:size()
    files[side] = {file = file, triangles = triangles}
  end
  if not hub_written then
    local mesh = part.hub:tessellate(10 * chord_tol)
    mesh:write_stl("hecc_hub.stl")
    local _, triangles = mesh:size()
    report.hub = {file = "hecc_hub.stl", triangles = triangles, chord_tol_mm = 10 * chord_tol}
    hub_written = true
  end
  local figure = string.format("hecc_%s_section_fit.svg", blade)
  fit_svg(figure, string.format("HECC %s blade (%s): given section points to the lofted flanks", blade, set),
          part.fit.sections)
  local edges = {}
  for k, e in ipairs(part.edges) do
    edges[k] = {le_radius_mm = e.leading.radius, te_radius_mm = e.trailing.radius}
  end
  local rows, grid_cols = part.pressure:size()
  report.blades[blade] = {
    blades = part.blades, sections = part.sections, grid = {rows = rows, cols = grid_cols},
    rotation = part.rotation, rotation_from = part.rotation_from, camber_agrees = part.camber_agrees,
    fit = {max_mm = part.fit.max_mm, rms_mm = part.fit.rms_mm, points = part.fit.points,
           pressure = part.fit.pressure, suction = part.fit.suction, sections = part.fit.sections},
    edges = edges, flanks = files, figure = figure,
  }
  print(string.format("HECC %-8s (%s): %d sections, fit max %.2f um, RMS %.3f um over %d points; LE r %.2f..%.2f mm; %d + %d triangles",
                      blade, set, part.sections, part.fit.max_mm * 1000, part.fit.rms_mm * 1000, part.fit.points,
                      part.edges[#part.edges].leading.radius, part.edges[1].leading.radius,
                      files.pressure.triangles, files.suction.triangles))
end
bliskrun.write_json("hecc_impeller_model.json", report)
