-- A belt-grinding cell with a KUKA KR 120 R2700-2 arm holding the blade
-- (belt paper §1, SPEC §6.3): three belt grinders in front of the robot —
-- coarse, fine, polish — each contact wheel's axis vertical, its contact
-- point 1.5-1.7 m out at 900 mm height, the wheel's outward normal facing
-- the robot.
-- Arm: KUKA KR 120 R2700-2 (KR QUANTEC), ortho-parallel with a spherical
-- wrist (core/machine/robot.h). Lengths, limits and axis speeds as KUKA's
-- public ROS description gives them (github.com/kroshu/kuka_robot_descriptions,
-- kuka_quantec_support/urdf/kr120_r2700_2_macro.xacro and
-- config/kr120_r2700_2_joint_limits.yaml, commit 7766e92): A2 330 mm ahead of
-- A1 and 645 mm above the base, upper arm 1150 mm, A4 115 mm above the
-- forearm's A3 line, A3 to the wrist 1220 mm, wrist to flange 215 mm; speeds
-- 2.0385, 1.9452, 2.0833, 3.3161, 3.1416, 4.5379 rad/s. Joint zeros and
-- directions in KUKA's convention (A2 = -90 deg stands the upper arm up; A1,
-- A4, A6 count clockwise seen along their axes). Nominal, not a calibrated robot.
return robot_cell {
  name = "KUKA KR 120 R2700-2 belt-grinding cell",
  controller = "kuka",
  opw = { a1 = 330, a2 = -115, b = 0, c1 = 645, c2 = 1150, c3 = 1220, c4 = 215 },
  joints = {
    { zero = 0,  sign = -1, min = -185, max = 185, speed = 116.8 },
    { zero = 90, sign = 1,  min = -140, max = -5,  speed = 111.4 },
    { zero = 0,  sign = 1,  min = -120, max = 168, speed = 119.3 },
    { zero = 0,  sign = -1, min = -350, max = 350, speed = 190.0 },
    { zero = 0,  sign = 1,  min = -125, max = 125, speed = 180.0 },
    { zero = 0,  sign = -1, min = -350, max = 350, speed = 260.0 },
  },
  home = { 0, -90, 90, 0, 30, 0 },
  -- Wheels: rubber contact wheels. `compliance` is how far the rubber and the
  -- belt give under the station's grinding force (assumed for this nominal
  -- cell: more at the coarse station's higher force; measure your wheels).
  -- Widths: on a face concave along the path a rigid wheel's ends would sit
  -- (w/2)^2 k / 2 inside it; the built-in blade's pressure flank near the LE
  -- (k up to ~0.04 1/mm) asks 0.3 mm of an 8 mm wheel, 0.8 mm of a 12 mm one.
  stations = {
    coarse = { contact = { 1500, -700, 900 }, normal = { -0.906, 0.423, 0 }, axis = { 0, 0, 1 },
               wheel = { radius = 25, width = 8, compliance = 0.8 }, belt = "ceramic, 120 grit", speed = 5.6 },
    fine   = { contact = { 1700, 0, 900 }, normal = { -1, 0, 0 }, axis = { 0, 0, 1 },
               wheel = { radius = 20, width = 8, compliance = 0.6 }, belt = "ceramic, 240 grit", speed = 18.3 },
    polish = { contact = { 1500, 700, 900 }, normal = { -0.906, -0.423, 0 }, axis = { 0, 0, 1 },
               wheel = { radius = 15, width = 6, compliance = 0.5 }, belt = "nylon polishing belt", speed = 18.3 },
  },
}
