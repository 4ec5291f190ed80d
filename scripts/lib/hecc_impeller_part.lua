-- The NASA HECC impeller (bliskrun.read_hecc: 15 main + 15 splitter blades,
-- lofted from the archive's sections) presented as the impeller the job
-- model machines (scripts/lib/job.lua, scripts/lib/impeller_world.lua), with
-- the methods of bliskrun.impeller{} the job calls:
--
--   local hecc = require("hecc_impeller_part")
--   local part = hecc.load{}              -- {path = "nasa_hecc_impeller", set = "design"|"cold"}
--   part:face(blade, "plus"|"minus", "main"|"splitter")   -> the ruled fit the job plans on
--   part:design_face(blade, side, kind)                    -> the lofted face (the blade as designed)
--   part:hub(), part:hub_meridian(), part:blade_count(), part:has_splitter(), part:outer_radius()
--   part:ruled_fit(kind, side)             -> {max, rms, worst_row, worst_col} (mm) of blade 1's fit
--
-- The HECC blades are not ruled. Flank milling and the channel planner's
-- finishing axes need ruled faces, so face() is the least-squares ruled fit
-- of the lofted face (bliskrun.fit_ruled, between the hub and tip sections);
-- what is proved against and simulated is the lofted face (design_face),
-- and flank finishing measures its residual there (flank_mill{design=}).
-- The fit's error (ruled_fit) is what flank finishing can miss the design by.
--
-- Frame. The archive's axis runs from the inlet towards the outlet (flow
-- towards +Z), so the channels open towards -Z. The job's clearance surface
-- and machines take the part with its channels open upward, like the built-in
-- impeller: the part is turned half round X (x, y, z) -> (x, -y, z0 - z), z0
-- the hub's axial position at the outlet (the back of the disc at z = 0).
-- That turn is a rotation, so every face keeps its normal out of the
-- material and u from hub to tip; the rotor, which the data turn towards +θ,
-- then turns towards -θ. Its pressure faces look along the rotation, i.e.
-- back towards -θ: they are the "plus" faces (v TE -> LE, as the built-in
-- impeller's), the suction faces the "minus" faces (v LE -> TE).
-- Then it is turned about Z to put blade 1 where the job's simulation looks
-- (below). Blade k is blade 1 turned by (k - 1) · 360°/N about Z; splitter k
-- the splitter between main blades k and k + 1.

local M = {}

local function turned_grid(g, z0)
  local rows, cols = g:size()
  local pts = {}
  for i = 1, rows do
    for j = 1, cols do
      local p = g:point(i, j)
      pts[#pts + 1] = {p[1], -p[2], z0 - p[3]}
    end
  end
  return bliskrun.point_grid{rows = rows, cols = cols, points = pts}
end

local function polar_angle(p) return math.atan(p[2], p[1]) end

local function wrap(a)
  while a > math.pi do a = a - 2 * math.pi end
  while a < -math.pi do a = a + 2 * math.pi end
  return a
end

-- o = {path = "nasa_hecc_impeller" (under --data), set = "design"}.
function M.load(o)
  o = o or {}
  for k in pairs(o) do
    if k ~= "path" and k ~= "set" then
      error(string.format("hecc_impeller_part.load: unknown option '%s', expected one of: path, set", tostring(k)), 2)
    end
  end
  local path, set = o.path or "nasa_hecc_impeller", o.set or "design"
  -- span_extension = 0: the faces end at the hub and tip sections, as the
  -- blade is (the extension past them is for a CAD face that a hub trims).
  local data = {}
  for _, kind in ipairs{"main", "splitter"} do
    data[kind] = bliskrun.read_hecc(path, {blade = kind, set = set, span_extension = 0})
  end
  local n = data.main.blades
  if data.splitter.blades ~= n then error("hecc_impeller_part: main and splitter blade counts differ", 2) end
  -- The hub: the design flow path's hub line runs on from the impeller into
  -- the diffuser and back to an axial exit, and upstream over a spinner. The
  -- impeller's hub is the part of it from `hub_extension` (10 mm, as the
  -- built-in impeller's) of meridional length before the blades' leading
  -- edges to as far past their trailing edges.
  local flow = data.main.hub_meridian        -- {{z, r}, ...} inlet -> outlet
  local line = require("impeller_world").polyline(flow)
  local arc, arc_of = line.arc, line.arc_of
  local function at_arc(s) return {line.at_arc(s)} end
  local s_le, s_te = math.huge, -math.huge
  for _, kind in ipairs{"main", "splitter"} do
    for _, side in ipairs{"pressure", "suction"} do
      local g = data[kind][side]
      local _, cols = g:size()
      for _, j in ipairs{1, cols} do
        local p = g:point(1, j)
        local s = arc_of(p[3], math.sqrt(p[1] ^ 2 + p[2] ^ 2))
        s_le, s_te = math.min(s_le, s), math.max(s_te, s)
      end
    end
  end
  local extension = 10
  local s0, s1 = math.max(0, s_le - extension), math.min(arc[#arc], s_te + extension)
  local trimmed = {at_arc(s0)}
  for i = 1, #flow do
    if arc[i] > s0 + 1e-6 and arc[i] < s1 - 1e-6 then trimmed[#trimmed + 1] = flow[i] end
  end
  trimmed[#trimmed + 1] = at_arc(s1)
  local z0 = -math.huge
  for _, q in ipairs(trimmed) do z0 = math.max(z0, q[1]) end
  -- Outlet -> inlet, as bliskrun.impeller's hub_meridian.
  local meridian = {}
  for i = #trimmed, 1, -1 do meridian[#meridian + 1] = {z0 - trimmed[i][1], trimmed[i][2]} end
  local hub = bliskrun.surface_of_revolution{meridian = meridian}

  local grids = {}  -- blade 1's grids in the job's frame: grids[kind][side]
  local side_of = {plus = "pressure", minus = "suction"}
  for _, kind in ipairs{"main", "splitter"} do
    grids[kind] = {}
    for side, name in pairs(side_of) do grids[kind][side] = turned_grid(data[kind][name], z0) end
  end
  -- Blade 1 is set where the job simulates one pitch of the hub (angles 0
  -- to 360°/N about Z): its suction ("minus") face meets the hub at θ = 0
  -- at mid-chord, so blade 1's channels lie in that window there (the blade
  -- wraps about two pitches from leading to trailing edge).
  local mid_hub = grids.main.minus:surface():point(0, 0.5)
  local phi = -math.deg(polar_angle(mid_hub))
  for _, kind in ipairs{"main", "splitter"} do
    for _, side in ipairs{"plus", "minus"} do grids[kind][side] = grids[kind][side]:rotated(phi) end
  end
  local pitch_deg = 360 / n
  -- Where splitter 1 sits: between main 1 and main 2 (+θ) unless the data
  -- put it on the other side of main 1, then the next one over is.
  local mid_main, mid_split = grids.main.plus:surface():point(0.5, 0.5), grids.splitter.plus:surface():point(0.5, 0.5)
  local offset = wrap(polar_angle(mid_split) - polar_angle(mid_main)) / math.rad(pitch_deg)
  local splitter_turn = offset < 0 and pitch_deg or 0

  local part = {set = set, splitter_offset = offset < 0 and offset + 1 or offset}
  local fits, faces, designs = {}, {}, {}
  for _, kind in ipairs{"main", "splitter"} do
    fits[kind] = {}
    for _, side in ipairs{"plus", "minus"} do
      local f = bliskrun.fit_ruled(grids[kind][side])
      fits[kind][side] = {max = f.max, rms = f.rms, worst_row = f.worst_row, worst_col = f.worst_col}
    end
  end
  local function check(blade, side, kind)
    kind = kind or "main"
    if math.type(blade) ~= "integer" or blade < 1 or blade > n then
      error(string.format("HECC impeller: blade %s does not exist; the part has %d", tostring(blade), n), 3)
    end
    if side ~= "plus" and side ~= "minus" then error("HECC impeller: side expected 'plus' or 'minus'", 3) end
    if kind ~= "main" and kind ~= "splitter" then error("HECC impeller: kind expected 'main' or 'splitter'", 3) end
    return kind
  end
  local function grid_of(blade, side, kind)
    local turn = (blade - 1) * pitch_deg + (kind == "splitter" and splitter_turn or 0)
    local g = grids[kind][side]
    return turn ~= 0 and g:rotated(turn) or g
  end
  function part:face(blade, side, kind)
    kind = check(blade, side, kind)
    local key = kind .. blade .. side
    if not faces[key] then faces[key] = bliskrun.fit_ruled(grid_of(blade, side, kind)).surface end
    return faces[key]
  end
  function part:design_face(blade, side, kind)
    kind = check(blade, side, kind)
    local key = kind .. blade .. side
    if not designs[key] then designs[key] = grid_of(blade, side, kind):surface() end
    return designs[key]
  end
  function part:ruled_fit(kind, side) return fits[kind][side] end
  function part:hub() return hub end
  function part:hub_meridian() return meridian end
  function part:blade_count() return n end
  function part:has_splitter() return true end
  function part:outer_radius()
    local r = 0
    for _, q in ipairs(meridian) do r = math.max(r, q[2]) end
    return r
  end
  -- The turn from the data's frame into the job's (for a report).
  part.frame = string.format("HECC (flow towards +Z) turned half round X, (x, y, z) -> (x, -y, %.3f - z) mm, "
                             .. "then %.3f deg about Z", z0, phi)
  return setmetatable(part, {__tostring = function()
    return string.format("NASA HECC impeller (%s set): %d main + %d splitter blades, ruled fits of the lofted faces",
                         set, n, n)
  end})
end

return M
