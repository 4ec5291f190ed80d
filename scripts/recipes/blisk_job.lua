-- The built-in blisk's blades finished as one job (issue 18): both flanks by
-- the drum wheel (blisk_drum_finish.lua), the trailing edges by the bottom of
-- a flat-end mill (blade_edges.lua), the roots and channel floor by a ball
-- (blisk_hub_finish.lua), the leading edges last with the part turned over;
-- linked through a clearance can, simulated (every unit, the seams between
-- operations, one map of blade 1) and posted for an A/C trunnion (Fanuc) and
-- a B/C head-table (Heidenhain TCPM), each program read back and replayed.
-- Blade 1 is planned, the others get its paths turned by the pitch.
--
--   bliskrun scripts/recipes/blisk_job.lua --out out [--set blades=2] [--set sides=both|pressure|suction]
--     [--set edges=false] [--set hub=false] [--set edge_span=0.1,0.9] [--set periodic=false] [--set hub_top=MM]
--     [--set samples_u=100 --set samples_v=500] [--set edge_samples_u=200 --set edge_samples_v=400]
--     [--set tool_life=MM] (sister wheels T15, T25, ...) [--set blade_map=lean|false] [--set seam_spacing=0.1]
local job, finish = require("job"), require("blisk_finish")
local function on(v) return v ~= false and v ~= "false" end

local blisk = bliskrun.blisk{}
local blades = job.first_blades(blisk, args.blades or 2)
local sides = ({both = {"pressure", "suction"}, pressure = {"pressure"}, suction = {"suction"}})[args.sides or "both"]
assert(sides, "--set sides= expects both, pressure or suction")
local a, b = tostring(args.edge_span or "0.1,0.9"):match("^%s*([%d.]+)%s*,%s*([%d.]+)%s*$")
assert(a, "--set edge_span= expects two numbers a,b with 0 <= a < b <= 1")
local span, periodic, edges, hub = {tonumber(a), tonumber(b)}, on(args.periodic), on(args.edges), on(args.hub)

local wheel = finish.design_wheels(blisk, {c_range = 30}).wheels.extended  -- the extended wheel of Table 2
local mill = bliskrun.flat_end_mill{radius = 3, corner_radius = 0.5, flute_length = 9,
                                    shank = {diameter = 6, length = 50}, holder = {diameter = 12, length = 40}}
-- 40 mm of flute to reach the hub from outside the casing.
local ball = bliskrun.tapered_ball_end_mill{tip_radius = 1.5, half_angle = 2.5, flute_length = 40,
                                            shank = {diameter = 8, length = 30}, holder = {diameter = 32, length = 40}}
-- Every tool axis within 118 deg of the table's in its setup (the A cradle
-- and the B head tilt to 120); turned over, the leading edges' also 35 deg
-- off it, clear of the cone where the A/C cradle changes sides of A = 0.
local operations = {job.drum_finish{tool = "wheel", blades = blades, sides = sides, residual = 0.014, chord_tol = 0.002,
                                    feed = 600, periodic = periodic}}
if edges then
  operations[#operations + 1] = job.edge_finish{tool = "mill", blades = blades, edges = {"trailing"}, span = span,
                                                feed = 400, periodic = periodic, reach = {axis = {0, 0, 1}, max = 118}}
end
if hub then  -- the root strip's top 0.5 mm over the edges' first rows (or --set hub_top=MM)
  operations[#operations + 1] = job.hub_finish{tool = "ball", blades = blades, scallop = 0.005, feed = 800,
                                               periodic = periodic, top = args.hub_top and tonumber(args.hub_top)}
end
if edges then
  operations[#operations + 1] = job.edge_finish{tool = "mill", blades = blades, edges = {"leading"}, span = span,
                                                feed = 400, periodic = periodic,
                                                reach = {axis = {0, 0, -1}, min = 35, max = 118}}
end
local j = job.new{
  name = "blisk blades" .. (edges and ", edges" or "") .. (hub and ", hub and roots" or ""),
  part = blisk, clearance_radius = 110, operations = operations,
  -- --set tool_life=MM: whole blades per wheel up to that cutting length, then the next sister wheel.
  tools = {wheel = {number = 5, length = 110, spindle_rpm = 8000, tool = wheel, life_mm = args.tool_life,
                    sisters = args.tool_life and {15, 25, 35, 45, 55, 65, 75} or nil},
           mill = {number = 7, length = 100, spindle_rpm = 12000, tool = mill},
           ball = {number = 9, length = 130, spindle_rpm = 15000, tool = ball}},
}
-- The leading edges face the table (the blisk's axis on C, inlet down): cut
-- in a second setup, turned over. A seam beyond its operations' promises
-- fails the run after the report.
j:run{name = "blisk_job",
  simulate = {samples_u = args.samples_u or 100, samples_v = args.samples_v or 500, seam_spacing = args.seam_spacing,
              edge_samples_u = args.edge_samples_u, edge_samples_v = args.edge_samples_v},
  blade_map = edges and hub and on(args.blade_map) and (args.blade_map == "lean" and "lean" or true),
  setups = {{name = "inlet down"}, {name = "turned over (inlet up)", flip = true, from = "leading edge"}},
  programs = {{machine = "dmg_like_ac_trunnion", post = "fanuc", file = "blisk_job_ac_fanuc.nc"},
              {machine = "monoblock_like_head_table", post = "heidenhain", file = "blisk_job_bc_heidenhain.h"}},
  settings = {blades = #blades, sides = args.sides or "both", edges = edges,
              edge_span = string.format("%g, %g", span[1], span[2]), periodic = periodic, tool_life_mm = args.tool_life or "none", samples_u = args.samples_u or 100,
              samples_v = args.samples_v or 500}}
