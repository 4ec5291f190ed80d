-- Notching and widening of the built-in impeller's channels (impeller paper
-- §4.1–4.2; issue 13 items 2–3): the channel between main blades 1 and 2 is
-- opened in its middle in depth levels from the shroud contour to the stock
-- above the hub (notching), then widened towards both faces along the hub
-- (which roughs the hub to the scallop asked for).
--   bliskrun scripts/recipes/impeller_channel_roughing.lua --out out/
-- The splitter divides the channel's outer part, so it is three channels:
--   inlet    main 1 (minus face) to main 2 (plus face), from the inlet to just
--            before the splitter's leading edge;
--   left     main 1 to the splitter, from the splitter's leading edge out;
--   right    the splitter to main 2, the same.
-- Every pose, every motion between poses, every link and the leads are proved
-- with the whole tool against both main blades, the splitter and the hub
-- (core/planning/channel_roughing.h); a pose that is not clear splits its
-- pass and is reported, never written.
-- Writes
--   impeller_channel_<name>.apt       APT/CL per channel (GOTO tip, axis; RAPID before links and leads)
--   impeller_channel_roughing.json    passes, widths, step-over, measured scallop, refusals per channel
--   impeller_channel_roughing.pvd, report.html   faces, hub and toolpaths for ParaView; the run's page
-- Options: --help lists them (--set NAME=VALUE).

local opt = require("recipe_options"){
  stations = {type = "integer", default = 41, range = {3, 1000}, help = "stations along the channel"},
  stock = {type = "number", unit = "mm", default = 0.5, range = {0, 10}, help = "stock left on the faces"},
  min_stock = {type = "number", unit = "mm", default = 0.2, range = {0, 10}, help = "least stock any move may leave on a face or the hub"},
  scallop = {type = "number", unit = "mm", default = 0.01, range = {1e-4, 1}, help = "scallop height of the widening"},
  depth_step = {type = "number", unit = "mm", default = 5, range = {0.1, 50}, help = "depth step of the notch"},
  tip_radius = {type = "number", unit = "mm", default = 3, range = {0.5, 20}, help = "tip (ball) radius of the tapered ball end"},
  half_angle = {type = "number", unit = "deg", default = 2, range = {0, 15}, help = "half angle of the cutter's taper"},
  mesh_tol = {type = "number", unit = "mm", default = 0.05, range = {1e-4, 1}, help = "chord tolerance of the collision meshes"},
  channels = {type = "string", default = "inlet,left,right", check = function(v) for c in v:gmatch("[^,]+") do if c ~= "inlet" and c ~= "left" and c ~= "right" then return "'" .. c .. "' is not inlet, left or right" end end end, help = "channels to rough, a comma list of inlet, left, right"},
  splitter_gap = {type = "number", unit = "mm", default = 20, range = {0, 200}, help = "how far (meridional) the inlet channel stops short of the splitter's leading edge"},
}
local stations = opt.stations
local stock = opt.stock
-- The least stock any move may leave on a face or the hub (the cutter's
-- clearance): the last widening path is the finishing (swarf) pose of the
-- cutter grown by the stock, which on these twisted faces cuts up to
-- ~0.17 mm into the grown offset mid-ruling (the flank-milling residual).
local min_stock = opt.min_stock
local scallop = opt.scallop
local depth_step = opt.depth_step
local tip_radius, half_angle = opt.tip_radius, opt.half_angle
local mesh_tol = opt.mesh_tol
local wanted = {}
for name in tostring(opt.channels):gmatch("[^,]+") do wanted[name] = true end

local imp = bliskrun.impeller{}
local hub = imp:hub()
local tool = bliskrun.tapered_ball_end_mill{tip_radius = tip_radius, half_angle = half_angle, flute_length = 90,
                                            shank = {diameter = 16, length = 60},
                                            holder = {diameter = 50, length = 60}}

-- The channel between main blades 1 and 2, as three channels around the
-- splitter, and what they are proved against (scripts/lib/impeller_world.lua).
local iw = require("impeller_world")
local gap = opt.splitter_gap  -- mm (meridional) the inlet channel stops short of the splitter's leading edge
local channels = iw.channels(imp, {gap = gap})
local meshes = iw.meshes(imp, mesh_tol)
local world = iw.channel_world(imp, meshes)

local report = {part = "built-in impeller", tool = tool:description(), channels = {},
                settings = {stations = stations, stock = stock, min_stock = min_stock, scallop = scallop,
                            depth_step = depth_step, splitter_gap = gap,
                            mesh_tol = mesh_tol}}
