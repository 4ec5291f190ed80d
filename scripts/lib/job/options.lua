-- Option tables of the job library (scripts/lib/job.lua) checked where the
-- recipe writes them: an unknown key (with the list of valid ones), a wrong
-- type or an impossible value is an error at that recipe line.
local M = {}

-- spec: key -> {type = "number"|"string"|"table"|"boolean"|"userdata"|"any",
-- required = bool, check = function(v) -> message or nil}. `level` is the
-- error level of the recipe line (2: the caller of the function that checks).
local function check_options(what, t, spec, level)
  level = level + 1
  if type(t) ~= "table" then error(what .. ": expected an option table, got " .. type(t), level) end
  for k in pairs(t) do
    if not spec[k] then
      local names = {}
      for name in pairs(spec) do names[#names + 1] = name end
      table.sort(names)
      error(string.format("%s: unknown option '%s', expected one of: %s", what, tostring(k),
                          table.concat(names, ", ")), level)
    end
  end
  for k, s in pairs(spec) do
    local v = t[k]
    if v == nil then
      if s.required then error(string.format("%s: missing option '%s'", what, k), level) end
    else
      if s.type ~= "any" and type(v) ~= s.type then
        error(string.format("%s: option '%s': expected a %s, got %s", what, k, s.type, type(v)), level)
      end
      local problem = s.check and s.check(v)
      if problem then error(string.format("%s: option '%s': %s", what, k, problem), level) end
    end
  end
end

local function positive(v) if not (v > 0) or v ~= v or v == math.huge then return "expected a finite value > 0" end end

-- A list of blade numbers 1, 2, ...
local function blade_list(v)
  if #v == 0 then return "expected a list of blade numbers" end
  for _, b in ipairs(v) do if math.type(b) ~= "integer" or b < 1 then return "expected blade numbers 1, 2, ..." end end
end

M.check, M.positive, M.blade_list = check_options, positive, blade_list
return M
