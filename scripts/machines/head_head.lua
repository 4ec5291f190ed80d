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
local five_axis = machine_lib "five_axis"

local function plausible_bodies(p)
  local pl, t = p.pivot_length, p.table_top
  return {
    { name = "machine table", frame = "base", box = { { p.x[1] - 300, p.y[1] - 300, t - 200 }, { p.x[2] + 300, p.y[2] + 300, t } } },
    -- Tool side, relative to the spindle gauge point at home (Z carries it).
    five_axis.spindle_nose(55),
    { name = "head housing", frame = "spindle", box = { { -80, -90, 90 }, { 80, 90, pl - 60 } } },
    { name = "A hub", frame = "spindle", cylinder = { { -130, 0, pl }, { 130, 0, pl } }, radius = 100 },
    { name = "fork arm +X", frame = "C", box = { { 150, -100, pl - 100 }, { 210, 100, pl + 260 } } },
    { name = "fork arm -X", frame = "C", box = { { -210, -100, pl - 100 }, { -150, 100, pl + 260 } } },
    { name = "fork top", frame = "C", box = { { -210, -100, pl + 261 }, { 210, 100, pl + 400 } } },
    { name = "Z ram", frame = "Z", cylinder = { { 0, 0, pl + 410 }, { 0, 0, pl + 1400 } }, radius = 160 },
  }
end

return parametric {
  parameters = five_axis.parameters(
    { name = "head-head C/A fork", x = { -1500, 1500 }, y = { -1000, 1000 }, z = { -600, 400 },
      feed = "per_minute", rotaries = { "c", "a" } },
    {
      a            = { default = { -110, 110 }, doc = "A travel {min, max}, deg" },
      c            = { default = { -360, 360 }, doc = "C travel {min, max}, deg; false = continuous" },
      pivot_length = { default = 300, doc = "A axis above the spindle gauge point, mm" },
      c_offset     = { default = { 0, 0, 0 }, doc = "C axis line from the spindle axis at home (x, y, 0), mm" },
      table_top    = { default = -150, doc = "Z of the machine table's face in the machine frame, mm (the plausible bodies)" },
    }),
  build = function(p)
    return machine(five_axis.definition(p, {  -- chain order: C carries the A fork
      five_axis.rotary(p, { name = "C", carrier = "tool", direction = { 0, 0, 1 }, pivot = p.c_offset, iso841 = true }),
      five_axis.rotary(p, { name = "A", carrier = "tool", direction = { 1, 0, 0 }, pivot = { 0, 0, p.pivot_length }, iso841 = true }),
    }, plausible_bodies))
  end,
}
