-- The report of a job's run (scripts/lib/job.lua is the entry; j:run,
-- job/run.lua, calls it): what the job planned, simulated and posted,
-- printed as it goes, gathered into the run's JSON report and laid out as
-- its report.html. One list of steps per part kind — planned, simulated,
-- posted, page — each a function of the run's state `r`:
--   r = {job, o (j:run's options), json (the JSON report), planned,
--        plan_seconds, sim, blade_map}.
-- `requirements(r, stop)` lists what the run is judged by (its verdict,
-- run_report.verdict): each with its limit and measured value, deviations
-- in µm; `stop` is the reason nothing was posted, if so.
local Job = require("job.model").Job
local seams = require("job.seams")
local simulate = require("job.simulate")
local run_report = require("run_report")

-- What every job states: with a blank, no rapid and no shank or holder in
-- the stock (job/stock.lua); no refusal (planning stops at the first one and
-- names it, so a run that got here has none), and every posted program's
-- cutter and tool within the post's tolerances of the proved motion as its
-- controller moves (the read-back sweep).
local function common_requirements(r, q)
  require("job.stock").requirements(r, q)
  q[#q + 1] = {name = "refused poses and links", unit = "count", measured = r.json.refusals or 0, at_most = 0,
               note = "planning stops at a refusal"}
  -- The limit is the post's tolerance plus what the output resolution
  -- explains at the block nearest it (post.write's *_tightest).
  for _, p in ipairs(r.json.programs) do
    local c, t = p.swept_cutter_tightest_mm, p.swept_tool_tightest_mm
    if c then
      q[#q + 1] = {name = p.file .. ": cutter off the proved motion (read back, swept; tightest block)", unit = "µm",
                   measured = 1e3 * c[1], at_most = 1e3 * c[2],
                   note = string.format("largest %.3g µm; tolerance %.3g µm + output resolution", 1e3 * p.swept_cutter_mm,
                                        1e3 * p.chord_tol_mm)}
      q[#q + 1] = {name = p.file .. ": tool body off the proved motion (tightest block)", unit = "µm",
                   measured = 1e3 * t[1], at_most = 1e3 * t[2]}
    end
    if p.machine_check then q[#q + 1] = run_report.machine_requirement(p.file, p.machine_check) end
  end
  return q
end

local M = {blisk = {}, impeller = {}}

-- One section per posted program: the machine simulation's verdict and, beside
-- it, the machine at the closest approach of two bodies (post.write's
-- machine_picture; a note where POV-Ray is not installed).
local function machine_sections(programs)
  local out = {}
  for _, p in ipairs(programs) do
    local mc = p.machine_check
    if mc and mc.verdict ~= "SKIPPED" then
      local near = {}
      for k = 1, math.min(5, #mc.closest) do
        local c = mc.closest[k]
        near[k] = run_report.approach_text(c, mc.near_zone_mm)
      end
      local text = {mc.summary, string.format("%d pairs of bodies, %d distance queries, %.1f s CPU; nearest: %s.",
                                              mc.pairs, mc.queries, mc.cpu_seconds or 0, table.concat(near, ", "))}
      if mc.picture_note then text[#text + 1] = mc.picture_note end
      out[#out + 1] = {title = "Machine simulation: " .. p.file, text = text, image = mc.picture}
    elseif mc then
      out[#out + 1] = {title = "Machine simulation: " .. p.file, text = "WARNING: " .. (mc.warning or "not run")}
    end
  end
  return out
end

-- ---- a blisk -------------------------------------------------------------

function M.blisk.planned(r)
  local j, planned, json = r.job, r.planned, r.json
  json.flanks, json.links, json.moves, json.tool_groups = {}, planned.links, #planned.moves, planned.tool_groups
  print(string.format("Job '%s': %d plans, %d moves, %d links through %s, each proved clear",
                      j.name, #planned.flanks, #planned.moves, planned.links, j.clearance_surface.description))
  for _, g in ipairs(planned.tool_groups) do
    print(string.format("  tool T%d: blades %d-%d, cutting length %.0f mm", g.tool, g.blades[1], g.blades[#g.blades],
                        g.cutting_length_mm))
  end
  -- Turned units are their first blade's: the first two blades and the
  -- last are printed, the others elided.
  -- The roughing's figures: the first channel planned (the others its
  -- path turned), its levels, engagement and the cusps it measured.
  for _, f in ipairs(planned.flanks) do
    if f.kind == "rough_channels" and not f.turned_from then
      local p = f.report
      json.roughing = json.roughing or {}
      json.roughing[#json.roughing + 1] = {channel = f.blade, levels = p.levels, levels_added = p.levels_added,
        passes = p.row_count, poses = p.poses, steps = p.steps, links = p.links, turned = p.turned,
        inserted = p.inserted,
        stock_mm = p.stock, hub_stock_mm = p.hub_stock, step_down_mm = p.step_down, step_over_mm = p.step_over,
        level_step_max_mm = p.level_step_max, step_over_max_mm = p.step_over_max,
        axial_engagement_max_mm = p.axial_engagement_max, slot_width_mm = p.slot_width,
        face_cusp_max_mm = p.face_cusp_max, hub_cusp_max_mm = p.hub_cusp_max, scallop_mm = p.scallop,
        corner_mm = p.corner, top_height_mm = p.top_height, cutter_clearance_mm = p.cutter_clearance}
      print(string.format("  roughing, channel %d (blade %d suction to blade %d pressure): %d levels (%d added for the "
                          .. "cusp), %d passes, %d poses, joined by %d steps at the feed and %d links up the tool "
                          .. "axis; stock %.2f mm (hub %.2f)", f.blade, f.blade, f.blade % j.part:blade_count() + 1,
                          p.levels, p.levels_added, p.row_count, p.poses, p.steps, p.links, p.stock, p.hub_stock))
      print(string.format("    engagement: levels %.3f mm apart (step-down %.2f), paths %.3f mm apart (step-over "
                          .. "%.2f), axial at most %.3f mm, the slot %.2f mm wide; cusps measured %.1f / %.1f um on "
                          .. "the flanks, %.1f um on the hub (scallop %.0f um)", p.level_step_max, p.step_down,
                          p.step_over_max, p.step_over, p.axial_engagement_max, p.slot_width,
                          1e3 * p.face_cusp_max[1], 1e3 * p.face_cusp_max[2], 1e3 * p.hub_cusp_max,
                          1e3 * p.scallop))
    end
  end
  for _, f in ipairs(planned.flanks) do
    if not f.turned_from or f.blade <= 2 or f.blade == j.part:blade_count() then
      print(string.format("  blade %2d %-14s  rows %3d%s  poses %5d  refused 0%s", f.blade, f.side, f.report.row_count,
                          f.report.infill_rows and string.format(" (+%d partial)", f.report.infill_rows) or "",
                          f.report.poses, f.turned_from and string.format("  (blade %d's, turned)", f.turned_from) or ""))
    elseif f.blade == 3 and f.side ~= "suction" then
      print("  ...")
    end
    json.flanks[#json.flanks + 1] = {blade = f.blade, side = f.side, operation = f.kind, rows = f.report.row_count,
                                     partial_rows = f.report.infill_rows, poses = f.report.poses, moves = f.moves,
                                     turned_from = f.turned_from}
  end
end

-- Every unit simulated after the moves that machine it, and the seams
-- between the operations on blade 1 (j:simulate, j:simulate_seams).
function M.blisk.simulated(r)
  local sim, json = r.sim, r.json
  json.simulation = {undercut_max_mm = sim.undercut_max, overcut_mm = sim.overcut, flanks = {}}
  for _, f in ipairs(sim.flanks) do
    json.simulation.flanks[#json.simulation.flanks + 1] = {blade = f.blade, side = f.side, operation = f.kind,
      undercut_max_mm = f.undercut_max, undercut_mean_mm = f.undercut_mean, overcut_mm = f.overcut,
      overcut_move = f.overcut_move, overcut_motion = f.overcut_motion, turned_from = f.turned_from,
      unreached = f.unreached, fillet_left_max_mm = f.fillet_left_max}
  end
  for _, f in ipairs(sim.flanks) do
    if f.kind == "rough_channels" and not f.turned_from and f.stock then
      -- The stock the roughing leaves, per surface where it reaches.
      local entry
      for _, e in ipairs(json.roughing or {}) do if e.channel == f.blade then entry = e end end
      local surfaces = {}
      for _, s in ipairs(f.stock.surfaces) do
        surfaces[#surfaces + 1] = {name = s.name, stock_min_mm = s.stock_min_mm, stock_max_mm = s.stock_max_mm,
                                   untouched = s.untouched, samples = s.samples}
        print(string.format("  simulated roughing, channel %d, %-18s stock left %s (%d samples, %d untouched)",
                            f.blade, s.name .. ":", s.stock_min_mm and string.format("%.3f..%.3f mm", s.stock_min_mm,
                              s.stock_max_mm) or "none reached", s.samples, s.untouched))
      end
      if entry then
        entry.simulated = {surfaces = surfaces, stock_min_mm = f.stock.stock_min_mm, stock_max_mm = f.stock.stock_max_mm}
      end
    end
  end
  for _, f in ipairs(sim.flanks) do
    if f.kind == "edge_finish" and not f.turned_from then
      print(string.format("  simulated blade %d %s: material left up to %.2f um (e2 20 um), overcut %.2f um (edge and "
                          .. "flanks)", f.blade, f.side, 1e3 * f.undercut_max, 1e3 * f.overcut))
    elseif f.kind == "hub_finish" and not f.turned_from then
      print(string.format("  simulated blade %d root strip and channel floor: material left up to %.2f um, %d samples "
                          .. "unreached, overcut %.2f um; the fillet (the ball's radius in the sharp corner) up to %.3f mm",
                          f.blade, 1e3 * f.undercut_max, f.unreached, 1e3 * f.overcut, f.fillet_left_max))
    end
  end
  print(string.format("  simulated: undercut max %.2f um, overcut %.2f um%s", 1e3 * sim.undercut_max, 1e3 * sim.overcut,
                      sim.overcut_at and sim.overcut_at.overcut_move and string.format(" (job move %d, %s, blade %d %s)",
                        sim.overcut_at.overcut_move, sim.overcut_at.overcut_motion, sim.overcut_at.blade,
                        sim.overcut_at.side) or ""))
  json.seams, r.seam_failures = {}, {}
  for _, s in ipairs(sim.seams or {}) do
    json.seams[#json.seams + 1] = {seam = s.name, surface = s.surface, operations = s.operations,
      heights_mm = s.heights_mm, samples = s.samples, unreached = s.unreached, material_left_max_mm = s.material_left_max_mm,
      material_left_min_mm = s.material_left_min_mm, material_left_at = s.material_left_at, overcut_mm = s.overcut_mm,
      overcut_move = s.overcut_move, overcut_at = s.overcut_at, tolerance = s.tolerance, ok = s.ok, reason = s.reason}
    print(string.format("  seam, blade 1 %-34s %s, heights %s mm: material left %s, unreached %d of %d, deepest cut "
                        .. "%.2f um (within %.1f / %.1f um): %s", s.name .. ",", s.surface,
                        s.heights_mm and string.format("%.2f-%.2f", s.heights_mm[1], s.heights_mm[2]) or "-",
                        s.material_left_max_mm and string.format("up to %.2f um at %.2f mm", 1e3 * s.material_left_max_mm,
                          s.material_left_at.height_mm) or "none reached", s.unreached, s.samples, 1e3 * s.overcut_mm,
                        1e3 * s.tolerance.material_left_mm, -1e3 * s.tolerance.overcut_mm,
                        s.ok and "ok" or "FAIL (" .. s.reason .. ")"))
    if not s.ok then r.seam_failures[#r.seam_failures + 1] = string.format("%s: %s", s.name, s.reason) end
  end
  json.seam_failures = #r.seam_failures
end

-- One colour scale for every map of a run (µm, symmetric), so two maps
-- compare: the recipe's map_scale_um, else twice the loosest tolerance the
-- run states (an operation's material left or deepest cut; an impeller's
-- thickness tolerance and allowed overcut), rounded up to 1, 2, 3 or 5
-- x 10^k so the colour bar reads in round numbers.
local function round_scale_um(x)
  if not (x > 0) then return 10 end
  local p = 10 ^ math.floor(math.log(x, 10))
  for _, f in ipairs({1, 2, 3, 5, 10}) do
    if x <= f * p * (1 + 1e-9) then return f * p end
  end
  return 10 * p
end
function M.map_scale_um(r)
  if r.map_scale_um then return r.map_scale_um end
  local t = 0
  if r.job.part_kind == "impeller" then
    t = r.o.thickness_tolerance or 0
    for _, a in pairs(r.json.units and simulate.impeller_overcut_allowed(r.json.units, r.o.overcut_slack or 0.005)
                      or {}) do
      t = math.max(t, math.abs(a))
    end
  else
    for _, op in ipairs(r.job.operations) do
      -- The maps are of the finished part: the roughing's stock (which no
      -- map shows) would spread their scale a hundredfold.
      if op.kind ~= "rough_channels" then
        local p = seams.promise(op)
        t = math.max(t, math.abs(p.left), math.abs(p.cut))
      end
    end
  end
  r.map_scale_um = r.o.map_scale_um or round_scale_um(2e3 * t)
  r.json.map_scale_um = r.map_scale_um
  return r.map_scale_um
end

-- The operations a job runs, for a title: "drum finish, edge finish, hub finish".
local function operation_kinds(job)
  local kinds, seen = {}, {}
  for _, op in ipairs(job.operations) do
    local k = op.kind:gsub("_", " ")
    if not seen[k] then seen[k], kinds[#kinds + 1] = true, k end
  end
  return table.concat(kinds, ", ")
end

-- One map of blade 1 (j:simulate_blade): every surface of the blade swept
-- by every operation's moves with their own tools, one picture and one
-- summary per region. `lean` samples coarsely.
function M.blisk.blade_map(r, lean)
  local t_map = os.clock()
  local bm = r.job:simulate_blade(lean and {flank_samples = {16, 60}, edge_samples = {40, 12}, root_samples = {12, 160},
                                            floor_samples = {40, 30}} or {})
  print(string.format("  blade 1 map: %.1f s CPU", os.clock() - t_map))
  local map = {material_left_max_mm = bm.material_left_max_mm, overcut_mm = bm.overcut_mm,
               unreached = bm.unreached, picture = r.o.name .. "_blade1_map.png", regions = {}}
  for _, g in ipairs(bm.regions) do
    map.regions[#map.regions + 1] = {name = g.name, material_left_max_mm = g.material_left_max_mm,
      material_left_min_mm = g.material_left_min_mm, overcut_mm = g.overcut_mm, overcut_move = g.overcut_move,
      unreached = g.unreached, samples = g.samples}
    print(string.format("  blade 1 map, %-14s material left %s, overcut %.2f um%s, unreached %d of %d (%.1f s)",
                        g.name .. ":", g.material_left_max_mm and string.format("%.2f..%.2f um",
                          1e3 * g.material_left_min_mm, 1e3 * g.material_left_max_mm) or "none reached",
                        1e3 * g.overcut_mm, g.overcut_move and string.format(" (job move %d)", g.overcut_move) or "",
                        g.unreached, g.samples, g.seconds))
  end
  -- The run's one scale (the fillet's ball radius is clamped to it).
  bm.map:write_png(map.picture, {title = "Blade 1 after every operation's moves (" .. operation_kinds(r.job)
                                         .. "): material left, µm; red above the design, blue below",
                                 scale_um = M.map_scale_um(r), width = 1200, height = 480})
  -- The same, painted on the blade itself, seen from each side (POV-Ray;
  -- skipped with a note where it is not installed).
  map.painted = {}
  if bliskrun.part_renderer_available() then
    local pieces = {}
    for _, g in ipairs(bm.regions) do
      if g.piece and g.name ~= "fillet" then pieces[#pieces + 1] = g.piece end  -- the fillet shares the root's surface
    end
    local mid = pieces[1].surface:point(0.5, 0.5)
    for _, side in ipairs{{"pressure", false}, {"suction", true}} do
      local picture = string.format("%s_blade1_%s_side.png", r.o.name, side[1])
      bliskrun.paint_part{path = picture, pieces = pieces, behind = side[2], up = {mid.x, mid.y, 0},
                          scale_um = M.map_scale_um(r), title = "Blade 1 from its " .. side[1]
                            .. " side: material left after every operation, µm",
                          footer = "flanks, edges, root strip and channel floor as swept for the map above; "
                                   .. "the fillet (under the root strip) is not painted"}
      map.painted[#map.painted + 1] = picture
    end
  else
    map.painted_note = "POV-Ray not installed: the painted blade is not drawn (apt-get install povray)"
    print("  " .. map.painted_note)
  end
  r.json.blade_map = map
end

-- One budget per program: what it can cut below the design is the plan's
-- deepest cut (the simulation) plus how far the program's cutter leaves
-- the proved motion as its controller moves (the sweep: the split
-- tolerance and the output resolution's rounding).
function M.blisk.posted(r)
  if not r.sim then return end
  for _, p in ipairs(r.json.programs) do
    p.overcut_bound_mm = r.sim.overcut - p.swept_cutter_mm
    print(string.format("  %s: overcut at most %.2f um (plan %.2f um, program off the plan by at most %.2f um)", p.file,
                        -1e3 * p.overcut_bound_mm, -1e3 * r.sim.overcut, 1e3 * p.swept_cutter_mm))
  end
end

-- The page's sections, pictures and ParaView blocks: every unit with its
-- simulation, the first four painted with their undercut.
function M.blisk.page(r)
  local planned, json, name = r.planned, r.json, r.o.name
  local unit_rows, blocks, pictures = {}, {{name = "job toolpath", moves = planned.moves}}, {}
  for i, f in ipairs(r.sim and r.sim.flanks or {}) do
    unit_rows[i] = {f.blade, f.side, planned.flanks[i].report.row_count, planned.flanks[i].report.poses,
                    1e3 * f.undercut_max, 1e3 * f.undercut_mean, 1e3 * f.overcut}
    if i <= 4 and f.map then
      local picture = string.format("%s_undercut_blade%d_%s.png", name, f.blade, f.side)
      -- A unit's map is its own operation's moves alone (the blade map
      -- sweeps every operation's), and says so.
      local swept = f.kind:gsub("_", " ") .. " moves only"
      local surface = (f.side == "pressure" or f.side == "suction") and f.side .. " flank" or f.side
      f.map:write_png(picture, {title = string.format("Blade %d %s, material left by the %s (µm)", f.blade, surface,
                                                      swept), scale_um = M.map_scale_um(r)})
      pictures[#pictures + 1] = {title = string.format("Material left, blade %d %s: the %s", f.blade, f.side, swept),
                                 image = picture}
      blocks[#blocks + 1] = {name = string.format("blade %d %s, undercut", f.blade, f.side),
                             surface = planned.flanks[i].plan:trimmed(), map = f.map, samples_u = 60, samples_v = 150}
    end
  end
  local program_rows = {}
  for i, p in ipairs(json.programs) do
    program_rows[i] = {p.file, p.machine, p.post, p.blocks, p.positioning, 1e3 * p.max_position_mm,
                       1e3 * p.swept_cutter_mm, 1e3 * p.swept_tool_mm,
                       -- no bound without the simulation (j:run{simulate = false}): a cell all the same
                       p.overcut_bound_mm and -1e3 * p.overcut_bound_mm or "not simulated"}
  end
  local sections = {
    {title = "Operations", text = string.format("%d moves, %d links through %s.", #planned.moves, planned.links,
                                                r.job.clearance_surface.description),
     table = {columns = {"blade", "flank, edge or root", "rows", "poses", "material left max (µm)", "mean (µm)",
                         "overcut (µm)"}, rows = unit_rows}},
    {title = "Programs, read back and swept as each controller moves", table = {columns = {"file", "machine", "post",
      "blocks", "positioning moves", "tip deviation (µm)", "cutter off the proved motion (µm)",
      "tool off the proved motion (µm)", "overcut at most (µm)"}, rows = program_rows}}}
  for _, e in ipairs(json.roughing or {}) do
    local rows = {{"levels (added for the cusp)", string.format("%d (%d)", e.levels, e.levels_added)},
                  {"passes, poses; steps and links between passes", string.format("%d, %d; %d, %d", e.passes, e.poses,
                                                                                     e.steps, e.links)},
                  {"depth between levels (step-down)", string.format("%.3f mm (%.2f)", e.level_step_max_mm, e.step_down_mm)},
                  {"distance between paths (step-over)", string.format("%.3f mm (%.2f)", e.step_over_max_mm, e.step_over_mm)},
                  {"axial engagement at most (level + the cusp above)", string.format("%.3f mm", e.axial_engagement_max_mm)},
                  {"the slot's width (full radial engagement)", string.format("%.2f mm", e.slot_width_mm)},
                  {"cusp measured: left flank, right flank, hub", string.format("%.1f, %.1f, %.1f µm (scallop %.0f)",
                    1e3 * e.face_cusp_max_mm[1], 1e3 * e.face_cusp_max_mm[2], 1e3 * e.hub_cusp_max_mm, 1e3 * e.scallop_mm)}}
    for _, s in ipairs(e.simulated and e.simulated.surfaces or {}) do
      rows[#rows + 1] = {"stock left (simulated), " .. s.name, s.stock_min_mm and string.format("%.3f .. %.3f mm (%d samples)",
                           s.stock_min_mm, s.stock_max_mm, s.samples) or "not reached"}
    end
    sections[#sections + 1] = {title = string.format("Channel roughing, channel %d (the others its path turned)", e.channel),
      text = string.format("Levels from the top down to the hub, %.2f mm stock left on both flanks and %.2f mm on the hub; "
                           .. "every pose, motion and link proved with the whole tool against both blades and the hub, "
                           .. "the cutter at least %.3f mm off them.", e.stock_mm, e.hub_stock_mm, e.cutter_clearance_mm),
      table = {columns = {"figure", "value"}, rows = rows}}
  end
  for _, m in ipairs(machine_sections(json.programs)) do sections[#sections + 1] = m end
  if json.blade_map then
    pictures[#pictures + 1] = {title = "Blade 1 after the job, one map (flanks, edges, root strip, fillet, channel floor)",
                               image = json.blade_map.picture}
    for _, p in ipairs(json.blade_map.painted) do
      pictures[#pictures + 1] = {title = "Blade 1 after the job, painted on the part", image = p}
    end
    if json.blade_map.painted_note then pictures[#pictures + 1] = {title = "Blade 1 painted", text = json.blade_map.painted_note} end
  end
  for _, p in ipairs(pictures) do sections[#sections + 1] = p end
  local files = {{name .. "_undercut_*.png", "the undercut maps above"}}
  if json.blade_map then files[2] = {json.blade_map.picture, "blade 1's whole surface after the job, one map"} end
  return sections, blocks, files
end

-- A blisk job: the deepest cut within the loosest operation's promise,
-- each operation's material left within its promise on the units it
-- finished, and every seam between operations within its tolerances.
function M.blisk.requirements(r, stop)
  local q, sim = {}, r.sim
  if sim then
    local allowed, by_kind = 0, {}
    for _, op in ipairs(r.job.operations) do
      allowed = math.min(allowed, seams.promise(op).cut)
      by_kind[op.kind] = by_kind[op.kind] or {promise = seams.promise(op), left = nil}
    end
    q[#q + 1] = {name = "overcut: deepest cut below the design (simulated, every unit)", unit = "µm",
                 measured = math.max(0, -1e3 * sim.overcut), at_most = -1e3 * allowed + 0.1,
                 note = stop and "nothing posted" or nil}
    for _, f in ipairs(sim.flanks) do
      local k = by_kind[f.kind]
      if k then k.left = math.max(k.left or -math.huge, f.undercut_max) end
      if k and f.stock and f.stock.stock_min_mm then k.least = math.min(k.least or math.huge, f.stock.stock_min_mm) end
    end
    for _, op in ipairs(r.job.operations) do
      local k = by_kind[op.kind]
      if k and k.left and not k.listed then
        k.listed = true
        q[#q + 1] = {name = string.format("material left, %s (simulated, its units)", op.kind:gsub("_", " ")),
                     unit = "µm", measured = 1e3 * k.left, at_most = 1e3 * k.promise.left}
        -- The roughing's stock is also bounded below: the finishers meet it.
        if k.promise.least then
          q[#q + 1] = {name = string.format("least stock left, %s (simulated, its units)", op.kind:gsub("_", " ")),
                       unit = "µm", measured = k.least and 1e3 * k.least, at_least = 1e3 * k.promise.least}
        end
      end
    end
    for _, f in ipairs(sim.seams or {}) do
      q[#q + 1] = {name = "seam " .. f.name .. ": material left", unit = "µm",
                   measured = f.material_left_max_mm and 1e3 * f.material_left_max_mm,
                   at_most = 1e3 * f.tolerance.material_left_mm, pass = f.ok, note = not f.ok and f.reason or nil}
    end
  end
  return common_requirements(r, q)
end

-- ---- an impeller -----------------------------------------------------------

-- An impeller job: each surface of blade 1 cut no deeper than its
-- operations allow (a face its flank finish's planned residual, the rest
-- the sweep's 2 µm), and with a thickness tolerance each flank-finished face
-- within it.
function M.impeller.requirements(r, stop)
  local q = {}
  local allowed = simulate.impeller_overcut_allowed(r.json.units, r.o.overcut_slack or 0.005)
  for _, s in ipairs(r.sim and r.sim.surfaces or {}) do
    if s.total then
      q[#q + 1] = {name = "overcut, blade 1 " .. s.name .. " (simulated)", unit = "µm",
                   measured = math.max(0, -1e3 * s.total.overcut), at_most = -1e3 * (allowed[s.name] or -0.002),
                   note = stop and s.total.overcut < (allowed[s.name] or -0.002) and "nothing posted" or nil}
    end
  end
  for _, u in ipairs(r.json.units) do
    local f = r.json.finish and r.json.finish[u.name]
    if (u.operation == "flank_finish" or u.operation == "point_mill") and f then
      q[#q + 1] = {name = u.operation:gsub("_", " ") .. ", " .. u.name .. ": largest deviation from the face as designed"
                     .. (u.operation == "point_mill" and " (simulated)" or ""), unit = "µm",
                   measured = 1e3 * math.max(f.residual_max_mm, -f.residual_min_mm),
                   at_most = 1e3 * r.json.thickness_tolerance_mm}
      -- The root strip (the face from the fillet line up to the hub stop):
      -- its material is the face's too, so an unfinished strip fails the
      -- face; measured the same way whether the rows stop above it or are
      -- carried down through it.
      if u.operation == "point_mill" and f.root_strip then
        q[#q + 1] = {name = "point mill, " .. u.name .. string.format(": root strip (%.2f mm high, %s up to the hub "
                       .. "stop) material left", f.root_strip.height_mm,
                       f.root_strip.from_fillet and "fillet line" or "hub edge"), unit = "µm",
                     measured = 1e3 * f.root_strip.left_max_mm, at_most = 1e3 * r.json.thickness_tolerance_mm,
                     note = f.root_strip.finished_by and ("finished by " .. f.root_strip.finished_by)
                       or "unfinished: no operation of the job finishes it"}
      end
    end
  end
  return common_requirements(r, q)
end

-- The units of blade 1 (every other blade's are them turned), the moves per
-- operation, and with a thickness tolerance the flank finish's verdict per
-- face: its residual against the face as designed within it or not.
function M.impeller.planned(r)
  local j, planned, json = r.job, r.planned, r.json
  local poses = 0
  for _, f in ipairs(planned.flanks) do poses = poses + (f.report.poses or 0) end
  json.blades, json.moves, json.links, json.tool_groups = j:blade_count_used(), #planned.moves, planned.links,
                                                          planned.tool_groups
  json.poses, json.refusals, json.units = poses, 0, {}
  print(string.format("Job '%s': %d blades, %d channel and face plans (%d poses, none refused: a refusal stops the "
                      .. "job and names the channel or face), %d moves, %d links over %s, each proved clear; planned "
                      .. "in %.1f s CPU", j.name, json.blades, #planned.flanks, poses, #planned.moves, planned.links,
                      j.clearance_surface.description, r.plan_seconds))
  for _, g in ipairs(planned.tool_groups) do
    print(string.format("  operation %d, tool T%d: blades %d-%d, cutting length %.0f mm", g.operation, g.tool,
                        g.blades[1], g.blades[#g.blades], g.cutting_length_mm))
  end
  local by_op = {}
  for _, m in ipairs(planned.moves) do by_op[m.operation_kind] = (by_op[m.operation_kind] or 0) + 1 end
  json.moves_by_operation = by_op
  print(string.format("  moves: notch %d, widen %d, flank finish %d, links %d", by_op.notch or 0, by_op.widen or 0,
                      by_op.flank_finish or 0, by_op.link or 0))
  if by_op.point_mill then print(string.format("  moves: point mill %d", by_op.point_mill)) end
  local tolerance = r.o.thickness_tolerance
  if tolerance then json.thickness_tolerance_mm, json.finish = tolerance, {} end
  for _, f in ipairs(planned.flanks) do
    if f.blade == 1 then
      json.units[#json.units + 1] = {operation = f.kind, name = f.side, moves = f.moves, report = f.report}
      if tolerance and f.kind == "flank_finish" then M.impeller.verdict(r, f, tolerance) end
      if tolerance and f.kind == "point_mill" then M.impeller.point_verdict(r, f, tolerance) end
    end
  end
end

-- A face's flank finish against the thickness tolerance. A part planned on
-- ruled fits of faces that are not ruled (part:ruled_fit) says what the fit
-- cost: flank finishing on it cannot follow the face as designed.
function M.impeller.verdict(r, f, tolerance)
  local part = r.job.part
  local p, fit = f.report, type(part) == "table" and part.ruled_fit and part:ruled_fit(f.side:match("^(%a+) (%a+)$"))
  local ok = p.residual_max <= tolerance and p.residual_min >= -tolerance
  r.json.finish[f.side] = {ruled_fit_max_mm = fit and fit.max, residual_max_mm = p.residual_max,
    residual_min_mm = p.residual_min, within_tolerance = ok,
    note = ok and "flank finishing holds the design within the tolerance"
      or fit and "NOT within tolerance: the blade is not ruled; flank finishing on its ruled fit undercuts and "
                 .. "overcuts the lofted face (point milling needed to finish it)"
      or "NOT within tolerance"}
  print(string.format("  %s: flank finish%s leaves %+.3f .. %+.3f mm against the face as designed: %s", f.side,
                      fit and string.format(" on the ruled fit (fit %.3f mm)", fit.max) or "", p.residual_min,
                      p.residual_max, ok and "within tolerance" or string.format("NOT within +-%.3f mm", tolerance)))
end

-- A face's point milling against the thickness tolerance: the material its
-- own moves leave on the face as designed and how deep they cut it
-- (simulated), the scallop measured against the recipe's, and why the face
-- is point-milled (job.point_mill's instead_of_flank: the flank finish's
-- residual beyond the tolerance).
function M.impeller.point_verdict(r, f, tolerance)
  local p = f.report
  local rows_ok = p.residual_max <= tolerance and p.residual_min >= -tolerance
  -- The root strip (hub_stop high, below the first row) is the face's
  -- too: unfinished, the face is not within the tolerance whatever the
  -- rows' residual says.
  -- Measured, never assumed: a strip the rows were carried through still
  -- fails beyond the tolerance.
  local strip_ok = not p.strip_left_max or p.strip_left_max <= tolerance
  local ok = rows_ok and strip_ok
  local d = p.decision
  local strip_note = p.strip_left_max and string.format("root strip %.2f mm high (%s up to the hub stop) leaves up to "
    .. "%.3f mm%s", p.strip_height, p.strip_from_fillet and "fillet line" or "hub edge", p.strip_left_max,
    strip_ok and (p.strip_finished_by and (" (" .. p.strip_finished_by .. ")") or "")
      or (p.strip_finished_by and ": NOT within tolerance although " .. p.strip_finished_by
          or ": UNFINISHED, no operation finishes it"))
    .. (p.root_corner_max and string.format("; root corner below the fillet line %.3f mm (the ball's fillet, apart)",
                                            p.root_corner_max) or "") or nil
  r.json.finish[f.side] = {method = "point milling", residual_max_mm = p.residual_max, residual_min_mm = p.residual_min,
    scallop_mm = p.scallop, scallop_measured_mm = p.scallop_measured, max_turn_deg_per_mm = p.max_turn,
    flank_residual_mm = d and d.flank_residual_mm, within_tolerance = ok, rows_within_tolerance = rows_ok,
    root_strip = p.strip_left_max and {height_mm = p.strip_height, height_min_mm = p.strip_height_min,
                                       left_max_mm = p.strip_left_max, left_mean_mm = p.strip_left_mean,
                                       from_fillet = p.strip_from_fillet, finished = strip_ok,
                                       finished_by = strip_ok and p.strip_finished_by or nil} or nil,
    root_corner_max_mm = p.root_corner_max, follows_fillet = p.follows_fillet,
    note = (d and string.format("flank milling leaves %.3f mm (> %.3f): point-milled; ", d.flank_residual_mm,
                                d.tolerance_mm) or "")
      .. (rows_ok and "the rows hold the design within the tolerance" or "the rows are NOT within tolerance")
      .. (strip_note and "; " .. strip_note or "")}
  print(string.format("  %s: point milling%s, %d rows, scallop %.1f um measured (%.1f um asked), leaves %+.3f .. "
                      .. "%+.3f mm over the rows against the face as designed (simulated)%s: %s", f.side,
                      d and string.format(" (flank residual %.3f mm > %.3f)", d.flank_residual_mm, d.tolerance_mm) or "",
                      p.rows, 1e3 * p.scallop_measured, 1e3 * p.scallop, p.residual_min, p.residual_max,
                      strip_note and "; " .. strip_note or "",
                      ok and "within tolerance" or string.format("NOT within +-%.3f mm", tolerance)))
end

function M.impeller.simulated(r)
  local search_below = r.o.simulate and r.o.simulate.search_below
  r.simulated = r.job:report_simulation(r.sim, {pictures = r.o.name .. "_left_", search_below = search_below,
                                                 scale_um = M.map_scale_um(r)})
  r.json.simulation = r.simulated.json
  print(string.format("  simulation: %.1f s CPU%s", r.sim.seconds, search_below
                        and string.format(" (overcut measured down to %.3f mm)", search_below) or ""))
end

function M.impeller.posted() end

function M.impeller.page(r)
  local planned, json = r.planned, r.json
  local unit_rows, program_rows = {}, {}
  for _, u in ipairs(json.units) do unit_rows[#unit_rows + 1] = {u.operation, u.name, u.moves, u.report.poses} end
  for i, p in ipairs(json.programs) do
    program_rows[i] = {p.file, p.machine, p.post, p.blocks, p.positioning, 1e3 * p.max_position_mm}
  end
  local sections = {
    {title = "Blade 1's plans", text = string.format("%d moves in all, %d links over %s.", #planned.moves,
                                                     planned.links, r.job.clearance_surface.description),
     table = {columns = {"operation", "channel / face", "moves", "poses"}, rows = unit_rows}}}
  if json.finish then
    local rows = {}
    for _, u in ipairs(json.units) do
      local f = json.finish[u.name]
      if (u.operation == "flank_finish" or u.operation == "point_mill") and f then
        rows[#rows + 1] = {u.name, u.operation == "point_mill" and "point milling" or "flank milling",
                           1e3 * f.residual_min_mm, 1e3 * f.residual_max_mm, f.within_tolerance and "yes" or "NO"}
      end
    end
    sections[#sections + 1] = {title = "Face finishing against the faces as designed", text = string.format(
      "Flank milling: residual of the ruled cutter's axes (balanced) against the design; point milling: the "
      .. "material its moves leave (simulated); thickness tolerance %.3f mm.", json.thickness_tolerance_mm),
      table = {columns = {"face", "method", "residual min (µm)", "residual max (µm)", "within tolerance"}, rows = rows}}
  end
  sections[#sections + 1] = {title = "Material left (simulated, blade 1's faces and one pitch of the hub)",
    table = {columns = {"surface", "moves of", "left min (µm)", "left max (µm)", "undercut mean (µm)", "overcut (µm)",
                        "overcut at move", "untouched samples"}, rows = r.simulated.rows}}
  sections[#sections + 1] = {title = "Programs, read back and replayed", table = {columns = {"file", "machine", "post",
    "blocks", "positioning moves", "tip deviation (µm)"}, rows = program_rows}}
  for _, m in ipairs(machine_sections(json.programs)) do sections[#sections + 1] = m end
  for _, p in ipairs(r.simulated.pictures) do sections[#sections + 1] = p end
  return sections, {{name = "job toolpath", moves = planned.moves}},
         {{r.o.name .. "_left_*.png", "the maps of the material left above"}}
end

-- An impeller job's simulation (j:simulate) for a run's report: prints each
-- surface's state after the job, writes its map (o.pictures .. name ..
-- ".png") and returns {json = {surfaces, seconds}, rows = (the report
-- table's rows), pictures = {{title, image}, ...}}. o.search_below: the
-- depth an overcut was measured to — one reaching it is printed "AT LEAST"
-- and flagged overcut_at_window_depth. o.scale_um: the colour scale of
-- every map (default: each map's own).
function Job:report_simulation(sim, o)
  local out = {json = {surfaces = {}, seconds = sim.seconds}, rows = {}, pictures = {}}
  for _, s in ipairs(sim.surfaces) do
    local entry = {name = s.name, groups = {}}
    for _, g in ipairs(s.groups) do
      entry.groups[#entry.groups + 1] = {name = g.name, operation = g.operation, residual_min_mm = g.residual_min,
        residual_max_mm = g.residual_max, undercut_mean_mm = g.undercut_mean, overcut_mm = g.overcut,
        overcut_move = g.overcut_move, overcut_operation = g.overcut_operation, untouched = g.untouched,
        samples = g.samples, seconds = g.seconds}
      out.rows[#out.rows + 1] = {s.name, g.name, g.residual_min and 1e3 * g.residual_min or "-",
                                 g.residual_max and 1e3 * g.residual_max or "-", 1e3 * g.undercut_mean, 1e3 * g.overcut,
                                 g.overcut_move or "-", g.untouched}
    end
    out.json.surfaces[#out.json.surfaces + 1] = entry
    local t = s.total
    if t then
      entry.overcut_at_window_depth = o.search_below and t.overcut <= -o.search_below + 1e-9 or nil
      print(string.format("  simulated %-14s after the job: %s, overcut %s%.1f um%s", s.name,
                          t.residual_min and string.format("material left %.3f..%.3f mm", t.residual_min, t.residual_max)
                            or "not reached by this job", entry.overcut_at_window_depth and "AT LEAST " or "",
                          -1e3 * t.overcut,
                          t.overcut_move and string.format(" (job move %d, %s)", t.overcut_move, t.overcut_operation) or ""))
      local picture = o.pictures .. s.name:gsub(" ", "_") .. ".png"
      local ops, seen = {}, {}
      for _, g in ipairs(s.groups) do
        local op = g.name
        if op and not seen[op] then seen[op], ops[#ops + 1] = true, tostring(op):gsub("_", " ") end
      end
      t.map:write_png(picture, {title = "Blade 1 " .. s.name .. ": material left after the moves of "
                                        .. (#ops > 0 and table.concat(ops, ", ") or "the job") .. " (µm)",
                                scale_um = o.scale_um})
      out.pictures[#out.pictures + 1] = {title = "Material left, " .. s.name, image = picture}
    end
  end
  return out
end

return M
