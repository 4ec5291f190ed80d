-- What the generic five-axis machine files (table_table_ac, table_table_bc,
-- head_table_bc, head_head) have in common, written once: the parameters
-- every one of them takes, its rotary axes' and machine { ... }'s fields
-- made from those parameters, and the plausible bodies two or more of them
-- share. A machine file gets it with
--
--   local five_axis = machine_lib "five_axis"
--
-- (scripts/machines/lib/five_axis.lua, run afresh for each machine file:
-- every table it returns is new, nothing is shared between machines).
-- Lengths mm, angles deg.
local five_axis = {}

-- The parameters of a generic file: those every file takes, with the
-- file's defaults `d` = {name =, x =, y =, z = (travels {min, max}), feed =,
-- rotaries = {"a", "c"} (the letters of its rotary axes, chain order)},
-- and the file's `own` (its rotary travels, pivots, the sizes of its
-- plausible bodies).
function five_axis.parameters(d, own)
  local speed_keys = {}
  for i, letter in ipairs(d.rotaries) do speed_keys[i] = letter .. " = ..." end
  local parameters = {
    name        = { default = d.name, doc = "machine name" },
    x           = { default = d.x, doc = "X travel {min, max}, mm" },
    y           = { default = d.y, doc = "Y travel {min, max}, mm" },
    z           = { default = d.z, doc = "Z travel {min, max}, mm" },
    part_origin = { default = { 0, 0, 0 }, doc = "part frame origin at home, mm" },
    tool_length = { default = "tip", doc = "'tip' (controller length compensation) or 'gauge'" },
    feed        = { default = d.feed, doc = "'inverse_time' (G93) or 'per_minute' (G94)" },
    resolution  = { default = { linear = 0.001, rotary = 0.001 }, doc = "controller resolution, mm and deg" },
    speed       = { default = false,
                    doc = "top speed of each rotary axis, deg/min: {" .. table.concat(speed_keys, ", ")
                          .. "}; false = not stated" },
    safe_z      = { default = false,
                    doc = "safe height for retracts and tool changes, Z word mm; false = the top of the Z travel" },
    rapid       = { default = { feed = 10000, linear = false },
                    doc = "rapid feed for positioning moves, mm/min; linear = the controller interpolates rapids linearly" },
    bodies      = { default = false,
                    doc = "the machine's solids {{name=, frame=, box=|cylinder=|cone=, radius=}, ...} (docs/lua_api/machines_and_posts.md); "
                          .. "false = this file's plausible bodies (dimensions of the machine class, not of a maker's drawing); 'none' = no bodies" },
    slides      = { default = false, doc = "which side each linear slide carries, base outwards: {tool = {...}, part = {...}}; false = the file's" },
    dynamics    = { default = false,
                    doc = "axis limits for the cycle-time estimate: {X = {max_velocity = mm/min, max_accel = mm/s^2, "
                          .. "max_jerk = mm/s^3}, ..., <rotary> = {deg/min, deg/s^2, deg/s^3}, tool_change_s = s}; "
                          .. "false = the documented defaults" },
  }
  for key, declaration in pairs(own) do
    if parameters[key] then error("five_axis.parameters: '" .. key .. "' is a common parameter", 2) end
    parameters[key] = declaration
  end
  return parameters
end

-- One rotary axis of machine { rotary = ... } from `axis` = {name =,
-- carrier =, direction =, pivot =, iso841 =}: its travel is the parameter
-- of its letter (p.a for "A"), its speed the letter's entry of p.speed.
function five_axis.rotary(p, axis)
  local letter = axis.name:lower()
  return { name = axis.name, carrier = axis.carrier, direction = axis.direction, pivot = axis.pivot,
           travel = p[letter], iso841 = axis.iso841, speed = p.speed and p.speed[letter] or nil }
end

-- The table for machine { ... } from the parameters `p`: the two `rotary`
-- axes (chain order), a vertical spindle, and the bodies `p.bodies` asks
-- for: its own list, none ("none"), or (false) plausible_bodies(p).
function five_axis.definition(p, rotary, plausible_bodies)
  local bodies
  if p.bodies == "none" then
    bodies = nil
  elseif p.bodies then
    bodies = p.bodies
  else
    bodies = plausible_bodies(p)
  end
  return {
    name = p.name,
    linear = { X = p.x, Y = p.y, Z = p.z },
    rotary = rotary,
    spindle = { 0, 0, 1 },
    part_origin = p.part_origin,
    tool_length = p.tool_length,
    feed = p.feed,
    resolution = p.resolution,
    rapid = p.rapid,
    dynamics = p.dynamics or nil,
    safe_z = p.safe_z or nil,
    bodies = bodies,
    slides = p.slides or nil,
  }
