-- Hub and blade-root finishing of the built-in blisk (issue 18 item 2):
-- blade 1's root strip all around the blade (pressure flank -> TE round ->
-- suction flank -> LE round) and the channel floor between blades 1 and 2,
-- with a tapered ball end long enough to reach the hub from outside the
-- casing (bliskrun.hub_finish, core/planning/hub_finish.h).
--   root:    the fillet row (the ball on hub and blade at once: the design's
--            sharp corner is left as a fillet of the ball's radius), then
--            closed rows at constant height above the hub up to `top`
--            (4 mm: above the drum finish's ~2-3 mm and the edge finish's
--            ~3.4 mm strips, overlapping what they finished);
--   channel: rows across the channel at constant z, the ball on the hub,
--            from where it touches blade 1 to where it touches blade 2,
--            inlet to outlet, one zigzag pass joined along the fillet.
-- Rows by the ball's scallop closed form, steps by the chord of the ball
-- centre's path; every pose tilted clear of the neighbours and the hub
-- (whole tool), the ball and cone checked against the design surfaces,
-- steps and links proved; the root's last pose joined to the channel's
-- first by a proved link (through the channel, round the leading edge).
-- Then the simulation (core/sim) of every move on
-- blade 1's closed surface over the root strip and on the hub around the
-- channel, the neighbours' copies of the plan included (the blisk is
-- periodic: a job turns this plan onto every blade).
--
--   bliskrun scripts/recipes/blisk_hub_finish.lua --out out [--set NAME=VALUE]... (--help lists them)
-- Outputs: blisk_hub_finish.json, blisk_hub_finish.apt, report.html (opening with the verdict; the run
-- fails after writing it when a requirement fails).
local t_start = os.clock()
local opt = require("recipe_options"){
  ball = {type = "number", unit = "mm", default = 1.5, range = {0.5, 3}, help = "tip (ball) radius of the tapered ball"},
  taper = {type = "number", unit = "deg", default = 2.5, range = {0, 5}, help = "half angle of the taper"},
  top = {type = "number", unit = "mm", default = 4, range = {0.5, 20}, help = "height of the root strip above the hub"},
  scallop = {type = "number", unit = "mm", default = 0.005, range = {1e-4, 0.1}, help = "scallop height between rows"},
  chord_tol = {type = "number", unit = "mm", default = 0.001, range = {1e-4, 0.05},
               help = "chord deviation allowed between steps"},
  simulate = {type = "boolean", default = true, help = "simulate the plan on the blade and the hub"},
}
local ball, taper, top, scallop, chord_tol = opt.ball, opt.taper, opt.top, opt.scallop, opt.chord_tol
local simulate = opt.simulate

local blisk = bliskrun.blisk{}
local n = blisk:blade_count()
-- Each blade's flanks and edge rounds (check surfaces: the flanks end where
-- the rounds begin, and a round stands up to its radius in front of them).
local function faces(k) return require("blisk_world").blade_faces(blisk, k) end
-- 40 mm of flute: from the ball on the hub (r 60..66) past the casing
-- (r 90..96) with the 8 mm shank and the holder outside it.
local tool = bliskrun.tapered_ball_end_mill{tip_radius = ball, half_angle = taper, flute_length = 40,
                                            shank = {diameter = 8, length = 30}, holder = {diameter = 32, length = 40}}

local plan = bliskrun.hub_finish{blade = faces(1), next = faces(2), previous = faces(n), hub = blisk:hub(),
                                 tool = tool, top = top, scallop = scallop, chord_tol = chord_tol}
local r = plan:report()
print(string.format("hub finish, blade 1 and the channel to blade 2: %s", r.tool))
for _, name in ipairs{"root", "channel"} do
  local p = r[name]
  print(string.format("  %-7s %3d rows, %d passes, %5d poses (%d tilted), %d refused, %d steps, %d links, "
                      .. "%d refused links; step %.4f..%.4f mm, chord %.2f um; %.2f s",
                      name, p.rows, p.passes, p.poses, p.tilted, p.refusals, p.steps, p.links, p.refused_links,
                      p.step_min, p.step_max, p.max_deviation * 1000, p.seconds))
  for _, why in ipairs(p.refused) do print("    refused link: " .. why) end
end
print(string.format("  root: fillet of r %.2f mm left in the sharp corner (the fillet row touches the blade %.3f..%.3f mm "
                    .. "above the hub); rows %.3f..%.3f mm above the hub", r.fillet.radius, r.fillet.contact_min,
                    r.fillet.contact_max, r.heights[1], r.heights[2]))
