-- A head-table machining centre in the manner of a monoBLOCK layout with a
-- Heidenhain TNC: B swivel head -120..+30 deg, its axis 210 mm above the
-- spindle gauge point; C rotary table continuous. X 735 / Y 650 / Z 560 mm.
-- Program zero on the C axis at the table face; part origin 100 mm above it.
-- The TNC runs it with TCPM, feed per minute.
return generic "head_table_bc" {
  name = "monoBLOCK-like B head / C table",
  x = { -367.5, 367.5 },
  y = { -325, 325 },
  z = { -160, 400 },
  b = { -120, 30 },
  c = false,
  pivot_length = 210,
  c_pivot = { 0.004, -0.009, 0 },
  part_origin = { 0, 0, 100 },
  tool_length = "tip",
  feed = "per_minute",
  resolution = { linear = 0.001, rotary = 0.001 },
}
