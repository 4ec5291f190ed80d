-- What a recipe accepts on the command line (--set NAME=VALUE), declared
-- once: name, type, unit, plausible range, default and one line of help.
-- The declaration checks `args` before anything is planned and returns the
-- typed values; `bliskrun RECIPE.lua --help` prints it and ends the run.
--
--   local opt = require("recipe_options"){
--     blades    = {type = "integer", default = 2, range = {1, 200}, help = "blades to machine, from blade 1"},
--     chord_tol = {type = "number", unit = "mm", default = 0.002, range = {1e-5, 0.1},
--                  help = "chord tolerance of the steps along a row"},
--     sides     = {type = "string", default = "both", choices = {"both", "pressure", "suction"}, help = "..."},
--     tool_life = {type = "number", unit = "mm", range = {1, 1e6}, help = "... (none when not set)"},
--   }
--   ... opt.blades, opt.chord_tol ...
--
-- Fields of a declaration:
--   type     "number", "integer", "boolean", "string" or "choice" (one of
--            `choices`, which may mix booleans and strings: {true, false, "lean"})
--   unit     "mm", "deg", "mm/min", "um", ... shown in --help and in messages
--   range    {lo, hi}, inclusive, numbers: what is plausible in that unit. A
--            value outside is refused with what was expected (a chord
--            tolerance of 2 mm is a micrometre value typed in millimetres).
--   choices  the allowed strings (type "string" or "choice")
--   default  the value when --set does not give one (absent: nil)
--   default_text  how --help shows a default computed by the recipe
--   check    function(value) -> message or nil, for what a range cannot say
--   help     one line
-- Errors (an unknown name, with the known ones and the closest; a wrong
-- type; a value out of range) are raised at the recipe's declaring line.
-- Reading an undeclared name from the returned table is an error too.

local TYPES = {number = true, integer = true, boolean = true, string = true, choice = true}
local FIELDS = {type = true, unit = true, range = true, choices = true, default = true, default_text = true,
                check = true, help = true}

