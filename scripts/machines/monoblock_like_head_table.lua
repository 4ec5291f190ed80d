-- A large head-table machining centre in the manner of a monoBLOCK 125
-- layout with a Heidenhain TNC: B swivel head -120..+30 deg, its axis 210 mm
-- above the spindle gauge point; C rotary table continuous. Gauge-point
-- travel X 1250 / Y 1000 / Z 1000 mm: the slide reaches low and far enough
-- for the swivelled head to work a blisk flank with the tool along the span
-- (tool tip at r = 130 mm, head pivot a further 300 mm out).
-- Program zero on the C axis at the table face; part origin 100 mm above it.
-- The TNC runs it with TCPM, feed per minute.
-- Its bodies are head_table_bc's plausible ones (a C table of 150 mm
-- radius at the table face, a B head with a 150 mm hub, the Z ram 160 mm
-- above the B axis): monoBLOCK-like values, not DMG MORI's drawings.
return generic "head_table_bc" {
  name = "monoBLOCK-like B head / C table",
  x = { -625, 625 },
  y = { -500, 500 },
  z = { -400, 600 },
  b = { -120, 30 },
  c = false,
  pivot_length = 210,
  c_pivot = { 0.004, -0.009, 0 },
  part_origin = { 0, 0, 100 },
  -- A C table of 300 mm diameter: with a larger one the shipped blisk
  -- programs (the B head past horizontal, the part 100 mm over the table)
  -- put the head housing on the table — on a real machine of this class
  -- the fixture would have to stand higher.
  table_radius = 150,
  tool_length = "tip",
  feed = "per_minute",
  resolution = { linear = 0.001, rotary = 0.001 },
  speed = { b = 12600, c = 10800 },  -- 35 and 30 1/min, as such heads and tables are rated
  rapid = { feed = 30000, linear = true },   -- TNC: L ... FMAX is a straight line
  -- Axis limits for the cycle-time estimate (mm or deg per min, per s^2, per s^3).
  dynamics = { X = { max_velocity = 30000, max_accel = 4000, max_jerk = 60000 },
               Y = { max_velocity = 30000, max_accel = 4000, max_jerk = 60000 },
               Z = { max_velocity = 30000, max_accel = 4000, max_jerk = 60000 },
               B = { max_velocity = 12600, max_accel = 1500, max_jerk = 15000 },
               C = { max_velocity = 10800, max_accel = 1800, max_jerk = 18000 },
               tool_change_s = 7 },
}
