-- The built-in blisk from the blank to the finished blades as one job
-- (issues 18, 41): the channels either side of the blades roughed in levels
-- by a tapered ball end, 0.5 mm of stock left on the flanks and the hub
-- (job.rough_channels; --set rough=false starts from a part already
-- roughed), then both flanks finished by
-- the drum wheel (blisk_drum_finish.lua), the trailing edges by the bottom of
-- a flat-end mill (blade_edges.lua), the roots and channel floor by a ball
-- (blisk_hub_finish.lua), the leading edges last with the part turned over;
-- linked through a clearance can, simulated (every unit, the seams between
-- operations, one map of blade 1) and posted for an A/C trunnion (Fanuc) and
-- a B/C head-table (Heidenhain TCPM), each program read back and replayed.
-- Blade 1 is planned, the others get its paths turned by the pitch.
--
--   bliskrun scripts/recipes/blisk_job.lua --out out [--set NAME=VALUE]...
--   (bliskrun scripts/recipes/blisk_job.lua --help lists the options below)
local opt = require("recipe_options"){
  blades = {type = "integer", default = 2, range = {1, 1000}, help = "blades to machine, from blade 1"},
  rough = {type = "boolean", default = true,
           help = "rough the channels either side of the blades first (tapered ball end, levels from the casing)"},
  stock = {type = "number", unit = "mm", range = {0.1, 3}, default = 0.5,
           help = "stock the roughing leaves on the flanks and the hub"},
  blank_top = {type = "number", unit = "mm", range = {4, 30}, default_text = "the casing (30)",
               help = "the blank's blade ring turned to this height over the hub (radially) instead of the casing; the roughing starts there"},
  rough_samples = {type = "string", default = "60,300", help = "simulation samples u,v of the roughing's stock (span, chord)",
                   check = function(v)
                     local u, w = v:match("^%s*(%d+)%s*,%s*(%d+)%s*$")
                     if not (u and tonumber(u) >= 2 and tonumber(w) >= 2) then return "expected two integers u,v >= 2" end
                   end},
  sides = {type = "string", default = "both", choices = {"both", "pressure", "suction"},
           help = "flanks the drum wheel finishes"},
  edges = {type = "boolean", default = true, help = "finish the leading and trailing edges (flat-end mill)"},
  hub = {type = "boolean", default = true, help = "finish the roots and the channel floor (tapered ball)"},
  edge_span = {type = "string", default = "0,1", help = "span fractions a,b of the edge finish, 0 <= a < b <= 1",
               check = function(v)
                 local a, b = v:match("^%s*([%d.]+)%s*,%s*([%d.]+)%s*$")
                 a, b = tonumber(a), tonumber(b)
                 if not (a and b and 0 <= a and a < b and b <= 1) then return "expected two numbers a,b with 0 <= a < b <= 1" end
               end},
  periodic = {type = "boolean", default = true, help = "plan blade 1 and turn its paths by the pitch onto the others"},
  hub_top = {type = "number", unit = "mm", range = {0.1, 30}, default_text = "4 (the hub finish's)",
             help = "height of the root strip's top above the hub"},
  samples_u = {type = "integer", default = 100, range = {2, 5000}, help = "simulation samples along the span"},
  samples_v = {type = "integer", default = 500, range = {2, 20000}, help = "simulation samples along the chord"},
  machine_clearance = {type = "number", unit = "mm", default = 0.5, range = {0.001, 100},
                       help = "machine simulation: no contact deeper than this is missed"},
  machine_near_zone = {type = "number", unit = "mm", default = 10, range = {0.001, 1e6},
                       help = "machine simulation: closest approaches measured within this zone (at least the clearance)"},
  edge_short_lift = {type = "number", unit = "mm", range = {0, 10}, default = 0.2,
                     help = "edge finish: near passes joined by a fed lift this high (0: none; bliskrun.edge_finish short_lift)"},
  edge_samples_u = {type = "integer", range = {2, 5000}, default_text = "the job's", help = "edge simulation samples, span"},
  edge_samples_v = {type = "integer", range = {2, 20000}, default_text = "the job's", help = "edge simulation samples, chord"},
  seam_spacing = {type = "number", unit = "mm", range = {0.001, 10}, default_text = "the job's",
                  help = "sample spacing of the seams between operations"},
  tool_life = {type = "number", unit = "mm", range = {1, 1e7}, default_text = "none",
               help = "cutting length per wheel, then the next sister wheel (T15, T25, ...)"},
  -- 1 mm: the figures within ~1 % of 0.5 mm's (removed, air share) at a sixth of the cost (bench/RESULTS.md)
  blank_resolution = {type = "number", unit = "mm", range = {0.05, 5}, default = 1,
                      help = "ray spacing of the stock model (the blank cut by every move: removed, air cut, left)"},
  blank = {type = "boolean", default = true,
           help = "with rough: cut the blank of revolution by every move, the stock reported after every operation"},
  blade_map = {type = "choice", default = true, choices = {true, false, "lean"},
               help = "the blade-1 map of every operation (lean: fewer samples)"},
}
local job, finish = require("job"), require("blisk_finish")

