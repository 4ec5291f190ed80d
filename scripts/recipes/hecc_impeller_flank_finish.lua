-- Flank finishing of the NASA HECC impeller (15 main + 15 splitter blades) as
-- ruled blades (issue 12 items 2–6).
--   bliskrun scripts/recipes/hecc_impeller_flank_finish.lua --data ../shared/data --out out/
-- The HECC blades are not exactly ruled: each lofted face (bliskrun.read_hecc)
-- is fitted with a ruled surface (least-squares line per span column of its
-- section rows, bliskrun.fit_ruled) and the fit is reported (max / RMS, um)
-- against the thickness tolerance — a shop decides from it whether flank
-- milling is allowed; where the fit exceeds it the report says so and the
-- face is planned anyway on the ruled approximation. Each face is then flank
-- milled (bliskrun.flank_mill: axis through D1, D2 at the tapered cutter's
-- radius at each contact height, ball centre on the hub offset, chord
-- stations, poses and motions checked against the neighbouring main and
-- splitter blades, this face and the hub, tilt or refusal, leads).
-- Writes
--   hecc_<main|splitter>_<pressure|suction>.apt, ..._residual.png, hecc_ruled_<...>.stl
--   hecc_impeller_flank_finish.json   ruled fit, poses, refusals, residual per face
--   hecc_impeller_flank_finish.pvd, report.html  faces and cutter axes for ParaView; the run's page
-- Options: --help lists them (--set NAME=VALUE).

local opt = require("recipe_options"){
  set = {type = "string", default = "design", choices = {"design", "cold"}, help = "which HECC geometry set"},
  chord_tol = {type = "number", unit = "mm", default = 0.005, range = {1e-5, 0.1}, help = "chord deviation allowed between steps"},
  mesh_tol = {type = "number", unit = "mm", default = 0.05, range = {1e-4, 1}, help = "chord tolerance of the collision meshes"},
  residual_points = {type = "integer", default = 40, range = {2, 1000}, help = "points per ruling where the residual is measured"},
  tolerance = {type = "number", unit = "mm", default = 0.05, range = {1e-4, 1}, help = "blade thickness tolerance"},
  tip_radius = {type = "number", unit = "mm", default = 2, range = {0.5, 20}, help = "tip (ball) radius of the tapered ball end"},
  half_angle = {type = "number", unit = "deg", default = 2, range = {0, 15}, help = "half angle of the cutter's taper"},
  balance = {type = "boolean", default = true, help = "centre each axis's residual band on zero (false: the paper's axes)"},
  optimise = {type = "boolean", default = true, help = "fit each axis to the face (least squares, then minimax; false: as balanced)"},
  max_axis_correction = {type = "number", unit = "deg", default = 0.5, range = {0, 10}, help = "largest turn of a fitted axis from the balanced one"},
  flute_length = {type = "number", unit = "mm", default = 90, range = {5, 300}, help = "flute length of the cutter"},
}
local set = opt.set
local chord_tol = opt.chord_tol
local mesh_tol = opt.mesh_tol
local residual_points = opt.residual_points
local tolerance = opt.tolerance
local tip_radius, half_angle = opt.tip_radius, opt.half_angle
local balance = opt.balance

local parts = {}
for _, blade in ipairs{"main", "splitter"} do
  parts[blade] = bliskrun.read_hecc("nasa_hecc_impeller", {blade = blade, set = set})
end
local n = parts.main.blades
local pitch = 360 / n
local hub = parts.main.hub
local tool = bliskrun.tapered_ball_end_mill{tip_radius = tip_radius, half_angle = half_angle,
                                            flute_length = opt.flute_length,
                                            shank = {diameter = 12, length = 60},
                                            holder = {diameter = 40, length = 60}}

local function flank_mesh(blade, side, turn)
  local g = parts[blade][side]
  if turn ~= 0 then g = g:rotated(turn) end
  return g:surface():tessellate(mesh_tol)
end
local neighbours = {}
for _, nb in ipairs{{"main", pitch}, {"main", -pitch}, {"splitter", 0}, {"splitter", -pitch}, {"splitter", pitch}} do
  for _, side in ipairs{"pressure", "suction"} do
    neighbours[#neighbours + 1] = {name = string.format("%s %+g deg %s", nb[1], nb[2], side),
                                   mesh = flank_mesh(nb[1], side, nb[2]), margin = mesh_tol}
  end
end
local hub_mesh = hub:tessellate(mesh_tol)

local report = {part = "NASA HECC impeller (" .. set .. ")", blades = n, tool = tool:description(),
                settings = {chord_tol = chord_tol, mesh_tol = mesh_tol, residual_points = residual_points,
                            thickness_tolerance = tolerance}, faces = {}}
