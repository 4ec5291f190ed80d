-- NASA Rotor 67 (22-blade transonic fan, the blade count of the blisk paper):
-- the analogue of the paper's Tables 1 and 2 on a real blade.
--   bliskrun scripts/recipes/rotor67_wheel_design.lua --data ../shared/data --out out/
-- Reads nasa_rotor67/rotor67geometry.dat from a --data folder (feet,
-- converted to mm by the reader), lofts both flanks from the 14 stream
-- surfaces (edge circles left out), analyses their curvature over K < 0 with
-- the C-axis range, measures the narrowest passage to the next blade and
-- sizes the drum wheel by the traditional and the extended rule.
-- Options: --set c_range=30 --set cols=200

local wheel_design = require("blade_wheel_design")

local rotor = bliskrun.read_rotor67("nasa_rotor67/rotor67geometry.dat", {cols = args.cols or 200, span_extension = 0})
bliskrun.log(string.format("Rotor 67: %d blades, %d stream surfaces", rotor.blades, rotor.sections))
wheel_design.run(rotor, {name = "NASA Rotor 67", prefix = "rotor67", c_range = args.c_range or 30})
