-- Generic table-table 5-axis machine with a B/C trunnion: the B cradle
-- (about machine Y) carries the C rotary table; vertical spindle. C is the
-- primary axis, singular at B = 0.
-- Lengths mm, angles deg; pivots with all axes at zero, machine frame.
return parametric {
  parameters = {
    name        = { default = "table-table B/C trunnion", doc = "machine name" },
    x           = { default = { -300, 300 }, doc = "X travel {min, max}, mm" },
    y           = { default = { -250, 250 }, doc = "Y travel {min, max}, mm" },
    z           = { default = { -300, 300 }, doc = "Z travel {min, max}, mm" },
    b           = { default = { -110, 110 }, doc = "B travel {min, max}, deg" },
    c           = { default = false, doc = "C travel {min, max}, deg; false = continuous" },
    b_pivot     = { default = { 0, 0, -50 }, doc = "a point on the B axis line, mm" },
    c_pivot     = { default = { 0, 0, 0 }, doc = "a point on the C axis line at B = 0, mm" },
    part_origin = { default = { 0, 0, 0 }, doc = "part frame origin at home, mm" },
    tool_length = { default = "tip", doc = "'tip' (controller length compensation) or 'gauge'" },
    feed        = { default = "inverse_time", doc = "'inverse_time' (G93) or 'per_minute' (G94)" },
    resolution  = { default = { linear = 0.001, rotary = 0.001 }, doc = "controller resolution, mm and deg" },
  },
  build = function(p)
    return machine {
      name = p.name,
      linear = { X = p.x, Y = p.y, Z = p.z },
      rotary = {
        { name = "B", carrier = "part", direction = { 0, 1, 0 }, pivot = p.b_pivot, travel = p.b },
        { name = "C", carrier = "part", direction = { 0, 0, 1 }, pivot = p.c_pivot, travel = p.c },
      },
      spindle = { 0, 0, 1 },
      part_origin = p.part_origin,
      tool_length = p.tool_length,
      feed = p.feed,
      resolution = p.resolution,
    }
  end,
}
