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
-- Plausible bodies of a 650-class A/C trunnion centre (the machine class's
-- proportions, not a maker's drawing): a C table of `table_radius` 45 mm
-- thick on an A cradle whose trough hangs 90 mm below the A axis, with
-- cheeks up to the table's underside (the arms that carry it); trunnion supports beyond the
-- cheeks; a travelling column behind the table (on the Y slide: it travels in X and Y) carrying the Z ram, spindle
-- housing 220 mm square and an HSK-63 nose of 120 mm diameter.
local function bodies_of(p)
  if p.bodies == "none" then return nil end
  if p.bodies then return p.bodies end
  local R, cp, za = p.table_radius, p.c_pivot, p.a_pivot[3]
  return {
    { name = "C table", frame = "C", cylinder = { { cp[1], cp[2], -45 }, { cp[1], cp[2], 0 } }, radius = R },
    { name = "cradle", frame = "A", box = { { -R - 20, -R - 10, za - 90 }, { R + 20, R + 10, -46 } } },
    { name = "cradle cheek +X", frame = "A", box = { { R + 21, -120, za - 90 }, { R + 80, 120, -46 } } },
    { name = "cradle cheek -X", frame = "A", box = { { -R - 80, -120, za - 90 }, { -R - 21, 120, -46 } } },
    { name = "trunnion support +X", frame = "base", box = { { R + 90, -150, za - 400 }, { R + 190, 150, za + 90 } } },
    { name = "trunnion support -X", frame = "base", box = { { -R - 190, -150, za - 400 }, { -R - 90, 150, za + 90 } } },
    { name = "bed", frame = "base", box = { { -R - 190, -450, za - 500 }, { R + 190, 450, za - R - 60 } } },
    { name = "column", frame = "Y", box = { { -350, 560, za - 200 }, { 350, 1000, 1500 } } },
    -- Tool side, relative to the spindle gauge point at home (Z carries it).
    { name = "spindle nose", frame = "spindle", cylinder = { { 0, 0, 0 }, { 0, 0, 90 } }, radius = 60 },
    { name = "spindle housing", frame = "spindle", box = { { -110, -110, 90 }, { 110, 110, 450 } } },
    { name = "Z ram", frame = "Z", box = { { -150, 111, 90 }, { 150, 400, 1000 } } },
  }
end

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
    table_radius = { default = 175, doc = "C table radius, mm (scales the plausible bodies)" },
    bodies      = { default = false,
                    doc = "the machine's solids {{name=, frame=, box=|cylinder=|cone=, radius=}, ...} (docs/lua_api/machines_and_posts.md); "
                          .. "false = this file's plausible bodies (dimensions of the machine class, not of a maker's drawing); 'none' = no bodies" },
    slides      = { default = false, doc = "which side each linear slide carries, base outwards: {tool = {...}, part = {...}}; false = the file's" },
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
      bodies = bodies_of(p),
      slides = p.slides or nil,
    }
  end,
}
