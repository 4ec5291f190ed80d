-- Generic table-table 5-axis machine with a B/C trunnion: the B cradle
-- (about machine Y) carries the C rotary table; vertical spindle. C is the
-- primary axis, singular at B = 0.
-- Lengths mm, angles deg; pivots with all axes at zero, machine frame.
--
-- Rotary senses (ISO 841, checked when the file loads): a positive table
-- angle turns the part right-handed about the axis direction, so relative to
-- the part the tool turns the other way -- the reverse of ISO 841's positive
-- sense (iso841 = false). A table that turns the other way for a positive
-- command gets the opposite direction and iso841 = true.
-- Plausible bodies of an 800-class B/C trunnion centre (the machine class's
-- proportions, not a maker's drawing): a C table of `table_radius` 45 mm
-- thick on a B cradle (about Y) whose trough hangs 90 mm below the B axis,
-- cheeks at +-Y up to the table's underside, trunnion supports beyond
-- them; a column behind the table (on the Y slide: it travels in X and Y) carrying the Z ram, a spindle housing
-- 220 mm square and an HSK-63 nose of 120 mm diameter.
local function bodies_of(p)
  if p.bodies == "none" then return nil end
  if p.bodies then return p.bodies end
  local R, cp, zb = p.table_radius, p.c_pivot, p.b_pivot[3]
  return {
    { name = "C table", frame = "C", cylinder = { { cp[1], cp[2], -45 }, { cp[1], cp[2], 0 } }, radius = R },
    { name = "cradle", frame = "B", box = { { -R - 10, -R - 20, zb - 90 }, { R + 10, R + 20, -46 } } },
    { name = "cradle cheek +Y", frame = "B", box = { { -120, R + 21, zb - 90 }, { 120, R + 80, -46 } } },
    { name = "cradle cheek -Y", frame = "B", box = { { -120, -R - 80, zb - 90 }, { 120, -R - 21, -46 } } },
    { name = "trunnion support +Y", frame = "base", box = { { -150, R + 90, zb - 400 }, { 150, R + 190, zb + 90 } } },
    { name = "trunnion support -Y", frame = "base", box = { { -150, -R - 190, zb - 400 }, { 150, -R - 90, zb + 90 } } },
    { name = "bed", frame = "base", box = { { -450, -R - 190, zb - 500 }, { 450, R + 190, zb - R - 60 } } },
    { name = "column", frame = "Y", box = { { -350, R + 600, zb - 200 }, { 350, R + 1000, 1500 } } },
    -- Tool side, relative to the spindle gauge point at home (Z carries it).
    { name = "spindle nose", frame = "spindle", cylinder = { { 0, 0, 0 }, { 0, 0, 90 } }, radius = 60 },
    { name = "spindle housing", frame = "spindle", box = { { -110, -110, 90 }, { 110, 110, 450 } } },
    { name = "Z ram", frame = "Z", box = { { -150, 111, 90 }, { 150, 400, 1000 } } },
  }
end

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
    speed       = { default = false,
                    doc = "top speed of each rotary axis, deg/min: {b = ..., c = ...}; false = not stated" },
    safe_z      = { default = false,
                    doc = "safe height for retracts and tool changes, Z word mm; false = the top of the Z travel" },
    table_radius = { default = 175, doc = "C table radius, mm (scales the plausible bodies)" },
    bodies      = { default = false,
                    doc = "the machine's solids {{name=, frame=, box=|cylinder=|cone=, radius=}, ...} (docs/lua_api/machines_and_posts.md); "
                          .. "false = this file's plausible bodies (dimensions of the machine class, not of a maker's drawing); 'none' = no bodies" },
    slides      = { default = false, doc = "which side each linear slide carries, base outwards: {tool = {...}, part = {...}}; false = the file's" },
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
      rotary = {
        { name = "B", carrier = "part", direction = { 0, 1, 0 }, pivot = p.b_pivot, travel = p.b, iso841 = false, speed = p.speed and p.speed.b or nil },
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
