-- A planned job simulated (core/sim; Job methods, scripts/lib/job.lua is the
-- entry): a blisk's units each after all the moves that machine them (and
-- the seams between them, job/seams.lua), an impeller's blade-1 faces and
-- one pitch of its hub under each operation, the links and the whole job;
-- and the stops after it — nothing is posted after an overcut the
-- operations do not allow.
local options = require("job.options")
local seams = require("job.seams")
local Job = require("job.model").Job

local check_options, positive = options.check, options.positive

local M = {}

local function integer_2(v) if math.type(v) ~= "integer" or v < 2 then return "expected an integer >= 2" end end

-- j:simulate's options (j:run checks its `simulate` table against them).
M.options = {
  samples_u = {type = "number", check = integer_2},
  samples_v = {type = "number", check = integer_2},
  edge_samples_u = {type = "number", check = integer_2},
  edge_samples_v = {type = "number", check = integer_2},
  sweep_step = {type = "number", check = positive},
  search_above = {type = "number", check = positive},
  search_below = {type = "number", check = positive},
  seams = {type = "boolean"},
  seam_spacing = {type = "number", check = positive},
  rough_samples = {type = "table", check = function(v)
    if not (math.type(v[1]) == "integer" and math.type(v[2]) == "integer" and v[1] >= 2 and v[2] >= 2) then
      return "expected {span, chord} integers >= 2"
    end
  end},
}

