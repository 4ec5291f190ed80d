-- The report.html a recipe writes at the end of its run (bliskrun.report):
-- the run's settings as a table first, the recipe's own sections, the numbers
-- of its JSON report (when given), and a last section naming the other files
-- of the run and what opens them (docs/looking_at_results.md). With `vtk`,
-- the run's geometry goes to a ParaView collection too.
--
--   local run_report = require("run_report")
--   run_report.write{title =, subtitle =, settings = {key = value, ...},
--                    verdict = run_report.verdict{...},
--                    sections = {...}, numbers = report_table,
--                    vtk = {path = "run.pvd", blocks = {...}},
--                    files = {{"name", "what it holds"}, ...}}
--
-- Every page opens with the run's verdict (issue 37): PASS or FAIL per
-- requirement the run states, with its limit and measured value, and the
-- overall verdict. A failed verdict fails the run — after the page is
-- written, so the engineer reads why — with an error naming each failed
-- requirement: the process exits non-zero. Put the same verdict in the
-- run's JSON as `verdict` (bliskrun.write_json writes it first).
local M = {}

-- run_report.verdict({{name=, unit=, measured=, at_most= | at_least=
-- [, pass=] [, note=]}, ...} [, summary]) -> {pass=, summary=,
-- requirements=}. A requirement passes when `measured` is a number within
-- its limits (unless `pass` is given: a judgement the limits cannot state);
-- one not measured fails. Deviations are given in µm (unit "µm").
function M.verdict(requirements, summary)
  local out, pass = {requirements = {}, summary = summary}, true
  for i, q in ipairs(requirements) do
    assert(type(q.name) == "string" and type(q.unit) == "string",
           string.format("run_report.verdict: requirement %d: expected name= and unit= (strings)", i))
    local ok = q.pass
    if ok == nil then
      local m = q.measured
      ok = type(m) == "number" and m == m and (q.at_most == nil or m <= q.at_most)
           and (q.at_least == nil or m >= q.at_least)
    end
    out.requirements[i] = {name = q.name, unit = q.unit, measured = q.measured, at_most = q.at_most,
                           at_least = q.at_least, note = q.note, pass = ok and true or false}
    pass = pass and ok and true or false
  end
  out.pass, out.overall = pass, pass and "PASS" or "FAIL"
  if #requirements == 0 and not summary then
    out.summary = "This run states no tolerance to judge it by (a design or study run); nothing failed."
  end
  return out
end

-- The requirement a posted program's machine simulation states (post.write's
-- machine_check, as the job's program entry keeps it): no contact of the
-- machine's bodies, fixture, stock and tool; a skipped simulation passes
-- with its warning as the note, so a recipe that chose to skip it says so.
-- One pair's closest approach as a line: "spindle nose / blade 3 6.8 mm
-- (line 4509)", or "> 10 mm" for a pair only proved to stay beyond the
-- near-miss zone (its nearest sample is not its closest approach). `c` as
-- post.write's machine_check.closest entries or the job's (distance_mm).
function M.approach_text(c, near_zone)
  local figure = c.beyond_zone and string.format("> %g mm", near_zone)
                 or string.format("%.1f mm", c.distance_mm or c.distance)
  return string.format("%s / %s %s (line %d)", c.a, c.b, figure, c.line)
end

function M.machine_requirement(file, mc)
  if mc.verdict == "SKIPPED" then
    return {name = file .. ": machine simulation (bodies, fixture, stock)", unit = "mm", measured = "skipped",
            pass = true, note = "WARNING: " .. (mc.warning or "not run")}
  end
  local near = mc.closest and mc.closest[1]
  return {name = file .. ": machine simulation, closest approach of two bodies", unit = "mm",
          measured = near and (near.beyond_zone and string.format("> %g", mc.near_zone_mm) or near.distance_mm) or nil,
          at_least = 0, pass = mc.verdict == "PASS",
          note = mc.summary}
end

-- The failed requirements of a verdict as one line.
function M.failures(verdict)
  local list = {}
  for _, q in ipairs(verdict.requirements) do
    if not q.pass then
      local limit = q.at_most and string.format("<= %.3g", q.at_most) or q.at_least and string.format(">= %.3g", q.at_least)
                    or "required"
      list[#list + 1] = string.format("%s %s %s (limit %s %s)%s", q.name,
                                      type(q.measured) == "number" and string.format("%.3g", q.measured)
                                        or tostring(q.measured or "not measured"), q.unit, limit, q.unit,
                                      q.note and " — " .. q.note or "")
    end
  end
  return table.concat(list, "; ")
end

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
  local verdict = opts.verdict or M.verdict({})
  local path = opts.path or "report.html"
  local written = bliskrun.report{path = path, title = opts.title, subtitle = opts.subtitle, verdict = verdict,
                                  sections = sections}
  if not verdict.pass and opts.fail ~= false then
    error(string.format("verdict FAIL: %s (see %s)", M.failures(verdict), path), 0)
  end
  return written
end

-- A picture section for a PNG written by this run.
function M.picture(title, file, caption)
  return {title = title, image = file, caption = caption}
end

return M
