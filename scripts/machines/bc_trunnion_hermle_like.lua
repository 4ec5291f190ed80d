-- A compact B/C trunnion machining centre (Hermle-like C-series layout):
-- X 800 / Y 800 / Z 550 mm, the B cradle swivels +-115 deg about Y with its
-- axis 80 mm below the table face, C table continuous. Program zero on the
-- C axis at the table face, part origin 90 mm above it.
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
}
