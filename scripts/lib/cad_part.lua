-- Your own blisk from a STEP or IGES file, for the blisk recipes' --set
-- part=cad (docs/lua_api/cad.md, "bliskrun.cad_blisk"):
--
--   local cad_part = require("cad_part")
--   local opt = require("recipe_options")(cad_part.with_blisk_options{...the recipe's own options...})
--   local blisk = opt.part == "cad" and cad_part.blisk(opt) or bliskrun.blisk{}
--
-- The blade is the file's one face (a closed airfoil, split by
-- bliskrun.cad_blade) or its two flank faces (told apart by
-- bliskrun.cad_blisk); hub and casing are meridian curves, from their own
-- files or from the blade's file.

local M = {}

-- The options of part=cad, added to a recipe's declaration.
M.blisk_options = {
  part = {type = "string", default = "builtin", choices = {"builtin", "cad"},
          help = "the built-in blisk, or your own from STEP/IGES (cad: --set cad=FILE --set blade_count=N)"},
  cad = {type = "string", help = "part=cad: a STEP or IGES file with one blade: one closed airfoil face or its two flank faces"},
  cad_faces = {type = "string", default_text = "the file's faces",
               help = "part=cad: the blade's face names in the file, one (airfoil) or two (flanks), comma separated"},
  cad_hub = {type = "string", default_text = "cad's curves",
             help = "part=cad: a STEP or IGES file whose first curve is the hub's meridian"},
  cad_casing = {type = "string", default_text = "cad's curves",
                help = "part=cad: a STEP or IGES file whose first curve is the casing's (blade tip's) meridian"},
  cad_coordinates = {type = "string", default = "cartesian", choices = {"cartesian", "x_rtheta_r"},
                     help = "part=cad: cartesian (axis Z) or x axial, y = R theta, z = R"},
  cad_axial_origin = {type = "number", unit = "mm", default = 0, range = {-1e5, 1e5},
                      help = "part=cad, x_rtheta_r: the file's axial coordinate that becomes z = 0"},
  blade_count = {type = "integer", range = {2, 400}, help = "part=cad: the number of blades"},
}

-- `own` (a recipe's option declaration) with blisk_options added.
function M.with_blisk_options(own)
  for k, v in pairs(M.blisk_options) do
    assert(own[k] == nil, "option " .. k .. " is declared twice")
    own[k] = v
  end
  return own
end

local function fail(fmt, ...) error(string.format(fmt, ...), 0) end

-- The blade's faces of `model` (read_cad's), by cad_faces or all of them.
local function blade_faces(model, file, names)
  if not names then
    if #model.faces ~= 1 and #model.faces ~= 2 then
      local all = {}
      for _, f in ipairs(model.faces) do all[#all + 1] = f.name end
      fail("--set cad=%s: expected one face (the closed airfoil) or two (the flanks); the file has %d (%s): "
           .. "name them with --set cad_faces=", file, #model.faces, table.concat(all, ", "))
    end
    return model.faces
  end
  local faces = {}
  for name in names:gmatch("[^,]+") do
    name = name:match("^%s*(.-)%s*$")
    local found
    for _, f in ipairs(model.faces) do if f.name == name then found = f end end
    if not found then fail("--set cad_faces=%s: %s has no face named '%s'", names, file, name) end
    faces[#faces + 1] = found
  end
  if #faces ~= 1 and #faces ~= 2 then fail("--set cad_faces=%s: expected one or two names, got %d", names, #faces) end
  return faces
end

-- A curve's mean distance from the axis (Z, or x for x_rtheta_r), over the
-- points of it that Curve:eval reaches (t in [0, 1]).
local function mean_radius(curve, coordinates)
  local sum, n = 0, 0
  for i = 0, 10 do
    local ok, d = pcall(curve.eval, curve, i / 10)
    if ok then
      local p = d.point
      sum, n = sum + (coordinates == "x_rtheta_r" and math.sqrt(p.y ^ 2 + p.z ^ 2) or math.sqrt(p.x ^ 2 + p.y ^ 2)), n + 1
    end
  end
  return n > 0 and sum / n or 0
end

-- Hub and casing meridians: from their files, else the blade file's two
-- curves (named hub and casing, else the lower one is the hub).
local function meridians(opt, model)
  local function first_curve(path, what)
    local c = bliskrun.read_cad(path).curves[1]
    if not c then fail("--set cad_%s=%s: expected a file with the %s's meridian curve; it has none", what, path, what) end
    return c.curve
  end
  local hub = opt.cad_hub and first_curve(opt.cad_hub, "hub")
  local casing = opt.cad_casing and first_curve(opt.cad_casing, "casing")
  if hub and casing then return hub, casing end
  local named = {}
  for _, c in ipairs(model.curves) do
    local n = c.name:lower()
    if n:find("hub", 1, true) then named.hub = c.curve elseif n:find("casing", 1, true) or n:find("shroud", 1, true) then
      named.casing = c.curve end
  end
  if not (named.hub and named.casing) and #model.curves == 2 then
    local a, b = model.curves[1].curve, model.curves[2].curve
    if mean_radius(a, opt.cad_coordinates) > mean_radius(b, opt.cad_coordinates) then a, b = b, a end
    named.hub, named.casing = a, b
  end
  hub, casing = hub or named.hub, casing or named.casing
  if not hub or not casing then
    fail("--set cad=%s: its %d curves do not say which are the hub and the casing (two curves, or curves named hub "
         .. "and casing, are expected): give --set cad_hub=FILE and --set cad_casing=FILE", opt.cad, #model.curves)
  end
  return hub, casing
end

-- The blisk of --set part=cad (opt: the recipe's options with blisk_options).
function M.blisk(opt)
  if not opt.cad then fail("--set part=cad needs --set cad=FILE (the blade's STEP or IGES file)") end
  if not opt.blade_count then fail("--set part=cad needs --set blade_count=N (the number of blades)") end
  local model = bliskrun.read_cad(opt.cad)
  local faces = blade_faces(model, opt.cad, opt.cad_faces)
  local hub, casing = meridians(opt, model)
  local args = {blade_count = opt.blade_count, hub = hub, casing = casing, coordinates = opt.cad_coordinates,
                axial_origin = opt.cad_axial_origin, name = opt.cad}
  if #faces == 1 then
    args.blade = bliskrun.cad_blade{surface = faces[1].surface, coordinates = opt.cad_coordinates,
                                    axial_origin = opt.cad_axial_origin}
  else
    args.faces = {faces[1].surface, faces[2].surface}
  end
  return bliskrun.cad_blisk(args)
end

-- ---- impellers ---------------------------------------------------------------

local function sub(a, b) return {a[1] - b[1], a[2] - b[2], a[3] - b[3]} end
local function dot(a, b) return a[1] * b[1] + a[2] * b[2] + a[3] * b[3] end
local function cross(a, b) return {a[2] * b[3] - a[3] * b[2], a[3] * b[1] - a[1] * b[3], a[1] * b[2] - a[2] * b[1]} end
local function radius(p) return math.sqrt(p[1] ^ 2 + p[2] ^ 2) end

-- A hub of revolution about Z from a meridian Curve (points (x, y, z):
-- axial z, radius hypot(x, y), 200 points of its [0, 1]) or a surface of
-- revolution as it is. Returns the surface and its meridian {{z, r}, ...}
-- from the outlet (largest radius) to the inlet, as bliskrun.impeller's.
local function impeller_hub(hub, what)
  local meridian = {}
  -- A Surface has :point, a Curve only :eval and :project.
  local is_surface = type(hub) == "userdata" and hub.point ~= nil
  if type(hub) == "userdata" and not is_surface and hub.eval ~= nil then
    for i = 0, 199 do
      local p = hub:eval(i / 199).point
      meridian[#meridian + 1] = {p[3], radius(p)}
    end
  elseif is_surface then
    for i = 0, 199 do
      local p = hub:point(i / 199, 0)
      meridian[#meridian + 1] = {p[3], radius(p)}
    end
  else
    fail("%s: expected the hub's meridian as a Curve (a read_cad curve) or a surface of revolution, got %s", what,
         tostring(hub))
  end
  if meridian[1][2] < meridian[#meridian][2] then
    local r = {}
    for i = #meridian, 1, -1 do r[#r + 1] = meridian[i] end
    meridian = r
  end
  return bliskrun.surface_of_revolution{meridian = meridian}, meridian
end

-- The two faces of one blade (surfaces, or read_cad faces), oriented as the
-- built-in impeller's (core/parts/impeller.h): u from the hub (the edge
-- nearest the hub surface) to the shroud, pu x pv away from the other face
-- (out of the material); then "plus" is the face whose v runs trailing ->
-- leading edge (radius decreasing along v: a centrifugal impeller's leading
-- edge is its inner end) and "minus" the other. Exact: the faces' parameters
-- swapped or reversed (Surface:reoriented), nothing re-fitted.
local function impeller_blade(faces, hub, what)
  if type(faces) ~= "table" or #faces ~= 2 then fail("%s: expected the blade's two faces", what) end
  local s = {}
  for i = 1, 2 do
    local f = faces[i]
    if type(f) == "table" then f = f.surface end
    if type(f) ~= "userdata" then fail("%s: face %d: expected a Surface or a read_cad face", what, i) end
    s[i] = f
  end
  for i = 1, 2 do
    -- The hub edge: the edge whose middle is nearest the hub.
    local best, edge = math.huge, nil
    for _, e in ipairs{{"u0", 0, 0.5}, {"u1", 1, 0.5}, {"v0", 0.5, 0}, {"v1", 0.5, 1}} do
      local foot = hub:project(s[i]:point(e[2], e[3]))
      if foot and foot.distance < best then best, edge = foot.distance, e[1] end
    end
    s[i] = s[i]:reoriented{swap = edge == "v0" or edge == "v1", flip_u = edge == "u1" or edge == "v1"}
  end
  for i = 1, 2 do
    local d = s[i]:eval(0.5, 0.5)
    local foot = s[3 - i]:project(d.point)
    if not foot or foot.on_boundary then
      fail("%s: face %d's middle has no foot inside face %d: the two faces are not one blade's", what, i, 3 - i)
    end
    if dot(cross(d.pu, d.pv), sub(foot.point, d.point)) > 0 then s[i] = s[i]:reoriented{flip_v = true} end
  end
  local out = {}
  for i = 1, 2 do
    local te_to_le = radius(s[i]:point(0.5, 0)) > radius(s[i]:point(0.5, 1))
    local side = te_to_le and "plus" or "minus"
    if out[side] then fail("%s: both faces run the same way along the chord: not the two faces of one blade", what) end
    out[side] = s[i]
  end
  return out
end

-- An impeller from CAD faces, the part the impeller operations take
-- (scripts/lib/impeller_world.lua, job/impeller_ops.lua; the methods of
-- bliskrun.impeller{} that they call, as scripts/lib/hecc_impeller_part.lua):
--
--   local part = cad_part.impeller{blade = {face, face}, splitter = {face, face} (optional),
--                                  hub = curve_or_revolution, blade_count = N, rows = 30, cols = 120}
--   part:face(k, "plus"|"minus", "main"|"splitter")  -> the ruled face flank milling plans on
--   part:design_face(k, side, kind)                  -> the CAD face itself, turned into place
--   part:ruled_fit(kind, side) -> {max, rms, worst_row, worst_col}: how far the CAD face is from
--                                  ruled (bliskrun.fit_ruled on rows x cols of its points)
--   part:hub(), part:hub_meridian(), part:blade_count(), part:has_splitter(), part:outer_radius()
--
-- Blade k is blade 1 turned by (k - 1) 360/N deg about +Z (exactly:
-- Surface:rotated); splitter k lies where the file puts splitter 1, turned
-- as blade k. Faces that are ruled (CAD ruled surfaces, or B-splines linear
-- along the span) are planned on their ruled fit, which is then the face to
-- round-off; general faces on their least-squares ruled fit, the fit's
-- error in ruled_fit.
function M.impeller(o)
  local what = "cad_part.impeller"
  for k in pairs(o) do
    if not ({blade = true, splitter = true, hub = true, blade_count = true, rows = true, cols = true, name = true})[k] then
      error(string.format("%s: unknown option '%s', expected one of: blade, splitter, hub, blade_count, rows, cols, name",
                          what, tostring(k)), 2)
    end
  end
  local n = o.blade_count
  if math.type(n) ~= "integer" or n < 2 or n > 400 then
    fail("%s: blade_count: expected an integer in [2, 400], got %s", what, tostring(n))
  end
  local rows, cols = o.rows or 30, o.cols or 120
  if not o.hub then fail("%s: hub: expected the hub's meridian, got none", what) end
  local hub, meridian = impeller_hub(o.hub, what .. ": hub")
  local blades = {main = impeller_blade(o.blade, hub, what .. ": blade")}
  if o.splitter then blades.splitter = impeller_blade(o.splitter, hub, what .. ": splitter") end
  local pitch = 360 / n
  local fits, ruled, designs, faces = {}, {}, {}, {}
  for kind, b in pairs(blades) do
    fits[kind], ruled[kind] = {}, {}
    for side, s in pairs(b) do
      local pts = {}
      for i = 0, rows - 1 do
        for j = 0, cols - 1 do pts[#pts + 1] = s:point(i / (rows - 1), j / (cols - 1)) end
      end
      local f = bliskrun.fit_ruled(bliskrun.point_grid{rows = rows, cols = cols, points = pts})
      fits[kind][side] = {max = f.max, rms = f.rms, worst_row = f.worst_row, worst_col = f.worst_col}
      ruled[kind][side] = f.surface
    end
  end
  local part = {}
  local function check(blade, side, kind)
    kind = kind or "main"
    if math.type(blade) ~= "integer" or blade < 1 or blade > n then
      error(string.format("CAD impeller: blade %s does not exist; the part has %d", tostring(blade), n), 3)
    end
    if side ~= "plus" and side ~= "minus" then error("CAD impeller: side expected 'plus' or 'minus'", 3) end
    if kind ~= "main" and kind ~= "splitter" then error("CAD impeller: kind expected 'main' or 'splitter'", 3) end
    if not blades[kind] then error("CAD impeller: the part has no splitter blades", 3) end
    return kind
  end
  local function turned(cache, from, blade, side, kind)
    local key = kind .. blade .. side
    if not cache[key] then
      local s = from[kind][side]
      cache[key] = blade == 1 and s or s:rotated((blade - 1) * pitch)
    end
    return cache[key]
  end
  function part:face(blade, side, kind)
    kind = check(blade, side, kind)
    return turned(faces, ruled, blade, side, kind)
  end
  function part:design_face(blade, side, kind)
    kind = check(blade, side, kind)
    return turned(designs, blades, blade, side, kind)
  end
  function part:ruled_fit(kind, side) return fits[kind][side] end
  function part:hub() return hub end
  function part:hub_meridian() return meridian end
  function part:blade_count() return n end
  function part:has_splitter() return blades.splitter ~= nil end
  -- The largest distance of a blade point from the axis (as bliskrun.impeller's).
  function part:outer_radius()
    local r = 0
    for _, b in pairs(blades) do
      for _, s in pairs(b) do
        for i = 0, 20 do for j = 0, 40 do r = math.max(r, radius(s:point(i / 20, j / 40))) end end
      end
    end
    return r
  end
  return setmetatable(part, {__tostring = function()
    return string.format("CAD impeller%s: %d blades%s, ruled fits of the CAD faces", o.name and " (" .. o.name .. ")" or "",
                         n, blades.splitter and " + splitters" or "")
  end})
end

-- Refuses cad* options on a run of the built-in part.
function M.check_unused(opt)
  if opt.part ~= "cad" then
    for _, k in ipairs{"cad", "cad_faces", "cad_hub", "cad_casing", "blade_count"} do
      if opt[k] ~= nil then fail("--set %s is for --set part=cad (this run is on the built-in blisk)", k) end
    end
  end
end

return M
