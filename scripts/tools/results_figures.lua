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
      local v = get(report, path)
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

return M
