-- The NASA HECC impeller (15 main + 15 splitter blades) machined as one job
-- (issue 13), as impeller_job.lua machines the built-in one. Its faces
-- (scripts/lib/hecc_impeller_part.lua) are planned on their ruled fits and
-- proved against, simulated on and measured against the lofted faces. The
-- blades are not ruled (fits 0.7-1 mm off): roughing leaves the largest fit
-- error + 0.5 mm as stock, and flank finishing with a ruled cutter spreads
-- the fit error + and - over the lofted face, far beyond a 0.05 mm thickness
-- tolerance — the run says so per face (finish.<face>.within_tolerance):
-- these faces need point milling.
--
--   bliskrun scripts/recipes/hecc_impeller_job.lua --data ../shared/data --out out [--set blades=15]
--            [--set stations=41] [--set stock=MM] [--set min_stock=0.2] [--set depth_step=5] [--set scallop=0.01]
--            [--set hub_stock=0] [--set chord_tol=0.005] [--set finish_life=MM] [--set rough_life=MM]
--            [--set channels=inlet,left,right] [--set "faces=main plus,main minus,splitter plus,splitter minus"]
--            [--set sim_u=60] [--set sim_v=300] [--set simulate=false] [--set tolerance=0.05] [--set set=design|cold]
local job = require("job")

local part = require("hecc_impeller_part").load{set = args.set or "design"}
local blades = job.first_blades(part, args.blades)
local fits, fit_max = {}, 0
for _, face in ipairs{"main plus", "main minus", "splitter plus", "splitter minus"} do
  local f = part:ruled_fit(face:match("^(%a+) (%a+)$"))
  fits[face], fit_max = {max_mm = f.max, rms_mm = f.rms, worst_row = f.worst_row, worst_col = f.worst_col},
                        math.max(fit_max, f.max)
end
local min_stock = args.min_stock or 0.2
local stock = args.stock or math.max(0.5, math.ceil((fit_max + 0.5) * 10 - 1e-9) / 10)
print(string.format("HECC impeller: %d main + %d splitter blades; ruled fits of the lofted faces %.3f mm at worst; "
                    .. "roughing stock %.2f mm (min %.2f)", part:blade_count(), part:blade_count(), fit_max, stock,
                    min_stock))
-- The HECC flank recipe's tapered ball ends (its inlet channels are narrower than the built-in impeller's).
local cutter = bliskrun.tapered_ball_end_mill{tip_radius = 2, half_angle = 2, flute_length = 90,
                                              shank = {diameter = 12, length = 60},
                                              holder = {diameter = 40, length = 60}}
local finish_life = args.finish_life or 4000
local j = job.new{
  name = "hecc impeller", part = part, clearance = 10,
  tools = {
    rougher = {number = 1, length = 150, spindle_rpm = 15000, tool = cutter, ball_radius = 2,
               life_mm = args.rough_life, sisters = args.rough_life and {11, 21, 31, 41, 51, 61, 71} or nil},
    finisher = {number = 2, length = 150, spindle_rpm = 18000, tool = cutter, ball_radius = 2,
                life_mm = finish_life, sisters = {12, 22, 32, 42, 52, 62, 72}},
  },
  operations = {
    job.notch{tool = "rougher", blades = blades, stock = stock, min_stock = min_stock,
              depth_step = args.depth_step or 5, stations = args.stations or 41,
              channels = job.split_list(args.channels), feed = 800},
    job.widen{tool = "rougher", blades = blades, scallop = args.scallop or 0.01, hub_stock = args.hub_stock or 0,
              feed = 1000},
    job.flank_finish{tool = "finisher", blades = blades, chord_tol = args.chord_tol or 0.005,
                     faces = job.split_list(args.faces), feed = 600},
  },
}
-- Simulated: stock up to the roughing stock + the fit error tracked; an
-- overcut measured down to half the thinnest blade. A face may be cut what
-- its flank finish's plan says (+ 20 um for sampling a residual of tenths).
local thinnest = job.thinnest_blade(part)
local search_below, tolerance = math.min(fit_max + 0.5, thinnest / 2), args.tolerance or 0.05
j:run{name = "hecc_impeller_job", title = "Job: NASA HECC impeller", thickness_tolerance = tolerance,
  simulate = args.simulate ~= false and {samples_u = args.sim_u or 60, samples_v = args.sim_v or 300,
                                         search_above = stock + fit_max + 0.5, search_below = search_below},
  overcut_slack = 0.02,
  programs = {{machine = "bc_trunnion_hermle_like", post = "heidenhain", file = "hecc_impeller_job_bc_heidenhain.h"},
              {machine = bliskrun.machine.load("table_table_bc", {name = "B/C trunnion 600 (Fanuc)"}),
               name = "table_table_bc", post = "fanuc", file = "hecc_impeller_job_bc_fanuc.nc"}},
  json = {part = tostring(part), frame = part.frame, ruled_fit = fits, roughing_stock_mm = stock,
          min_stock_mm = min_stock, blade_thickness_min_mm = thinnest, simulation_search_below_mm = search_below},
  settings = {blades = #blades, stations = args.stations or 41, roughing_stock_mm = stock,
              finish_life_mm = finish_life, thickness_tolerance_mm = tolerance, tool = cutter:description()},
  -- The recipe's own section: the fits the faces are planned on.
  sections = function()
    local rows = {}
    for _, face in ipairs{"main plus", "main minus", "splitter plus", "splitter minus"} do
      rows[#rows + 1] = {face, 1e3 * fits[face].max_mm, 1e3 * fits[face].rms_mm}
    end
    return {{title = "Ruled fits of the lofted faces (blade 1)", text = "The faces are planned on these fits; the "
               .. "roughing stock is the largest fit error + 0.5 mm.",
             table = {columns = {"face", "fit max (µm)", "fit RMS (µm)"}, rows = rows}}}
  end}
