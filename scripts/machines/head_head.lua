-- Generic head-head 5-axis machine (gantry with a fork head): the C axis
-- (about machine Z) carries the A fork (about X at C = 0), which turns the
-- spindle; the part stays put. C is the primary axis, singular when the tool
-- is vertical (A = 0). The fork pivot is given from the spindle gauge point.
-- Lengths mm, angles deg.
--
-- Rotary senses (ISO 841, checked when the file loads): a positive head
-- angle turns the tool right-handed about the axis direction, as ISO 841
-- says (iso841 = true).
-- Plausible bodies of a gantry with a C/A fork head (the machine class's
-- proportions, not a maker's drawing): the machine table, its face at
-- `table_top`; the A head: an HSK-63 nose of 110 mm diameter, a housing
-- 160 x 180 mm and the A hub (200 mm diameter) about the A axis; the C
-- fork's arms beside the hub and its top; the Z ram above the fork.
local function bodies_of(p)
  if p.bodies == "none" then return nil end
  if p.bodies then return p.bodies end
  local pl, t = p.pivot_length, p.table_top
  return {
    { name = "machine table", frame = "base", box = { { p.x[1] - 300, p.y[1] - 300, t - 200 }, { p.x[2] + 300, p.y[2] + 300, t } } },
    -- Tool side, relative to the spindle gauge point at home (Z carries it).
    { name = "spindle nose", frame = "spindle", cylinder = { { 0, 0, 0 }, { 0, 0, 90 } }, radius = 55 },
    { name = "head housing", frame = "spindle", box = { { -80, -90, 90 }, { 80, 90, pl - 60 } } },
    { name = "A hub", frame = "spindle", cylinder = { { -130, 0, pl }, { 130, 0, pl } }, radius = 100 },
    { name = "fork arm +X", frame = "C", box = { { 150, -100, pl - 100 }, { 210, 100, pl + 260 } } },
    { name = "fork arm -X", frame = "C", box = { { -210, -100, pl - 100 }, { -150, 100, pl + 260 } } },
    { name = "fork top", frame = "C", box = { { -210, -100, pl + 261 }, { 210, 100, pl + 400 } } },
    { name = "Z ram", frame = "Z", cylinder = { { 0, 0, pl + 410 }, { 0, 0, pl + 1400 } }, radius = 160 },
  }
end

return parametric {
  parameters = {
    name        = { default = "head-head C/A fork", doc = "machine name" },
    x           = { default = { -1500, 1500 }, doc = "X travel {min, max}, mm" },
    y           = { default = { -1000, 1000 }, doc = "Y travel {min, max}, mm" },
    z           = { default = { -600, 400 }, doc = "Z travel {min, max}, mm" },
    a           = { default = { -110, 110 }, doc = "A travel {min, max}, deg" },
    c           = { default = { -360, 360 }, doc = "C travel {min, max}, deg; false = continuous" },
    pivot_length = { default = 300, doc = "A axis above the spindle gauge point, mm" },
    c_offset    = { default = { 0, 0, 0 }, doc = "C axis line from the spindle axis at home (x, y, 0), mm" },
    part_origin = { default = { 0, 0, 0 }, doc = "part frame origin at home, mm" },
    tool_length = { default = "tip", doc = "'tip' (controller length compensation) or 'gauge'" },
    feed        = { default = "per_minute", doc = "'inverse_time' (G93) or 'per_minute' (G94)" },
    resolution  = { default = { linear = 0.001, rotary = 0.001 }, doc = "controller resolution, mm and deg" },
    speed       = { default = false,
                    doc = "top speed of each rotary axis, deg/min: {c = ..., a = ...}; false = not stated" },
    safe_z      = { default = false,
                    doc = "safe height for retracts and tool changes, Z word mm; false = the top of the Z travel" },
    table_top   = { default = -150, doc = "Z of the machine table's face in the machine frame, mm (the plausible bodies)" },
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
      rotary = {  -- chain order: C carries the A fork
        { name = "C", carrier = "tool", direction = { 0, 0, 1 }, pivot = p.c_offset, travel = p.c, iso841 = true, speed = p.speed and p.speed.c or nil },
        { name = "A", carrier = "tool", direction = { 1, 0, 0 }, pivot = { 0, 0, p.pivot_length }, travel = p.a, iso841 = true, speed = p.speed and p.speed.a or nil },
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
