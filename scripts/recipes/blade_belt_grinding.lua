-- Robotic belt grinding of a blade's flanks: contact-wheel paths for the three
-- stations of the belt paper (papers/robot-belt-grinding-trajectory §2, SPEC
-- §6.3) — coarse and fine ceramic belts and a polishing belt — by the paper's
-- flow (first path on the edge, trimmed by half the wheel width, steps by the
-- chord error with eq. 6, step-over from the scallop height on convex and
-- concave regions, next path at the smallest step-over), with the chord error
-- and the scallop measured by sampled distances, not taken from the formulas.
--
-- The blade: blade 1 of the built-in blisk, ground as a separate blade
-- between its hub and tip curves; with --data ../shared/data, blade 1 of
-- NASA Rotor 67 (--set part=rotor67).
-- Outputs: blade_belt_grinding.json (per station and flank: paths, points,
-- measured chord and scallop maxima, the guarantee's corrections, and every
-- path's points, normals and wheel axes), blade_belt_grinding.pvd (flanks and
-- paths for ParaView), report.html.
--
--   bliskrun scripts/recipes/blade_belt_grinding.lua --out out/
--   options: --set part=builtin|rotor67  --set sides=both|pressure|suction
--
-- Not yet here (issue 15): the robot holding the blade (six-axis inverse
-- kinematics is in core/machine/robot.h), scan registration and the RAPID /
-- KRL programs.

local part_name = args.part or "builtin"
assert(part_name == "builtin" or part_name == "rotor67", "--set part= expects 'builtin' or 'rotor67'")
local sides = args.sides or "both"
assert(sides == "both" or sides == "pressure" or sides == "suction",
       "--set sides= expects 'both', 'pressure' or 'suction'")

-- The stations (the paper: ceramic belts of 120 and 240 grit, a nylon
-- polishing belt; contact-wheel speeds 5.6 and 18.3 m/s). Chord error and
-- scallop tighten from station to station; the wheels are the shop's.
local stations = {
  {name = "coarse", belt = "ceramic, 120 grit", speed = 5.6, wheel = {radius = 25, width = 12},
   chord_tol = 0.02, scallop = 0.01},
  {name = "fine", belt = "ceramic, 240 grit", speed = 18.3, wheel = {radius = 20, width = 10},
   chord_tol = 0.01, scallop = 0.005},
  {name = "polish", belt = "nylon", speed = 18.3, wheel = {radius = 15, width = 8},
   chord_tol = 0.005, scallop = 0.002},
}

-- Each flank between the hub and tip curves; pu x pv points out of the
-- material on both flanks of both parts (the wheel's side).
local faces = {}
local function add_faces(flank_of, hub, casing)
  for _, side in ipairs{"pressure", "suction"} do
    if sides == "both" or sides == side then
      faces[#faces + 1] = {side = side,
                           surface = bliskrun.trim_flank{flank = flank_of(side), hub = hub, casing = casing}}
    end
  end
end
if part_name == "builtin" then
  local blisk = bliskrun.blisk{grid_rows = 100, grid_cols = 500}
  add_faces(function(side) return bliskrun.interpolate_grid(blisk:flank_grid(1, side)) end,
            blisk:hub(), blisk:casing())
else
  local part = bliskrun.read_rotor67("nasa_rotor67/rotor67geometry.dat")
  add_faces(function(side) return part[side]:surface() end, part.hub, part.casing)
end

local report = {part = part_name, stations = {}}
local station_rows, blocks = {}, {}  -- report.html, ParaView
for _, f in ipairs(faces) do
  blocks[#blocks + 1] = {name = f.side .. " flank", surface = f.surface, samples_u = 40, samples_v = 150}
end
print(string.format("%-7s %-9s %6s %7s %12s %12s %9s %9s", "station", "flank", "paths", "points",
                    "chord max", "scallop max", "steps cut", "overs cut"))
for _, st in ipairs(stations) do
  st.contact_wheel = bliskrun.contact_wheel(st.wheel)
  local entry = {name = st.name, belt = st.belt, speed = st.speed, wheel = st.wheel,
                 chord_tol = st.chord_tol, scallop = st.scallop, flanks = {}}
  for _, f in ipairs(faces) do
    local plan = bliskrun.belt_paths{face = f.surface, wheel = st.contact_wheel, chord_tol = st.chord_tol,
                                     scallop = st.scallop}
    -- The measurement, not the formula, is what the recipe stands on.
    if plan.chord_max > st.chord_tol * (1 + 1e-9) or plan.scallop_max > st.scallop * (1 + 1e-9) then
      error(string.format("%s %s: measured chord %.4f / scallop %.4f mm beyond %.4f / %.4f", st.name, f.side,
                          plan.chord_max, plan.scallop_max, st.chord_tol, st.scallop))
    end
    print(string.format("%-7s %-9s %6d %7d %9.2f µm %9.2f µm %9d %9d", st.name, f.side, #plan.paths, plan.points,
                        plan.chord_max * 1000, plan.scallop_max * 1000, plan.step_halvings, plan.step_over_shrinks))
    station_rows[#station_rows + 1] = {st.name, f.side, #plan.paths, plan.points, 1e3 * plan.chord_max,
                                       1e3 * plan.scallop_max, plan.step_halvings, plan.step_over_shrinks}
    -- The paths as polylines for ParaView: the contact points, the wheel axis as the "tool axis".
    local moves = {}
    for j, p in ipairs(plan.paths) do
      for i, pt in ipairs(p.points) do
        moves[#moves + 1] = {kind = i == 1 and "rapid" or "feed", tip = pt, axis = p.tangents[i], row = j}
      end
    end
    blocks[#blocks + 1] = {name = st.name .. " " .. f.side .. " paths", moves = moves}
    entry.flanks[f.side] = {paths = #plan.paths, points = plan.points, chord_max = plan.chord_max,
                            scallop_max = plan.scallop_max, step_halvings = plan.step_halvings,
                            step_over_shrinks = plan.step_over_shrinks, path = {}}
    for j, p in ipairs(plan.paths) do
      local xyz = function(list)
        local out = {}
        for i, v in ipairs(list) do out[i] = {v.x, v.y, v.z} end
        return out
      end
      entry.flanks[f.side].path[j] = {across = p.across, length = p.length, chord_max = p.chord_max,
                                      scallop_max = p.scallop_max, points = xyz(p.points),
                                      normals = xyz(p.normals), wheel_axes = xyz(p.tangents)}
    end
  end
  report.stations[#report.stations + 1] = entry
end
bliskrun.write_json("blade_belt_grinding.json", report)
require("run_report").write{title = "Belt-grinding paths, " .. (part_name == "builtin" and "built-in blade 1" or "NASA Rotor 67 blade 1"),
  subtitle = "chord error and scallop measured by sampled distances, every station within its tolerances",
  settings = {part = part_name, sides = sides},
  sections = {{title = "Stations", text = "Steps / step-overs cut: shortened where the measurement exceeded the tolerance.",
               table = {columns = {"station", "flank", "paths", "points", "chord max (um)", "scallop max (um)",
                                   "steps cut", "step-overs cut"}, rows = station_rows}}},
  vtk = {path = "blade_belt_grinding.pvd", blocks = blocks},
  files = {{"blade_belt_grinding.json", "stations, paths, points, normals and wheel axes"}}}