local face_rows, pictures, blocks = {}, {}, {{name = "hub", mesh = hub_mesh}}  -- report.html, ParaView
for _, blade in ipairs{"main", "splitter"} do
  local part = parts[blade]
  for _, side in ipairs{"pressure", "suction"} do
    local fit = bliskrun.fit_ruled(part[side], {first_row = part.hub_row, last_row = part.tip_row})
    local face = fit.surface
    local name = string.format("hecc_%s_%s", blade, side)
    face:tessellate(mesh_tol):write_stl("hecc_ruled_" .. blade .. "_" .. side .. ".stl")
    local surfaces = {{name = "this face", mesh = face:tessellate(mesh_tol), parts = {"shank", "holder"}, margin = mesh_tol},
                      {name = "hub", mesh = hub_mesh, parts = {"shank", "holder"}, margin = mesh_tol}}
    local other = side == "pressure" and "suction" or "pressure"
    surfaces[#surfaces + 1] = {name = "own " .. other, mesh = flank_mesh(blade, other, 0), parts = {"shank", "holder"}}
    for _, s in ipairs(neighbours) do
      if not (s.name:find("^" .. blade .. " %+0 deg")) then surfaces[#surfaces + 1] = s end
    end
    local world = bliskrun.collision_world{surfaces = surfaces}
    -- Planned on the ruled fit; the residual (and the balancing shift of
    -- each axis) against the lofted face, the blade as designed.
    local plan = bliskrun.flank_mill{face = face, design = part[side]:surface(), hub = hub, tool = tool,
                                     ball_radius = tip_radius, world = world, chord_tol = chord_tol,
                                     residual_points = residual_points, balance = balance,
                                     optimise = opt.optimise, max_axis_correction = opt.max_axis_correction}
    bliskrun.write_text(name .. ".apt", plan.apt)
    if plan.residual_map then
      plan.residual_map:write_png(name .. "_residual.png",
                                  {title = name .. ": flank-milling residual (µm), + undercut, - overcut"})
      pictures[#pictures + 1] = {title = "Residual to the lofted face, " .. name, image = name .. "_residual.png"}
    end
    local path = {}
    for i, p in ipairs(plan.poses) do path[i] = {kind = "feed", tip = p.tip, axis = p.axis, row = 1} end
    blocks[#blocks + 1] = {name = name .. " (lofted)", surface = part[side]:surface(), samples_u = 40, samples_v = 150}
    blocks[#blocks + 1] = {name = name .. " cutter axes", moves = path}
    face_rows[#face_rows + 1] = {name, fit.max * 1000, fit.rms * 1000, fit.max <= tolerance and "yes" or "NO",
                                 #plan.poses, #plan.refusals, 1e3 * (plan.residual.max or 0), 1e3 * (plan.residual.min or 0)}
    report.faces[name] = {ruled_fit = {max_um = fit.max * 1000, rms_um = fit.rms * 1000,
                                       worst_row = fit.worst_row, worst_col = fit.worst_col,
                                       within_tolerance = fit.max <= tolerance,
                                       note = fit.max <= tolerance and "flank milling allowed by the ruled fit"
                                         or "ruled fit exceeds the thickness tolerance: planned on the ruled approximation"},
                          stations = plan.stations, poses = #plan.poses, refused = #plan.refusals,
                          refusals = plan.refusals, tilted = plan.tilted,
                          lead_in = plan.lead_in.clear, lead_out = plan.lead_out.clear,
                          residual = plan.residual, residual_unbalanced = plan.residual_unbalanced,
                          residual_before = plan.residual_before, optimised = plan.optimised,
                          balanced = plan.balanced}
    print(string.format("%-22s ruled fit max %8.1f um RMS %7.1f um %s; %3d stations, %3d poses, %3d refused, %2d tilted; residual to the lofted face max %+.4f min %+.4f mm (paper's axes %+.4f / %+.4f)",
                        name, fit.max * 1000, fit.rms * 1000, fit.max <= tolerance and "(ok)" or "(EXCEEDS tolerance)",
                        plan.stations, #plan.poses, #plan.refusals, plan.tilted, plan.residual.max or 0, plan.residual.min or 0,
                        plan.residual_unbalanced.max or 0, plan.residual_unbalanced.min or 0))
  end
end
-- The verdict, per face: flank finishing holds the thickness tolerance
-- against the lofted face (it cannot where the blade is not ruled: the run
-- then FAILs after writing everything), every station's pose clear.
local requirements = {}
local face_names = {}
for name in pairs(report.faces) do face_names[#face_names + 1] = name end
table.sort(face_names)
for _, name in ipairs(face_names) do
  local f = report.faces[name]
  local r = f.residual
  requirements[#requirements + 1] = {name = name .. ": largest deviation from the lofted face", unit = "µm",
    measured = r.max and 1e3 * math.max(r.max, -r.min), at_most = 1e3 * tolerance,
    note = not f.ruled_fit.within_tolerance and string.format("ruled fit %.3g µm: not a ruled blade", f.ruled_fit.max_um)
           or nil}
  requirements[#requirements + 1] = {name = name .. ": refused stations", unit = "count", measured = f.refused,
                                     at_most = 0}
end
report.verdict = require("run_report").verdict(requirements)
bliskrun.write_json("hecc_impeller_flank_finish.json", report)
local sections = {{title = "Ruled fit and flank milling per face", text = string.format(
  "Ruled fit against the thickness tolerance %.3f mm; residual of the plan against the lofted face.", tolerance),
  table = {columns = {"face", "ruled fit max (µm)", "RMS (µm)", "within tolerance", "poses", "refused",
                      "residual max (µm)", "residual min (µm)"}, rows = face_rows}}}
for _, p in ipairs(pictures) do sections[#sections + 1] = p end
require("run_report").write{title = "NASA HECC impeller: flank finishing as ruled blades", verdict = report.verdict,
  settings = {set = set, chord_tol_mm = chord_tol, mesh_tol_mm = mesh_tol, thickness_tolerance_mm = tolerance,
              balance = balance, tool = tool:description()},
  sections = sections, vtk = {path = "hecc_impeller_flank_finish.pvd", blocks = blocks},
  files = {{"hecc_impeller_flank_finish.json", "the report"}, {"hecc_*.apt", "APT/CL per face"},
           {"hecc_*_residual.png", "the residual maps above"}, {"hecc_ruled_*.stl", "the ruled fits"}}}
