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
