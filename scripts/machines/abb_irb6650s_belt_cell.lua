-- The belt paper's cell (§3: an ABB IRB 6650S-125/3.5 holding the blade;
-- ceramic belts of 120 and 240 grit, a nylon polishing belt; wheel speeds
-- 5.6 and 18.3 m/s) with three belt grinders in front of the robot, each
-- contact wheel's axis vertical, the wheel's outward normal facing the robot.
-- Arm: ABB IRB 6650S-125/3.5, ortho-parallel with a spherical wrist
-- (core/machine/robot.h). Lengths, limits and axis speeds as the
-- ROS-Industrial description gives them (github.com/ros-industrial/
-- abb_experimental, abb_irb6650s_support/urdf/irb6650s_125_350_macro.xacro,
-- commit 20b9cf8): axis 2 600 mm ahead of axis 1 and 630 mm above the base,
-- lower arm 1280 mm, axis 4 200 mm above axis 3, axis 3 to the wrist 1592 mm,
-- wrist to flange 200 mm; speeds 110, 90, 90, 150, 120, 235 deg/s. ABB's
-- joint convention (axis 3 zero with the forearm level). The S is a shelf
-- robot, mounted here on the floor. Nominal, not a calibrated robot.
return robot_cell {
  name = "ABB IRB 6650S-125/3.5 belt-grinding cell",
  controller = "abb",
  opw = { a1 = 600, a2 = -200, b = 0, c1 = 630, c2 = 1280, c3 = 1592, c4 = 200 },
  joints = {
    { zero = 0,  sign = 1, min = -180, max = 180, speed = 110 },
    { zero = 0,  sign = 1, min = -40,  max = 160, speed = 90 },
    { zero = 90, sign = 1, min = -180, max = 70,  speed = 90 },
    { zero = 0,  sign = 1, min = -300, max = 300, speed = 150 },
    { zero = 0,  sign = 1, min = -120, max = 120, speed = 120 },
    { zero = 0,  sign = 1, min = -360, max = 360, speed = 235 },
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
