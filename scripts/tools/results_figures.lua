-- Which figures of each recipe's JSON report bench/RESULTS.md shows, declared
-- once per recipe: {label, dotted path (arrays 1-based) or fmt(...), scale,
-- significant digits}. Lengths in the reports are mm; lengths here are mostly
-- µm (scale UM). A key the report no longer has is listed at the end of
-- RESULTS.md (scripts/tools/results.lua) instead of silently dropped.
local UM = 1000

local function get(report, path)
  local v = report
  for key in path:gmatch("[^.]+") do
    if type(v) ~= "table" then return nil end
    v = v[tonumber(key) or key]
  end
  return v
end

-- fmt("%d rows, %.2f um", "a.rows", {"a.left", UM}): several keys in one cell;
-- returns nil and the first missing key when one is absent.
local function fmt(pattern, ...)
  local specs = {...}
  return function(report)
    local values = {}
    for i, s in ipairs(specs) do
      local path, scale = s, nil
      if type(s) == "table" then path, scale = s[1], s[2] end
      local v
      if type(path) == "function" then v, path = path(report) else v = get(report, path) end
      if v == nil then return nil, path end
      values[i] = scale and v * scale or v
    end
    return string.format(pattern, table.unpack(values))
  end
end

-- A drum-finish plan's report with its simulation (blisk_drum_finish.json).
local function drum_flank(label, p)
  local s = p .. ".simulation"
  return {
    {label .. ": rows (inserted), poses (tilted)",
     fmt("%d (%d), %d (%d)", p .. ".row_count", p .. ".inserted_rows", p .. ".poses", p .. ".tilted_poses")},
    {label .. ": refused poses / links", fmt("%d / %d", p .. ".refusals", p .. ".refused_links")},
    {label .. ": largest chord deviation (µm)", p .. ".max_deviation", UM},
    {label .. ": material left max / mean (µm), overcut (µm)",
     fmt("%.2f / %.2f, %.2f", {s .. ".undercut_max_mm", UM}, {s .. ".undercut_mean_mm", UM}, {s .. ".overcut_mm", UM})},
  }
end

