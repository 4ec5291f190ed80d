-- Generic table-table 5-axis machine with an A/C trunnion: the A cradle
-- (about machine X) carries the C rotary table (about Z); the spindle stays
-- vertical. Inverse kinematics: C is the primary axis, singular when the tool
-- axis is along the table's C axis (A = 0).
--
-- Frames (see core/machine/machine_definition.h): the machine frame has its
-- origin at the program zero (G54) and its axes along X, Y, Z; pivots and
-- the part origin are given with all axes at zero. Lengths mm, angles deg.
--
-- Rotary senses (ISO 841, checked when the file loads): a positive table
-- angle turns the part right-handed about the axis direction, so relative to
-- the part the tool turns the other way -- the reverse of ISO 841's positive
-- sense (iso841 = false). A table that turns the other way for a positive
-- command gets the opposite direction and iso841 = true.
return parametric {
  parameters = {
    name        = { default = "table-table A/C trunnion", doc = "machine name" },
    x           = { default = { -300, 300 }, doc = "X travel {min, max}, mm" },
    y           = { default = { -250, 250 }, doc = "Y travel {min, max}, mm" },
    z           = { default = { -300, 300 }, doc = "Z travel {min, max}, mm" },
    a           = { default = { -120, 30 }, doc = "A travel {min, max}, deg" },
    c           = { default = false, doc = "C travel {min, max}, deg; false = continuous" },
    a_pivot     = { default = { 0, 0, -50 }, doc = "a point on the A axis line, mm" },
    c_pivot     = { default = { 0, 0, 0 }, doc = "a point on the C axis line at A = 0, mm" },
    part_origin = { default = { 0, 0, 0 }, doc = "part frame origin at home, mm" },
    tool_length = { default = "tip", doc = "'tip' (controller length compensation) or 'gauge'" },
    feed        = { default = "inverse_time", doc = "'inverse_time' (G93) or 'per_minute' (G94)" },
    resolution  = { default = { linear = 0.001, rotary = 0.001 }, doc = "controller resolution, mm and deg" },
    speed       = { default = false,
                    doc = "top speed of each rotary axis, deg/min: {a = ..., c = ...}; false = not stated" },
    safe_z      = { default = false,
                    doc = "safe height for retracts and tool changes, Z word mm; false = the top of the Z travel" },
    rapid       = { default = { feed = 10000, linear = false },
                    doc = "rapid feed for positioning moves, mm/min; linear = the controller interpolates rapids linearly" },
    dynamics    = { default = false,
                    doc = "axis limits for the cycle-time estimate: {X = {max_velocity = mm/min, max_accel = mm/s^2, "
                          .. "max_jerk = mm/s^3}, ..., <rotary> = {deg/min, deg/s^2, deg/s^3}, tool_change_s = s}; "
                          .. "false = the documented defaults" },
  },
  build = function(p)
    return machine {
      name = p.name,
      linear = { X = p.x, Y = p.y, Z = p.z },
      rotary = {  -- chain order: the cradle carries the table
        { name = "A", carrier = "part", direction = { 1, 0, 0 }, pivot = p.a_pivot, travel = p.a, iso841 = false, speed = p.speed and p.speed.a or nil },
        { name = "C", carrier = "part", direction = { 0, 0, 1 }, pivot = p.c_pivot, travel = p.c, iso841 = false, speed = p.speed and p.speed.c or nil },
      },
      spindle = { 0, 0, 1 },
      part_origin = p.part_origin,
      tool_length = p.tool_length,
      feed = p.feed,
      resolution = p.resolution,
      rapid = p.rapid,
      dynamics = p.dynamics or nil,
      safe_z = p.safe_z or nil,
    }
  end,
}
