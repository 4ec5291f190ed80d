-- The built-in impeller's channels and check surfaces (impeller paper §4),
-- shared by the channel-roughing and flank-finishing recipes and the job.
-- Everything is built for blade 1: the model is exactly symmetric under
-- turns of 360°/N about Z, so blade k's plans are blade 1's turned and the
-- proofs carry over (see turn()).
--
--   local iw = require("impeller_world")
--   local meshes = iw.meshes(imp, 0.05)                -- tessellated once, shared
--   for _, c in ipairs(iw.channels(imp, {gap = 20})) do ... end
--   local world = iw.channel_world(imp, meshes)
--   local world = iw.face_world(imp, meshes, "main", "plus")

local M = {}

-- A blade face as designed. A part whose blades are not ruled is planned on
-- ruled fits of its faces (face) and gives the faces themselves as
-- design_face (scripts/lib/hecc_impeller_part.lua): what the tool is proved
-- against, what is simulated and what flank finishing's residual is measured
-- on. The built-in impeller's faces are the design.
function M.design_face(imp, blade, side, kind)
  if type(imp) == "table" and imp.design_face then return imp:design_face(blade, side, kind) end
  return imp:face(blade, side, kind)
end

-- What closes a blade between its two faces at the "leading" or
-- "trailing" edge, u hub -> tip, pu x pv out of the material. A part that
-- models its edges gives them (edge_face: the HECC impeller's faces end 3 %
-- of the chord short of each edge, and the strip and the round between
-- stand 4-8 mm beyond the line between the faces' ends). The built-in
-- impeller's faces end at the blade's ends, the two end rulings 2h apart
-- (1.8 mm at the leading edge, 2.4 mm at the trailing edge): no round is
-- designed, so the blade ends blunt, the ruled strip between them (so a
-- CAD impeller's, scripts/lib/cad_part.lua, where its faces end apart; nil
-- where they meet: the faces close the blade themselves).
function M.edge_face(imp, blade, edge, kind)
  if type(imp) == "table" and imp.edge_face then return imp:edge_face(blade, edge, kind) end
  if edge ~= "leading" and edge ~= "trailing" then error("impeller_world.edge_face: edge expected 'leading' or 'trailing'", 2) end
  -- The "plus" face's v runs TE -> LE, the "minus" face's LE -> TE: from the
  -- face that runs into the edge to the one that runs out of it. The end
  -- rulings are straight (the faces are ruled) and sampled evenly: the
  -- bicubic through the strip's points is the bilinear strip itself.
  local into, from = M.design_face(imp, blade, "plus", kind), M.design_face(imp, blade, "minus", kind)
  if edge == "trailing" then into, from = from, into end
  return M.strip(function(s) return into:point(s, 1) end, function(s) return from:point(s, 0) end, 4)
end

-- What closes a blade at its tip, between its two faces' tip curves (the
-- faces end at the tip section; an open impeller's blade ends flat there):
-- the ruled strip between the "plus" face's and the "minus" face's tip
-- curves at equal chord parameters (plus v = 1 - t, minus v = t), up to
-- 3.2 mm wide on the built-in impeller, 2.5 on the HECC's, where a ball
-- reaches 0.4 mm in without coming near either face. Not oriented. nil
-- where the two curves meet (a CAD blade's faces carrying its edges).
-- The HECC faces end 3 % of the chord short of the edges: the edges' own
-- tip ends (at most 1.4 mm wide there) stay open.
function M.tip_face(imp, blade, kind)
  local plus, minus = M.design_face(imp, blade, "plus", kind), M.design_face(imp, blade, "minus", kind)
  return M.strip(function(s) return plus:point(1, 1 - s) end, function(s) return minus:point(1, s) end, 41)
end

-- The ruled strip between two curves a(s), b(s), s in [0, 1], sampled at
-- `rows` values of s and 4 points across (s along u, across along v); nil
-- where they lie within 0.01 mm of each other all along (nothing lies
-- between). Curves that meet at their ends only — a CAD blade's tip curves
-- at its edges, its faces carrying the edges — still have the blade
-- between them elsewhere: the strip over the part of s where they are
-- 0.01 mm apart or more (of 201 samples; what it leaves open is narrower
-- than that, inside every mesh's margin).
function M.strip(a_of, b_of, rows)
  local lo, hi
  for i = 0, 200 do
    local a, b = a_of(i / 200), b_of(i / 200)
    if math.sqrt((a[1] - b[1]) ^ 2 + (a[2] - b[2]) ^ 2 + (a[3] - b[3]) ^ 2) >= 0.01 then
      lo, hi = lo or i / 200, i / 200
    end
  end
  if not lo or hi - lo < 1e-9 then return nil end
  local a_at = function(s) return a_of(lo + (hi - lo) * s) end
  local b_at = function(s) return b_of(lo + (hi - lo) * s) end
  local pts = {}
  for i = 0, rows - 1 do
    local a, b = a_at(i / (rows - 1)), b_at(i / (rows - 1))
    for j = 0, 3 do
      local t = j / 3
      pts[#pts + 1] = {a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2]), a[3] + t * (b[3] - a[3])}
    end
  end
  return bliskrun.point_grid{rows = rows, cols = 4, points = pts}:surface()
end

-- A cache of the faces' (as designed), the edges', the tips' and the hub's
-- meshes at one tolerance: meshes.face(kind, blade, side),
-- meshes.edge(kind, blade, edge), meshes.tip(kind, blade) (false where
-- edge_face / tip_face is nil), meshes.hub(); meshes.tol.
function M.meshes(imp, tol)
  local cache, n = {}, imp:blade_count()
  local self = {tol = tol}
  function self.face(kind, blade, side)
    blade = (blade - 1) % n + 1
    local key = kind .. blade .. side
    if not cache[key] then cache[key] = M.design_face(imp, blade, side, kind):tessellate(tol) end
    return cache[key]
  end
  local function closing(key, make)
    if cache[key] == nil then
      local e = make()
      cache[key] = e and e:tessellate(tol) or false
    end
    return cache[key]
  end
  function self.edge(kind, blade, edge)
    blade = (blade - 1) % n + 1
    return closing(kind .. blade .. edge, function() return M.edge_face(imp, blade, edge, kind) end)
  end
  function self.tip(kind, blade)
    blade = (blade - 1) % n + 1
    return closing(kind .. blade .. "tip", function() return M.tip_face(imp, blade, kind) end)
  end
  -- What closes blade `blade` between its faces: {{name, mesh}, ...}, its
  -- edges and tip where it has them.
  function self.closing(kind, blade)
    local out = {}
    for _, edge in ipairs{"leading", "trailing"} do
      local m = self.edge(kind, blade, edge)
      if m then out[#out + 1] = {name = edge .. " edge", mesh = m} end
    end
    local m = self.tip(kind, blade)
    if m then out[#out + 1] = {name = "tip", mesh = m} end
    return out
  end
  function self.hub()
    if not cache.hub then cache.hub = imp:hub():tessellate(tol) end
    return cache.hub
  end
  -- The hub surface `depth` mm inside the hub (into its material): the
  -- surface of revolution.
  function self.hub_inside(depth)
    local key = string.format("hub_inside %.6g", depth)
    if not cache[key] then
      local hub = imp:hub()
      -- Which way the hub's normal points: towards the blades (the channel)
      -- or into the material.
      local q = imp:face(1, "plus", "main"):point(0.5, 0.5)
      local foot = hub:project(q)
      local n = hub:eval(foot.u, foot.v).normal
      local up = (q[1] - foot.point[1]) * n[1] + (q[2] - foot.point[2]) * n[2] + (q[3] - foot.point[3]) * n[3]
      cache[key] = bliskrun.offset_revolution(hub, up > 0 and -depth or depth)
    end
    return cache[key]
  end
  return self
end

local function meridional(p) return math.sqrt(p[1] ^ 2 + p[2] ^ 2), p[3] end

-- Where along a main face's hub curve the splitter starts: the v whose hub
-- point lies `gap` mm (in the meridional plane) short of the splitter's
-- leading edge at the hub — searched on the hub curve, then bisected.
-- Returns that v and the v nearest the edge.
local function v_before(face, inlet_v, outlet_v, edge_point, gap)
  local er, ez = meridional(edge_point)
  local function distance(t)
    local r, z = meridional(face:point(0, inlet_v + (outlet_v - inlet_v) * t))
    return math.sqrt((r - er) ^ 2 + (z - ez) ^ 2)
  end
  local best, best_t = math.huge, 0
  for i = 0, 400 do
    local d = distance(i / 400)
    if d < best then best, best_t = d, i / 400 end
  end
  local a, b = 0, best_t  -- the distance falls from the inlet to the edge
  if distance(a) < gap then error("the splitter starts within " .. gap .. " mm of the inlet", 0) end
  for _ = 1, 60 do
    local m = 0.5 * (a + b)
    if distance(m) > gap then a = m else b = m end
  end
  return inlet_v + (outlet_v - inlet_v) * a, inlet_v + (outlet_v - inlet_v) * best_t
end

-- The channel between main blades 1 and 2 as the channel planner takes it
-- (bliskrun.channel_rough's left/left_v/right/right_v). Without splitters it
-- is one channel; with them, three: "inlet" (main 1 minus face to main 2 plus
-- face, stopping o.gap mm of meridional length short of the splitter's
-- leading edge at the hub — the edge leans forward above the hub), "left"
-- (main 1 to the splitter) and "right" (the splitter to main 2). The "minus"
-- face of a blade looks towards the next blade (+θ), its v from inlet to
-- outlet; the "plus" face looks back, its v from outlet to inlet.
function M.channels(imp, o)
  o = o or {}
  local left_main, right_main = imp:face(1, "minus", "main"), imp:face(2, "plus", "main")
  if not imp:has_splitter() then
    return {{name = "channel", left = left_main, left_v = {0, 1}, right = right_main, right_v = {1, 0}}}
  end
  local split_plus, split_minus = imp:face(1, "plus", "splitter"), imp:face(1, "minus", "splitter")
  local gap = o.gap or 20
  local left_end, left_split = v_before(left_main, 0, 1, split_minus:point(0, 0), gap)
  local right_end, right_split = v_before(right_main, 1, 0, split_plus:point(0, 1), gap)
  return {
    {name = "inlet", left = left_main, left_v = {0, left_end}, right = right_main, right_v = {1, right_end}},
    {name = "left", left = left_main, left_v = {left_split, 1}, right = split_plus, right_v = {1, 0}},
    {name = "right", left = split_minus, left_v = {0, 1}, right = right_main, right_v = {right_split, 0}},
  }
end

-- The listed blades ({kind, blade}) whole: both faces, both edges and the
-- tip (edge_face, tip_face: what closes the blade between its faces).
local function add_faces(surfaces, imp, meshes, list, parts)
  for _, f in ipairs(list) do
    local kind, blade = f[1], f[2]
    if kind == "main" or imp:has_splitter() then
      for _, side in ipairs{"plus", "minus"} do
        surfaces[#surfaces + 1] = {name = string.format("%s %d %s", kind, blade, side),
                                   mesh = meshes.face(kind, blade, side), parts = parts, margin = meshes.tol}
      end
      for _, c in ipairs(meshes.closing(kind, blade)) do
        surfaces[#surfaces + 1] = {name = string.format("%s %d %s", kind, blade, c.name), mesh = c.mesh,
                                   parts = parts, margin = meshes.tol}
      end
    end
  end
end

-- What the channel between main blades 1 and 2 is proved against: both faces,
-- edges and tip of both main blades and of the splitter between them, and
-- the hub, for every tool part (the tessellation tolerance added as margin).
--
-- o.hub_finish = {cutter_clearance = c}: the channel's passes on the hub
-- finish it (bliskrun.channel_rough's hub_stock = 0), so the ball touches
-- the hub. The hub then stands for the shank and holder only, and for the
-- cutter the hub less (c + allowance) — the surface of revolution that far
-- inside it, measured analytically (no mesh: the cutter's sphere cover
-- against the meridian, core/geometry/revolution_distance.h): a cutter kept
-- c from it is proved to reach no deeper than `allowance` into the hub, on
-- every pose, motion, step, link and lead: a guard against gross errors (a
-- flute, step or link dipping into the hub), as the roughing's 0.2 mm
-- clearance was. What the ball really takes (its centre kept within 0.005
-- mm of the hub's offset by the planner) the job's simulation measures,
-- and the job fails on any overcut of the hub. The allowance is the slack
-- conservative advancement steps by: each step of a motion proof still
-- queries the faces' meshes.
M.hub_finish_allowance = 0.3
function M.channel_world(imp, meshes, o)
  local surfaces = {}
  if o and o.hub_finish then
    surfaces[1] = {name = "hub", mesh = meshes.hub(), parts = {"shank", "holder"}, margin = meshes.tol}
    surfaces[2] = {name = "hub (cutter, less the allowance)",
                   revolution = meshes.hub_inside(o.hub_finish.cutter_clearance + M.hub_finish_allowance),
                   parts = {"cutter"}}
  else
    surfaces[1] = {name = "hub", mesh = meshes.hub(), margin = meshes.tol}
  end
  add_faces(surfaces, imp, meshes, {{"main", 1}, {"main", 2}, {"splitter", 1}})
  return bliskrun.collision_world{surfaces = surfaces}
end

-- What flank finishing of one face of blade 1 is proved against: the main
-- blades and splitters either side, faces, edges and tips (every tool part), this
-- face, the blade's other face, its edges and tip and the hub (shank and holder
-- only: the cutter is meant to touch them — the face up to its end, where
-- the edge begins; the job's simulation measures what it cuts of the edges).
-- o.hub_cutter = true (point milling, whose ball is not meant to touch the
-- hub): the hub also for the cutter, as the surface of revolution itself
-- (analytic, no mesh); a number d (point milling carried down to the
-- fillet, whose ball touches the hub and whose planner guards it): the hub
-- less d for the cutter.
function M.face_world(imp, meshes, kind, side, o)
  local n = imp:blade_count()
  local other = side == "plus" and "minus" or "plus"
  local surfaces = {
    {name = "this face", mesh = meshes.face(kind, 1, side), parts = {"shank", "holder"}, margin = meshes.tol},
    {name = "own other face", mesh = meshes.face(kind, 1, other), parts = {"shank", "holder"}, margin = meshes.tol},
    {name = "hub", mesh = meshes.hub(), parts = {"shank", "holder"}, margin = meshes.tol}}
  for _, c in ipairs(meshes.closing(kind, 1)) do
    surfaces[#surfaces + 1] = {name = "own " .. c.name, mesh = c.mesh, parts = {"shank", "holder"}, margin = meshes.tol}
  end
  if o and o.hub_cutter then
    local depth = type(o.hub_cutter) == "number" and o.hub_cutter or 0
    surfaces[#surfaces + 1] = {name = depth > 0 and "hub (cutter, less the allowance)" or "hub (cutter)",
                               revolution = meshes.hub_inside(depth), parts = {"cutter"}}
  end
  local neighbours = kind == "main" and {{"main", 2}, {"main", n}, {"splitter", 1}, {"splitter", n}}
                                     or {{"main", 1}, {"main", 2}, {"splitter", 2}, {"splitter", n}}
  add_faces(surfaces, imp, meshes, neighbours)
  return bliskrun.collision_world{surfaces = surfaces}
end

-- Everything near blade 1 — main blades and splitters N, 1 and 2 (faces,
-- edges, tips) and the hub, every tool part: what a link's first and last leg (out of, or into,
-- blade 1's channel or faces) is proved against.
function M.neighbourhood(imp, meshes)
  local n = imp:blade_count()
  local surfaces = {{name = "hub", mesh = meshes.hub(), margin = meshes.tol}}
  add_faces(surfaces, imp, meshes, {{"main", n}, {"main", 1}, {"main", 2}, {"splitter", n}, {"splitter", 1},
                                    {"splitter", 2}})
  return bliskrun.collision_world{surfaces = surfaces}
end

-- Every blade (faces, edges, tips) and the hub: what a link's travel over the part is proved
-- against (coarse meshes; their tolerance is added as margin).
function M.whole(imp, meshes)
  local surfaces = {{name = "hub", mesh = meshes.hub(), margin = meshes.tol}}
  local list = {}
  for b = 1, imp:blade_count() do
    list[#list + 1] = {"main", b}
    list[#list + 1] = {"splitter", b}
  end
  add_faces(surfaces, imp, meshes, list)
  return bliskrun.collision_world{surfaces = surfaces}
end

-- The impeller's blades as bodies of the machine simulation (post.write's
-- `part`): all main blades' and splitters' faces as one mesh body "blades",
-- each blade's named after it (mesh_names: "blade 3", "splitter 3"), in the
-- part frame, from the same cache the worlds take (meshes = iw.meshes(imp,
-- tol)), the tolerance as margin. One body, not one per blade: every
-- impeller blade's box holds the tool (the blades wrap round the axis), so
-- each of 30 blade bodies was sampled against every machine body and tool
-- part on its own (579 pairs; the HECC job's post over the hour), where one
-- hierarchy over all of them prunes the far blades at once.
-- What closes each blade between its faces (edges and tip: meshes.closing)
-- is a body "blade edges" of its own, from `closing` (a cache of coarser
-- meshes, default iw.meshes(imp, 0.2), its tolerance the margin): at the
-- faces' 0.05 mm the HECC edges' rounds are 14 052 triangles a main blade
-- and splitter, and the one body's machine simulation cost 5x the CPU of
-- the faces alone (HECC blades=1, 7.7 -> 39.0 s), as a body of its own at
-- 0.2 mm 1.8x (13.9 s); a distance to it counts 0.2 mm nearer.
-- And the hub, a body "hub" of its own (every world checks the shank and
-- holder against it; no stock body stands for it, as the blisk's disc does).
function M.part_bodies(imp, meshes, closing)
  closing = closing or M.meshes(imp, 0.2)
  local body = {name = "blades", meshes = {}, mesh_names = {}, margin = meshes.tol}
  local ends = {name = "blade edges", meshes = {}, mesh_names = {}, margin = closing.tol}
  for b = 1, imp:blade_count() do
    for _, kind in ipairs(imp:has_splitter() and {"main", "splitter"} or {"main"}) do
      local name = (kind == "main" and "blade " or "splitter ") .. b
      for _, face in ipairs{"plus", "minus"} do
        body.meshes[#body.meshes + 1] = meshes.face(kind, b, face)
        body.mesh_names[#body.mesh_names + 1] = name
      end
      for _, c in ipairs(closing.closing(kind, b)) do
        ends.meshes[#ends.meshes + 1] = c.mesh
        ends.mesh_names[#ends.mesh_names + 1] = name
      end
    end
  end
  return {body, ends, {name = "hub", mesh = meshes.hub(), margin = meshes.tol}}
end

-- A 2-D polyline {{x, y}, ...} with its arc length: line.arc[i] at point
-- i, line.arc_of(x, y) the arc length of the polyline point nearest (x, y),
-- line.at_arc(s) -> x, y (clamped to the ends). Meridian profiles of the
-- clearance surface and of a part's flow path.
function M.polyline(points)
  local arc = {0}
  for i = 2, #points do
    arc[i] = arc[i - 1] + math.sqrt((points[i][1] - points[i - 1][1]) ^ 2 + (points[i][2] - points[i - 1][2]) ^ 2)
  end
  local line = {arc = arc}
  function line.arc_of(x, y)
    local best, best_s = math.huge, 0
    for i = 2, #points do
      local a, b = points[i - 1], points[i]
      local dx, dy = b[1] - a[1], b[2] - a[2]
      local t = math.max(0, math.min(1, ((x - a[1]) * dx + (y - a[2]) * dy) / (dx * dx + dy * dy)))
      local d = (a[1] + t * dx - x) ^ 2 + (a[2] + t * dy - y) ^ 2
      if d < best then best, best_s = d, arc[i - 1] + t * (arc[i] - arc[i - 1]) end
    end
    return best_s
  end
  function line.at_arc(s)
    for i = 2, #points do
      if s <= arc[i] or i == #points then
        local t = math.max(0, math.min(1, (s - arc[i - 1]) / (arc[i] - arc[i - 1])))
        return points[i - 1][1] + t * (points[i][1] - points[i - 1][1]), points[i - 1][2] + t * (points[i][2] - points[i - 1][2])
      end
    end
  end
  return line
end

-- The clearance surface over an impeller: the surface of revolution `margin`
-- mm above the part's meridional outline (hub, shroud edges and leading
-- edges of main blades and splitters) — the upper envelope of discs of that
-- radius about the outline's points, profile z(r) sampled every 1 mm of r,
-- constant towards the axis inside the hub's nose, and a wall at the
-- outermost radius. A tool backed out along its axis meets it close above
-- the channel, not on a sphere round the whole part: at the inlet, where the
-- axes lie nearly horizontal, a sphere would put the gauge point out of a
-- trunnion machine's Z travel. Links travel over it (job.lua).
--   env.back_out(pose) -> the pose moved up its axis onto the surface, or nil
--   env.travel(out, into) -> points over the surface from out to into, into last
function M.envelope(imp, margin)
  local pts = {}
  local function keep(p) pts[#pts + 1] = {math.sqrt(p[1] ^ 2 + p[2] ^ 2), p[3]} end
  for _, q in ipairs(imp:hub_meridian()) do pts[#pts + 1] = {q[2], q[1]} end
  for _, kind in ipairs(imp:has_splitter() and {"main", "splitter"} or {"main"}) do
    for _, side in ipairs{"plus", "minus"} do
      local face = M.design_face(imp, 1, side, kind)
      for i = 0, 200 do keep(face:point(1, i / 200)) end               -- the shroud edge
      for i = 0, 50 do keep(face:point(i / 50, 0)); keep(face:point(i / 50, 1)) end  -- both blade ends
    end
  end
  local r_max, z_min = 0, math.huge
  for _, q in ipairs(pts) do r_max, z_min = math.max(r_max, q[1]), math.min(z_min, q[2]) end
  local wall = r_max + margin           -- outside this radius everything is clear
  local n = math.ceil(wall)
  local zs = {}                          -- zs[i + 1] = z of the surface at r = i * wall / n
  for i = 0, n do
    local r, z = i * wall / n, -math.huge
    for _, q in ipairs(pts) do
      local d = math.abs(q[1] - r)
      if d <= margin then z = math.max(z, q[2] + math.sqrt(margin * margin - d * d)) end
    end
    zs[i + 1] = z
  end
  local first = 1                        -- inside the hub's nose no points: constant towards the axis
  while zs[first] == -math.huge do first = first + 1 end
  for i = 1, first - 1 do zs[i] = zs[first] end
  for i = 2, n + 1 do if zs[i] == -math.huge then zs[i] = zs[i - 1] end end
  local function z_at(r)
    local x = r / wall * n
    local i = math.min(n - 1, math.floor(x))
    local f = x - i
    return zs[i + 1] * (1 - f) + zs[i + 2] * f
  end
  local function outside(p)
    local r = math.sqrt(p[1] ^ 2 + p[2] ^ 2)
    return r >= wall or p[3] >= z_at(r)
  end
  -- The profile as a polyline with arc length: over the top from the axis
  -- to the wall, then down the wall to below the part.
  local prof = {}
  for i = 0, n do prof[#prof + 1] = {i * wall / n, zs[i + 1]} end
  prof[#prof + 1] = {wall, z_min - margin}
  local line = M.polyline(prof)
  local s_of, at_s = line.arc_of, line.at_arc
  local env = {margin = margin, wall = wall, top = zs[1], outside = outside}
  function env.back_out(pose)
    local p, a = pose.tip, pose.axis
    local function at(t) return {p[1] + t * a[1], p[2] + t * a[2], p[3] + t * a[3]} end
    local lo, hi = 0, nil
    if outside(p) then return {tip = p, axis = a} end
    for t = 0.5, 2000, 0.5 do
      if outside(at(t)) then hi = t; break end
      lo = t
    end
    if not hi then return nil end
    for _ = 1, 30 do
      local m = 0.5 * (lo + hi)
      if outside(at(m)) then hi = m else lo = m end
    end
    return {tip = at(hi), axis = a}
  end
  function env.travel(out, into)
    local function polar(p) return math.atan(p[2], p[1]), s_of(math.sqrt(p[1] ^ 2 + p[2] ^ 2), p[3]) end
    local t1, s1 = polar(out.tip)
    local t2, s2 = polar(into.tip)
    local dt = t2 - t1
    while dt > math.pi do dt = dt - 2 * math.pi end
    while dt < -math.pi do dt = dt + 2 * math.pi end
    -- Steps of at most 5 mm along the surface (round at the larger radius).
    local r1, r2 = math.sqrt(out.tip[1] ^ 2 + out.tip[2] ^ 2), math.sqrt(into.tip[1] ^ 2 + into.tip[2] ^ 2)
    local length = math.abs(s2 - s1) + math.abs(dt) * math.max(r1, r2)
    local steps = math.max(1, math.ceil(length / 5))
    local points = {}
    for i = 1, steps do
      local f = i / steps
      if i == steps then
        points[i] = into.tip
      else
        local r, z = at_s(s1 + f * (s2 - s1))
        local t = t1 + f * dt
        points[i] = {r * math.cos(t), r * math.sin(t), z}
      end
    end
    return points
  end
  return env
end

-- A pose (or point, with axis nil) turned by `angle` radians about Z.
function M.turn(pose, angle)
  local c, s = math.cos(angle), math.sin(angle)
  local function rot(v) return {c * v[1] - s * v[2], s * v[1] + c * v[2], v[3]} end
  return {tip = rot(pose.tip), axis = rot(pose.axis)}
end

-- The angle that turns blade 1 onto blade k.
function M.pitch_angle(imp, k) return 2 * math.pi * (k - 1) / imp:blade_count() end

return M
