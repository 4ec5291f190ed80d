-- A 650-class trunnion machining centre in the manner of DMG MORI's A/C
-- models: X 650 / Y 520 / Z 475 mm of travel, A cradle -120..+30 deg with
-- its axis 50 mm below the table face, C table continuous. Program zero
-- (G54) on the C axis at the table face; the blisk fixture puts the part
-- frame origin (rotor axis = part Z) 120 mm above it. The cradle and table
-- axes are off by the few hundredths a calibration measures.
-- Feed in inverse time (G93) when written in machine axes.
-- Its bodies are table_table_ac's plausible ones (a C table of 175 mm
-- radius, the cradle, a travelling column, a 220 mm spindle housing):
-- DMG-like values of the machine class, not DMG MORI's drawings.
return generic "table_table_ac" {
  name = "DMG-like A/C trunnion 650",
  x = { -325, 325 },
  y = { -260, 260 },
  z = { -130, 345 },
  a = { -120, 30 },
  c = false,
  a_pivot = { 0, 0.012, -50.03 },
  c_pivot = { -0.008, 0.015, 0 },
  part_origin = { 0, 0, 120 },
  tool_length = "tip",
  feed = "inverse_time",
  resolution = { linear = 0.001, rotary = 0.001 },
  speed = { a = 7200, c = 10800 },  -- 20 and 30 1/min, as such cradles are rated
  rapid = { feed = 30000, linear = false },  -- Fanuc: rapids not set to interpolate linearly
  -- Axis limits for the cycle-time estimate (mm or deg per min, per s^2, per s^3).
  dynamics = { X = { max_velocity = 30000, max_accel = 3000, max_jerk = 50000 },
               Y = { max_velocity = 30000, max_accel = 3000, max_jerk = 50000 },
               Z = { max_velocity = 30000, max_accel = 3000, max_jerk = 50000 },
               A = { max_velocity = 7200, max_accel = 1200, max_jerk = 12000 },
               C = { max_velocity = 10800, max_accel = 1800, max_jerk = 18000 },
               tool_change_s = 6 },
}
