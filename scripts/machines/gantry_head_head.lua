-- A five-axis gantry milling machine with a fork head (Zimmermann-like
-- layout, Siemens 840D with TRAORI): X 3000 / Y 2200 / Z 1000 mm, C -360..+360
-- deg (cable-limited), A fork +-110 deg with its axis 320 mm above the
-- spindle gauge point. Program zero on the fixture; the part lies there.
-- Its bodies are head_head's plausible ones (the machine table 150 mm
-- below program zero, an A head with a 200 mm hub in a C fork): values of
-- the machine class ("-like"), not a maker's drawings.
return generic "head_head" {
  name = "gantry C/A fork head",
  x = { -1500, 1500 },
  y = { -1100, 1100 },
  z = { -700, 300 },
  a = { -110, 110 },
  c = { -360, 360 },
  pivot_length = 320,
  c_offset = { 0.01, -0.006, 0 },
  part_origin = { 0, 0, 0 },
  tool_length = "tip",
  feed = "per_minute",
  resolution = { linear = 0.001, rotary = 0.001 },
  rapid = { feed = 20000, linear = false },
  -- Axis limits for the cycle-time estimate (mm or deg per min, per s^2, per s^3).
  dynamics = { X = { max_velocity = 20000, max_accel = 2000, max_jerk = 30000 },
               Y = { max_velocity = 20000, max_accel = 2000, max_jerk = 30000 },
               Z = { max_velocity = 20000, max_accel = 2000, max_jerk = 30000 },
               tool_change_s = 10 },
}
