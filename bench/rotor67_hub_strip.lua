-- Check (issue 38, the strip above the hub): does the hub finish's root
-- strip on NASA Rotor 67 blade 1 reach over the strip the edge finish leaves
-- above the hub (blade_edges.lua --data: LE 6.71 mm, TE 8.61 mm)? As
-- job.hub_finish would plan it: the root strip only, its top the highest
-- edge first row + 0.5 mm (top_over_edges; --set top=MM), the job's
-- tapered ball (r 1.5, 2.5 deg) with a shank long
-- enough for Rotor 67's 100-150 mm blades (150 mm), then plan:simulate's
-- strip (the blade from the fillet row's contact up to top). The faces are
-- the edge finish's (edge_margin 0, cosine spacing: they carry the data's
-- own rounds and close_blade joins them at their edges; the default loft's
-- faces stop 3 % of the chord short of the edges, where the half circle
-- that closes them meets them 40 degrees off, so the ball was refused at
-- the edges in every row). Figures go to
-- bench/RESULTS.md.
--
--   bliskrun bench/rotor67_hub_strip.lua --data ../shared/data --out /tmp/x
--     [--set top=MM] [--set simulate=false]
local part = bliskrun.read_rotor67("nasa_rotor67/rotor67geometry.dat", {edge_margin = 0, spacing = "cosine"})
local pitch = 360 / part.blades
local function faces(turn)
  return {pressure = part.pressure:rotated(turn):surface(), suction = part.suction:rotated(turn):surface()}
end
local top = tonumber(args.top) or 9.11
local tool = bliskrun.tapered_ball_end_mill{tip_radius = 1.5, half_angle = 2.5, flute_length = 40,
                                            shank = {diameter = 8, length = 150}, holder = {diameter = 32, length = 40}}
local t0 = os.clock()
local plan = bliskrun.hub_finish{threads = 2, blade = faces(0), next = faces(pitch), previous = faces(-pitch),
                                 hub = part.hub, tool = tool, top = top, channel = false}
local r = plan:report()
local p = r.root
print(string.format("root strip to %.2f mm: %d rows, %d passes, %d poses (%d tilted), %d refused contacts, "
                    .. "%d refused links, %d rows entered from the row before; %.1f s CPU", top, p.rows, p.passes,
                    p.poses, p.tilted, p.refusals, p.refused_links, p.entered_rows, os.clock() - t0))
print(string.format("closed blades' edge kink %.2f deg", r.edge_kink))
print(string.format("fillet radius %.2f mm, the fillet row touches the blade %.2f..%.2f mm up", r.fillet.radius,
                    r.fillet.contact_min, r.fillet.contact_max))
for i, why in ipairs(p.refused) do if i <= 3 then print("  refused link: " .. why) end end
for i, f in ipairs(r.refusals) do if i <= 3 then print("  refused contact: " .. (f.reason or "?")) end end
if args.simulate == false then return end
local s = plan:simulate{}
print(string.format("strip: %d samples, %d never reached, left max %.1f um, mean %.1f um, overcut %.1f um",
                    s.strip.samples, s.strip.unreached, 1e3 * s.strip.left_max, 1e3 * s.strip.left_mean,
                    1e3 * s.strip.overcut))
