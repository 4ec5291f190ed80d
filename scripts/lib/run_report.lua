-- The report.html a recipe writes at the end of its run (bliskrun.report):
-- the run's settings as a table first, the recipe's own sections, and a last
-- section naming the other files of the run and what opens them
-- (docs/looking_at_results.md).
--
--   local run_report = require("run_report")
--   run_report.write{title =, subtitle =, settings = {key = value, ...},
--                    sections = {...}, files = {{"name", "what it holds"}, ...}}
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

function M.write(opts)
  local sections = {{title = "Settings", table = M.settings_table(opts.settings or {})}}
  for _, s in ipairs(opts.sections or {}) do sections[#sections + 1] = s end
  if opts.files and #opts.files > 0 then
    sections[#sections + 1] = {title = "Files of this run",
                               text = "Beside this page in the out folder; see docs/looking_at_results.md.",
                               table = {columns = {"file", "what"}, rows = opts.files}}
  end
  return bliskrun.report{path = opts.path or "report.html", title = opts.title, subtitle = opts.subtitle,
                         sections = sections}
end

return M
