-- The built-in impeller machined as one job (impeller paper §4; issue 13):
-- every channel notched and widened, the widening finishing the hub as in
-- the paper (the faces keep the stock), then both faces of every main blade
-- and splitter flank-finished, the finishing cutters grouped per blade by
-- tool life as in the paper (17 blades: 5, 4, 4, 4 per cutter). Blade 1's
-- plans are proved with the whole tool (scripts/lib/impeller_world.lua), the
-- other blades' are them turned; links run 10 mm over the part, every leg
-- proved; blade 1's faces and one pitch of the hub simulated (core/sim);
-- posted for two B/C trunnions (Heidenhain TCPM, Fanuc), each program read
-- back and replayed. Nothing is posted after an overcut the operations do
-- not allow (a face: its flank finish's residual, eq. 33-36, + 5 um).
--
--   bliskrun scripts/recipes/impeller_job.lua --out out [--set NAME=VALUE]...
--            (--help lists them; e.g. --set "faces=main plus,splitter minus" --set finish_life=MM)
local opt = require("recipe_options")(require("impeller_job_options"){
  stock = {type = "number", unit = "mm", default = 0.5, range = {0, 10}, help = "stock the roughing leaves on the faces"},
  simulate = {type = "boolean", default = true, help = "simulate blade 1's faces and one pitch of the hub"},
})
local job = require("job")

local imp = bliskrun.impeller{}
local blades = job.first_blades(imp, opt.blades)
-- The paper's tapered ball-end mill for roughing and finishing (two tools of
-- the same form: the rougher wears, the finisher holds the size).
local cutter = bliskrun.tapered_ball_end_mill{tip_radius = 3, half_angle = 2, flute_length = 90,
                                              shank = {diameter = 16, length = 60},
                                              holder = {diameter = 50, length = 60}}
-- Finishing cutting length per cutter: the default puts the 17 blades on 4 cutters (5, 4, 4, 4).
local finish_life = opt.finish_life
local j = job.new{
  name = "impeller", part = imp,
  clearance = 10,  -- links run 10 mm over the impeller's outline (hub, shroud, blade ends)
  tools = {
    rougher = {number = 1, length = 150, spindle_rpm = 12000, tool = cutter, ball_radius = 3,
               life_mm = opt.rough_life, sisters = opt.rough_life and {11, 21, 31, 41, 51, 61, 71} or nil},
    finisher = {number = 2, length = 150, spindle_rpm = 15000, tool = cutter, ball_radius = 3,
                life_mm = finish_life, sisters = {12, 22, 32, 42, 52, 62, 72}},
  },
  operations = {
    job.notch{tool = "rougher", blades = blades, stock = opt.stock, depth_step = opt.depth_step,
              stations = opt.stations, channels = job.split_list(opt.channels), feed = 800},
    job.widen{tool = "rougher", blades = blades, scallop = opt.scallop, hub_stock = opt.hub_stock,
              feed = 1000},
    job.flank_finish{tool = "finisher", blades = blades, chord_tol = opt.chord_tol,
                     faces = job.split_list(opt.faces), feed = 600},
  },
}
-- B/C trunnions, whose cradle swivels both ways: at the outlet the widening
-- carries the tool axis over the pole of the table's C axis, where an A/C
-- cradle that tilts one way (-120..+30 deg) runs out of travel.
j:run{name = "impeller_job", json = {part = "built-in impeller"},
  simulate = opt.simulate ~= false and {samples_u = opt.sim_u, samples_v = opt.sim_v},
  machine_clearance = opt.machine_clearance, machine_near_zone = opt.machine_near_zone,
  programs = {{machine = "bc_trunnion_hermle_like", post = "heidenhain", file = "impeller_job_bc_heidenhain.h"},
              {machine = bliskrun.machine.load("table_table_bc", {name = "B/C trunnion 600 (Fanuc)"}),
               name = "table_table_bc", post = "fanuc", file = "impeller_job_bc_fanuc.nc"}},
  settings = {blades = #blades, stations = opt.stations, finish_life_mm = finish_life,
              tool = cutter:description()}}
