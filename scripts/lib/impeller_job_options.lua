-- The options both impeller jobs (impeller_job.lua, hecc_impeller_job.lua)
-- accept, as recipe_options declarations: a fresh table, to which a recipe
-- adds its own before declaring them.
--
--   local opt = require("recipe_options")(require("impeller_job_options"){stock = {...}, ...})

-- A comma list of names from `known`: nil, or what was expected.
local function list_of(v, known)
  for item in v:gmatch("[^,]+") do
    local ok = false
    for _, k in ipairs(known) do ok = ok or k == item end
    if not ok then return "'" .. item .. "' is not one of " .. table.concat(known, ", ") end
  end
end

return function(own)
  local decl = {
    blades = {type = "integer", range = {1, 1000}, default_text = "all", help = "blades to machine, from blade 1"},
    stations = {type = "integer", default = 41, range = {3, 1000}, help = "stations of the notch along the channel"},
    finish_life = {type = "number", unit = "mm", default = 4000, range = {1, 1e7},
                   help = "cutting length per finishing cutter; sisters T12, T22, ... follow"},
    rough_life = {type = "number", unit = "mm", range = {1, 1e7}, default_text = "none",
                  help = "cutting length per roughing cutter; sisters T11, T21, ... follow"},
    scallop = {type = "number", unit = "mm", default = 0.01, range = {1e-4, 1}, help = "scallop height of the widening"},
    depth_step = {type = "number", unit = "mm", default = 5, range = {0.1, 50}, help = "depth step of the notch"},
    hub_stock = {type = "number", unit = "mm", default = 0, range = {0, 10}, help = "left on the hub by the widening"},
    chord_tol = {type = "number", unit = "mm", default = 0.005, range = {1e-5, 0.1},
                 help = "chord deviation allowed between steps of the flank finish"},
    channels = {type = "string", default_text = "inlet,left,right", help = "channels to notch, a comma list",
                check = function(v) return list_of(v, {"inlet", "left", "right"}) end},
    faces = {type = "string", default_text = "every face", help = "faces to finish, a comma list",
             check = function(v) return list_of(v, {"main plus", "main minus", "splitter plus", "splitter minus"}) end},
    sim_u = {type = "integer", default = 60, range = {2, 5000}, help = "simulation samples along the span"},
    sim_v = {type = "integer", default = 300, range = {2, 20000}, help = "simulation samples along the chord"},
    machine_clearance = {type = "number", unit = "mm", default = 0.5, range = {0.001, 100},
                         help = "machine simulation: no contact deeper than this is missed"},
    machine_near_zone = {type = "number", unit = "mm", default = 10, range = {0.001, 1e6},
                         help = "machine simulation: closest approaches measured within this zone (at least the clearance)"},
  }
  for name, d in pairs(own or {}) do decl[name] = d end
  return decl
end
