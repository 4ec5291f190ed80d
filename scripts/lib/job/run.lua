-- A whole job run (Job:run; scripts/lib/job.lua is the entry): planned,
-- simulated, stopped before posting on an overcut its operations do not
-- allow, posted for every machine (and setup), and reported — printed as it
-- goes, the JSON report and report.html assembled from what it planned,
-- simulated and posted (job/report.lua), with the recipe's own entries and
-- sections added where it gives them.
local options = require("job.options")
local simulate = require("job.simulate")
local report = require("job.report")
local Job = require("job.model").Job
local run_report = require("run_report")

local check_options, positive = options.check, options.positive

-- The job's moves as setups: setups = {{name=, flip=, clocking_deg=, from=},
-- ...}; the first starts at the first move, each later one at the first unit
-- whose side is `from` ("leading edge"), and is left out when the job has
-- none; each ends with the last move of the unit before the next (the link
-- between them belongs to neither: each program has its own ways in and out).
local function split_setups(planned, setups)
  local out = {{name = setups[1].name, flip = setups[1].flip, clocking_deg = setups[1].clocking_deg, first = 1}}
  for k = 2, #setups do
    for i, f in ipairs(planned.flanks) do
      if f.side == setups[k].from and i > 1 then
        local before = planned.flanks[i - 1]
        out[#out].last = before.first_move + before.moves - 1
        out[#out + 1] = {name = setups[k].name, flip = setups[k].flip, clocking_deg = setups[k].clocking_deg,
                         first = f.first_move}
        break
      end
    end
  end
  out[#out].last = #planned.moves
  return out
end

-- One program per machine and setup: file "x.nc" becomes "x_setup1.nc", ...
-- when there is more than one setup.
local function program_list(programs, setups, defaults)
  local list = {}
  for _, m in ipairs(programs) do
    for k, setup in ipairs(setups or {false}) do
      local p = {}
      for key, value in pairs(defaults) do p[key] = value end
      for key, value in pairs(m) do p[key] = value end
      if setup then
        p.setup = setup
        if #setups > 1 then p.file = m.file:gsub("(%.[^.]*)$", string.format("_setup%d%%1", k)) end
      end
      list[#list + 1] = p
    end
  end
  return list
end

-- j:run{name=, programs=, ...}: the whole job (docs/lua_api.md, Jobs).
-- Returns the run's state {json, planned, sim, ...}.
-- "drum finish, blades 1-2, pressure, suction": an operation and its
-- surfaces, for the run's progress line.
local function describe(op)
  local parts = {(op.kind:gsub("_", " "))}
  local b = op.blades
  if type(b) == "table" and #b > 0 then
    parts[#parts + 1] = #b == 1 and "blade " .. b[1] or string.format("blades %d-%d", b[1], b[#b])
  end
  local surfaces = op.sides or op.edges or op.faces or op.channels
  if type(surfaces) == "table" and #surfaces > 0 then parts[#parts + 1] = table.concat(surfaces, ", ") end
  return table.concat(parts, ", ")
end

function Job:run(o)
  check_options("job:run", o, {
    name = {type = "string", required = true},  -- the run's files: <name>.json, <name>.pvd, <name>_*.png
    title = {type = "string"},
    settings = {type = "table"},
    simulate = {type = "any", check = function(v)
      if v ~= false and type(v) ~= "table" then return "expected j:simulate's options, or false" end
    end},
    blade_map = {type = "any", check = function(v)
      if v ~= false and v ~= true and v ~= "lean" then return "expected true, \"lean\" or false" end
    end},
    thickness_tolerance = {type = "number", check = positive},
    -- Every map of the run on one colour scale, ± µm (default: twice the loosest tolerance).
    map_scale_um = {type = "number", check = positive},
    overcut_slack = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
    setups = {type = "table", check = function(v)
      if #v == 0 or type(v[1]) ~= "table" then return "expected a list of setups {name=, flip=, from=}" end
    end},
    programs = {type = "table", required = true, check = function(v)
      if #v == 0 then return "expected a list of programs {machine=, post=, file=}" end
    end},
    json = {type = "table"},
    sections = {type = "function"},
    -- Every program's machine simulation, where its entry does not say
    -- (post.write's machine_clearance and machine_near_zone, mm).
    machine_clearance = {type = "number", check = positive},
    machine_near_zone = {type = "number", check = positive},
  }, 2)
  if type(o.simulate) == "table" then check_options("job:run simulate", o.simulate, simulate.options, 2) end
  local steps = report[self.part_kind]
  local r = {job = self, o = o, json = {programs = {}}}
  for k, v in pairs(o.json or {}) do r.json[k] = v end
  -- One progress line for the whole job (bliskrun.progress_step): each
  -- operation's planning, the simulation, the blade map, posting, the report.
  local total = #self.operations + (self.blank and 1 or 0) + (o.simulate ~= false and 1 or 0) + 2
                + ((o.blade_map and self.part_kind == "blisk") and 1 or 0)
  local k = 0
  local function step(what)
    k = k + 1
    bliskrun.progress_step(k, total, what)
  end
  self.on_plan_step = function(op) step("plan " .. describe(op)) end
  local t0 = os.clock()
  r.planned = self:plan()
  self.on_plan_step = nil
  r.plan_seconds = os.clock() - t0
  steps.planned(r)
  if r.planned.stock then require("job.stock").report(r) end
  if o.simulate ~= false then
    step("simulate every operation's moves on the part")
    r.sim = self:simulate(o.simulate or {})
  elseif self.part_kind == "impeller" then
    r.sim = {surfaces = {}, seconds = 0}
  end
  if r.sim then steps.simulated(r) end
  if o.blade_map and self.part_kind == "blisk" then
    step("map blade 1 after the whole job")
    steps.blade_map(r, o.blade_map == "lean")
  end
  -- Nothing is posted after a simulated overcut the operations do not
  -- allow: the report is written with the verdict FAIL and no program.
  local stop
  if self.part_kind == "blisk" then
    stop = r.sim and self:blisk_overcut(r.sim)
  else
    stop = self:check_overcut(r.sim, r.json.units, o.overcut_slack or 0.005)
  end
  if not stop then
    step(string.format("post and read back %d program%s", #o.programs * (o.setups and #o.setups or 1),
                       #o.programs * (o.setups and #o.setups or 1) == 1 and "" or "s"))
    local setups = o.setups and split_setups(r.planned, o.setups)
    r.json.programs = self:post_programs(program_list(o.programs, setups,
                                                              {machine_clearance = o.machine_clearance,
                                                               machine_near_zone = o.machine_near_zone}), 4)
    steps.posted(r)
  end
  local verdict = run_report.verdict(steps.requirements(r, stop), stop and "Nothing posted: " .. stop or nil)
  r.json.verdict = verdict
  bliskrun.write_json(o.name .. ".json", r.json)

  step("write the report")
  local sections, blocks, files = steps.page(r)
  if r.planned.stock then table.insert(sections, math.min(2, #sections + 1), require("job.stock").section(r)) end
  local sheets = {}
  for _, p in ipairs(r.json.programs) do sheets[#sheets + 1] = p.setup_sheet end
  for _, s in ipairs(require("setup_sheet").sections(sheets)) do sections[#sections + 1] = s end
  if o.sections then
    local own = o.sections(r.json)
    for i = #own, 1, -1 do table.insert(sections, 1, own[i]) end
  end
  local listed = {{o.name .. ".json", "the report"}}
  for _, p in ipairs(r.json.programs) do
    listed[#listed + 1] = {p.file, string.format("%s program, %s%s", p.post, p.machine,
                                                 p.setup and ", setup " .. p.setup or "")}
    listed[#listed + 1] = {p.setup_sheet.files.html, "its setup sheet (and " .. p.setup_sheet.files.json .. ")"}
  end
  for _, f in ipairs(files) do listed[#listed + 1] = f end
  bliskrun.progress_step()  -- the job's line ends
  -- A failed requirement fails the run after the page is written: an
  -- overcut posts nothing; material left beyond a seam's tolerance posts
  -- programs proved safe for a part not finished within tolerance.
  run_report.write{title = o.title or "Job: " .. self.name, settings = o.settings, sections = sections,
                   verdict = verdict, vtk = {path = o.name .. ".pvd", blocks = blocks}, files = listed}
  return r
end

return {}
