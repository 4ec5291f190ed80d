-- A compact B/C trunnion machining centre (Hermle-like C-series layout):
-- X 800 / Y 800 / Z 550 mm, the B cradle swivels +-115 deg about Y with its
-- axis 80 mm below the table face, C table continuous. Program zero on the
-- C axis at the table face, part origin 90 mm above it.
-- Its bodies are table_table_bc's plausible ones (a C table of 175 mm
-- radius, the B cradle, a column, a 220 mm spindle housing): Hermle-like
-- values of the machine class, not Hermle's drawings.
return generic "table_table_bc" {
  name = "B/C trunnion 800 (Hermle-like)",
  x = { -400, 400 },
  y = { -400, 400 },
  z = { -150, 400 },
  b = { -115, 115 },
  c = false,
  b_pivot = { 0.01, 0, -80.02 },
  c_pivot = { 0.006, -0.011, 0 },
  part_origin = { 0, 0, 90 },
  tool_length = "tip",
  feed = "inverse_time",
  resolution = { linear = 0.001, rotary = 0.001 },
  speed = { b = 9000, c = 14400 },  -- 25 and 40 1/min, as such trunnions are rated
  rapid = { feed = 35000, linear = true },   -- TNC: L ... FMAX is a straight line
  -- Axis limits for the cycle-time estimate (mm or deg per min, per s^2, per s^3).
  dynamics = { X = { max_velocity = 35000, max_accel = 5000, max_jerk = 75000 },
               Y = { max_velocity = 35000, max_accel = 5000, max_jerk = 75000 },
               Z = { max_velocity = 35000, max_accel = 5000, max_jerk = 75000 },
               B = { max_velocity = 9000, max_accel = 1200, max_jerk = 12000 },
               C = { max_velocity = 14400, max_accel = 2400, max_jerk = 24000 },
               tool_change_s = 5 },
}
