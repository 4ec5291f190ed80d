-- The report.html a recipe writes at the end of its run (bliskrun.report):
-- the run's settings as a table first, the recipe's own sections, the numbers
-- of its JSON report (when given), and a last section naming the other files
-- of the run and what opens them (docs/looking_at_results.md). With `vtk`,
-- the run's geometry goes to a ParaView collection too.
--
--   local run_report = require("run_report")
--   run_report.write{title =, subtitle =, settings = {key = value, ...},
--                    sections = {...}, numbers = report_table,
--                    vtk = {path = "run.pvd", blocks = {...}},
--                    files = {{"name", "what it holds"}, ...}}
local M = {}

-- {key = value} -> {columns, rows} sorted by key; nested tables are skipped.
function M.settings_table(settings)
  local keys = {}
  for k, v in pairs(settings) do
    if type(v) ~= "table" then keys[#keys + 1] = k end
  end
  table.sort(keys)
  local rows = {}
  for i, k in ipairs(keys) do rows[i] = {k, settings[k]} end
  return {columns = {"setting", "value"}, rows = rows}
end

-- Every number, string and boolean of a (JSON) report table as rows
-- {"a.b.c", value}, sorted by key path; lists longer than `max_list` (8)
-- are summarised by their length (toolpaths, per-point data).
function M.numbers_table(report, max_list)
  max_list = max_list or 8
  local rows = {}
  local function walk(value, path, depth)
    if type(value) ~= "table" then
      rows[#rows + 1] = {path, type(value) == "boolean" and tostring(value) or value}
      return
    end
    if depth > 6 then return end
    if #value > max_list then
      rows[#rows + 1] = {path, string.format("(%d entries, in the JSON)", #value)}
      return
    end
    local keys = {}
    for k in pairs(value) do keys[#keys + 1] = k end
    table.sort(keys, function(a, b) return tostring(a) < tostring(b) end)
    for _, k in ipairs(keys) do
      walk(value[k], path == "" and tostring(k) or (path .. "." .. tostring(k)), depth + 1)
    end
  end
  walk(report, "", 0)
  return {columns = {"key", "value"}, rows = rows}
end

function M.write(opts)
  local sections = {{title = "Settings", table = M.settings_table(opts.settings or {})}}
  for _, s in ipairs(opts.sections or {}) do sections[#sections + 1] = s end
  if opts.numbers then
    sections[#sections + 1] = {title = "All numbers of the run",
                               text = "The JSON report's values by key; long lists are in the JSON.",
                               table = M.numbers_table(opts.numbers)}
  end
  local files = opts.files or {}
  if opts.vtk and #opts.vtk.blocks > 0 then
    bliskrun.write_vtk(opts.vtk)
    files[#files + 1] = {opts.vtk.path, "ParaView collection (geometry, toolpaths; docs/looking_at_results.md)"}
  end
  if #files > 0 then
    sections[#sections + 1] = {title = "Files of this run",
                               text = "Beside this page in the out folder; see docs/looking_at_results.md.",
                               table = {columns = {"file", "what"}, rows = files}}
  end
  return bliskrun.report{path = opts.path or "report.html", title = opts.title, subtitle = opts.subtitle,
                         sections = sections}
end

-- A picture section for a PNG written by this run.
function M.picture(title, file, caption)
  return {title = title, image = file, caption = caption}
end

return M