local blisk = bliskrun.blisk{}
local blades = job.first_blades(blisk, opt.blades)
local sides = ({both = {"pressure", "suction"}, pressure = {"pressure"}, suction = {"suction"}})[opt.sides]
local a, b = opt.edge_span:match("^%s*([%d.]+)%s*,%s*([%d.]+)%s*$")
local span, periodic, edges, hub = {tonumber(a), tonumber(b)}, opt.periodic, opt.edges, opt.hub

local wheel = finish.design_wheels(blisk, {c_range = 30}).wheels.extended  -- the extended wheel of Table 2
-- A 60 mm slim holder, 120 mm stick-out: on 100 mm (a 40 mm holder) the
-- machine simulation put the DMG-like trunnion's spindle nose (Ø120) 3.4 mm
-- into blades 6 and 7 while the trunnion tilted blade 1's trailing edge
-- under the tool.
local mill = bliskrun.flat_end_mill{radius = 3, corner_radius = 0.5, flute_length = 9,
                                    shank = {diameter = 6, length = 50}, holder = {diameter = 12, length = 60}}
-- 40 mm of flute to reach the hub from outside the casing.
local ball = bliskrun.tapered_ball_end_mill{tip_radius = 1.5, half_angle = 2.5, flute_length = 40,
                                            shank = {diameter = 8, length = 30}, holder = {diameter = 32, length = 40}}
-- Every tool axis within 118 deg of the table's in its setup (the A cradle
-- and the B head tilt to 120); turned over, the leading edges' also 35 deg
-- off it, clear of the cone where the A/C cradle changes sides of A = 0.
-- The roughing tool: a 6 mm tapered ball end (1.5 deg), 36 mm of flute to
-- reach the hub from outside the casing with its axis tilted between the
-- blades (the narrowest passage is 10.5 mm: the ball and 0.5 mm each side
-- leave 3.5 mm to tilt in).
local rougher = bliskrun.tapered_ball_end_mill{tip_radius = 3, half_angle = 1.5, flute_length = 36,
                                               shank = {diameter = 10, length = 40}, holder = {diameter = 32, length = 40}}