print(string.format("  channel: z %.1f..%.1f mm, pitch %.3f deg; setup %.2f s", r.z[1], r.z[2], r.pitch, r.setup_seconds))
if r.join.clear then
  print(string.format("  root to channel: joined %s, %d legs, %.2f mm up the axes, smallest margin %.3f mm (%s), "
                      .. "deepest cut %.2f um; %.2f s", r.join.route, r.join.legs, r.join.offset, r.join.margin, r.join.margin_at,
                      math.abs(r.join.deepest_cut) * 1000, r.join.seconds))
else
  print("  root to channel: NOT joined, a STOP between them: " .. r.join.reason)
end
for i, f in ipairs(r.refusals) do
  if i > 5 then print(string.format("    ... %d refused contacts in all", #r.refusals)) break end
  print(string.format("    refused %s row %d: %s", f.operation, f.row, f.reason))
end

local report = {tool = r.tool, scallop = scallop, chord_tol = chord_tol, top = top, root = r.root,
                channel = r.channel, join = r.join, fillet = r.fillet, heights = r.heights, z = r.z,
                refusals = #r.refusals}
if simulate then
  local s = plan:simulate{}
  local function line(name, st)
    print(string.format("  simulated %-12s %6d samples, %d unreached, material left max %.2f um (mean %.2f), "
                        .. "overcut %.2f um", name, st.samples, st.unreached, st.left_max * 1000, st.left_mean * 1000,
                        -st.overcut * 1000))
  end
  line("root strip", s.strip)
  line("floor", s.floor)
  line("floor middle", s.floor_middle)
  print(string.format("  the fillet (below the fillet row): %d samples, material left up to %.3f mm (the ball's fillet); "
                      .. "simulation %.2f s", s.fillet.samples, s.fillet.left_max, s.seconds))
  report.simulation = {strip = s.strip, floor = s.floor, floor_middle = s.floor_middle,
                       root_overcut = s.root_overcut, floor_overcut = s.floor_overcut}
end
-- The verdict: no refusal, the chord within its tolerance, and simulated
-- no cut deeper than the planner's allowed 2 um (+ 0.2 um for the sweep's
-- sampling), the floor's middle (away from the fillet's corner) within the
-- scallop plus twice the chord (job/seams.lua's promise) and every sample
-- of it reached.
local refused = #r.refusals + r.root.refused_links + r.channel.refused_links
local requirements = {
  {name = "refused contacts and links", unit = "count", measured = refused, at_most = 0},
  {name = "chord error (largest step, root and channel)", unit = "µm",
   measured = 1e3 * math.max(r.root.max_deviation, r.channel.max_deviation), at_most = 1e3 * chord_tol * (1 + 1e-9)},
  {name = "root joined to the channel by a proved link", unit = "yes/no", measured = r.join.clear and "yes" or "no",
   pass = r.join.clear and true or false}}
if report.simulation then
  local s = report.simulation
  local allowed_um = 2.2
  requirements[#requirements + 1] = {name = "overcut, root strip (simulated)", unit = "µm",
                                     measured = math.max(0, -1e3 * s.root_overcut), at_most = allowed_um}
  requirements[#requirements + 1] = {name = "overcut, channel floor (simulated)", unit = "µm",
                                     measured = math.max(0, -1e3 * s.floor_overcut), at_most = allowed_um}
  requirements[#requirements + 1] = {name = "material left, channel floor's middle (scallop, simulated)", unit = "µm",
                                     measured = 1e3 * s.floor_middle.left_max, at_most = 1e3 * (scallop + 2 * chord_tol)}
  requirements[#requirements + 1] = {name = "samples never reached, channel floor's middle", unit = "count",
                                     measured = s.floor_middle.unreached, at_most = 0}
end
report.verdict = require("run_report").verdict(requirements)
bliskrun.write_json("blisk_hub_finish.json", report)
plan:write_apt("blisk_hub_finish.apt")
local rows = {}
for _, name in ipairs{"root", "channel"} do
  local p = r[name]
  rows[#rows + 1] = {name, p.rows, p.poses, p.refusals + p.refused_links, 1e3 * p.max_deviation}
end
require("run_report").write{title = "Hub and blade-root finish, blade 1 and its channel", verdict = report.verdict,
  settings = {tool = r.tool, scallop_mm = scallop, chord_tol_mm = chord_tol, top_mm = top, simulate = simulate},
  sections = {{title = "Root strip and channel floor", table = {columns = {"region", "rows", "poses", "refused",
                                                                          "chord error max (µm)"}, rows = rows}}},
  files = {{"blisk_hub_finish.json", "the report"}, {"blisk_hub_finish.apt", "APT/CL toolpath"}}}
print(string.format("wrote blisk_hub_finish.json and blisk_hub_finish.apt (%.1f s CPU)", os.clock() - t_start))
