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
local five_axis = machine_lib "five_axis"

local function plausible_bodies(p)
  local R, zb = p.table_radius, p.b_pivot[3]
  return five_axis.concat(
    five_axis.trunnion_bodies(p, "b"),
    { { name = "column", frame = "Y", box = { { -350, R + 600, zb - 200 }, { 350, R + 1000, 1500 } } } },
    five_axis.trunnion_tool_side())
end

return parametric {
  parameters = five_axis.parameters(
    { name = "table-table B/C trunnion", x = { -300, 300 }, y = { -250, 250 }, z = { -300, 300 },
      feed = "inverse_time", rotaries = { "b", "c" } },
    five_axis.trunnion_parameters("b", { -110, 110 })),
  build = function(p)
    return machine(five_axis.definition(p, five_axis.trunnion_rotary(p, "b"), plausible_bodies))
  end,
}
