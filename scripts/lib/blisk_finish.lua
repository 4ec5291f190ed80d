-- Blisk flank finishing with a drum wheel on the built-in blisk (blisk paper
-- §2.2-§4), shared by blisk_drum_finish.lua and blisk_drum_study.lua:
-- the wheel design of Tables 1-3, the C-axis limit at a blade, and the
-- planning settings.
--
--   local finish = require("blisk_finish")
--   local design = finish.design_wheels(blisk, {c_range = 30})
--   local plan = finish.plan(blisk, 1, "pressure", design.wheels.extended, world, {residual = 0.014})

local M = {}

-- The design flank of blade k, rebuilt from its 100 x 500 grid as the paper
-- does (§1, eq. 4-8), u hub -> tip; pu x pv points out of the material.
function M.flank(blisk, k, side)
  return blisk:flank_grid(k, side):surface()
end

-- Table 1 (curvature over K < 0 of both flanks of blade 1, k_e within the
-- C range), Table 2 (traditional and extended wheel) and the two wheels of
-- Table 3 as tools (head length 4, shank 6 x 96 mm).
-- opts: c_range (deg, 30), head_length (4), shank = {diameter, length}.
function M.design_wheels(blisk, opts)
  opts = opts or {}
  local c_range = opts.c_range or 30
  local table1 = require("blade_wheel_design").analyse(
    {pressure = M.flank(blisk, 1, "pressure"), suction = M.flank(blisk, 1, "suction")}, {c_range = c_range})
  local d_min = blisk:narrowest_passage()
  local design = bliskrun.design_drum_wheel{k1_max = table1.k1_max, ke_max = table1.ke_max, d_min = d_min}
  local shank = opts.shank or {diameter = 6, length = 96}
  local wheels = {}
  for _, rule in ipairs{"traditional", "extended"} do
    wheels[rule] = bliskrun.drum_wheel{max_diameter = design[rule].max_diameter,
                                       barrel_radius = design[rule].barrel_radius,
                                       head_length = opts.head_length or 4, shank = shank}
  end
  return {table1 = table1, table2 = design, d_min = d_min, c_range = c_range, wheels = wheels}
end

-- The paper's C-axis limit (§2.2, Fig. 3-4) at blade k: the blade's radial
-- direction is the machine's Y; the tool axis, projected on the blade's
-- meridional plane (radial and rotor axis), stays within ±c_range degrees
-- of it. The same reading as curvature_stats' k_e (docs/lua_api.md).
function M.c_axis_limit(blisk, k, c_range)
  return M.c_axis_limit_at(blisk:flank(k, "pressure"), c_range)
end

-- The same for any blade, from one of its flanks (Z the rotor axis): the
-- radial direction through the flank's middle is the machine's Y.
function M.c_axis_limit_at(flank, c_range)
  local p = flank:point(0.5, 0.5)
  local a = math.atan(p[2], p[1])
  return {name = "C", rotary_axis = {-math.sin(a), math.cos(a), 0}, reference = {math.cos(a), math.sin(a), 0},
          min = -c_range, max = c_range}
end

-- The widest diameter of the tool's cutter, mm: its profile's points and
-- 256 heights between them (the barrel bulges between its ends).
local function cutter_diameter(tool)
  local r_max, z_lo, z_hi = 0, math.huge, -math.huge
  for _, piece in ipairs(tool:profile("cutter")) do
    for _, p in ipairs{piece.from, piece.to} do
      r_max, z_lo, z_hi = math.max(r_max, p[1]), math.min(z_lo, p[2]), math.max(z_hi, p[2])
    end
  end
  for i = 0, 256 do r_max = math.max(r_max, tool:radius_at(z_lo + (z_hi - z_lo) * i / 256)) end
  return 2 * r_max
end

-- A drum wheel must pass between two blades: one as wide as the narrowest
-- passage (blisk paper eq. 13, d_min) can reach no flank, and the planner
-- would tilt every pose in vain before refusing them all. Refused here,
-- before planning, with the two numbers. passage: a blisk (its
-- narrowest_passage()) or, for a real part read from data, d_min in mm as
-- bliskrun.narrowest_passage measured it between two neighbouring blades.
function M.check_wheel_fits(passage, tool)
  if not tool:kind():find("drum wheel", 1, true) then return end
  local d_min, source = passage, "bliskrun.narrowest_passage"
  if type(passage) ~= "number" then d_min, source = passage:narrowest_passage(), "blisk:narrowest_passage()" end
  local d = cutter_diameter(tool)
  if d >= d_min then
    error(string.format("%s: its diameter %.3f mm is not below the narrowest passage between the "
                        .. "blades, d_min = %.3f mm (%s); it cannot enter the channel. "
                        .. "Expected a wheel narrower than %.3f mm (finish.design_wheels sizes one)",
                        tool:description(), d, d_min, source, d_min), 2)
  end
end

-- Options for bliskrun.drum_finish / drum_finish_all common to every flank.
-- opts: residual (mm, 0.014), chord_tol (mm, 0.002), steps ("variable"),
-- guarantee (true), zigzag (true), link ("normal"), link_overcut (chord_tol),
-- clearance ({cutter = 0, shank = 0.1,
-- holder = 1}). The shank clearance matters on the concave pressure flank
-- near the hub: the shank (d 6 x 96) lies along the blade there and the
-- tilt loop raises the lead to clear it, which moves the contact along the
-- barrel by R_c sin(lead) - off the 4 mm head for R_c 50 beyond 2.3 deg -
-- and rows are inserted to keep the residual (measured on blade 1: shank
-- clearance 0.1 / 0.25 / 0.5 mm gives 18 / 20 / 26 rows with wheel 2
-- against 20 with wheel 1).
-- blisk may be nil (a real part): set hub and casing yourself.
function M.settings(blisk, tool, opts)
  opts = opts or {}
  if blisk then M.check_wheel_fits(blisk, tool) end
  return {
    hub = blisk and blisk:hub(), casing = blisk and blisk:casing(), tool = tool,
    residual = opts.residual or 0.014, chord_tol = opts.chord_tol or 0.002,
    steps = opts.steps or "variable", guarantee = opts.guarantee ~= false, zigzag = opts.zigzag ~= false,
    top_down = opts.top_down,
    clearance = opts.clearance or {cutter = 0, shank = opts.shank_clearance or 0.1, holder = 1},
    -- Links leave along the flank normal, proved against the finished flank
    -- with chord_tol as the allowed overcut (link = "axis" retracts along
    -- the wheel's axis instead, still proved: on a concave flank it drags
    -- the barrel into it and is accepted only at a tiny offset).
    link = opts.link, link_overcut = opts.link_overcut,
  }
end

-- Plans one flank of blade k (opts as for M.settings, plus c_range: apply
-- the C-axis limit, degrees; nil = none).
function M.plan(blisk, k, side, tool, world, opts)
  opts = opts or {}
  local s = M.settings(blisk, tool, opts)
  s.flank = M.flank(blisk, k, side)
  s.world = world
  s.name = string.format("blade %d %s", k, side)
  if opts.c_range then s.axis_limit = M.c_axis_limit(blisk, k, opts.c_range) end
  return bliskrun.drum_finish(s)
end

return M