local function concat(...)
  local out = {}
  for _, list in ipairs{...} do for _, v in ipairs(list) do out[#out + 1] = v end end
  return out
end

local M = {}

M["blisk_wheel_design.lua"] = {
  json = "blisk_wheel_design.json",
  about = "Curvature of the machined flanks of blade 1 (trimmed between the hub and casing curves, "
          .. "edges excluded) and the drum wheel that fits. k1: the largest concave principal curvature; "
          .. "k2: the largest convex one; k_e: the largest curvature along any axis direction the C axis "
          .. "reaches within ±30°; d_min: the narrowest passage between two blades. Wheel: barrel radius "
          .. "R_c below 1/k1 (traditional) or 1/k_e (extended), diameter D_t below d_min − 2 mm. For "
          .. "comparison, the blisk paper's blisk: k1 0.0435, k_e 0.0195 mm⁻¹ → R_c 20 / 50, D_t 8 mm.",
  rows = {
    {"narrowest passage d_min (mm)", "part.narrowest_passage_mm", 1, 4},
    {"k1 max (1/mm), flank", fmt("%.4f, %s", "table1.k1_max", "table1.k1_max_flank")},
    {"k2 max (1/mm), flank", fmt("%.4f, %s", "table1.k2_max", "table1.k2_max_flank")},
    {"k_e max (1/mm), flank", fmt("%.4f, %s", "table1.ke_max", "table1.ke_max_flank")},
    {"where: k1 max, k_e max (span fraction from the hub, chord fraction from the LE)", function(r)
      local t = r.table1
      if not (t and r.flanks) then return nil, "flanks" end
      local function at(key)
        local e = r.flanks[t[key .. "_flank"]][key]
        -- v runs LE to TE on the pressure flank, TE to LE on the suction flank.
        local chord = t[key .. "_flank"] == "suction" and 1 - e.v or e.v
        return string.format("%.2f, %.2f", e.u, chord)
      end
      return string.format("(%s), (%s)", at("k1_max"), at("ke_max"))
    end},
    {"whole grid, extension below the hub included: k1 / k_e max (1/mm)",
     fmt("%.4f / %.4f", "table1_whole_grid.k1_max", "table1_whole_grid.ke_max")},
    {"traditional wheel: R_c / D_t (mm)",
     fmt("%g / %g", "table2.traditional.barrel_radius", "table2.traditional.max_diameter")},
    {"extended wheel: R_c / D_t (mm)", fmt("%g / %g", "table2.extended.barrel_radius", "table2.extended.max_diameter")},
  },
}

M["blisk_drum_finish.lua"] = {
  json = "blisk_drum_finish.json",
  about = "Both flanks of blade 1 with the extended wheel, 14 µm residual, 2 µm chord tolerance; every move "
          .. "of the program simulated at 200 × 1000 samples.",
  rows = concat(drum_flank("pressure", "flanks.pressure"), drum_flank("suction", "flanks.suction")),
}

M["blisk_drum_study.lua"] = {
  json = "blisk_drum_study.json",
  about = "One flank: a/b the traditional wheel with constant / variable steps, c/d the extended wheel with "
          .. "constant / variable steps. Constant steps are planned as the paper plans them and not measured, "
          .. "so their chord error may exceed the 2 µm tolerance; variable steps are measured within it.",
  rows = (function()
    local rows = {}
    for _, g in ipairs{"a", "b", "c", "d"} do
      local p = "groups." .. g
      rows[#rows + 1] = {"group " .. g .. ": rows, poses", fmt("%d, %d", p .. ".rows", p .. ".poses")}
      rows[#rows + 1] = {"group " .. g .. ": largest chord error (µm), rows over tolerance",
                         fmt("%.2f, %d", {p .. ".max_chord_error_mm", UM}, p .. ".rows_over_tolerance")}
      rows[#rows + 1] = {"group " .. g .. ": material left max / mean (µm), overcut (µm)",
                         fmt("%.2f / %.2f, %.2f", {p .. ".table5.undercut_max_mm", UM},
                             {p .. ".table5.undercut_mean_mm", UM}, {p .. ".table5.overcut_mm", UM})}
    end
    return rows
  end)(),
}

M["blisk_post.lua"] = {
  json = "blisk_post.json",
  about = "The suction flank's plan posted and read back: the A/C trunnion (Fanuc, machine axes) and the "
          .. "B/C head-table (Heidenhain, TCPM). Positioning moves: rapids that turn a rotary axis, "
          .. "written as feed moves.",
  rows = {
    {"planned moves", "planned_moves"},
    {"Fanuc: blocks (inserted, positioning)",
     fmt("%d (%d, %d)", "programs.1.blocks", "programs.1.inserted", "programs.1.positioning")},
    {"Fanuc: tip within (µm) of the plan, read back", "programs.1.max_position_mm", UM},
    {"Heidenhain: blocks (inserted, positioning)",
     fmt("%d (%d, %d)", "programs.2.blocks", "programs.2.inserted", "programs.2.positioning")},
    {"Heidenhain: tip within (µm) of the plan, read back", "programs.2.max_position_mm", UM},
  },
}

M["blisk_hub_finish.lua"] = {
  json = "blisk_hub_finish.json",
  about = "Blade 1's root strip and the channel floor to blade 2 with a tapered ball end (r 1.5 mm), 5 µm "
          .. "scallop, 1 µm chord. The fillet: the design's sharp corner between hub and blade, which the "
          .. "ball leaves as its own radius, reported apart.",
  rows = {
    {"root strip: rows, poses (tilted), refused",
     fmt("%d, %d (%d), %d", "root.rows", "root.poses", "root.tilted", "root.refusals")},
    {"channel floor: rows, poses (tilted), refused",
     fmt("%d, %d (%d), %d", "channel.rows", "channel.poses", "channel.tilted", "channel.refusals")},
    {"root strip simulated: unreached, material left max / mean (µm), overcut (µm)",
     fmt("%d, %.2f / %.2f, %.2f", "simulation.strip.unreached", {"simulation.strip.left_max", UM},
         {"simulation.strip.left_mean", UM}, {"simulation.strip.overcut", UM})},
    {"floor simulated: unreached, material left max / mean (µm), overcut (µm)",
     fmt("%d, %.2f / %.2f, %.2f", "simulation.floor.unreached", {"simulation.floor.left_max", UM},
         {"simulation.floor.left_mean", UM}, {"simulation.floor.overcut", UM})},
    {"fillet left in the sharp corner (mm)", "fillet.radius", 1, 3},
  },
}

-- The largest (machined − design) thickness of an edge, µm, over the measured spans.
local function thickness_excess(edge)
  return function(report)
    local list = get(report, "edges." .. edge .. ".thickness")
    if not list then return nil, "edges." .. edge .. ".thickness" end
    local worst
    for _, t in ipairs(list) do
      if t.measured then
        local d = UM * (t.machined - t.design)
        if not worst or math.abs(d) > math.abs(worst) then worst = d end
      end
    end
    return worst and string.format("%+.2f", worst) or "not measured"
  end
end

M["blade_edges.lua"] = {
  json = "blade_edges.json",
  about = "Blade 1's leading and trailing edge with the bottom of a flat-end mill (R 3, corner r 0.5 mm), "
          .. "material left held within the band of −1 to 20 µm. Side-edge rows: how many rows the cutter's "
          .. "side would need instead. Partial rows fill where tilted poses cut narrower strips.",
  rows = (function()
    local rows = {}
    for _, e in ipairs{"leading", "trailing"} do
      local p = "edges." .. e
      rows[#rows + 1] = {e .. ": rows (side-edge rows), partial rows",
                         fmt("%d (%d), %d", p .. ".row_count", p .. ".side_rows", p .. ".infill_rows")}
      rows[#rows + 1] = {e .. ": widest strip on the compared row, bottom / side edge (mm)", function(r)
        local c = get(r, p .. ".comparison")
        if not (c and c.emitted and c.side) then return nil, p .. ".comparison" end
        return string.format("%.2f / %.2f", math.max(table.unpack(c.emitted)), math.max(table.unpack(c.side)))
      end}
      rows[#rows + 1] = {e .. ": poses (tilted, lifted), refused poses / links",
                         fmt("%d (%d, %d), %d / %d", p .. ".poses", p .. ".tilted_contacts", p .. ".lifted_contacts",
                             p .. ".refusals", p .. ".refused_links")}
      rows[#rows + 1] = {e .. ": material left max (µm), overcut edge / flanks (µm)",
                         fmt("%.2f, %.2f / %.2f", {p .. ".simulation.undercut_max_mm", UM},
                             {p .. ".simulation.overcut_mm", UM}, {p .. ".simulation.flank_overcut_mm", UM})}
      rows[#rows + 1] = {e .. ": machined thickness − design, largest (µm)", thickness_excess(e)}
      rows[#rows + 1] = {e .. ": hub strip left for the hub operation (mm)", p .. ".hub_strip", 1, 3}
    end
    return rows
  end)(),
}

-- Over a list (arrays 1-based): the min/max/sum of a field.
local function over(path, field, op, scale)
  return function(report)
    local list = get(report, path)
    if not list then return nil, path end
    local acc
    for _, x in ipairs(list) do
      local v = x[field]
      if v == nil then return nil, path .. ".*." .. field end
      if acc == nil then acc = v
      elseif op == "max" then acc = math.max(acc, v)
      elseif op == "min" then acc = math.min(acc, v)
      else acc = acc + v end
    end
    return acc and acc * (scale or 1)
  end
end

local function cells(pattern, ...)
  local fns = {...}
  return function(report)
    local values = {}
    for i, f in ipairs(fns) do
      local v, absent = f(report)
      if v == nil then return nil, absent end
      values[i] = v
    end
    return string.format(pattern, table.unpack(values))
  end
end

M["blade_belt_grinding.lua"] = {
  json = "blade_belt_grinding.json",
  about = "Both flanks of the built-in blade 1 at three stations (coarse, fine, polish), one KUKA KRL and one "
          .. "ABB RAPID program per station and flank. Scallop: the ridge between two paths; joint speed: the "
          .. "fraction of each joint's maximum while grinding; rubber give: how far the contact wheel's "
          .. "rubber is asked to yield on a concave flank.",
  rows = (function()
    local rows = {}
    for i, s in ipairs{"coarse", "fine", "polish"} do
      local p = "stations." .. i .. ".flanks"
      rows[#rows + 1] = {s .. ": paths pressure / suction, scallop max (µm)",
                         fmt("%d / %d, %.2f / %.2f", p .. ".pressure.paths", p .. ".suction.paths",
                             {p .. ".pressure.scallop_max", UM}, {p .. ".suction.scallop_max", UM})}
    end
    rows[#rows + 1] = {"programs, moves per program", cells("%d, %d–%d", function(r)
      local l = r.programs return l and #l, "programs" end, over("programs", "moves", "min"),
      over("programs", "moves", "max"))}
    rows[#rows + 1] = {"branch changes, largest grinding joint speed (of the maximum)",
                       cells("%d, %.2f", over("programs", "branch_changes", "sum"),
                             over("programs", "joint_speed_ratio", "max"))}
    rows[#rows + 1] = {"wheel poses checked, rejected", cells("%d, %d", over("programs", "wheel_poses_checked", "sum"),
                                                              over("programs", "wheel_rejected", "sum"))}
    rows[#rows + 1] = {"rubber give, largest (mm)", over("programs", "wheel_conformity_mm", "max"), 1, 3}
    rows[#rows + 1] = {"read back: tip within (µm)", over("programs", "max_position_mm", "max", UM), 1, 3}
    rows[#rows + 1] = {"scan registration: points, clamping error moving blade points by (mm), left after (µm)",
                       fmt("%d, %.3f, %.2f", "scan.points", "scan.blade_error_uncorrected_mm",
                           "scan.blade_error_corrected_um")}
    rows[#rows + 1] = {"scan registration: rms (µm), condition, a point's sigma (µm)",
                       fmt("%.2f, %.3g, %.2f", "scan.rms_um", "scan.condition", "scan.sigma.point_um")}
    return rows
  end)(),
}

local function repair(label)
  return {
    json = "blade_repair.json",
    about = "The built-in blade 1 twisted 1.5°, bent 0.3 mm and damaged (" .. label .. "), measured on 30 planes × "
            .. "2000 points (σ 2 µm), rebuilt, its damaged region found and re-machined with a ball end (R 3): "
            .. "finishing layer simulated on the rebuilt surface.",
    rows = {
      {"measured points: mean / max deviation from the rebuilt blade (µm); noise floor (µm)",
       fmt("%.2f / %.2f; %.2f", "rebuild.mean_deviation_um", "rebuild.max_deviation_um", "rebuild.noise_floor_um")},
      {"Gaussian curvature 1–99 % (1/mm²): rebuilt / design",
       fmt("%.4f…%.4f / %.4f…%.4f", "gaussian_curvature.rebuilt.p01", "gaussian_curvature.rebuilt.p99",
           "gaussian_curvature.design.p01", "gaussian_curvature.design.p99")},
      {"damaged region: volume (mm³), largest thickness (mm)",
       fmt("%.1f, %.2f", "region.volume_mm3", "region.max_thickness_mm")},
      {"repair paths: pattern, layers, poses, refused",
       fmt("%s, %d, %d, %d", "repair_paths.pattern", "repair_paths.layers", "repair_paths.poses",
           "repair_paths.refusals")},
      {"finishing layer: material left max (µm) of allowed, overcut region / band (µm)",
       fmt("%.2f of %.1f, %.2f / %.2f", {"repair_paths.simulation.residual_max_mm", UM},
           {"repair_paths.simulation.allowed_undercut_mm", UM}, {"repair_paths.simulation.overcut_mm", UM},
           {"repair_paths.simulation.band_overcut_mm", UM})},
    },
  }
end
-- blade_repair.lua runs twice (tip, edge): keyed by recipe and settings.
M["blade_repair.lua"] = repair("tip broken off at 80 % span")
M["blade_repair.lua damage=edge"] = repair("leading edge nicked 1 mm deep")

M["blade_repair_paths.lua"] = {
  json = "blade_repair_paths.json",
  about = "Repair toolpaths through a 2 mm weld deposit on the built-in blade 1 (ball end R 3): the tip as a "
          .. "spiral per layer, the leading edge as zigzag passes; finishing simulated on the design; the tip's "
          .. "finish posted for the A/C trunnion (Fanuc) and read back.",
  rows = (function()
    local rows = {}
    for _, g in ipairs{"tip", "edge"} do
      local p = "regions." .. g
      rows[#rows + 1] = {g .. ": poses, passes, refused", fmt("%d, %d, %d", p .. ".poses", p .. ".passes", p .. ".refusals")}
      rows[#rows + 1] = {g .. ": material left max / mean (µm), overcut region / band (µm)",
                         fmt("%.2f / %.2f, %.2f / %.2f", {p .. ".simulation.residual_max_mm", UM},
                             {p .. ".simulation.undercut_mean_mm", UM}, {p .. ".simulation.overcut_mm", UM},
                             {p .. ".simulation.band_overcut_mm", UM})}
    end
    rows[#rows + 1] = {"tip program: blocks, tip within (µm) on read-back",
                       fmt("%d, %.2f", "post.blocks", {"post.max_position_mm", UM})}
    return rows
  end)(),
}

M["impeller_flank_finish.lua"] = {
  json = "impeller_flank_finish.json",
  about = "Blade 1's four faces (main blade and splitter, plus and minus side) flank-milled with a tapered ball "
          .. "end (r 3, 2°). Residual: the distance of the machined face from the design, > 0 material left, "
          .. "< 0 cut below; each axis fitted to the face (least squares, then minimax; issue 40), before the "
          .. "fit (shifted to centre its residual: balanced), and the paper's axes.",
  rows = (function()
    local rows = {{"poses, tilted, refused", fmt("%d, %d, %d", "totals.poses", "totals.tilted", "totals.refused")}}
    for _, f in ipairs{"main_plus", "main_minus", "splitter_plus", "splitter_minus"} do
      local p = "faces.impeller_" .. f
      rows[#rows + 1] = {f:gsub("_", " ") .. ": residual fitted / balanced / paper's axes, max / min (mm)",
                         fmt("%+.3f / %+.3f, %+.3f / %+.3f, %+.3f / %+.3f", p .. ".residual.max", p .. ".residual.min",
                             p .. ".residual_before.max", p .. ".residual_before.min",
                             p .. ".residual_unbalanced.max", p .. ".residual_unbalanced.min")}
    end
    return rows
  end)(),
}

M["impeller_channel_roughing.lua"] = {
  json = "impeller_channel_roughing.json",
  about = "The channel between main blades 1 and 2, split by the splitter into three (inlet, left, right): "
          .. "notched in its middle in levels of at most 5 mm, then widened to both faces for a 10 µm cusp, "
          .. "0.5 mm stock left on the faces.",
  rows = (function()
    local rows = {{"poses, refused", fmt("%d, %d", "totals.poses", "totals.refused")}}
    for _, c in ipairs{"inlet", "left", "right"} do
      local p = "channels." .. c
      rows[#rows + 1] = {c .. ": notch levels, widening paths left + right (added), cusp max (µm)",
                         fmt("%d, %d + %d (%d), %.2f", p .. ".notch_levels", p .. ".widen_left", p .. ".widen_right",
                             p .. ".paths_added", {p .. ".scallop_max", UM})}
    end
    return rows
  end)(),
}

-- One row per program of a job: blocks and read-back deviation.
local function programs(report)
  local rows = {}
  for _, p in ipairs(report.programs or {}) do
    rows[#rows + 1] = string.format("%s %d (%.2f µm)", p.file, p.blocks, UM * p.max_position_mm)
  end
  if #rows == 0 then return nil, "programs" end
  return table.concat(rows, "; ")
end

-- Blade 1's simulation per operation (not the turned copies).
local function blade1_simulation(report)
  local rows = {}
  for _, f in ipairs(get(report, "simulation.flanks") or {}) do
    if f.blade == 1 and not f.turned_from and f.operation ~= "rough_channels" then  -- the roughing's stock: its own row
      rows[#rows + 1] = string.format("%s %.2f / %.2f", f.side, UM * f.undercut_max_mm, UM * f.overcut_mm)
    end
  end
  if #rows == 0 then return nil, "simulation.flanks" end
  return table.concat(rows, "; ")
end

M["blisk_job.lua"] = {
  json = "blisk_job.json",
  about = "The built-in blisk's first blades as one job from the blank: the channels either side roughed in "
          .. "levels (0.5 mm stock left), then drum finish of both flanks, trailing edges, root "
          .. "strips and channel floors, leading edges last; blade 1 planned, simulated and turned onto the "
          .. "others; posted per machine and setup (setup 2: the part turned over for the leading edges). The "
          .. "fillet region is the design's sharp corner between hub and blade, which the r 1.5 mm ball leaves "
          .. "as its own radius (reported apart).",
  rows = {
    {"plans, moves, links", fmt("%d, %d, %d", function(r) return r.flanks and #r.flanks, "flanks" end, "moves", "links")},
    {"roughing, channel 1: levels, passes, poses; level step, path step (mm); cusps flanks / hub (µm)", function(r)
      local g = get(r, "roughing")
      if not g or not g[1] then return nil, "roughing" end
      g = g[1]
      return string.format("%d, %d, %d; %.3f, %.3f; %.1f / %.1f / %.1f", g.levels, g.passes, g.poses,
                           g.level_step_max_mm, g.step_over_max_mm, UM * g.face_cusp_max_mm[1],
                           UM * g.face_cusp_max_mm[2], UM * g.hub_cusp_max_mm)
    end},
    {"roughing, channel 1: stock left, simulated (mm)", function(r)
      local s = get(r, "roughing")
      s = s and s[1] and s[1].simulated
      if not s then return nil, "roughing[1].simulated" end
      local out = {}
      for _, g in ipairs(s.surfaces) do
        out[#out + 1] = string.format("%s %.3f..%.3f", g.name, g.stock_min_mm, g.stock_max_mm)
      end
      return table.concat(out, "; ")
    end},
    {"blade 1 per operation: material left max / overcut (µm)", blade1_simulation},
    {"seams between operations on blade 1: material left max (µm), unreached, overcut (µm)", function(r)
      if not r.seams or #r.seams == 0 then return nil, "seams" end
      local left, unreached, over = 0, 0, 0
      for _, s in ipairs(r.seams) do
        left = math.max(left, s.material_left_max_mm or 0)
        unreached = unreached + s.unreached
        over = math.min(over, s.overcut_mm)
      end
      return string.format("%.2f, %d, %.2f", UM * left, unreached, UM * over)
    end},
    {"blade 1 as one map: unreached, overcut (µm)", fmt("%d, %.2f", "blade_map.unreached", {"blade_map.overcut_mm", UM})},
    {"blade 1 as one map, material left max per region (µm)", function(r)
      local regions = get(r, "blade_map.regions")
      if not regions then return nil, "blade_map.regions" end
      local out = {}
      for _, g in ipairs(regions) do
        out[#out + 1] = string.format("%s %s", g.name, g.material_left_max_mm
                                      and string.format("%.2f", UM * g.material_left_max_mm) or "—")
      end
      return table.concat(out, "; ")
    end},
    {"programs: blocks (tip within, read back)", programs},
  },
}

M["impeller_job.lua"] = {
  json = "impeller_job.json",
  about = "The built-in impeller as one job: channels notched and widened (the widening finishing the hub), "
          .. "faces flank-finished, blade 1 planned and turned onto the others, simulated, posted for two B/C "
          .. "trunnions (Heidenhain with TCPM, Fanuc without). A quick run (2 blades, one channel, one face) "
          .. "leaves the stock on what it does not finish: those surfaces show up to 1 mm (faces) or 2 mm (hub) left.",
  rows = {
    {"blades, moves, links", fmt("%d, %d, %d", "blades", "moves", "links")},
    {"moves: notch, widen, flank finish, link",
     fmt("%d, %d, %d, %d", "moves_by_operation.notch", "moves_by_operation.widen", "moves_by_operation.flank_finish",
         "moves_by_operation.link")},
    {"after the job, per simulated surface: material left max / overcut (mm)", function(r)
      local surfaces = get(r, "simulation.surfaces")
      if not surfaces then return nil, "simulation.surfaces" end
      local out = {}
      for _, s in ipairs(surfaces) do
        for _, g in ipairs(s.groups) do
          if g.name == "job" and g.residual_max_mm then
            out[#out + 1] = string.format("%s %.3f / %.3f", s.name, g.residual_max_mm, g.overcut_mm)
          end
        end
      end
      return #out > 0 and table.concat(out, "; ") or "nothing reached"
    end},
    {"programs: blocks (tip within, read back)", programs},
  },
}

local function rotor_wheel(name, json)
  return {
    json = json,
    about = name .. " (NASA data, lofted from its sections), analysed between the hub and tip sections; "
            .. "symbols as for `blisk_wheel_design.lua` above.",
    rows = {
      {"narrowest passage d_min (mm)", "part.narrowest_passage_mm", 1, 4},
      {"k1 max (1/mm), flank", fmt("%.4f, %s", "table1.k1_max", "table1.k1_max_flank")},
      {"k2 max (1/mm), flank", fmt("%.4f, %s", "table1.k2_max", "table1.k2_max_flank")},
      {"k_e max (1/mm), flank", fmt("%.4f, %s", "table1.ke_max", "table1.ke_max_flank")},
      {"traditional / extended wheel R_c, D_t (mm)",
       fmt("%g / %g, %g", "table2.traditional.barrel_radius", "table2.extended.barrel_radius",
           "table2.extended.max_diameter")},
      {"loft: fit of the given points max / RMS (µm)", fmt("%.3f / %.4f", {"fit.max_mm", UM}, {"fit.rms_mm", UM})},
    },
  }
end
M["rotor67_wheel_design.lua --data"] = rotor_wheel("NASA Rotor 67", "rotor67_wheel_design.json")
M["rotor37_wheel_design.lua --data"] = rotor_wheel("NASA Rotor 37", "rotor37_wheel_design.json")

M["hecc_impeller_model.lua --data"] = {
  json = "hecc_impeller_model.json",
  about = "The NASA HECC impeller's design-intent blades lofted from their sections. Fit: the given points "
          .. "against the lofted flanks; left out: each interior section against the loft of the others (the "
          .. "honest measure between sections).",
  rows = (function()
    local rows = {}
    for _, b in ipairs{"main", "splitter"} do
      local p = "blades." .. b
      rows[#rows + 1] = {b .. ": sections, fit max / RMS (µm), left out max / RMS (µm)",
                         fmt("%d, %.2f / %.3f, %.1f / %.1f", p .. ".sections", {p .. ".fit.max_mm", UM},
                             {p .. ".fit.rms_mm", UM}, {p .. ".fit.left_out.max_mm", UM},
                             {p .. ".fit.left_out.rms_mm", UM})}
    end
    return rows
  end)(),
}

M["hecc_impeller_flank_finish.lua --data"] = {
  json = "hecc_impeller_flank_finish.json",
  about = "Each lofted HECC face fitted with a ruled surface and flank-milled on it (tapered ball end r 2, 2°); "
          .. "the residual is measured against the lofted (true) face. The blades are not ruled: the fit is "
          .. "far outside the 0.05 mm thickness tolerance, and the report flags it.",
  rows = (function()
    local rows = {}
    for _, f in ipairs{"main_pressure", "main_suction", "splitter_pressure", "splitter_suction"} do
      local p = "faces.hecc_" .. f
      rows[#rows + 1] = {f:gsub("_", " ") .. ": ruled fit max / RMS (µm), poses, refused, residual max / min (mm), before the axis fit",
                         fmt("%.0f / %.0f, %d, %d, %+.3f / %+.3f, %+.3f / %+.3f", p .. ".ruled_fit.max_um",
                             p .. ".ruled_fit.rms_um", p .. ".poses", p .. ".refused", p .. ".residual.max",
                             p .. ".residual.min", p .. ".residual_before.max", p .. ".residual_before.min")}
    end
    return rows
  end)(),
}

return M