-- The independent simulation (core/sim) of every flank after all the moves
-- that machine it: o = {samples_u = 200, samples_v = 1000}. Returns per flank
-- {operation, blade, side, undercut_max, undercut_mean, overcut, overcut_move
-- (index in the job's moves), overcut_motion} and the totals (undercut_max,
-- overcut, where), and for a blisk the seams between the operations'
-- windows (simulate_seams; o.seams = false skips them, o.seam_spacing its
-- spacing): out.seams, out.seam_failures. Link moves stay 0.05 mm or more
-- off every surface (proved in plan()), so they remove nothing and need no
-- sweep. An
-- impeller job is simulated on its surfaces instead (simulate_impeller;
-- sweep_step, search_above and search_below apply there).
function Job:simulate(o)
  o = o or {}
  check_options("job:simulate", o, M.options, 2)
  if not self.planned then error("job:simulate: plan the job first (j:plan())", 2) end
  if self.part_kind == "impeller" then return self:simulate_impeller(o) end
  local out = {flanks = {}, undercut_max = 0, overcut = 0}
  -- A turned plan (a periodic operation's other blades) is its first
  -- blade's path turned with the blade: simulated once.
  local done = {}
  for _, f in ipairs(self.planned.flanks) do
    local sim = done[f.plan]
    if not sim then
      if f.kind == "rough_channels" then
        -- The stock the roughing leaves on both flanks and the hub
        -- (job.rough_channels' rough_stock), apart from the finishers'
        -- figures: it is what they meet, not what the job leaves.
        sim = f.plan:simulate{samples = o.rough_samples}
      elseif f.kind == "edge_finish" then
        sim = f.plan:simulate{samples_u = o.edge_samples_u or 200, samples_v = o.edge_samples_v or 400,
                              flanks = f.design_flanks}
      elseif f.kind == "hub_finish" then
        -- The root strip above the fillet row and the channel floor; the
        -- fillet itself (the ball's radius in the sharp corner) apart.
        local h = f.plan:simulate{}
        sim = {undercut_max = math.max(h.strip.left_max, h.floor.left_max),
               undercut_mean = 0.5 * (h.strip.left_mean + h.floor.left_mean),
               overcut = math.min(h.root_overcut, h.floor_overcut), unreached = h.strip.unreached + h.floor.unreached,
               fillet_left_max = h.fillet.left_max}
      else
        sim = f.plan:simulate{samples_u = o.samples_u or 200, samples_v = o.samples_v or 1000}
      end
      done[f.plan] = sim
    end
    local r = {operation = f.operation, kind = f.kind, blade = f.blade, side = f.side, undercut_max = sim.undercut_max,
               undercut_mean = sim.undercut_mean, overcut = sim.overcut, overcut_motion = sim.overcut_motion,
               overcut_move = sim.overcut_move and f.first_move + sim.overcut_move - 1 or nil, map = sim.map,
               flank_overcut = sim.flank_overcut, turned_from = f.turned_from, unreached = sim.unreached,
               fillet_left_max = sim.fillet_left_max, stock = f.kind == "rough_channels" and sim or nil}
    if sim.flank_overcut and sim.flank_overcut < r.overcut then r.overcut = sim.flank_overcut end
    out.flanks[#out.flanks + 1] = r
    if f.kind ~= "rough_channels" and sim.undercut_max > out.undercut_max then out.undercut_max = sim.undercut_max end
    if sim.overcut < out.overcut then
      out.overcut = sim.overcut
      out.overcut_at = r
    end
  end
  -- And across the boundaries between operations (simulate_seams): each
  -- plan above is measured over its own window only.
  if o.seams ~= false then
    local s = self:simulate_seams{spacing = o.seam_spacing}
    out.seams, out.seam_failures = s.seams, s.failures
  end
  return out
end

-- (as designed: impeller_world.design_face) and one pitch of the hub — every other blade's moves are blade 1's turned,
-- so blade 1's surfaces see what every blade sees — under the moves of each
-- operation alone, of the links, and of the whole job in order (the material
-- left after everything; a motion between two moves of different tools, the
-- tool change on the clearance surface, is not a cut). Motions that never
-- come within the cutter's reach of a surface are left out of its sweep.
-- Returns {surfaces = {{name, groups = {{name, operation, undercut_max,
-- residual_min, residual_max, overcut, overcut_move, overcut_operation,
-- untouched, seconds, map}, ...}, total = <the "job" group>}, ...},
-- overcut, overcut_at = {surface, move, operation}, seconds}.
function Job:simulate_impeller(o)
  local imp, moves = self.part, self.planned.moves
  local iw = require("impeller_world")
  local surfaces = {}
  for _, kind in ipairs(imp:has_splitter() and {"main", "splitter"} or {"main"}) do
    for _, side in ipairs({"plus", "minus"}) do
      surfaces[#surfaces + 1] = {name = kind .. " " .. side, surface = iw.design_face(imp, 1, side, kind)}
    end
  end
  -- And what closes the blades between their faces (impeller_world.edge_face):
  -- no operation finishes it, and no cutter may cut into it deeper than a
  -- face's finisher cuts that face (impeller_overcut_allowed). Where an
  -- edge meets a face at a corner (the built-in impeller's blunt ends), a
  -- face's overcut read along the edge's normal runs along the face, as
  -- deep as the search goes: the band of the edge within that face's cut
  -- (the deeper of its plan's residual and its simulated overcut, + 5 um)
  -- of it is the face's, left out of the edge's figures (`beside`: the
  -- faces at its v = 0 and v = 1 ends, simulated before it).
  local finishing = {}
  for _, f in ipairs(self.planned.flanks) do
    if f.blade == 1 then finishing[#finishing + 1] = {operation = f.kind, name = f.side, report = f.report} end
  end
  local planned_cut = M.impeller_overcut_allowed(finishing, 0)
  for _, kind in ipairs(imp:has_splitter() and {"main", "splitter"} or {"main"}) do
    for _, edge in ipairs({"leading", "trailing"}) do
      local e = iw.edge_face(imp, 1, edge, kind)
      if e then
        -- v = 0 on the face that runs into the edge (plus at the leading edge), 1 on the other.
        local into, from = edge == "leading" and "plus" or "minus", edge == "leading" and "minus" or "plus"
        surfaces[#surfaces + 1] = {name = kind .. " " .. edge .. " edge", surface = e,
                                   beside = {kind .. " " .. into, kind .. " " .. from}}
      end
    end
  end
  -- One pitch of the hub: every channel's floor once (blade feet untouched).
  local hub = imp:hub()
  local d = hub:eval(0.5, 0)
  local radial = {d.point.x, d.point.y, 0}
  local out = d.normal.x * radial[1] + d.normal.y * radial[2] + d.normal.z * math.sqrt(radial[1] ^ 2 + radial[2] ^ 2)
  surfaces[#surfaces + 1] = {name = "hub", surface = hub, v = {0, 1 / imp:blade_count()}, flip = out < 0,
                             search_above = 2}
  -- The cutter's reach per tool number (the sweep only uses the cutter).
  local reach = {}
  local function cutter_reach(n)
    if not reach[n] then
      local r = 0
      for _, seg in ipairs(self:tool_entry(n).tool:profile("cutter")) do
        for _, q in ipairs({seg.from, seg.to}) do r = math.max(r, math.sqrt(q[1] ^ 2 + q[2] ^ 2)) end
      end
      reach[n] = r
    end
    return reach[n]
  end
  local function group_of(i)
    local a, b = moves[i - 1], moves[i]
    if a.tool ~= b.tool then return nil end  -- the tool change, off the part
    if a.operation_kind == "link" or b.operation_kind == "link" then return "links" end
    return b.operation
  end
  local function segment_distance(c, p, q)
    local d = {q[1] - p[1], q[2] - p[2], q[3] - p[3]}
    local dd = d[1] ^ 2 + d[2] ^ 2 + d[3] ^ 2
    local t = dd > 0 and math.max(0, math.min(1, ((c[1] - p[1]) * d[1] + (c[2] - p[2]) * d[2] + (c[3] - p[3]) * d[3]) / dd)) or 0
    return math.sqrt((p[1] + t * d[1] - c[1]) ^ 2 + (p[2] + t * d[2] - c[2]) ^ 2 + (p[3] + t * d[3] - c[3]) ^ 2)
  end
  local result = {surfaces = {}, overcut = 0}
  local t0 = os.clock()
  local face_cut = {}  -- a face's deepest cut so far: its plan's, or simulated
  for name, mm in pairs(planned_cut) do face_cut[name] = mm end
  for _, sfc in ipairs(surfaces) do
    if sfc.beside then
      sfc.keep = M.away_from_ends(sfc.surface, 0.005 - (face_cut[sfc.beside[1]] or 0),
                                  0.005 - (face_cut[sfc.beside[2]] or 0), o.samples_u or 60, o.samples_v or 300)
    end
    -- Bounding sphere of the sampled window.
    local pts, c = {}, {0, 0, 0}
    local v0, v1 = sfc.v and sfc.v[1] or 0, sfc.v and sfc.v[2] or 1
    for a = 0, 10 do
      for b = 0, 10 do
        local p = sfc.surface:point(a / 10, v0 + (v1 - v0) * b / 10)
        pts[#pts + 1] = {p.x, p.y, p.z}
        c = {c[1] + p.x, c[2] + p.y, c[3] + p.z}
      end
    end
    c = {c[1] / #pts, c[2] / #pts, c[3] / #pts}
    local radius = 0
    for _, p in ipairs(pts) do
      radius = math.max(radius, math.sqrt((p[1] - c[1]) ^ 2 + (p[2] - c[2]) ^ 2 + (p[3] - c[3]) ^ 2))
    end
    -- 11 x 11 samples can miss a little of the window's extent: 2 % and 5 mm more.
    radius = 1.02 * radius + 5
    -- o.search_above: deeper stock than the default window (1 mm over a
    -- face, 2 over the hub) is tracked, not counted untouched; o.search_below
    -- (0.5 mm): how deep an overcut is measured (a deeper one reads as that).
    local search_above = math.max(sfc.search_above or 1, o.search_above or 0)
    -- Passes: runs of consecutive motions of one group (an operation, or the
    -- links) near the surface. One sweep per group; the job's is the lowest
    -- of them (every motion is in one group), computed by bliskrun.simulate.
    local passes, first, names, last = {}, {}, {}, {}
    for i = 2, #moves do
      local key = group_of(i)
      if key and segment_distance(c, moves[i - 1].tip, moves[i].tip) <= radius + cutter_reach(moves[i].tool) + search_above then
        local name = key == "links" and "links" or tostring(key)
        if last[name] ~= i - 1 then
          passes[#passes + 1] = {tool = self:tool_entry(moves[i].tool).tool, poses = {moves[i - 1]}, group = name}
          first[#passes] = i - 1
          names[name] = #passes
        end
        local pass = passes[names[name]]
        pass.poses[#pass.poses + 1] = moves[i]
        last[name] = i
      end
    end
    local rs = {name = sfc.name, groups = {}}
    if #passes > 0 then
      local sim = bliskrun.simulate{surface = sfc.surface, passes = passes, samples_u = o.samples_u or 60,
                                    samples_v = o.samples_v or 300, v = sfc.v, flip_normal = sfc.flip, keep = sfc.keep,
                                    search_above = search_above, search_below = o.search_below or 0.5, sweep_step = o.sweep_step or 0.1}
      local function entry(r, key)
        local e = {name = key == "job" and "job" or key == "links" and "links" or self.operations[tonumber(key)].kind,
                   operation = tonumber(key), undercut_max = r.undercut_max, undercut_mean = r.undercut_mean,
                   residual_min = r.residual_min, residual_max = r.residual_max, overcut = r.overcut,
                   untouched = r.untouched, samples = r.samples, seconds = r.seconds, map = r.map}
        if r.overcut_pass then
          e.overcut_move = first[r.overcut_pass] + r.overcut_pose - 1
          e.overcut_operation = moves[e.overcut_move].operation_kind
          e.overcut_point = r.overcut_point
        end
        return e
      end
      local order = {}
      for k, g in ipairs(sim.groups) do order[k] = g end
      table.sort(order, function(a, b)
        local ka, kb = a.name == "links" and 1e9 or tonumber(a.name), b.name == "links" and 1e9 or tonumber(b.name)
        return ka < kb
      end)
      for _, g in ipairs(order) do rs.groups[#rs.groups + 1] = entry(g, g.name) end
      rs.total = entry(sim, "job")
      rs.groups[#rs.groups + 1] = rs.total
      if rs.total.overcut < result.overcut then
        result.overcut = rs.total.overcut
        result.overcut_at = {surface = sfc.name, move = rs.total.overcut_move, operation = rs.total.overcut_operation}
      end
    end
    result.surfaces[#result.surfaces + 1] = rs
    if rs.total then face_cut[sfc.name] = math.min(face_cut[sfc.name] or 0, rs.total.overcut) end
  end
  result.seconds = os.clock() - t0
  return result
end

-- bliskrun.simulate's `keep` over nu x nv samples of surface e: the samples
-- at least band0 mm (arc length along v) from its v = 0 end and band1 mm
-- from its v = 1 end.
function M.away_from_ends(e, band0, band1, nu, nv)
  local keep = {}
  for i = 0, nu - 1 do
    local arc, prev = {0}, e:point(i / (nu - 1), 0)
    for j = 1, nv - 1 do
      local p = e:point(i / (nu - 1), j / (nv - 1))
      arc[j + 1] = arc[j] + math.sqrt((p.x - prev.x) ^ 2 + (p.y - prev.y) ^ 2 + (p.z - prev.z) ^ 2)
      prev = p
    end
    for j = 1, nv do keep[#keep + 1] = arc[j] >= band0 and arc[nv] - arc[j] >= band1 end
  end
  return keep
end

-- The deepest cut (mm, negative) each of an impeller's surfaces allows:
-- {[surface name] = mm}; a surface not listed allows the sweep's 2 um.
function M.impeller_overcut_allowed(units, slack)
  local allowed = {}
  for _, u in ipairs(units) do
    if u.operation == "flank_finish" or u.operation == "point_mill" then
      allowed[u.name] = math.min(0, u.report.residual_min) - slack
      -- The edges close the faces: a cutter that finishes a face to its end
      -- cuts what it overcuts the face by round the corner too.
      local kind = u.name:match("^(%a+) ")
      for _, edge in ipairs({"leading", "trailing"}) do
        local name = kind .. " " .. edge .. " edge"
        allowed[name] = math.min(allowed[name] or -0.002, allowed[u.name])
      end
    end
    -- Point milling carried down to the fillet touches the hub: its
    -- planner proves no deeper than its allowed overcut there.
    if u.operation == "point_mill" and u.report.follows_fillet then
      allowed.hub = math.min(allowed.hub or -0.002, -u.report.allowed_overcut - slack)
    end
  end
  return allowed
end

-- The stop after an impeller job's simulation (j:simulate): a face may be
-- overcut by its own flank finish's planned residual (units: the plan's
-- {operation, name, report} of blade 1, `slack` mm for the simulation's
-- sampling), nothing else anywhere beyond the sweep's 2 um. Returns the
-- reason naming the surface, the depth and the job move that cut it (nothing
-- is to be posted), or nil.
function Job:check_overcut(sim, units, slack)
  local allowed = M.impeller_overcut_allowed(units, slack)
  for _, s in ipairs(sim.surfaces) do
    local t, floor = s.total, allowed[s.name] or -0.002
    if t and t.overcut < floor then
      return string.format("simulation: blade 1 %s is overcut %.1f um at job move %d (%s), beyond the %.1f um its "
                           .. "operations allow; nothing is posted", s.name, -1e3 * t.overcut, t.overcut_move or -1,
                           t.overcut_operation or "?", -1e3 * floor)
    end
  end
end

-- The stop after a blisk job's simulation: an overcut deeper than the
-- loosest of its operations' promises (job/seams.lua: the drum finish's
-- chord tolerance, the edge finish's e1, the hub finish's 2 um; 0.1 um for
-- the sweep's sampling), or a seam cut deeper than the operation that cut it
-- promises. Returns the reason (nothing is to be posted), or nil.
function Job:blisk_overcut(sim)
  local allowed = 0
  for _, op in ipairs(self.operations) do allowed = math.min(allowed, seams.promise(op).cut) end
  if sim.overcut < allowed - 1e-4 then
    return string.format("the simulation finds an overcut of %.2f um, beyond the %.1f um its operations allow; "
                         .. "nothing posted", -1e3 * sim.overcut, -1e3 * allowed)
  end
  for _, s in ipairs(sim.seams or {}) do
    if s.overcut_mm < s.tolerance.overcut_mm - 0.0005 then
      return string.format("seam %s: %s; nothing posted", s.name, s.reason)
    end
  end
end

-- The thinnest of an impeller's blades (mm): the least distance from a
-- sample of blade 1's plus face (31 x 61) to its minus face, main blade and
-- splitter, as designed. An overcut of a face is measured down to half of
-- it at most: deeper, the sweep would meet the cutter finishing the blade's
-- other face.
function M.thinnest_blade(part)
  local iw = require("impeller_world")
  local thinnest = math.huge
  for _, kind in ipairs(part:has_splitter() and {"main", "splitter"} or {"main"}) do
    local a, b = iw.design_face(part, 1, "plus", kind), iw.design_face(part, 1, "minus", kind)
    for i = 0, 30 do
      for k = 0, 60 do
        local foot = b:project(a:point(i / 30, k / 60))
        if foot then thinnest = math.min(thinnest, foot.distance) end
      end
    end
  end
  return thinnest
end

return M
