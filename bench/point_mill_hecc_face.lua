-- Bench (issue 40): one HECC main-blade face point-milled and proved, as
-- job.point_mill plans it in hecc_impeller_job.lua (the lofted face, its own
-- world: the blades either side and the hub, the finisher of that recipe),
-- then simulated against the lofted face. Times go to bench/RESULTS.md.
--
--   /usr/bin/time -v build/bliskrun bench/point_mill_hecc_face.lua --data ../shared/data --out OUT
--        [--set side=plus|minus] [--set kind=main|splitter] [--set scallop=0.02]
local opt = require("recipe_options"){
  side = {type = "string", default = "plus", choices = {"plus", "minus"}, help = "face side"},
  kind = {type = "string", default = "main", choices = {"main", "splitter"}, help = "blade kind"},
  scallop = {type = "number", unit = "mm", default = 0.02, range = {1e-4, 0.5}, help = "scallop height"},
  chord_tol = {type = "number", unit = "mm", default = 0.005, range = {1e-4, 0.5}, help = "chord tolerance"},
}
local iw = require("impeller_world")
local part = require("hecc_impeller_part").load{set = "design"}
local cutter = bliskrun.tapered_ball_end_mill{tip_radius = 2, half_angle = 2, flute_length = 90,
                                              shank = {diameter = 12, length = 60},
                                              holder = {diameter = 40, length = 60}}
local t0 = os.clock()
local meshes = iw.meshes(part, 0.05)
local world = iw.face_world(part, meshes, opt.kind, opt.side, {hub_cutter = true})
local other = opt.side == "plus" and "minus" or "plus"
local face, back = iw.design_face(part, 1, opt.side, opt.kind), iw.design_face(part, 1, other, opt.kind)
local e, q = face:eval(0.5, 0.5), back:point(0.5, 0.5)
local flip = e.normal[1] * (e.point[1] - q[1]) + e.normal[2] * (e.point[2] - q[2]) + e.normal[3] * (e.point[3] - q[3]) < 0
local t1 = os.clock()
local plan = bliskrun.point_mill{face = {surface = face, flip = flip, name = opt.kind .. " " .. opt.side},
                                 tool = cutter, world = world, scallop = opt.scallop, chord_tol = opt.chord_tol,
                                 clearance = 0.5, holder_clearance = 0.5}
local r = plan:report()
local t2 = os.clock()
local sim = plan:simulate{samples = {60, 240}}
local t3 = os.clock()
print(string.format("HECC %s %s face: %d rows, %d poses (%d tilted), complete %s; scallop %.1f um measured "
                    .. "(%.1f asked, closed form %.1f); chord %.2f um; axis turn %.2f deg/mm; %d steps, %d links",
                    opt.kind, opt.side, r.rows, r.poses, r.tilted, tostring(r.complete), 1e3 * r.scallop_measured,
                    1e3 * r.scallop, 1e3 * r.scallop_closed_form, 1e3 * r.max_deviation, r.max_turn, r.steps, r.links))
print(string.format("  simulated on the lofted face: left %.1f um max, overcut %.1f um", 1e3 * sim.left_max,
                    -1e3 * sim.overcut))
print(string.format("  CPU: world %.1f s, plan %.1f s (its own wall clock %.1f s), simulation %.1f s", t1 - t0,
                    t2 - t1, r.seconds, t3 - t2))
if not r.complete then
  for i = 1, math.min(5, #r.refusals) do print("  refused: " .. r.refusals[i].reason) end
  for i = 1, math.min(5, #r.refused) do print("  refused: " .. r.refused[i]) end
end
