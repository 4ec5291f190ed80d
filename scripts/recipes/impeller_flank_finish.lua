-- Five-axis flank finishing of the built-in impeller (impeller paper §4.3, §5;
-- issue 12): φ410 mm, 17 backswept blades + 17 splitters, ruled faces from
-- hub and shroud camber data, finished with a tapered ball-end mill whose side
-- lies along each ruling.
--   bliskrun scripts/recipes/impeller_flank_finish.lua --out out/
-- Per face (main and splitter, "plus" and "minus" side of the camber
-- surface): cutter axes through D1, D2 (the boundary curves offset by the
-- cutter radius at each contact's height), the ball centre on the hub offset,
-- stations by the chord tolerance on both boundary curves, every pose and
-- every motion between poses checked against the neighbouring blades and
-- splitters (all tool parts) and against this face and the hub (shank and
-- holder), tilted about the hub contact normal where it collides, refused
-- (never written) where nothing clears it; lead-in/out along the face normal.
-- The model is exactly symmetric under turns of 360°/17 about Z, so blade k's
-- plan is blade 1's turned by (k-1)·360°/17: the proofs carry over.
-- Writes
--   impeller_camber.dat                      the camber data (paper's format)
--   impeller_<main|splitter>_<plus|minus>.apt  APT/CL of blade 1's face (GOTO tip, axis)
--   impeller_<...>_residual.png              residual map (eq. 33–36), + undercut, − overcut
--   impeller_blade1_<...>.stl, impeller_hub.stl  the model
--   impeller_flank_finish.json               poses, refusals, tilts, residual per face and pose;
--                                            the material left in the root corner (where the
--                                            ruling meets the hub; the ball riding the hub
--                                            cannot reach it) apart from the residual, and
--                                            the clearance over poses and leads
--   impeller_flank_finish.pvd, report.html   faces, hub and cutter axes for ParaView; the run's page
-- Options: --help lists them (--set NAME=VALUE).

local opt = require("recipe_options"){
  chord_tol = {type = "number", unit = "mm", default = 0.005, range = {1e-5, 0.1}, help = "chord deviation allowed between steps"},
  mesh_tol = {type = "number", unit = "mm", default = 0.05, range = {1e-4, 1}, help = "chord tolerance of the collision meshes"},
  residual_points = {type = "integer", default = 40, range = {2, 1000}, help = "points per ruling where the residual is measured"},
  clearance = {type = "number", unit = "mm", default = 0.5, range = {0, 10}, help = "clearance of the whole tool from the neighbouring faces and the hub"},
  apt_blades = {type = "integer", default = 1, range = {1, 1000}, help = "blades written to APT, by rotation"},
  balance = {type = "boolean", default = true, help = "centre each axis's residual band on zero (false: the paper's axes)"},
  optimise = {type = "boolean", default = true, help = "fit each axis to the face (least squares, then minimax; false: as balanced)"},
  tip_radius = {type = "number", unit = "mm", default = 3, range = {0.5, 20}, help = "tip (ball) radius of the tapered ball end"},
  half_angle = {type = "number", unit = "deg", default = 2, range = {0, 15}, help = "half angle of the cutter's taper"},
}
local chord_tol = opt.chord_tol
local mesh_tol = opt.mesh_tol
local residual_points = opt.residual_points
local clearance = opt.clearance
local apt_blades = opt.apt_blades
local balance = opt.balance  -- centre each axis's residual band on zero (before/after reported)
local tip_radius, half_angle = opt.tip_radius, opt.half_angle

local imp = bliskrun.impeller{}
local n = imp:blade_count()
imp:write_camber("impeller_camber.dat")
local tool = bliskrun.tapered_ball_end_mill{tip_radius = tip_radius, half_angle = half_angle,
                                            flute_length = 90,
                                            shank = {diameter = 16, length = 60},
                                            holder = {diameter = 50, length = 60}}

-- Check surfaces of blade 1 and its neighbours, tessellated once
-- (scripts/lib/impeller_world.lua).
local iw = require("impeller_world")
local hub = imp:hub()
local meshes = iw.meshes(imp, mesh_tol)
hub:tessellate(10 * mesh_tol):write_stl("impeller_hub.stl")

local report = {part = "built-in impeller", blades = n, splitters = imp:has_splitter(),
                outer_diameter = 2 * imp:outer_radius(), tool = tool:description(),
                settings = {chord_tol = chord_tol, mesh_tol = mesh_tol, clearance = clearance,
                            residual_points = residual_points},
                faces = {}}
local totals = {poses = 0, refused = 0, tilted = 0, max_abs = 0}
local hub_mesh = meshes.hub()
local face_rows, pictures, blocks = {}, {}, {{name = "hub", mesh = hub_mesh}}  -- report.html, ParaView

for _, kind in ipairs{"main", "splitter"} do
  for _, side in ipairs{"plus", "minus"} do
    local face = imp:face(1, side, kind)
    meshes.face(kind, 1, side):write_stl(string.format("impeller_blade1_%s_%s.stl", kind, side))
    local world = iw.face_world(imp, meshes, kind, side)
    local plan = bliskrun.flank_mill{face = face, hub = hub, tool = tool, ball_radius = tip_radius,
                                     world = world, chord_tol = chord_tol, clearance = clearance,
                                     residual_points = residual_points, balance = balance,
                                     optimise = opt.optimise}
    local name = string.format("impeller_%s_%s", kind, side)
    -- APT of blade 1, and of further blades turned about Z.
    local apt = {plan.apt}
    for b = 2, apt_blades do
      local a = 2 * math.pi * (b - 1) / n
      local c, s = math.cos(a), math.sin(a)
      local lines = {string.format("$$ blade %d: blade 1 turned by %.6f deg about Z", b, math.deg(a))}
      for line in plan.apt:gmatch("[^\n]+") do
        local x, y, z, i, j, k = line:match("^GOTO/([^,]+),([^,]+),([^,]+),([^,]+),([^,]+),([^,]+)$")
        if x then
          x, y, i, j = tonumber(x), tonumber(y), tonumber(i), tonumber(j)
          lines[#lines + 1] = string.format("GOTO/%.6f,%.6f,%s,%.6f,%.6f,%s", c * x - s * y, s * x + c * y, z,
                                            c * i - s * j, s * i + c * j, k)
        elseif not line:match("^PARTNO") then
          lines[#lines + 1] = line
        end
      end
      apt[#apt + 1] = table.concat(lines, "\n") .. "\n"
    end
    bliskrun.write_text(name .. ".apt", table.concat(apt))
    if plan.residual_map then
      plan.residual_map:write_png(name .. "_residual.png",
                                  {title = name .. ": flank-milling residual (µm), + undercut, - overcut"})
      pictures[#pictures + 1] = {title = "Residual, " .. name, image = name .. "_residual.png",
                                 caption = "Along each cutter axis (up, hub at the bottom), poses across; µm."}
    end
    local path = {}
    for i, p in ipairs(plan.poses) do path[i] = {kind = "feed", tip = p.tip, axis = p.axis, row = 1} end
    blocks[#blocks + 1] = {name = name, mesh = meshes.face(kind, 1, side)}
    blocks[#blocks + 1] = {name = name .. " cutter axes", moves = path}
    face_rows[#face_rows + 1] = {name, plan.stations, #plan.poses, #plan.refusals, plan.tilted,
                                 1e3 * plan.residual.max, 1e3 * plan.residual.min, 1e3 * plan.residual_unbalanced.max,
                                 1e3 * plan.residual_unbalanced.min, plan.root_corner.max, plan.min_margin}
    local per_pose = {}
    for i, p in ipairs(plan.poses) do
      local r = plan.residual_per_pose[i]
      per_pose[i] = {v = p.v, tilt = p.tilt, max = r.max, min = r.min, mean = r.mean, root_corner = p.root_corner}
    end
    report.faces[name] = {stations = plan.stations, poses = #plan.poses, refused = #plan.refusals,
                          refusals = plan.refusals, tilted = plan.tilted, min_margin = plan.min_margin,
                          pose_min_margin = plan.pose_min_margin, lead_min_margin = plan.lead_min_margin,
                          lead_in = plan.lead_in.clear, lead_out = plan.lead_out.clear,
                          lead_reason = (plan.lead_in.reason or "") .. (plan.lead_out.reason or ""),
                          residual = plan.residual, residual_unbalanced = plan.residual_unbalanced,
                          residual_before = plan.residual_before, optimised = plan.optimised,
                          balanced = plan.balanced, per_pose = per_pose, root_corner = plan.root_corner}
    totals.poses = totals.poses + #plan.poses
    totals.refused = totals.refused + #plan.refusals
    totals.tilted = totals.tilted + plan.tilted
    totals.max_abs = math.max(totals.max_abs, plan.residual.max_abs)
    print(string.format("%-24s %3d stations, %3d poses, %2d refused, %2d tilted, %3d balanced; residual max %+.4f min %+.4f mean %+.4f std %.4f mm (unbalanced %+.4f / %+.4f); root corner up to %.3f mm; clearance %.3f mm (leads %.3f)",
                        name, plan.stations, #plan.poses, #plan.refusals, plan.tilted, plan.balanced, plan.residual.max,
                        plan.residual.min, plan.residual.mean, plan.residual.std, plan.residual_unbalanced.max,
                        plan.residual_unbalanced.min, plan.root_corner.max, plan.min_margin, plan.lead_min_margin or 0 / 0))
  end
end
report.totals = totals
-- The verdict: every station's pose clear (a refused station is a face
-- left unfinished there) and each face's lead-in and lead-out proved. The
-- residual against the face is reported, not judged: this recipe states
-- no thickness tolerance (hecc_impeller_flank_finish.lua does).
local requirements = {}
local face_names = {}
for name in pairs(report.faces) do face_names[#face_names + 1] = name end
table.sort(face_names)
for _, name in ipairs(face_names) do
  local f = report.faces[name]
  requirements[#requirements + 1] = {name = name .. ": refused stations", unit = "count", measured = f.refused,
                                     at_most = 0}
  requirements[#requirements + 1] = {name = name .. ": lead-in and lead-out proved clear", unit = "yes/no",
                                     measured = (f.lead_in and f.lead_out) and "yes" or "no",
                                     pass = (f.lead_in and f.lead_out) and true or false,
                                     note = f.lead_reason ~= "" and f.lead_reason or nil}
end
report.verdict = require("run_report").verdict(requirements)
bliskrun.write_json("impeller_flank_finish.json", report)
local sections = {{title = "Faces of blade 1", table = {columns = {"face", "stations", "poses", "refused", "tilted",
  "residual max (µm)", "residual min (µm)", "paper's axes max (µm)", "paper's axes min (µm)",
  "root corner left, max (mm)", "clearance incl. leads (mm)"}, rows = face_rows}}}
for _, p in ipairs(pictures) do sections[#sections + 1] = p end
require("run_report").write{title = "Flank finishing of the built-in impeller", verdict = report.verdict,
  settings = {chord_tol_mm = chord_tol, mesh_tol_mm = mesh_tol, clearance_mm = clearance, balance = balance,
              residual_points = residual_points, tool = tool:description()},
  sections = sections, vtk = {path = "impeller_flank_finish.pvd", blocks = blocks},
  files = {{"impeller_flank_finish.json", "the report"}, {"impeller_*.apt", "APT/CL per face"},
           {"impeller_*_residual.png", "the residual maps above"}, {"impeller_*.stl", "the model"},
           {"impeller_camber.dat", "the camber data (paper's format)"}}}
