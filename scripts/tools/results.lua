-- Writes bench/RESULTS.md, the one place measured figures live, from the
-- JSON reports of recipe runs (and Google Benchmark JSON when given).
-- bench/results.sh runs the recipes, times them and calls this script:
--
--   build/bliskrun scripts/tools/results.lua --data RUNS --out bench
--
-- RUNS holds index.json (written by results.sh: date, commit, machine, and
-- per run the recipe, its --set values, its out folder, wall/CPU seconds,
-- peak memory and exit code), each run's out folder, and optionally
-- bench.json (bliskrun_bench --benchmark_format=json). Which numbers of a
-- recipe's report are worth a row is declared once per recipe below
-- (FIGURES); a declared key the report no longer has is listed at the end of
-- the page instead of silently dropped. Figures measured earlier on runs too
-- long to repeat here (bench/earlier_results.lua) are carried, dated, for
-- every recipe this run did not cover.

-- A small JSON reader: the recipes' reports are written by bliskrun.write_json
-- (objects, arrays, numbers, strings, booleans, null).
local function decode_json(text, name)
  local pos = 1
  local function fail(what)
    error(string.format("%s: byte %d: %s", name, pos, what), 0)
  end
  local function skip()
    pos = text:find("[^ \t\r\n]", pos) or #text + 1
  end
  local value
  local escapes = {['"'] = '"', ["\\"] = "\\", ["/"] = "/", b = "\b", f = "\f", n = "\n", r = "\r", t = "\t"}
  local function string_value()
    local out, i = {}, pos + 1
    while true do
      local c = text:sub(i, i)
      if c == "" then fail("unterminated string") end
      if c == '"' then break end
      if c == "\\" then
        local e = text:sub(i + 1, i + 1)
        if e == "u" then
          out[#out + 1] = utf8.char(tonumber(text:sub(i + 2, i + 5), 16))
          i = i + 6
        else
          out[#out + 1] = escapes[e] or fail("bad escape \\" .. e)
          i = i + 2
        end
      else
        local j = text:find('["\\]', i) or #text + 1
        out[#out + 1] = text:sub(i, j - 1)
        i = j
      end
    end
    pos = i + 1
    return table.concat(out)
  end
  function value()
    skip()
    local c = text:sub(pos, pos)
    if c == "{" then
      local t = {}
      pos = pos + 1
      skip()
      if text:sub(pos, pos) == "}" then pos = pos + 1 return t end
      while true do
        skip()
        if text:sub(pos, pos) ~= '"' then fail("expected a key") end
        local k = string_value()
        skip()
        if text:sub(pos, pos) ~= ":" then fail("expected ':'") end
        pos = pos + 1
        t[k] = value()
        skip()
        local d = text:sub(pos, pos)
        pos = pos + 1
        if d == "}" then return t end
        if d ~= "," then fail("expected ',' or '}'") end
      end
    elseif c == "[" then
      local t = {}
      pos = pos + 1
      skip()
      if text:sub(pos, pos) == "]" then pos = pos + 1 return t end
      while true do
        t[#t + 1] = value()
        skip()
        local d = text:sub(pos, pos)
        pos = pos + 1
        if d == "]" then return t end
        if d ~= "," then fail("expected ',' or ']'") end
      end
    elseif c == '"' then
      return string_value()
    elseif text:sub(pos, pos + 3) == "true" then
      pos = pos + 4 return true
    elseif text:sub(pos, pos + 4) == "false" then
      pos = pos + 5 return false
    elseif text:sub(pos, pos + 3) == "null" then
      pos = pos + 4 return nil
    else
      local s, e = text:find("^-?%d+%.?%d*[eE]?[-+]?%d*", pos)
      if not s then fail("unexpected '" .. c .. "'") end
      pos = e + 1
      return tonumber(text:sub(s, e))
    end
  end
  local v = value()
  skip()
  if pos <= #text then fail("trailing text") end
  return v
end

local function read_json(path)
  local ok, text = pcall(bliskrun.read_text, path)
  if not ok then return nil end
  return decode_json(text, path)
end

-- report["a.b.1.c"]: dotted path, numbers index arrays.
local function at(report, path)
  local v = report
  for key in path:gmatch("[^.]+") do
    if type(v) ~= "table" then return nil end
    local n = tonumber(key)
    v = v[n or key]
    if v == nil and n then v = nil end
  end
  return v
end

-- Numbers as a reader wants them: up to 4 significant digits, integers whole.
local function show(v, scale, digits)
  if type(v) == "boolean" then return tostring(v) end
  if type(v) == "string" then return v end
  if type(v) ~= "number" then return "—" end
  if scale and not digits then return string.format("%.2f", v * scale) end   -- µm and the like: 2 decimals
  v = v * (scale or 1)
  if math.type(v) == "integer" then return string.format("%d", v) end
  return string.format("%." .. (digits or 4) .. "g", v)
end

local FIGURES = require("results_figures")

local index = read_json("index.json")
assert(index, "index.json not found in the --data folder: run bench/results.sh, which writes it")
local missing = {}
local lines = {}
local function out(s) lines[#lines + 1] = s or "" end

out("# Measured results")
out()
out("Generated by `bench/results.sh` (which runs the recipes below and then "
    .. "`scripts/tools/results.lua` on their JSON reports); do not edit by hand.")
out()
out(string.format("- Date: %s; commit `%s`", index.date, index.commit))
out(string.format("- Machine: %d cores (%s), %.1f GiB memory%s", index.nproc, index.cpu,
                  index.mem_total_kb / 1048576, index.load and string.format("; load average %s at the start", index.load) or ""))
out(string.format("- Each recipe run with `--threads %d`; wall and CPU seconds and peak memory (resident) "
                  .. "from `/usr/bin/time`. The machine may have been shared: times are what this run saw.",
                  index.threads))
out("- Material left (undercut) is measured above the design surface, > 0; overcut is how far the "
    .. "tool went below it, ≤ 0. Both come from simulating the tool along every move of the program, "
    .. "links included, through sample points of the surface.")
out()
out("To regenerate (Release build in `build/`): `bench/results.sh` (the built-in part's recipes, a few minutes); "
    .. "`bench/results.sh --data ../shared/data` adds the cheap real-data recipes; `--bench` adds the "
    .. "Google Benchmark harness. Figures no run here covers are carried from earlier runs, with their date, "
    .. "in the last section.")
out()

-- Cost of every run first: one table.
out("## Runs")
out()
out("| recipe | settings | exit | wall (s) | CPU (s) | peak memory (MB) |")
out("|---|---|---|---|---|---|")
for _, run in ipairs(index.runs) do
  out(string.format("| `%s` | %s | %d | %s | %s | %s |", run.recipe,
                    run.settings ~= "" and ("`" .. run.settings .. "`") or "defaults",
                    run.exit_code, show(run.wall_s, 1, 3), show(run.user_s + run.sys_s, 1, 3),
                    show(run.max_rss_kb / 1024, 1, 3)))
end
out()

-- Per recipe, the declared figures of its JSON report.
for _, run in ipairs(index.runs) do
  local spec = FIGURES[run.recipe .. " " .. run.settings] or FIGURES[run.recipe]
  if spec then
    local report = read_json(run.out .. "/" .. spec.json)
    out("## `" .. run.recipe .. "`" .. (run.settings ~= "" and (" `" .. run.settings .. "`") or ""))
    out()
    if spec.about then out(spec.about) out() end
    if not report then
      out("No report (`" .. spec.json .. "`): the run failed; see its exit code above.")
      out()
    else
      out("| figure | value |")
      out("|---|---|")
      for _, f in ipairs(spec.rows) do
        local label, path, scale, digits = f[1], f[2], f[3], f[4]
        local v
        local absent
        if type(path) == "function" then
          v, absent = path(report)   -- a figure of several keys names the one it missed
        else
          v, absent = at(report, path), path
        end
        if v == nil then missing[#missing + 1] = run.recipe .. ": " .. tostring(absent or label) end
        out(string.format("| %s | %s |", label, show(v, scale, digits)))
      end
      out()
    end
  end
end

local bench = read_json("bench.json")
if bench then
  out("## Benchmarks (`build/bench/bliskrun_bench`)")
  out()
  out("| benchmark | wall | CPU |")
  out("|---|---|---|")
  for _, b in ipairs(bench.benchmarks or {}) do
    out(string.format("| `%s` | %s %s | %s %s |", b.name, show(b.real_time, 1, 3), b.time_unit,
                      show(b.cpu_time, 1, 3), b.time_unit))
  end
  out()
end

local earlier = require("results_earlier")
local carried = {}
for _, e in ipairs(earlier) do
  -- Covered only by a run of the same recipe with the same settings: a quick
  -- run (2 blades) does not replace the 22-blade figures.
  local covered = e.recipe == "bench" and bench ~= nil
  for _, run in ipairs(index.runs) do
    if run.recipe == e.recipe and run.settings == (e.settings or "") then covered = true end
  end
  if not covered then carried[#carried + 1] = e end
end
if #carried > 0 then
  out("## Measured earlier, not re-run by this script")
  out()
  out("Runs too long or too large to repeat on every regeneration, or needing `../shared/data` "
      .. "when this run did not have it. Each is as last measured, on the date given, on the 2-core "
      .. "CI machine; a run of the same recipe and settings by `bench/results.sh` replaces it.")
  out()
  for _, e in ipairs(carried) do
    out(string.format("- `%s`%s (%s): %s", e.recipe, e.settings and (" `" .. e.settings .. "`") or "",
                      e.measured, e.figures))
  end
  out()
end

if #missing > 0 then
  out("## Declared figures not found")
  out()
  out("The recipe's report no longer has these keys; update `scripts/tools/results_figures.lua`:")
  out()
  for _, m in ipairs(missing) do out("- `" .. m .. "`") end
  out()
end

bliskrun.write_text("RESULTS.md", table.concat(lines, "\n"))
bliskrun.log("wrote " .. bliskrun.out_dir() .. "/RESULTS.md")
