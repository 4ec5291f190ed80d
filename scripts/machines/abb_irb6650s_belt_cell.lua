-- The belt paper's cell (§3: an ABB IRB 6650S-125/3.5 holding the blade;
-- ceramic belts of 120 and 240 grit, a nylon polishing belt; wheel speeds
-- 5.6 and 18.3 m/s) with three belt grinders in front of the robot, each
-- contact wheel's axis vertical, the wheel's outward normal facing the robot.
-- Arm: ortho-parallel with a spherical wrist (core/machine/robot.h), lengths
-- of the IRB 6650S 3.5 m class (nominal; the S is a shelf robot, mounted here
-- on the floor), ABB's joint convention (axis 3 zero with the forearm
-- level), limits and speeds of the class.
return robot_cell {
  name = "ABB IRB 6650S-125/3.5-like belt-grinding cell",
  controller = "abb",
  opw = { a1 = 600, a2 = -200, b = 0, c1 = 630, c2 = 1280, c3 = 1592.5, c4 = 200 },
  joints = {
    { zero = 0,  sign = 1, min = -180, max = 180, speed = 100 },
    { zero = 0,  sign = 1, min = -40,  max = 160, speed = 90 },
    { zero = 90, sign = 1, min = -180, max = 70,  speed = 90 },
    { zero = 0,  sign = 1, min = -300, max = 300, speed = 190 },
    { zero = 0,  sign = 1, min = -120, max = 120, speed = 140 },
    { zero = 0,  sign = 1, min = -300, max = 300, speed = 190 },
  },
  home = { 0, 0, 0, 0, 30, 0 },
  -- Wheels: rubber contact wheels. `compliance` is how far the rubber and the
  -- belt give under the station's grinding force (assumed for this nominal
  -- cell: more at the coarse station's higher force; measure your wheels).
  -- Widths: on a face concave along the path a rigid wheel's ends would sit
  -- (w/2)^2 k / 2 inside it; the built-in blade's pressure flank near the LE
  -- (k up to ~0.04 1/mm) asks 0.3 mm of an 8 mm wheel, 0.8 mm of a 12 mm one.
  stations = {
    coarse = { contact = { 2000, -800, 1000 }, normal = { -0.928, 0.371, 0 }, axis = { 0, 0, 1 },
               wheel = { radius = 25, width = 8, compliance = 0.8 }, belt = "ceramic, 120 grit", speed = 5.6 },
    fine   = { contact = { 2200, 0, 1000 }, normal = { -1, 0, 0 }, axis = { 0, 0, 1 },
               wheel = { radius = 20, width = 8, compliance = 0.6 }, belt = "ceramic, 240 grit", speed = 18.3 },
    polish = { contact = { 2000, 800, 1000 }, normal = { -0.928, -0.371, 0 }, axis = { 0, 0, 1 },
               wheel = { radius = 15, width = 6, compliance = 0.5 }, belt = "nylon polishing belt", speed = 18.3 },
  },
}