end

-- The lists given, one after the other, in one new list.
function five_axis.concat(...)
  local all = {}
  for _, list in ipairs({ ... }) do
    for _, item in ipairs(list) do all[#all + 1] = item end
  end
  return all
end

-- Tool side, relative to the spindle gauge point at home (Z carries it):
-- an HSK-63 spindle nose of `radius`, 90 mm long.
function five_axis.spindle_nose(radius)
  return { name = "spindle nose", frame = "spindle", cylinder = { { 0, 0, 0 }, { 0, 0, 90 } }, radius = radius }
end

-- The tool side of a trunnion centre (its spindle does not swivel): a nose
-- of 120 mm diameter, a spindle housing 220 mm square and the Z ram behind
-- it.
function five_axis.trunnion_tool_side()
  return {
    five_axis.spindle_nose(60),
    { name = "spindle housing", frame = "spindle", box = { { -110, -110, 90 }, { 110, 110, 450 } } },
    { name = "Z ram", frame = "Z", box = { { -150, 111, 90 }, { 150, 400, 1000 } } },
  }
end

-- A trunnion (table-table) centre: a cradle about machine X (`tilt` "a")
-- or Y ("b") carries the C table; both turn the part.

-- A trunnion file's own parameters: the cradle's travel (default
-- `travel`) and axis line, the C table's travel, axis line and radius.
function five_axis.trunnion_parameters(tilt, travel)
  local T = tilt:upper()
  return {
    [tilt]             = { default = travel, doc = T .. " travel {min, max}, deg" },
    c                  = { default = false, doc = "C travel {min, max}, deg; false = continuous" },
    [tilt .. "_pivot"] = { default = { 0, 0, -50 }, doc = "a point on the " .. T .. " axis line, mm" },
    c_pivot            = { default = { 0, 0, 0 }, doc = "a point on the C axis line at " .. T .. " = 0, mm" },
    table_radius       = { default = 175, doc = "C table radius, mm (scales the plausible bodies)" },
  }
end

-- Its rotary axes, chain order (the cradle carries the table). A positive
-- table angle turns the part right-handed about the axis direction, so
-- relative to the part the tool turns the other way: against ISO 841.
function five_axis.trunnion_rotary(p, tilt)
  local T = tilt:upper()
  return {
    five_axis.rotary(p, { name = T, carrier = "part", direction = T == "A" and { 1, 0, 0 } or { 0, 1, 0 },
                          pivot = p[tilt .. "_pivot"], iso841 = false }),
    five_axis.rotary(p, { name = "C", carrier = "part", direction = { 0, 0, 1 }, pivot = p.c_pivot, iso841 = false }),
  }
end

-- Its part side below the column: a C table of p.table_radius, 45 mm
-- thick, on the cradle whose trough hangs 90 mm below the cradle's axis,
-- the cheeks (beside the table along the cradle's axis) reaching up to the
-- table's underside, the trunnion supports beyond them on the bed.
function five_axis.trunnion_bodies(p, tilt)
  local T = tilt:upper()
  local along = T == "A" and "X" or "Y"  -- the cradle's axis
  -- Boxes are written for a cradle about X ({along, across, z}); about Y
  -- the first two coordinates swap.
  local function at(a, b, z)
    if along == "X" then return { a, b, z } end
    return { b, a, z }
  end
  local R, cp, zt = p.table_radius, p.c_pivot, p[tilt .. "_pivot"][3]
  return {
    { name = "C table", frame = "C", cylinder = { { cp[1], cp[2], -45 }, { cp[1], cp[2], 0 } }, radius = R },
    { name = "cradle", frame = T, box = { at(-R - 20, -R - 10, zt - 90), at(R + 20, R + 10, -46) } },
    { name = "cradle cheek +" .. along, frame = T, box = { at(R + 21, -120, zt - 90), at(R + 80, 120, -46) } },
    { name = "cradle cheek -" .. along, frame = T, box = { at(-R - 80, -120, zt - 90), at(-R - 21, 120, -46) } },
    { name = "trunnion support +" .. along, frame = "base", box = { at(R + 90, -150, zt - 400), at(R + 190, 150, zt + 90) } },
    { name = "trunnion support -" .. along, frame = "base", box = { at(-R - 190, -150, zt - 400), at(-R - 90, 150, zt + 90) } },
    { name = "bed", frame = "base", box = { at(-R - 190, -450, zt - 500), at(R + 190, 450, zt - R - 60) } },
  }
end

return five_axis
