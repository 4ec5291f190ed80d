-- Generic head-table 5-axis machine: a B swivel head (about machine Y) turns
-- the spindle, a C rotary table turns the part. C is the primary axis,
-- singular at B = 0. The head pivot is given from the spindle gauge point
-- (the length the head manufacturer states as "pivot length").
-- Lengths mm, angles deg.
--
-- Rotary senses (ISO 841, checked when the file loads): a positive C turns
-- the part right-handed about +Z, so relative to the part the tool turns the
-- other way -- the reverse of ISO 841's +C (iso841 = false); a positive B
-- turns the tool right-handed about +Y, as ISO 841 says (iso841 = true).
-- Plausible bodies of a head-table centre (a B head over a C table, the
-- machine class's proportions, not a maker's drawing): a C table of
-- `table_radius` whose face is at program zero, 200 mm over the bed (its drive below it); a
-- column behind it (on the Y slide: it travels in X and Y) carrying the Z ram; the B head: an HSK-63 nose of 110 mm
-- diameter, a housing 120 x 160 mm up to 50 mm above the B axis and the
-- B hub (150 mm diameter) about that axis; the ram 160 mm above the axis.
local function bodies_of(p)
  if p.bodies == "none" then return nil end
  if p.bodies then return p.bodies end
  local R, cp, pl = p.table_radius, p.c_pivot, p.pivot_length
  return {
    { name = "C table", frame = "C", cylinder = { { cp[1], cp[2], -200 }, { cp[1], cp[2], 0 } }, radius = R },
    { name = "bed", frame = "base", box = { { -R - 300, -R - 200, -500 }, { R + 300, R + 200, -201 } } },
    { name = "column", frame = "Y", box = { { -400, R + 550, -55 }, { 400, R + 1000, 1600 } } },
    -- Tool side, relative to the spindle gauge point at home (Z carries it).
    { name = "spindle nose", frame = "spindle", cylinder = { { 0, 0, 0 }, { 0, 0, 90 } }, radius = 55 },
    { name = "head housing", frame = "spindle", box = { { -60, -80, 90 }, { 60, 80, pl + 50 } } },
    { name = "B hub", frame = "spindle", cylinder = { { 0, -100, pl }, { 0, 100, pl } }, radius = 75 },
    { name = "Z ram", frame = "Z", box = { { -160, -150, pl + 160 }, { 160, 150, pl + 1000 } } },
  }
end

return parametric {
  parameters = {
    name        = { default = "head-table B head / C table", doc = "machine name" },
    x           = { default = { -350, 350 }, doc = "X travel {min, max}, mm" },
    y           = { default = { -300, 300 }, doc = "Y travel {min, max}, mm" },
    z           = { default = { -400, 200 }, doc = "Z travel {min, max}, mm" },
    b           = { default = { -120, 30 }, doc = "B travel {min, max}, deg" },
    c           = { default = false, doc = "C travel {min, max}, deg; false = continuous" },
    pivot_length = { default = 200, doc = "B axis above the spindle gauge point, mm" },
    c_pivot     = { default = { 0, 0, 0 }, doc = "a point on the C axis line, mm" },
    part_origin = { default = { 0, 0, 0 }, doc = "part frame origin at home, mm" },
    tool_length = { default = "tip", doc = "'tip' (controller length compensation) or 'gauge'" },
    feed        = { default = "per_minute", doc = "'inverse_time' (G93) or 'per_minute' (G94)" },
    resolution  = { default = { linear = 0.001, rotary = 0.001 }, doc = "controller resolution, mm and deg" },
    speed       = { default = false,
                    doc = "top speed of each rotary axis, deg/min: {c = ..., b = ...}; false = not stated" },
    safe_z      = { default = false,
                    doc = "safe height for retracts and tool changes, Z word mm; false = the top of the Z travel" },
    table_radius = { default = 300, doc = "C table radius, mm (scales the plausible bodies)" },
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
      rotary = {  -- one axis on each side: the order only says which is which
        { name = "C", carrier = "part", direction = { 0, 0, 1 }, pivot = p.c_pivot, travel = p.c, iso841 = false, speed = p.speed and p.speed.c or nil },
        { name = "B", carrier = "tool", direction = { 0, 1, 0 }, pivot = { 0, 0, p.pivot_length }, travel = p.b, iso841 = true, speed = p.speed and p.speed.b or nil },
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
