-- Calls every function and method reachable from `bliskrun` with hostile
-- arguments: each call must return or raise a Lua error. Functions are found
-- at run time (bindings added later are covered without edits); methods come
-- from the metatables of every userdata a call returned, and every such
-- object is also passed to every function as a wrong-typed argument.
-- args.calls bounds the number of calls (default: all); args.rounds (default 2).
-- args.plan (the libFuzzer target fuzz/lua_api_fuzz.cpp): "p" then hex bytes,
-- read three at a time as (function or method, argument, argument) choices,
-- replaces the exhaustive walk.

local values = {
  false, true, 0, -1, 1, 0.5, -0.5, 1e300, -1e300, 2^53, math.mininteger, math.maxinteger,
  0/0, math.huge, -math.huge, "", "x", string.rep("y", 4096), {}, {1, 2, 3}, {x = 1, y = 2, z = 3},
  {{0, 0, 0}, {1, 1, 1}}, {{0, 0}, {1, 1}, {2, 3}}, print, coroutine.create(print),
}
local cyclic = {name = "cyclic"}
cyclic.self = cyclic
local deep = {}
do local t = deep; for _ = 1, 100000 do t[1] = {}; t = t[1] end end
values[#values + 1] = cyclic
values[#values + 1] = deep
local n_plain = #values

local functions, seen = {}, {}
local function collect(t, prefix)
  if seen[t] then return end
  seen[t] = true
  local keys = {}
  for k in pairs(t) do if type(k) == "string" then keys[#keys + 1] = k end end
  table.sort(keys)
  for _, k in ipairs(keys) do
    local v = t[k]
    if type(v) == "function" then functions[#functions + 1] = {prefix .. k, v}
    elseif type(v) == "table" then collect(v, prefix .. k .. ".") end
  end
end
collect(bliskrun, "bliskrun.")

local objects, object_types = {}, {}
local function keep(...)
  for i = 1, select("#", ...) do
    local r = select(i, ...)
    if type(r) == "userdata" then
      local mt = getmetatable(r)
      local name = type(mt) == "table" and type(mt.__name) == "string" and mt.__name
                   or tostring(r):match("^[%w%.]+") or "?"
      if not object_types[name] then
        object_types[name] = r
        objects[#objects + 1] = r
      end
    end
  end
end

local budget = args.calls or math.maxinteger
local calls, errors, slow = 0, 0, 0
-- A callable that has spent args.slow_s (default 0.5 s) of CPU is called no
-- more (Blisk:narrowest_passage ignores its arguments and takes ~0.2 s a call),
-- which keeps the suite's walk to a few seconds.
local spent, slow_s = {}, args.slow_s or 0.5
local function try(f, ...)
  if calls >= budget then return end
  if (spent[f] or 0) > slow_s then slow = slow + 1; return end
  calls = calls + 1
  local t0 = os.clock()
  local results = table.pack(pcall(f, ...))
  spent[f] = (spent[f] or 0) + os.clock() - t0
  if results[1] then keep(table.unpack(results, 2, results.n)) else errors = errors + 1 end
end

-- Seed objects through the public API itself: one valid object of every
-- cheap type, so each type's methods are walked (plans are left out: a
-- single default call of theirs runs a whole simulation).
pcall(function() keep(bliskrun.blisk{}) end)
pcall(function()
  local blisk = bliskrun.blisk{grid_rows = 12, grid_cols = 24}
  keep(blisk:flank_grid(1, "pressure"))
  keep(bliskrun.curvature_stats(blisk:flank(1, "pressure"), {samples_u = 6, samples_v = 8}).map)
end)
pcall(function()
  keep(bliskrun.drum_wheel{max_diameter = 8, barrel_radius = 50, head_length = 4, shank = {diameter = 6, length = 96}})
  keep(bliskrun.collision_world{surfaces = {{name = "plate", mesh = {
    vertices = {{-50, 60, -5}, {50, 60, -5}, {50, 60, 5}, {-50, 60, 5}}, triangles = {{1, 2, 3}, {1, 3, 4}}}}}})
end)
pcall(function()
  local m = bliskrun.machine.load("dmg_like_ac_trunnion")
  keep(m)
  local r = bliskrun.post.write{machine = m, post = "fanuc", file = "walk.nc", tool = {number = 1, length = 80},
                                path = {{kind = "rapid", tip = {40, 0, 30}, axis = {0, 0, 1}},
                                        {kind = "feed", tip = {40, 2, 5}, axis = {0, 0, 1}, feed = 500}}}
  keep(r.program)
end)

local function argument_sets(self)
  local sets = {}
  local pool = {}
  for _, v in ipairs(values) do pool[#pool + 1] = v end
  for _, o in ipairs(objects) do pool[#pool + 1] = o end
  sets[#sets + 1] = {n = 0}
  for _, v in ipairs(pool) do sets[#sets + 1] = {v, n = 1} end
  for i = 1, n_plain, 3 do sets[#sets + 1] = {values[i], values[(i * 7) % n_plain + 1], n = 2} end
  -- a name then a table: the shape of every writer and of most constructors
  for _, v in ipairs(values) do
    if type(v) == "table" then sets[#sets + 1] = {"x", v, n = 2} end
  end
  for _, s in ipairs(sets) do
    if self ~= nil then table.insert(s, 1, self); s.n = s.n + 1 end
  end
  return sets
end

local function methods_of(o)
  local mt = getmetatable(o)
  local index = type(mt) == "table" and mt.__index
  local list = {}
  if type(index) == "table" then
    local names = {}
    for k, v in pairs(index) do if type(v) == "function" then names[#names + 1] = k end end
    table.sort(names)
    for _, k in ipairs(names) do list[#list + 1] = index[k] end
  end
  return list
end

if type(args.plan) == "string" and args.plan:sub(1, 1) == "p" then
  local bytes = {}
  for hex in args.plan:sub(2):gmatch("%x%x") do bytes[#bytes + 1] = tonumber(hex, 16) end
  for i = 1, #bytes - 2, 3 do
    local pool = {}
    for _, v in ipairs(values) do pool[#pool + 1] = v end
    for _, o in ipairs(objects) do pool[#pool + 1] = o end
    local callables = {}
    for _, entry in ipairs(functions) do callables[#callables + 1] = {entry[2]} end
    for _, o in ipairs(objects) do
      for _, m in ipairs(methods_of(o)) do callables[#callables + 1] = {m, o} end
    end
    local c = callables[bytes[i] % #callables + 1]
    local a, b = pool[bytes[i + 1] % #pool + 1], pool[bytes[i + 2] % #pool + 1]
    if c[2] ~= nil then try(c[1], c[2], a, b) else try(c[1], a, b) end
  end
else
  for _ = 1, args.rounds or 2 do  -- a second round passes the objects the first made to every function
    for _, entry in ipairs(functions) do
      for _, a in ipairs(argument_sets(nil)) do try(entry[2], table.unpack(a, 1, a.n)) end
    end
    for _, o in ipairs(objects) do
      for _, m in ipairs(methods_of(o)) do
        for _, a in ipairs(argument_sets(o)) do try(m, table.unpack(a, 1, a.n)) end
        -- wrong self: every other object and a plain value
        for _, w in ipairs(objects) do if w ~= o then try(m, w) end end
        try(m, 1)
      end
    end
  end
end

local types = {}
for name in pairs(object_types) do types[#types + 1] = name end
table.sort(types)
bliskrun.write_json("api_walk.json", {functions = #functions, calls = calls, errors = errors, skipped_slow = slow, types = types})
