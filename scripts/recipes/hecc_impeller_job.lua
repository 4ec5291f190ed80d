-- The NASA HECC impeller (15 main + 15 splitter blades) machined as one job
-- (issue 13), as impeller_job.lua machines the built-in one. Its faces
-- (scripts/lib/hecc_impeller_part.lua) are planned on their ruled fits and
-- proved against, simulated on and measured against the lofted faces. The
-- blades are not ruled (fits 0.7-1 mm off): roughing leaves the largest fit
-- error + 0.5 mm as stock, and flank finishing with a ruled cutter spreads
-- the fit error + and - over the lofted face, far beyond a 0.05 mm thickness
-- tolerance. So each face is finished by flank milling where its flank plan's
-- residual against the lofted face (the flank finish's own figure) is within
-- the tolerance and by five-axis point milling (job.point_mill,
-- instead_of_flank) where it is not; the run says which per face
-- (finish.<face>.method) and simulates the point-milled faces against the
-- lofted faces (finish.<face>.within_tolerance).
--
--   bliskrun scripts/recipes/hecc_impeller_job.lua --data ../shared/data --out out [--set NAME=VALUE]...
--            (--help lists them)
local opt = require("recipe_options")(require("impeller_job_options"){
  simulate = {type = "boolean", default = true, help = "simulate blade 1's faces and one pitch of the hub"},
  stock = {type = "number", unit = "mm", range = {0, 10}, default_text = "largest fit error + 0.5, at least 0.5",
           help = "stock the roughing leaves on the faces"},
  min_stock = {type = "number", unit = "mm", default = 0.2, range = {0, 10}, help = "least stock the notch leaves"},
  tolerance = {type = "number", unit = "mm", default = 0.05, range = {1e-4, 1}, help = "blade thickness tolerance"},
  set = {type = "string", default = "design", choices = {"design", "cold"}, help = "which HECC geometry set"},
  point_mill = {type = "boolean", default = true,
                help = "point-mill the faces flank milling leaves beyond the tolerance (false: flank-mill every face)"},
  point_scallop = {type = "number", unit = "mm", default = 0.02, range = {1e-4, 0.5},
                   help = "scallop height of the point-milled faces, measured on the face"},
  point_chord_tol = {type = "number", unit = "mm", default = 0.005, range = {1e-4, 0.5},
                     help = "chord tolerance of the point-milled rows (the ball centre's path)"},
  point_overcut = {type = "number", unit = "mm", default = 0.005, range = {1e-4, 0.5},
                   help = "how far a point-milling move may cut below the face (caps the chord on convex rows)"},
  point_fillet = {type = "boolean", default = true,
                  help = "carry the point-milled rows down to the fillet line (false: stop 3 ball radii above the "
                         .. "hub, the root strip left unfinished)"},
})
local job = require("job")

local part = require("hecc_impeller_part").load{set = opt.set}
local blades = job.first_blades(part, opt.blades)
local fits, fit_max = {}, 0
for _, face in ipairs{"main plus", "main minus", "splitter plus", "splitter minus"} do
  local f = part:ruled_fit(face:match("^(%a+) (%a+)$"))
  fits[face], fit_max = {max_mm = f.max, rms_mm = f.rms, worst_row = f.worst_row, worst_col = f.worst_col},
                        math.max(fit_max, f.max)
end
local min_stock = opt.min_stock
local stock = opt.stock or math.max(0.5, math.ceil((fit_max + 0.5) * 10 - 1e-9) / 10)
print(string.format("HECC impeller: %d main + %d splitter blades; ruled fits of the lofted faces %.3f mm at worst; "
                    .. "roughing stock %.2f mm (min %.2f)", part:blade_count(), part:blade_count(), fit_max, stock,
                    min_stock))
-- The HECC flank recipe's tapered ball ends (its inlet channels are narrower than the built-in impeller's).
local cutter = bliskrun.tapered_ball_end_mill{tip_radius = 2, half_angle = 2, flute_length = 90,
                                              shank = {diameter = 12, length = 60},
                                              holder = {diameter = 40, length = 60}}
local finish_life = opt.finish_life
local j = job.new{
  name = "hecc impeller", part = part, clearance = 10,
  tools = {
    rougher = {number = 1, length = 150, spindle_rpm = 15000, tool = cutter, ball_radius = 2,
               life_mm = opt.rough_life, sisters = opt.rough_life and {11, 21, 31, 41, 51, 61, 71} or nil},
    finisher = {number = 2, length = 150, spindle_rpm = 18000, tool = cutter, ball_radius = 2,
                life_mm = finish_life, sisters = {12, 22, 32, 42, 52, 62, 72}},
    -- The point-milling finisher: the same cutter, its own pocket (a face
    -- point-milled is some 15-50 m of cutting: no flank finisher's life).
    point_finisher = opt.point_mill and {number = 3, length = 150, spindle_rpm = 18000, tool = cutter,
                                         ball_radius = 2} or nil,
  },
  operations = {
    job.notch{tool = "rougher", blades = blades, stock = stock, min_stock = min_stock,
              depth_step = opt.depth_step, stations = opt.stations,
              channels = job.split_list(opt.channels), feed = 800},
    job.widen{tool = "rougher", blades = blades, scallop = opt.scallop, hub_stock = opt.hub_stock,
              feed = 1000},
    job.flank_finish{tool = "finisher", blades = blades, chord_tol = opt.chord_tol,
                     faces = job.split_list(opt.faces), feed = 600},
    -- The faces the flank finish leaves beyond the tolerance, point-milled
    -- (their flank units dropped): scallop + chord well inside 0.05 mm.
    opt.point_mill and job.point_mill{tool = "point_finisher", blades = blades, faces = job.split_list(opt.faces),
                                      instead_of_flank = opt.tolerance, scallop = opt.point_scallop,
                                      chord_tol = opt.point_chord_tol, allowed_overcut = opt.point_overcut,
                                      follow_fillet = opt.point_fillet, feed = 600} or nil,
  },
}
-- Simulated: stock up to the roughing stock + the fit error tracked; an
-- overcut measured down to half the thinnest blade. A face may be cut what
-- its flank finish's plan says (+ 20 um for sampling a residual of tenths).
local thinnest = job.thinnest_blade(part)
local search_below, tolerance = math.min(fit_max + 0.5, thinnest / 2), opt.tolerance
j:run{name = "hecc_impeller_job", title = "Job: NASA HECC impeller", thickness_tolerance = tolerance,
  simulate = opt.simulate ~= false and {samples_u = opt.sim_u, samples_v = opt.sim_v,
                                         search_above = stock + fit_max + 0.5, search_below = search_below},
  overcut_slack = 0.02,
  machine_clearance = opt.machine_clearance, machine_near_zone = opt.machine_near_zone,
  programs = {{machine = "bc_trunnion_hermle_like", post = "heidenhain", file = "hecc_impeller_job_bc_heidenhain.h"},
              {machine = bliskrun.machine.load("table_table_bc", {name = "B/C trunnion 600 (Fanuc)"}),
               name = "table_table_bc", post = "fanuc", file = "hecc_impeller_job_bc_fanuc.nc"}},
  json = {part = tostring(part), frame = part.frame, ruled_fit = fits, roughing_stock_mm = stock,
          min_stock_mm = min_stock, blade_thickness_min_mm = thinnest, simulation_search_below_mm = search_below},
  settings = {blades = #blades, stations = opt.stations, roughing_stock_mm = stock,
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
