-- NASA Rotor 37 (36-blade transonic compressor rotor): the analogue of the
-- blisk paper's Tables 1 and 2 on a real blade.
--   bliskrun scripts/recipes/rotor37_wheel_design.lua --data ../shared/data --out out/
-- Reads the AGARD tables nasa_rotor37/agard_table/rotor37geometry.dat and
-- rotor37hub-shroud.dat from a --data folder (cm, converted to mm by the
-- reader), lofts both flanks from the 13 section loops (edge circles found
-- and left out), analyses their curvature over K < 0 with the C-axis range,
-- measures the narrowest passage to the next blade (one pitch, 360/36
-- degrees, away) and sizes the drum wheel by the traditional and the
-- extended rule.
-- Options: --help lists them (--set NAME=VALUE).

local opt = require("recipe_options"){
  c_range = {type = "number", unit = "deg", default = 30, range = {1, 90}, help = "C-axis range of the extended rule"},
  cols = {type = "integer", default = 200, range = {4, 10000}, help = "points per section of the loft"},
}
local wheel_design = require("blade_wheel_design")

local rotor = bliskrun.read_rotor37("nasa_rotor37", {cols = opt.cols, span_extension = 0})
bliskrun.log(string.format("Rotor 37: %d blades, %d sections, pressure side from the %s", rotor.blades,
                           rotor.sections, rotor.rotation_from))
wheel_design.run(rotor, {name = "NASA Rotor 37", prefix = "rotor37", c_range = opt.c_range})