local operations, rough_top = {}, nil
if opt.rough then
  -- The channels either side of the blades finished: channel k lies between
  -- blade k's suction flank and blade k+1's pressure flank, so blades 1..N
  -- need channels N (round to the last) and 1..N.
  local n, channels = blisk:blade_count(), {}
  for _, k in ipairs(blades) do channels[#channels + 1] = k end
  if #blades < n then channels[#channels + 1] = n end
  -- The blank's top (below): the casing's cone unless --set blank_top=MM.
  rough_top = opt.blank_top and {{-22, 60 + opt.blank_top}, {22, 66 + opt.blank_top}} or nil
  local su, sv = opt.rough_samples:match("(%d+)%s*,%s*(%d+)")
  operations[1] = job.rough_channels{tool = "rougher", blades = channels, stock = opt.stock, feed = 1200,
                                     periodic = periodic, top = rough_top,
                                     samples = {math.tointeger(tonumber(su)), math.tointeger(tonumber(sv))}}
end
operations[#operations + 1] = job.drum_finish{tool = "wheel", blades = blades, sides = sides, residual = 0.014,
                                              chord_tol = 0.002, feed = 600, periodic = periodic}
if edges then
  operations[#operations + 1] = job.edge_finish{tool = "mill", blades = blades, edges = {"trailing"}, span = span,
                                                feed = 400, periodic = periodic, reach = {axis = {0, 0, 1}, max = 118},
                                                short_lift = opt.edge_short_lift}
end
if hub then  -- the root strip's top 0.5 mm over the edges' first rows (or --set hub_top=MM)
  operations[#operations + 1] = job.hub_finish{tool = "ball", blades = blades, scallop = 0.005, feed = 800,
                                               periodic = periodic, top = opt.hub_top}
end
if edges then
  operations[#operations + 1] = job.edge_finish{tool = "mill", blades = blades, edges = {"leading"}, span = span,
                                                feed = 400, periodic = periodic,
                                                reach = {axis = {0, 0, -1}, min = 35, max = 118},
                                                short_lift = opt.edge_short_lift}
end
-- The stock for the machine simulation (j:run's programs below): the disc
-- under the blades, its conical hub (radius 60 at z = -22 to 66 at +22)
-- enclosed by four stepped discs 0.5 mm over it. The blades themselves are
-- the part, proved against the whole tool when planned; the machine's head
-- against them is not checked here (see docs/lua_api/machines_and_posts.md).
local blank = {}
for k, z in ipairs{-23, -11, 0, 11} do
  local top = ({-11, 0, 11, 23})[k]
  blank[k] = {name = "disc " .. k, cylinder = {{0, 0, z}, {0, 0, top}},
              radius = 63 + 3 * math.min(top, 22) / 22 + 0.5}
end
-- The blank (issue 41): the forged disc turned to a solid of revolution —
-- the disc, z -23 to 23, 0.5 mm over the hub (r 60 + 0.5 to 66 + 0.5: the
-- hub's stock), and over it the blade ring turned to the blades' envelope:
-- out to the casing cone (r 90 at z = -22 to 96 at 22; the roughing's
-- default top; --set blank_top=MM turns it to MM over the hub) and
-- axially 1 mm beyond the edges (the blades' leading
-- edges run from z = -15.7 at the hub, r 58.5, to -11.7 at r 97.5, the
-- trailing edges from 15.3 to 11.4, measured on blade 1's flanks), so the
-- annulus in front of and behind the blade row is the disc's alone. Only
-- with the roughing: without it the part is already roughed, not a blank.
-- Every move of every operation, links included, cuts it in program order
-- (job/stock.lua): the report gives per operation the volume removed, the
-- share of its cutting path in air and the stock left.
local function hub_r(z) return 63 + 3 * z / 22 + 0.5 end
local top_over_hub = opt.blank_top or 30
local function casing_r(z) return 63 + top_over_hub + 3 * z / 22 end
-- Where an edge's envelope (z = z0 + slope (r - 58.5), 1 mm out) meets a
-- cone r = r0 + 3 z / 22: solved for z.
local function meet(z0, slope, r0) return (z0 + slope * (r0 - 58.5)) / (1 - slope * 3 / 22) end
local le_hub, le_casing = meet(-16.68, 4 / 39, 63.5), meet(-16.68, 4 / 39, 63 + top_over_hub)
local te_hub, te_casing = meet(16.34, -3.96 / 39, 63.5), meet(16.34, -3.96 / 39, 63 + top_over_hub)
local stock_blank = opt.blank and opt.rough and {resolution = opt.blank_resolution,
  profile = {{0, -23}, {hub_r(-23), -23}, {hub_r(le_hub), le_hub}, {casing_r(le_casing), le_casing},
             {casing_r(te_casing), te_casing}, {hub_r(te_hub), te_hub}, {hub_r(23), 23}, {0, 23}}} or nil
local j = job.new{
  blank = stock_blank,
  name = (opt.rough and "blisk channels roughed, " or "") .. "blisk blades" .. (edges and ", edges" or "")
         .. (hub and ", hub and roots" or ""),
  part = blisk, clearance_radius = 110, operations = operations,
  -- --set tool_life=MM: whole blades per wheel up to that cutting length, then the next sister wheel.
  tools = {rougher = {number = 3, length = 125, spindle_rpm = 9000, tool = rougher, ball_radius = 3},
           wheel = {number = 5, length = 110, spindle_rpm = 8000, tool = wheel, life_mm = opt.tool_life,
                    sisters = opt.tool_life and {15, 25, 35, 45, 55, 65, 75} or nil},
           mill = {number = 7, length = 120, spindle_rpm = 12000, tool = mill},
           ball = {number = 9, length = 130, spindle_rpm = 15000, tool = ball}},
}
-- The leading edges face the table (the blisk's axis on C, inlet down): cut
-- in a second setup, turned over. A seam beyond its operations' promises
-- fails the run after the report.
j:run{name = "blisk_job",
  simulate = {samples_u = opt.samples_u, samples_v = opt.samples_v, seam_spacing = opt.seam_spacing,
              edge_samples_u = opt.edge_samples_u, edge_samples_v = opt.edge_samples_v},
  blade_map = edges and hub and opt.blade_map ~= false and (opt.blade_map == "lean" and "lean" or true),
  setups = {{name = "inlet down"}, {name = "turned over (inlet up)", flip = true, from = "leading edge"}},
  -- Each program is replayed with the machine's bodies, the fixture and the
  -- stock (post.write's machine simulation): the fixture a mandrel column
  -- from the table face (the part frame's origin stands 120 / 100 mm above
  -- it) to the disc's face, the stock the disc (above).
  machine_clearance = opt.machine_clearance, machine_near_zone = opt.machine_near_zone,
  programs = {{machine = "dmg_like_ac_trunnion", post = "fanuc", file = "blisk_job_ac_fanuc.nc",
               fixture = {{name = "fixture", cylinder = {{0, 0, -120}, {0, 0, -23}}, radius = 50}},
               stock = blank},
              {machine = "monoblock_like_head_table", post = "heidenhain", file = "blisk_job_bc_heidenhain.h",
               fixture = {{name = "fixture", cylinder = {{0, 0, -100}, {0, 0, -23}}, radius = 50}},
               stock = blank}},
  settings = {blades = #blades, rough = opt.rough, stock_mm = opt.rough and opt.stock or nil, blank_top_mm = opt.rough and opt.blank_top or nil,
              blank_resolution_mm = stock_blank and opt.blank_resolution or nil, sides = opt.sides, edges = edges,
              edge_span = string.format("%g, %g", span[1], span[2]), periodic = periodic, tool_life_mm = opt.tool_life or "none", samples_u = opt.samples_u,
              samples_v = opt.samples_v}}
