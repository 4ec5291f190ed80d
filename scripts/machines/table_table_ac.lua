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
local five_axis = machine_lib "five_axis"

local function plausible_bodies(p)
  local za = p.a_pivot[3]
  return five_axis.concat(
    five_axis.trunnion_bodies(p, "a"),
    { { name = "column", frame = "Y", box = { { -350, 560, za - 200 }, { 350, 1000, 1500 } } } },
    five_axis.trunnion_tool_side())
end

return parametric {
  parameters = five_axis.parameters(
    { name = "table-table A/C trunnion", x = { -300, 300 }, y = { -250, 250 }, z = { -300, 300 },
      feed = "inverse_time", rotaries = { "a", "c" } },
    five_axis.trunnion_parameters("a", { -120, 30 })),
  build = function(p)
    return machine(five_axis.definition(p, five_axis.trunnion_rotary(p, "a"), plausible_bodies))
  end,
}