local rows, blocks = {}, {{name = "hub", mesh = meshes.hub()}}
for _, f in ipairs{{"main", 1, "minus"}, {"main", 1, "plus"}, {"main", 2, "plus"}, {"main", 2, "minus"},
                   {"splitter", 1, "plus"}, {"splitter", 1, "minus"}} do
  blocks[#blocks + 1] = {name = string.format("%s %d %s", f[1], f[2], f[3]), mesh = meshes.face(f[1], f[2], f[3])}
end
local totals = {poses = 0, refused = 0, passes = 0}
-- The chosen channels, planned side by side on --threads.
local chosen, requests = {}, {}
for _, c in ipairs(channels) do
  if wanted[c.name] then
    chosen[#chosen + 1] = c
    requests[#requests + 1] = {left = c.left, left_v = c.left_v, right = c.right, right_v = c.right_v,
                               hub = hub, tool = tool, ball_radius = tip_radius, world = world,
                               stations = stations, stock = stock, scallop = scallop,
                               depth_step = depth_step, cutter_clearance = min_stock}
  end
end
local plans = #requests > 0 and bliskrun.channel_rough_all{channels = requests} or {}
for k, c in ipairs(chosen) do
  local plan = plans[k]
  for _, r in ipairs(plan.refusals) do
    print(string.format("channel %s: refused %s %d at t = %.3f: %s", c.name, r.kind, r.index, r.t, r.reason))
  end
  if not plan.complete then
    error(string.format("channel %s: the plan could not be completed: %s", c.name, plan.stopped), 0)
  end
  -- APT/CL: GOTO tip, axis; a RAPID before each link and lead move.
  local apt = {"PARTNO/bliskrun impeller channel " .. c.name, "$$ " .. tool:description(), "MULTAX/ON"}
  local moves = {}
  for i, m in ipairs(plan.moves) do
    if m.kind == "rapid" then apt[#apt + 1] = "RAPID" end
    apt[#apt + 1] = string.format("GOTO/%.6f,%.6f,%.6f,%.6f,%.6f,%.6f", m.tip[1], m.tip[2], m.tip[3],
                                  m.axis[1], m.axis[2], m.axis[3])
    moves[i] = {kind = m.kind, tip = m.tip, axis = m.axis, row = m.row}
  end
  apt[#apt + 1] = "FINI"
  bliskrun.write_text("impeller_channel_" .. c.name .. ".apt", table.concat(apt, "\n") .. "\n")
  blocks[#blocks + 1] = {name = "channel " .. c.name, moves = moves}
  report.channels[c.name] = {notch_levels = plan.notch_levels, widen_left = plan.widen_left,
                             widen_right = plan.widen_right, paths_added = plan.paths_added,
                             turned = plan.turned, step_over = plan.step_over,
                             outlet_width_left = plan.outlet_width_left, outlet_width_right = plan.outlet_width_right,
                             scallop_max = plan.scallop_max, scallop_outlet = plan.scallop_outlet,
                             deepest_step = plan.deepest_step, poses = plan.poses, passes = #plan.passes,
                             links = plan.links, moves = #plan.moves, refusals = plan.refusals,
                             left_v = c.left_v, right_v = c.right_v}
  rows[#rows + 1] = {c.name, plan.notch_levels, plan.widen_left, plan.widen_right, plan.step_over,
                     plan.outlet_width_left, plan.outlet_width_right, plan.scallop_max, #plan.passes, plan.poses,
                     #plan.refusals}
  totals.poses, totals.refused = totals.poses + plan.poses, totals.refused + #plan.refusals
  totals.passes = totals.passes + #plan.passes
  print(string.format("channel %-6s %d notch levels (step <= %.2f mm), %d + %d widening paths at %.3f mm "
                      .. "(outlet %.2f / %.2f mm; %d added where a cusp exceeded h), scallop measured <= %.4f mm; "
                      .. "%d passes, %d poses (%d turned), %d refused",
                      c.name, plan.notch_levels, plan.deepest_step, plan.widen_left, plan.widen_right, plan.step_over,
                      plan.outlet_width_left, plan.outlet_width_right, plan.paths_added, plan.scallop_max,
                      #plan.passes, plan.poses, plan.turned, #plan.refusals))
end
report.totals = totals
-- The verdict, per channel: the cusps between widening paths within the
-- scallop h (measured), no pose refused.
local requirements = {}
for _, c in ipairs(chosen) do
  local ch = report.channels[c.name]
  requirements[#requirements + 1] = {name = "channel " .. c.name .. ": scallop between widening paths (measured)",
                                     unit = "µm", measured = 1e3 * ch.scallop_max, at_most = 1e3 * scallop * (1 + 1e-9)}
  requirements[#requirements + 1] = {name = "channel " .. c.name .. ": refused poses", unit = "count",
                                     measured = #ch.refusals, at_most = 0}
end
report.verdict = require("run_report").verdict(requirements)
bliskrun.write_json("impeller_channel_roughing.json", report)
require("run_report").write{title = "Notching and widening of the built-in impeller's channel",
  verdict = report.verdict,
  settings = {stations = stations, stock_mm = stock, min_stock_mm = min_stock, scallop_mm = scallop,
              depth_step_mm = depth_step, splitter_gap_mm = gap,
              mesh_tol_mm = mesh_tol, tool = tool:description()},
  sections = {{title = "Channels between main blades 1 and 2", table = {columns = {"channel", "notch levels",
    "widen left", "widen right", "step-over (mm)", "outlet width left (mm)", "outlet width right (mm)",
    "scallop measured (mm)", "passes", "poses", "refused"}, rows = rows}}},
  vtk = {path = "impeller_channel_roughing.pvd", blocks = blocks},
  files = {{"impeller_channel_roughing.json", "the report"}, {"impeller_channel_*.apt", "APT/CL per channel"}}}
