-- Blade 1 of a blisk job swept by every operation's moves that reach it,
-- each with its own tool (Job methods; scripts/lib/job.lua is the entry):
-- the seams between the operations' windows (j:simulate_seams), which no
-- operation's own simulation measures, and one map of the whole blade
-- (j:simulate_blade).
local options = require("job.options")
local geometry = require("job.geometry")
local Job = require("job.model").Job

local check_options, positive, meridian_height = options.check, options.positive, geometry.meridian_height

local M = {}

-- Blade 1's passes (simulate_blade, simulate_seams): each operation's moves
-- on a blade, in job order, each with its tool — blade 1's drum, edge and
-- hub moves and the neighbours' hub moves (blade N's channel ends on blade
-- 1's pressure root, blade 2's root rows border blade 1's channel floor).
-- moves_of[pass][pose] is the pose's index in the job's moves.
local function blade_passes(self)
  local n = self.part:blade_count()
  local passes, last, moves_of = {}, nil, {}
  for i, m in ipairs(self.planned.moves) do
    -- Not the roughing's: it keeps its stock (less its tolerance) off the
    -- design everywhere (its plan's proofs, its own simulation), so what
    -- the finished blade keeps and where it is cut are the finishers'
    -- alone, and where no finisher reaches the map says so rather than
    -- showing the roughing's stock.
    local key = m.operation_kind ~= "link" and m.operation_kind ~= "rough_channels" and
                (m.blade == 1 or (m.operation_kind == "hub_finish" and
                (m.blade == n or m.blade == 2))) and (m.operation .. ":" .. m.blade) or nil
    if key then
      if key ~= last then
        passes[#passes + 1] = {tool = self:tool_entry(m.tool).tool, poses = {}}
        moves_of[#passes] = {}
      end
      local poses = passes[#passes].poses
      poses[#poses + 1] = m
      moves_of[#passes][#poses] = i
    end
    last = key
  end
  return passes, moves_of
end

-- Only what can reach a window (spec = {surface, u, v, search_above}): the
-- stretches of each pass whose poses come within the tool's reach of the
-- window's box, with the pose before and after (a motion from or to a far
-- pose can still cut) — as the hub plan's own simulation does; most of a
-- job's moves are far from any one surface of blade 1. `reach` caches each
-- tool's reach. Returns the passes and their poses' job move indices.
local function passes_near(passes, moves_of, spec, reach)
  local lo, hi = {math.huge, math.huge, math.huge}, {-math.huge, -math.huge, -math.huge}
  for i = 0, 16 do
    for k = 0, 64 do
      local p = spec.surface:point(spec.u[1] + (spec.u[2] - spec.u[1]) * i / 16,
                                   spec.v[1] + (spec.v[2] - spec.v[1]) * k / 64)
      local x = {p.x, p.y, p.z}
      for c = 1, 3 do lo[c], hi[c] = math.min(lo[c], x[c]), math.max(hi[c], x[c]) end
    end
  end
  local out, out_moves = {}, {}
  for pi, pass in ipairs(passes) do
    reach[pass.tool] = reach[pass.tool] or pass.tool:reach()
    local r2 = (reach[pass.tool] + (spec.search_above or 0.5) + 1) ^ 2
    local inside = {}
    for k, m in ipairs(pass.poses) do
      local d2 = 0
      for c = 1, 3 do
        local x = m.tip[c]
        local e = x < lo[c] and lo[c] - x or (x > hi[c] and x - hi[c] or 0)
        d2 = d2 + e * e
      end
      inside[k] = d2 < r2
    end
    local cur, cur_moves = nil, nil
    for k, m in ipairs(pass.poses) do
      if inside[k] or inside[k - 1] or inside[k + 1] then
        if not cur then
          cur, cur_moves = {tool = pass.tool, poses = {}}, {}
          out[#out + 1], out_moves[#out + 1] = cur, cur_moves
        end
        cur.poses[#cur.poses + 1] = m
        cur_moves[#cur.poses] = moves_of[pi][k]
      else
        cur = nil
      end
    end
  end
  return out, out_moves
end

-- One map of blade 1 (issue 18 item 4): the material left and the gouges
-- over the whole blade, each surface swept by every operation's moves that
-- can reach it, each move with its own tool (bliskrun.simulate, core/sim):
-- blade 1's drum, edge and hub moves, and the neighbours' hub moves (blade
-- N's channel ends on blade 1's pressure root, blade 2's root rows border
-- blade 1's channel floor). The regions: both flanks (the drum finish's
-- trimmed flanks, from 0.1 mm above the ball's fillet to the casing, edge to
-- edge), both edges (each edge region over its machined span window, 0.3 mm
-- onto the flanks), the root strip all around the blade up to the hub
-- operation's top and the fillet below it (the ball's radius in the design's
-- sharp corner: material is tracked up to 2 mm there, more counts unreached), and the channel
-- floor to blade 2 — the last three the hub plan's own windows and regions
-- (plan:regions). o = {flank_samples = {u, v}, edge_samples = {around, span},
-- root_samples = {span, around}, floor_samples = {meridian, around}}.
-- Returns {regions = {{name, surface, material_left_max_mm,
-- material_left_min_mm, overcut_mm, overcut_move, unreached, samples, map,
-- tile = {map =, transpose =}}, ...}, material_left_max_mm and unreached
-- (the fillet apart), overcut_mm (all regions), map} — `map` all regions as one
-- picture (bliskrun.map_mosaic: the flanks and edges around the blade, span
-- up; under them the root strip, the fillet and the channel floor).
function Job:simulate_blade(o)
  o = o or {}
  local function pair(v) return type(v) == "table" and #v == 2 and math.type(v[1]) == "integer" and
                                math.type(v[2]) == "integer" and v[1] >= 2 and v[2] >= 2 end
  check_options("job:simulate_blade", o, {
    flank_samples = {type = "table", check = function(v) if not pair(v) then return "expected {u, v} integers >= 2" end end},
    edge_samples = {type = "table", check = function(v) if not pair(v) then return "expected {u, v} integers >= 2" end end},
    root_samples = {type = "table", check = function(v) if not pair(v) then return "expected {u, v} integers >= 2" end end},
    floor_samples = {type = "table", check = function(v) if not pair(v) then return "expected {u, v} integers >= 2" end end},
  }, 2)
  if not self.planned then error("job:simulate_blade: plan the job first (j:plan())", 2) end
  if self.part_kind == "impeller" then error("job:simulate_blade: a blisk job's blade (impellers: j:simulate)", 2) end
  local fs, es = o.flank_samples or {40, 200}, o.edge_samples or {80, 40}
  local rs, ls = o.root_samples or {40, 400}, o.floor_samples or {100, 80}
  local passes, moves_of = blade_passes(self)
  local reach = {}
  local function near(spec) return passes_near(passes, moves_of, spec, reach) end
  local regions = {}
  local function simulate(name, spec, keep)
    local near_passes, near_moves = near(spec)
    if #near_passes == 0 then near_passes, near_moves = {passes[1]}, {moves_of[1]} end
    local r = bliskrun.simulate{surface = spec.surface, passes = near_passes, u = spec.u, v = spec.v,
                                samples_u = spec.samples_u, samples_v = spec.samples_v, flip_normal = spec.flip_normal,
                                search_above = spec.search_above or 0.5, sweep_step = spec.sweep_step, keep = keep}
    local samples = spec.samples_u * spec.samples_v
    if keep then
      samples = 0
      for _, k in ipairs(keep) do if k then samples = samples + 1 end end
    end
    local at = r.overcut_pass and near_moves[r.overcut_pass]
    local region = {name = name, material_left_max_mm = r.residual_max, material_left_min_mm = r.residual_min,
                    overcut_mm = r.overcut, unreached = r.untouched, samples = samples, map = r.map, seconds = r.seconds,
                    overcut_move = at and at[r.overcut_pose] or nil,
                    tile = {map = r.map, transpose = spec.transpose, label = name},
                    -- The region in 3D with its map (bliskrun.paint_part).
                    piece = {name = name, surface = spec.surface, map = r.map, u = spec.u, v = spec.v,
                             samples_u = math.min(spec.samples_u, 120), samples_v = math.min(spec.samples_v, 300)}}
    regions[#regions + 1] = region
    return region
  end
  local hub_plan, fillet_top
  for _, f in ipairs(self.planned.flanks) do
    if f.kind == "hub_finish" and f.blade == 1 then hub_plan, fillet_top = f.plan, f.report.fillet.contact_max end
  end
  local function dist(a, b) return math.sqrt((a.x - b.x) ^ 2 + (a.y - b.y) ^ 2 + (a.z - b.z) ^ 2) end
  local top, around = {}, {}
  for _, side in ipairs({"pressure", "trailing edge", "suction", "leading edge"}) do
    for _, f in ipairs(self.planned.flanks) do
      if f.blade == 1 and f.side == side and f.kind == "drum_finish" then
        local ts = f.plan:trimmed()
        local span = dist(ts:point(0, 0.5), ts:point(1, 0.5))
        local u0 = fillet_top and math.min(0.5, (fillet_top + 0.1) / span) or 0
        top[#top + 1] = simulate(side .. " flank", {surface = ts, u = {u0, 1}, v = {0, 1}, samples_u = fs[1],
                                                    samples_v = fs[2]}).tile
      elseif f.blade == 1 and f.side == side and f.kind == "edge_finish" then
        top[#top + 1] = simulate(side, {surface = f.surface, u = {0, 1}, v = {f.report.span_v0, f.report.span_v1},
                                        samples_u = es[1], samples_v = es[2], transpose = true}).tile
      end
    end
  end
  if hub_plan then
    -- The ball's regions at the hub plan's own sweep step (0.1 mm).
    local w = hub_plan:regions{root_samples = rs, floor_samples = ls}
    if w.floor then w.floor.sweep_step = 0.1 end
    if w.root then
      w.root.sweep_step = 0.1
      around[#around + 1] = simulate("root strip", w.root, w.root.strip).tile
      local fillet = {}
      for k, v in pairs(w.root) do fillet[k] = v end
      fillet.search_above = 2
      around[#around + 1] = simulate("fillet", fillet, w.root.fillet).tile
    end
    if w.floor then around[#around + 1] = simulate("channel floor", w.floor, w.floor.floor).tile end
  end
  local out = {regions = regions, material_left_max_mm = 0, overcut_mm = 0, unreached = 0}
  for _, r in ipairs(regions) do
    if r.name ~= "fillet" then
      if r.material_left_max_mm then out.material_left_max_mm = math.max(out.material_left_max_mm, r.material_left_max_mm) end
      out.unreached = out.unreached + r.unreached
    end
    out.overcut_mm = math.min(out.overcut_mm, r.overcut_mm)
  end
  local rows = {top}
  if #around > 0 then rows[2] = around end
  out.map = bliskrun.map_mosaic{rows = rows,
    u_label = "top row up: span, hub to tip",
    v_label = "top row across: each flank's chord, round each edge; bottom row: the hub surfaces' own parameters",
    footer = string.format(
    "blade 1: flanks and edges around (span up), under them the root strip, the fillet and the channel floor; "
    .. "left up to %.1f µm, %d unreached (fillet apart), overcut %.1f µm", 1e3 * out.material_left_max_mm,
    out.unreached, 1e3 * out.overcut_mm)}
  return out
end

-- What an operation promises where it finishes (material left, deepest
-- cut; mm), from its own options: the drum finish its residual (scallop)
-- plus the chord tolerance and the chord as overcut; the edge finish its
-- band e2 / e1; the hub finish its scallop plus the chord of the ball
-- centre's path twice (where a floor row ends on the fillet row, the row
-- and the step along the fillet to the next both pass a sample, each up to
-- its chord off on the concave corner) and the planner's allowed overcut
-- (2 um, HubFinishRequest::allowed_overcut_mm).
local function promise(op)
  if op.kind == "drum_finish" then return {left = op.residual + op.chord_tol, cut = -op.chord_tol} end
  if op.kind == "edge_finish" then return {left = op.e2, cut = op.e1} end
  if op.kind == "hub_finish" then return {left = op.scallop + 2 * op.chord_tol, cut = -0.002} end
  -- The roughing: its stock within its tolerance where it reaches (least:
  -- the thinnest stock it may leave); it cuts nothing below the design.
  if op.kind == "rough_channels" then
    return {left = op.stock + op.tolerance, least = op.hub_stock - op.tolerance, cut = 0}
  end
  return {left = 0, cut = 0}
end

-- Seams between operations on blade 1 (issue 34 item 8): each operation
-- reports the window it machines, so a band between two windows — or a
-- window's end that borders nothing — is measured by none of them (the
-- built-in LE kept 48.6 um in a band 4.2-4.5 mm above the hub, between the
-- root strip and the edge rows, beyond e2). Here every boundary between two
-- operations' regions is a band a margin either side of both boundaries,
-- simulated (bliskrun.simulate, core/sim) under every pass of every
-- operation that can reach it, each with its own tool and moves:
--   - root strip / edge: on each edge region, from the root strip's top
--     and the edge window's first row, `margin` below the lower to `margin`
--     above the higher (above the ball's fillet);
--   - edge window top: on each edge region, from `margin` below the window's
--     last row to the casing (what lies past the window is nobody's unless
--     the window reaches the blade's tip);
--   - edge / flank: on each drum-finished flank, the edge region's overlap
--     and `margin` more onto the flank at that edge's end, hub to casing;
--   - root strip / flank: on each flank, from above the ball's fillet to
--     `margin` above the root strip's top, edge to edge;
--   - channel floor / fillet (the hub by the blade's root): the floor's
--     samples within 1 mm of its rows' ends, where the floor rows meet the
--     fillet row (plan:regions: floor minus middle).
-- Tolerances: material left at most the looser of the two operations'
-- promises (the band is finished by either), the deepest cut at least the
-- promise of the operation whose move cut it, less `slack` (the sweep's
-- sampling); a sample no tool reaches within search_above (0.5 mm) is
-- unfinished. A seam beyond any of these is a FAIL with its reason — in the
-- result, never an error: the caller reports it.
-- o = {spacing = 0.1 (mm between samples), margin = 1 (mm), slack = 0.0005
-- (mm), only = {names} (those seams alone)}. Returns {seams = {{name,
-- surface, operations, u, v, heights_mm = {lo, hi} (above the hub),
-- samples, unreached, material_left_max_mm,
-- material_left_min_mm, material_left_at = {x, y, z, height_mm, u, v},
-- overcut_mm, overcut_move, overcut_operation, overcut_at, tolerance =
-- {material_left_mm, overcut_mm}, ok, reason, seconds}, ...}, failures,
-- seconds}.
function Job:simulate_seams(o)
  o = o or {}
  check_options("job:simulate_seams", o, {
    spacing = {type = "number", check = positive},
    margin = {type = "number", check = positive},
    slack = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
    only = {type = "table"},
  }, 2)
  if not self.planned then error("job:simulate_seams: plan the job first (j:plan())", 2) end
  local wanted
  if o.only then
    wanted = {}
    for _, name in ipairs(o.only) do wanted[name] = true end
  end
  if self.part_kind == "impeller" then error("job:simulate_seams: a blisk job's seams (impellers: j:simulate)", 2) end
  local t0 = os.clock()
  local spacing, margin, slack = o.spacing or 0.1, o.margin or 1, o.slack or 0.0005
  local hub_m, casing_m = self.part:hub_meridian(), self.part:casing_meridian()
  local function height(p) return meridian_height(hub_m, p) end
  local function below_casing(p) return -meridian_height(casing_m, p) end
  local function dist(a, b) return math.sqrt((a.x - b.x) ^ 2 + (a.y - b.y) ^ 2 + (a.z - b.z) ^ 2) end
  local function count(len) return math.max(4, math.min(600, math.ceil(len / spacing) + 1)) end
  local passes, moves_of = blade_passes(self)
  local reach = {}
  local hub, edges, flanks = nil, {}, {}
  for _, f in ipairs(self.planned.flanks) do
    if f.blade == 1 and not f.turned_from then
      if f.kind == "hub_finish" then hub = f
      elseif f.kind == "edge_finish" then edges[#edges + 1] = f
      elseif f.kind == "drum_finish" then flanks[#flanks + 1] = f end
    end
  end
  local floor_h = hub and hub.report.fillet.contact_max + 0.1 or 0.05
  local function op_name(f) return string.format("%s (operation %d)", f.kind, f.operation) end
  local seams, failures = {}, 0
  -- One band: spec = {name, surface, surface_name, owners = {f, ...}, u, v,
  -- samples_u, samples_v, keep (a function of the point, or a list), flip_normal}.
  local known = {}
  local function seam(spec)
    known[#known + 1] = spec.name
    if wanted and not wanted[spec.name] then return end
    local t = os.clock()
    local su, sv = spec.samples_u, spec.samples_v
    local keep, kept, lo_h, hi_h = nil, 0, math.huge, -math.huge
    if type(spec.keep) == "table" then keep = spec.keep end
    local tested = type(spec.keep) == "function"
    if tested then keep = {} end
    for i = 0, su - 1 do
      for k = 0, sv - 1 do
        local idx = i * sv + k + 1
        local p = spec.surface:point(spec.u[1] + (spec.u[2] - spec.u[1]) * i / (su - 1),
                                     spec.v[1] + (spec.v[2] - spec.v[1]) * k / (sv - 1))
        local ok = true
        if tested then ok = spec.keep(p); keep[idx] = ok elseif keep then ok = keep[idx] end
        if ok then
          kept = kept + 1
          local h = height(p)
          lo_h, hi_h = math.min(lo_h, h), math.max(hi_h, h)
        end
      end
    end
    local tol = {left = 0, cut = 0}
    local names = {}
    for _, f in ipairs(spec.owners) do
      local p = promise(self.operations[f.operation])
      tol.left, tol.cut = math.max(tol.left, p.left), math.min(tol.cut, p.cut)
      names[#names + 1] = op_name(f)
    end
    local out = {name = spec.name, surface = spec.surface_name, operations = names, u = spec.u, v = spec.v,
                 samples = kept, heights_mm = kept > 0 and {lo_h, hi_h} or nil,
                 tolerance = {material_left_mm = tol.left, overcut_mm = tol.cut}}
    if kept == 0 then
      out.ok, out.unreached, out.overcut_mm, out.seconds = true, 0, 0, os.clock() - t
      out.reason = "no sample of the band lies on the part"
      seams[#seams + 1] = out
      return out
    end
    local near, near_moves = passes_near(passes, moves_of, spec, reach)
    local r
    if #near > 0 then
      r = bliskrun.simulate{surface = spec.surface, passes = near, u = spec.u, v = spec.v, samples_u = su,
                            samples_v = sv, flip_normal = spec.flip_normal, search_above = 0.5,
                            sweep_step = spec.sweep_step, keep = keep}
    else
      r = {untouched = kept, overcut = 0}
    end
    out.unreached, out.overcut_mm = r.untouched, r.overcut
    out.material_left_max_mm, out.material_left_min_mm = r.residual_max, r.residual_min
    if r.residual_max_point then
      local p = r.residual_max_point
      out.material_left_at = {x = p.x, y = p.y, z = p.z, height_mm = height(p), u = r.residual_max_u,
                              v = r.residual_max_v}
    end
    -- The deepest cut against the promise of the operation that cut it
    -- (the looser of the owners' when the sweep's deepest sample lies
    -- outside the band and the band's deepest motion is not known).
    local cut_limit = tol.cut
    if r.overcut_pass then
      local move = near_moves[r.overcut_pass][r.overcut_pose]
      local m = self.planned.moves[move]
      out.overcut_move, out.overcut_operation = move, m.operation
      cut_limit = promise(self.operations[m.operation]).cut
    end
    if r.overcut_point then
      local p = r.overcut_point
      out.overcut_at = {x = p.x, y = p.y, z = p.z, height_mm = height(p), u = r.overcut_u, v = r.overcut_v}
    end
    out.tolerance.overcut_mm = cut_limit
    local reasons = {}
    if r.untouched > 0 then
      reasons[#reasons + 1] = string.format("%d of %d samples never reached (no tool within 0.5 mm: unfinished)",
                                            r.untouched, kept)
    end
    if r.residual_max and r.residual_max > tol.left then
      local at = out.material_left_at
      reasons[#reasons + 1] = string.format("%.1f um left, beyond %.1f um, %.2f mm above the hub", 1e3 * r.residual_max,
                                            1e3 * tol.left, at.height_mm)
    end
    if r.overcut < cut_limit - slack then
      reasons[#reasons + 1] = string.format("cut %.2f um deep (job move %s), beyond %.2f um", -1e3 * r.overcut,
                                            tostring(out.overcut_move), -1e3 * cut_limit)
    end
    out.ok = #reasons == 0
    out.reason = #reasons > 0 and table.concat(reasons, "; ") or nil
    if not out.ok then failures = failures + 1 end
    out.seconds = os.clock() - t
    seams[#seams + 1] = out
    return out
  end
  local function on_part(p) local h = height(p) return h >= floor_h and below_casing(p) >= 0 end
  -- The height range of an edge region's row v (over u around).
  local function row_heights(surface, v)
    local lo, hi = math.huge, -math.huge
    for i = 0, 20 do
      local h = height(surface:point(i / 20, v))
      lo, hi = math.min(lo, h), math.max(hi, h)
    end
    return lo, hi
  end
  -- The edge-region v where the row's lowest (highest) point is at height h.
  local function v_at(surface, h, highest)
    local a, b = 0, 1
    for _ = 1, 40 do
      local m = 0.5 * (a + b)
      local lo, hi = row_heights(surface, m)
      if (highest and hi or lo) < h then a = m else b = m end
    end
    return 0.5 * (a + b)
  end
  for _, e in ipairs(edges) do
    local surf, rep = e.surface, e.report
    local around = 0
    for i = 1, 20 do around = around + dist(surf:point((i - 1) / 20, 0.5), surf:point(i / 20, 0.5)) end
    local span = dist(surf:point(0.5, 0), surf:point(0.5, 1))
    local owners = {e}
    local first_lo, first_hi = row_heights(surf, rep.span_v0)
    local lo_h, hi_h = first_lo, first_hi
    if hub then
      lo_h, hi_h = math.min(lo_h, hub.report.heights[2]), math.max(hi_h, hub.report.heights[2])
      owners = {e, hub}
    end
    local v0 = v_at(surf, math.max(floor_h, lo_h - margin), true)
    local v1 = v_at(surf, hi_h + margin, false)
    seam{name = (hub and "root strip / " or "") .. e.side .. (hub and "" or ", window bottom"), surface = surf,
         surface_name = e.side .. " region", owners = owners, u = {0, 1}, v = {v0, v1}, samples_u = count(around),
         samples_v = count((v1 - v0) * span), keep = on_part}
    -- The top: past the window's last row up to the casing.
    local top_v = v_at(surf, select(2, row_heights(surf, rep.span_v1)) - margin, true)
    local casing_v = 1
    seam{name = e.side .. ", window top", surface = surf, surface_name = e.side .. " region", owners = {e},
         u = {0, 1}, v = {math.min(top_v, rep.span_v1), casing_v}, samples_u = count(around),
         samples_v = count((casing_v - math.min(top_v, rep.span_v1)) * span), keep = on_part}
  end
  for _, f in ipairs(flanks) do
    local ts = f.plan:trimmed()
    local span = dist(ts:point(0, 0.5), ts:point(1, 0.5))
    local chord = 0
    for i = 1, 40 do chord = chord + dist(ts:point(0.5, (i - 1) / 40), ts:point(0.5, i / 40)) end
    for _, e in ipairs(edges) do
      -- Pressure flank v: LE -> TE; suction: TE -> LE.
      local at_start = (f.side == "pressure") == (e.side == "leading edge")
      local w = math.min(0.5, (self.operations[e.operation].overlap + margin) / chord)
      local v = at_start and {0, w} or {1 - w, 1}
      seam{name = e.side .. " / " .. f.side .. " flank", surface = ts, surface_name = f.side .. " flank (trimmed)",
           owners = {e, f}, u = {0, 1}, v = v, samples_u = count(span), samples_v = count(w * chord), keep = on_part}
    end
    if hub then
      local u1 = math.min(1, (hub.report.heights[2] + margin) / span)
      seam{name = "root strip / " .. f.side .. " flank", surface = ts, surface_name = f.side .. " flank (trimmed)",
           owners = {hub, f}, u = {0, u1}, v = {0, 1}, samples_u = count(u1 * span), samples_v = count(chord),
           keep = on_part}
    end
  end
  if hub then known[#known + 1] = "channel floor / fillet" end
  for name in pairs(wanted or {}) do
    local found = false
    for _, k in ipairs(known) do found = found or k == name end
    if not found then
      error(string.format("job:simulate_seams: option 'only': no seam '%s' in this job, expected one of: %s", name,
                          table.concat(known, ", ")), 2)
    end
  end
  if hub and (not wanted or wanted["channel floor / fillet"]) then
    -- The channel floor where its rows end on the fillet row (the floor's
    -- samples within 1 mm of the rows' ends); the ball's regions at the hub
    -- plan's own sweep step (0.1 mm).
    local w = hub.plan:regions{root_samples = {4, 4}, floor_samples = {count(20), count(10)}}
    local f = w.floor
    if f then
      local keep = {}
      for i, k in ipairs(f.floor) do keep[i] = k and not f.middle[i] end
      seam{name = "channel floor / fillet", surface = f.surface, surface_name = "hub", owners = {hub}, u = f.u, v = f.v,
           samples_u = f.samples_u, samples_v = f.samples_v, flip_normal = f.flip_normal, keep = keep}
    end
  end
  return {seams = seams, failures = failures, seconds = os.clock() - t0}
end

M.promise = promise
return M
