-- NASA Rotor 67 (22-blade transonic fan, the blade count of the blisk paper):
-- the analogue of the paper's Tables 1 and 2 on a real blade.
--   bliskrun scripts/recipes/rotor67_wheel_design.lua --data ../shared/data --out out/
-- Reads nasa_rotor67/rotor67geometry.dat from a --data folder (feet,
-- converted to mm by the reader), lofts both flanks from the 14 stream
-- surfaces (edge circles left out), analyses their curvature over K < 0 with
-- the C-axis range, measures the narrowest passage to the next blade and
-- sizes the drum wheel by the traditional and the extended rule.
-- Options: --help lists them (--set NAME=VALUE).

local opt = require("recipe_options"){
  c_range = {type = "number", unit = "deg", default = 30, range = {1, 90}, help = "C-axis range of the extended rule"},
  cols = {type = "integer", default = 200, range = {4, 10000}, help = "points per section of the loft"},
}
local wheel_design = require("blade_wheel_design")

local rotor = bliskrun.read_rotor67("nasa_rotor67/rotor67geometry.dat", {cols = opt.cols, span_extension = 0})
bliskrun.log(string.format("Rotor 67: %d blades, %d stream surfaces", rotor.blades, rotor.sections))
wheel_design.run(rotor, {name = "NASA Rotor 67", prefix = "rotor67", c_range = opt.c_range})