-- Levenshtein distance, for "did you mean" on a misspelt name.
local function distance(a, b)
  local prev = {}
  for j = 0, #b do prev[j] = j end
  for i = 1, #a do
    local cur = {[0] = i}
    for j = 1, #b do
      local cost = a:sub(i, i) == b:sub(j, j) and 0 or 1
      cur[j] = math.min(prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost)
    end
    prev = cur
  end
  return prev[#b]
end

local function show(v)
  if type(v) == "string" then return v end
  if math.type(v) == "float" then return string.format("%g", v) end
  return tostring(v)
end

local function choices_text(d)
  local t = {}
  for _, c in ipairs(d.choices) do t[#t + 1] = show(c) end
  return table.concat(t, "|")
end

local function sorted_names(decl)
  local names = {}
  for name in pairs(decl) do names[#names + 1] = name end
  table.sort(names)
  return names
end

-- A declaration that cannot work is the recipe author's error.
local function check_declaration(decl)
  if type(decl) ~= "table" then error("recipe_options: expected a table of option declarations", 3) end
  for name, d in pairs(decl) do
    local where = "recipe_options: option '" .. tostring(name) .. "'"
    if type(name) ~= "string" or not name:match("^[%a_][%w_]*$") then error(where .. ": not a name", 3) end
    if type(d) ~= "table" then error(where .. ": expected a declaration table", 3) end
    for k in pairs(d) do
      if not FIELDS[k] then error(where .. ": unknown field '" .. tostring(k) .. "'", 3) end
    end
    if not TYPES[d.type] then
      error(where .. ": type must be number, integer, boolean, string or choice, got " .. tostring(d.type), 3)
    end
    if type(d.help) ~= "string" or d.help == "" then error(where .. ": needs a help line", 3) end
    if (d.type == "number" or d.type == "integer") then
      if type(d.range) ~= "table" or type(d.range[1]) ~= "number" or type(d.range[2]) ~= "number"
          or not (d.range[1] <= d.range[2]) then
        error(where .. ": a number needs range = {lo, hi}", 3)
      end
    elseif d.range then
      error(where .. ": range is for numbers", 3)
    end
    if d.type == "choice" and type(d.choices) ~= "table" then error(where .. ": a choice needs choices", 3) end
  end
end

-- nil when `v` is acceptable for declaration `d`, else what was expected.
local function problem(name, d, v)
  local unit = d.unit and (" " .. d.unit) or ""
  if d.type == "number" or d.type == "integer" then
    if type(v) ~= "number" then return string.format("expected a%s number%s", d.type == "integer" and " whole" or "", unit) end
    if d.type == "integer" and math.type(v) ~= "integer" then return "expected a whole number" .. unit end
    local lo, hi = d.range[1], d.range[2]
    if v ~= v or v < lo or v > hi then
      local msg = string.format("expected %s..%s%s", show(lo), show(hi), unit)
      -- The usual slip: a micrometre value typed where millimetres are read.
      if d.unit == "mm" and v / 1000 >= lo and v / 1000 <= hi then
        msg = msg .. string.format(" (values are in mm: %s um is %s=%s)", show(v), name, show(v / 1000))
      end
      return msg
    end
  elseif d.type == "boolean" then
    if type(v) ~= "boolean" then return "expected true or false" end
  elseif d.type == "string" then
    if type(v) ~= "string" then return "expected text" .. (d.choices and (": " .. choices_text(d)) or "") end
  end
  if d.choices then
    local ok = false
    for _, c in ipairs(d.choices) do ok = ok or c == v end
    if not ok then return "expected one of " .. choices_text(d) end
  end
  if d.check then return d.check(v) end
  return nil
end

local function type_text(d)
  if d.choices then return choices_text(d) end
  return d.type
end

-- The --help listing: one row per option, sorted by name.
local function help_text(decl)
  local rows = {{"option", "type", "unit", "default", "range", "help"}}
  for _, name in ipairs(sorted_names(decl)) do
    local d = decl[name]
    local default = d.default_text or (d.default ~= nil and show(d.default)) or "-"
    local range = d.range and (show(d.range[1]) .. ".." .. show(d.range[2])) or "-"
    rows[#rows + 1] = {name, type_text(d), d.unit or "-", default, range, d.help}
  end
  local width = {}
  for _, r in ipairs(rows) do
    for i = 1, 5 do width[i] = math.max(width[i] or 0, #r[i]) end
  end
  local lines = {}
  for _, r in ipairs(rows) do
    local cells = {}
    for i = 1, 5 do cells[i] = r[i] .. string.rep(" ", width[i] - #r[i]) end
    lines[#lines + 1] = "  " .. table.concat(cells, "  ") .. "  " .. r[6]
  end
  return table.concat(lines, "\n") .. "\n"
end

return function(decl)
  check_declaration(decl)
  bliskrun.options_help(help_text(decl))  -- a --help run ends here, before anything is planned
  local given = rawget(_G, "args") or {}
  local names = sorted_names(decl)
  for key, v in pairs(given) do
    if decl[key] == nil then
      local best, best_d = nil, math.huge
      for _, name in ipairs(names) do
        local dist = distance(tostring(key), name)
        if dist < best_d then best, best_d = name, dist end
      end
      local hint = best and best_d <= math.max(2, #best // 3) and string.format(" (did you mean '%s'?)", best) or ""
      error(string.format("--set %s=%s: this recipe has no option '%s'%s; it accepts: %s (--help lists them)",
                          tostring(key), show(v), tostring(key), hint,
                          #names > 0 and table.concat(names, ", ") or "no options"), 2)
    end
  end
  local values = {}
  for _, name in ipairs(names) do
    local d, v = decl[name], given[name]
    if v ~= nil then
      local p = problem(name, d, v)
      if p then
        error(string.format("--set %s=%s: %s (%s)", name, show(v), p, d.help), 2)
      end
      values[name] = v
    else
      values[name] = d.default
    end
  end
  -- An undeclared name read by the recipe is a typo in the recipe.
  return setmetatable(values, {__index = function(_, k)
    if decl[k] == nil then error("recipe option '" .. tostring(k) .. "' is not declared", 2) end
    return nil
  end})
end
