-- A belt-grinding cell with a KUKA KR 120 R2700-class arm holding the blade
-- (belt paper §1, SPEC §6.3): three belt grinders in front of the robot —
-- coarse, fine, polish — each contact wheel's axis vertical, its contact
-- point 1.5-1.7 m out at 900 mm height, the wheel's outward normal facing
-- the robot.
-- Arm: ortho-parallel with a spherical wrist (core/machine/robot.h), lengths
-- of the KR QUANTEC R2700 class (nominal, not a calibrated robot); joint
-- zeros and directions in KUKA's convention (A2 = -90 deg stands the upper
-- arm up; A1, A4, A6 count clockwise seen along their axes), limits and
-- speeds of the class.
return robot_cell {
  name = "KUKA KR 120 R2700-like belt-grinding cell",
  controller = "kuka",
  opw = { a1 = 350, a2 = -41, b = 0, c1 = 675, c2 = 1150, c3 = 1200, c4 = 215 },
  joints = {
    { zero = 0,  sign = -1, min = -185, max = 185, speed = 136 },
    { zero = 90, sign = 1,  min = -140, max = -5,  speed = 130 },
    { zero = 0,  sign = 1,  min = -120, max = 168, speed = 120 },
    { zero = 0,  sign = -1, min = -350, max = 350, speed = 292 },
    { zero = 0,  sign = 1,  min = -125, max = 125, speed = 258 },
    { zero = 0,  sign = -1, min = -350, max = 350, speed = 284 },
  },
  home = { 0, -90, 90, 0, 30, 0 },
  stations = {
    coarse = { contact = { 1500, -700, 900 }, normal = { -0.906, 0.423, 0 }, axis = { 0, 0, 1 },
               wheel = { radius = 25, width = 12 }, belt = "ceramic, 120 grit", speed = 5.6 },
    fine   = { contact = { 1700, 0, 900 }, normal = { -1, 0, 0 }, axis = { 0, 0, 1 },
               wheel = { radius = 20, width = 10 }, belt = "ceramic, 240 grit", speed = 18.3 },
    polish = { contact = { 1500, 700, 900 }, normal = { -0.906, -0.423, 0 }, axis = { 0, 0, 1 },
               wheel = { radius = 15, width = 8 }, belt = "nylon polishing belt", speed = 18.3 },
  },
}
