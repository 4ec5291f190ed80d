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
local five_axis = machine_lib "five_axis"

local function plausible_bodies(p)
  local R, cp, pl = p.table_radius, p.c_pivot, p.pivot_length
  return {
    { name = "C table", frame = "C", cylinder = { { cp[1], cp[2], -200 }, { cp[1], cp[2], 0 } }, radius = R },
    { name = "bed", frame = "base", box = { { -R - 300, -R - 200, -500 }, { R + 300, R + 200, -201 } } },
    { name = "column", frame = "Y", box = { { -400, R + 550, -55 }, { 400, R + 1000, 1600 } } },
    -- Tool side, relative to the spindle gauge point at home (Z carries it).
    five_axis.spindle_nose(55),
    { name = "head housing", frame = "spindle", box = { { -60, -80, 90 }, { 60, 80, pl + 50 } } },
    { name = "B hub", frame = "spindle", cylinder = { { 0, -100, pl }, { 0, 100, pl } }, radius = 75 },
    { name = "Z ram", frame = "Z", box = { { -160, -150, pl + 160 }, { 160, 150, pl + 1000 } } },
  }
end

return parametric {
  parameters = five_axis.parameters(
    { name = "head-table B head / C table", x = { -350, 350 }, y = { -300, 300 }, z = { -400, 200 },
      feed = "per_minute", rotaries = { "c", "b" } },
    {
      b            = { default = { -120, 30 }, doc = "B travel {min, max}, deg" },
      c            = { default = false, doc = "C travel {min, max}, deg; false = continuous" },
      pivot_length = { default = 200, doc = "B axis above the spindle gauge point, mm" },
      c_pivot      = { default = { 0, 0, 0 }, doc = "a point on the C axis line, mm" },
      table_radius = { default = 300, doc = "C table radius, mm (scales the plausible bodies)" },
    }),
  build = function(p)
    return machine(five_axis.definition(p, {  -- one axis on each side: the order only says which is which
      five_axis.rotary(p, { name = "C", carrier = "part", direction = { 0, 0, 1 }, pivot = p.c_pivot, iso841 = false }),
      five_axis.rotary(p, { name = "B", carrier = "tool", direction = { 0, 1, 0 }, pivot = { 0, 0, p.pivot_length }, iso841 = true }),
    }, plausible_bodies))
  end,
}
