-- The NASA HECC impeller (bliskrun.read_hecc: 15 main + 15 splitter blades,
-- lofted from the archive's sections) presented as the impeller the job
-- model machines (scripts/lib/job.lua, scripts/lib/impeller_world.lua), with
-- the methods of bliskrun.impeller{} the job calls:
--
--   local hecc = require("hecc_impeller_part")
--   local part = hecc.load{}              -- {path = "nasa_hecc_impeller", set = "design"|"cold"}
--   part:face(blade, "plus"|"minus", "main"|"splitter")   -> the ruled fit the job plans on
--   part:design_face(blade, side, kind)                    -> the lofted face (the blade as designed)
--   part:edge_face(blade, "leading"|"trailing", kind)      -> the blade between its faces' ends
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

-- The chord fraction the faces leave out at each edge (the loft's default),
-- and the columns of the loft to the edge point the edges are taken from.
M.edge_margin = 0.03
M.edge_cols = 200

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

-- A blade's two edges as grids, from the faces' ends round the edge point:
-- plus_full / minus_full the blade's "plus" and "minus" sides lofted to the
-- edge point (edge_margin 0, M.edge_cols cosine columns: the sides meet
-- there), plus / minus the faces' grids (edge_margin M.edge_margin, the
-- same sections as rows, the same frame). Each edge runs from the face whose
-- columns run into it, over that side's columns inside the margin, round
-- the edge point and out along the other side's to the other face's end:
-- the faces' own end columns close it, so the edge meets each face on its
-- end curve (no overlap: a cutter finishing a face up to its end is not
-- proved into the edge), and u hub -> tip, v as the faces' run, so
-- pu x pv points out of the material as theirs does. The edge point is
-- where the first side's end column meets the other's (within 0.01 mm;
-- else an error). Returns {leading = grid, trailing = grid}.
function M.edge_grids(plus_full, minus_full, plus, minus)
  local rows, cols = plus_full:size()
  local frows, fcols = plus:size()
  if rows ~= frows or select(1, minus_full:size()) ~= rows or select(1, minus:size()) ~= rows then
    error("hecc_impeller_part.edge_grids: the faces and the edge lofts have different sections", 2)
  end
  local function dist(a, b) return math.sqrt((a[1] - b[1]) ^ 2 + (a[2] - b[2]) ^ 2 + (a[3] - b[3]) ^ 2) end
  -- Columns of the full loft strictly inside the margin: f_j = (1 - cos(pi
  -- (j - 1) / (cols - 1))) / 2 < edge_margin, less one so that the last
  -- stays clear of the face's end (the spline through both).
  local inside = math.ceil(math.acos(1 - 2 * M.edge_margin) / math.pi * (cols - 1)) - 2
  -- Which ends meet: minus's first column with plus's last (v runs into
  -- the edge on plus), or minus's last with plus's first.
  local out = {}
  for _, pair in ipairs{{plus_full, plus, minus_full, minus}, {minus_full, minus, plus_full, plus}} do
    local into_full, into, from_full, from = table.unpack(pair)
    -- `into`'s last column meets `from`'s first at the edge point.
    local gap = 0
    for i = 1, rows do gap = math.max(gap, dist(into_full:point(i, cols), from_full:point(i, 1))) end
    if gap > 0.01 then error(string.format("hecc_impeller_part.edge_grids: the sides' ends are %.3f mm apart at the "
                                           .. "edge, not one edge point", gap), 2) end
    local pts = {}
    local n_cols = 2 * inside + 3
    for i = 1, rows do
      pts[#pts + 1] = into:point(i, fcols)
      for j = cols - inside, cols do pts[#pts + 1] = into_full:point(i, j) end
      for j = 2, inside + 1 do pts[#pts + 1] = from_full:point(i, j) end
      pts[#pts + 1] = from:point(i, 1)
    end
    local grid = bliskrun.point_grid{rows = rows, cols = n_cols, points = pts}
    -- The faces run the same way as the lofts to the edge point.
    local edge_point = into_full:point(1, cols)
    if dist(into:point(1, fcols), edge_point) > dist(into:point(1, 1), edge_point)
       or dist(from:point(1, 1), edge_point) > dist(from:point(1, fcols), edge_point) then
      error("hecc_impeller_part.edge_grids: the faces do not run as the edge lofts", 2)
    end
    -- Which edge: the leading edge lies nearer the axis at the hub (the
    -- inlet of a centrifugal impeller).
    local function radius(p) return math.sqrt(p[1] ^ 2 + p[2] ^ 2) end
    local key = radius(edge_point) < radius(into_full:point(1, 1)) and "leading" or "trailing"
    if out[key] then error("hecc_impeller_part.edge_grids: both edges lie at the same end", 2) end
    out[key] = grid
  end
  return out
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
  -- The faces leave out edge_margin of the chord at each edge (the edge
  -- circles: a flank planner's faces end short of the edge). The blade
  -- between the faces' ends — that strip of chord on both sides and the
  -- edge round (or the design set's blunt trailing edge) — is lofted again
  -- to the edge point (`edges`, cosine columns: the flanks meet there and
  -- carry the data's own round): it stands 4-8 mm beyond the line between
  -- the faces' ends, and the worlds and the machine simulation must see it.
  local data, edges = {}, {}
  for _, kind in ipairs{"main", "splitter"} do
    data[kind] = bliskrun.read_hecc(path, {blade = kind, set = set, span_extension = 0, edge_margin = M.edge_margin})
    edges[kind] = bliskrun.read_hecc(path, {blade = kind, set = set, span_extension = 0, edge_margin = 0,
                                            spacing = "cosine", cols = M.edge_cols})
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
  local edge_grids = {}  -- blade 1's: edge_grids[kind].leading / .trailing
  for _, kind in ipairs{"main", "splitter"} do
    edge_grids[kind] = M.edge_grids(turned_grid(edges[kind].pressure, z0):rotated(phi),
                                    turned_grid(edges[kind].suction, z0):rotated(phi), grids[kind].plus,
                                    grids[kind].minus)
  end
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
  -- Blade 1's grid g of a `kind` blade turned onto blade `blade`.
  local function into_place(g, blade, kind)
    local turn = (blade - 1) * pitch_deg + (kind == "splitter" and splitter_turn or 0)
    return turn ~= 0 and g:rotated(turn) or g
  end
  local function grid_of(blade, side, kind) return into_place(grids[kind][side], blade, kind) end
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
  -- The blade between its faces' ends at the "leading" or "trailing" edge
  -- (M.edge_grids), turned into place as the faces are.
  function part:edge_face(blade, edge, kind)
    kind = check(blade, "plus", kind)
    if edge ~= "leading" and edge ~= "trailing" then error("HECC impeller: edge expected 'leading' or 'trailing'", 2) end
    local key = kind .. blade .. edge
    if not designs[key] then designs[key] = into_place(edge_grids[kind][edge], blade, kind):surface() end
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
