-- The impeller operations of a job (impeller paper §4; scripts/lib/job.lua
-- is the entry): notching, widening with hub finishing, flank finishing.
-- Each plans blade 1's channels or faces, proved against the blades either
-- side and the hub with the whole tool (scripts/lib/impeller_world.lua), and
-- turns them onto every blade of the operation: the model is symmetric
-- under the blade pitch, so the proofs carry over.
local options = require("job.options")
local geometry = require("job.geometry")

local check_options, positive, blade_list = options.check, options.positive, options.blade_list
local add = geometry.add

local M = {}

local function require_impeller(j, what)
  if j.part_kind ~= "impeller" then error(what .. ": this operation machines an impeller; the job's part is a blisk", 0) end
end

-- Blade 1's units turned onto each blade of the operation: the model is
-- symmetric under turns of the blade pitch about Z, so the proofs carry over.
local function per_blade(j, units, blades)
  local iw = require("impeller_world")
  local out = {}
  for _, k in ipairs(blades) do
    local angle = iw.pitch_angle(j.part, k)
    for _, u in ipairs(units) do
      local moves = {}
      for i, m in ipairs(u.moves) do
        local p = iw.turn(m, angle)
        moves[i] = {kind = m.kind, tip = p.tip, axis = p.axis, row = m.row, motion = m.motion,
                    operation = m.operation}
      end
      out[#out + 1] = {blade = k, side = u.name, moves_list = moves, report = u.report}
    end
  end
  return out
end

-- Notching (§4.1): the channel's middle opened in depth levels from the
-- shroud contour to the stock above the hub (bliskrun.channel_rough). When a
-- job.widen follows it (same tool, same blades), each channel is notched and
-- widened in one plan, its passes linked inside the channel.
function M.notch(o)
  check_options("job.notch", o, {
    tool = {type = "string", required = true},
    blades = {type = "table", required = true, check = blade_list},
    stock = {type = "number", check = function(v) if not (v > 0 and v < 10) then return "expected 0 < stock < 10 mm" end end},
    min_stock = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
    depth_step = {type = "number", check = positive},
    stations = {type = "number", check = function(v) if math.type(v) ~= "integer" or v < 2 then return "expected an integer >= 2" end end},
    splitter_gap = {type = "number", check = positive},
    channels = {type = "table", check = function(v)
      if #v == 0 then return "expected a list of channel names" end
      for _, c in ipairs(v) do
        if c ~= "inlet" and c ~= "left" and c ~= "right" and c ~= "channel" then
          return "expected 'inlet', 'left', 'right' (with splitters) or 'channel' (without)"
        end
      end
    end},
    mesh_tol = {type = "number", check = positive},
    feed = {type = "number", check = positive},
  }, 2)
  local op = {kind = "notch", channels = o.channels, tool = o.tool, blades = o.blades, stock = o.stock or 0.5, depth_step = o.depth_step or 5,
              stations = o.stations or 41, splitter_gap = o.splitter_gap or 20, mesh_tol = o.mesh_tol or 0.05,
              feed = o.feed or 800}
  op.min_stock = o.min_stock or math.min(0.2, op.stock / 2)
  if op.min_stock > op.stock then error("job.notch: option 'min_stock': expected at most the stock", 2) end
  function op.plan_flanks(self, j, index)
    require_impeller(j, "job.notch")
    local iw = require("impeller_world")
    local widen = self.widen_op
    local meshes = j:impeller_meshes(self.mesh_tol)
    -- Where the widening leaves less on the hub than the cutter's clearance
    -- (the paper finishes it), the ball is meant to touch the hub.
    local hub_stock = widen and widen.hub_stock or self.stock
    local world = iw.channel_world(j.part, meshes, hub_stock < self.min_stock
                                   and {hub_finish = {cutter_clearance = self.min_stock - hub_stock}} or nil)
    local tool = j.tools[self.tool]
    local wanted, chosen, requests = {}, {}, {}
    for _, name in ipairs(self.channels or {}) do wanted[name] = true end
    for _, c in ipairs(iw.channels(j.part, {gap = self.splitter_gap})) do
      if not self.channels or wanted[c.name] then
        chosen[#chosen + 1] = c
        requests[#requests + 1] = {left = c.left, left_v = c.left_v, right = c.right, right_v = c.right_v,
                                   hub = j.part:hub(), tool = tool.tool, ball_radius = tool.ball_radius,
                                   world = world, stations = self.stations, stock = self.stock, hub_stock = hub_stock,
                                   scallop = widen and widen.scallop or nil, widen = widen ~= nil,
                                   depth_step = self.depth_step, cutter_clearance = self.min_stock}
      end
    end
    if #chosen == 0 then error("job.notch: none of the channels asked for is in this impeller", 0) end
    -- The channels are independent: planned side by side on --threads.
    local plans = bliskrun.channel_rough_all{channels = requests}
    local units = {}
    for k, c in ipairs(chosen) do
      local plan = plans[k]
      if #plan.refusals > 0 or not plan.complete then
        local first = plan.refusals[1]
        error(string.format("job.notch: channel %s: %d poses refused%s%s; nothing of it is emitted", c.name,
                            #plan.refusals, first and string.format(" (first: %s %d at t = %.3f: %s)", first.kind,
                                                                     first.index, first.t, first.reason) or "",
                            plan.complete and "" or ", stopped: " .. plan.stopped), 0)
      end
      -- A move belongs to the widening operation where its pass widens.
      local moves = {}
      for i, m in ipairs(plan.moves) do
        moves[i] = {kind = m.kind, tip = m.tip, axis = m.axis, row = m.row, motion = m.motion,
                    operation = widen and plan.passes[m.row].kind ~= "notch" and index + 1 or index}
      end
      units[#units + 1] = {name = c.name, moves = moves,
                           report = {notch_levels = plan.notch_levels, widen_left = plan.widen_left,
                                     widen_right = plan.widen_right, step_over = plan.step_over,
                                     scallop_max = plan.scallop_max, paths_added = plan.paths_added,
                                     poses = plan.poses, passes = #plan.passes, turned = plan.turned,
                                     inserted = plan.inserted, hub_stock = plan.hub_stock}}
    end
    return per_blade(j, units, self.blades)
  end
  return op
end

-- Widening with hub finishing (§4.2, eq. 12–14): from the notch towards both
-- faces along the hub, paths f = 2 sqrt(2rh - h^2) apart for the scallop h,
-- the last on each side the finishing pose of the cutter grown by the
-- faces' stock. As in the paper the widening finishes the hub in the same
-- passes: hub_stock (default 0) is what it leaves there, the faces keep the
-- notch's stock for flank finishing. Planned with the job.notch it must
-- directly follow (same tool and blades).
function M.widen(o)
  check_options("job.widen", o, {
    tool = {type = "string", required = true},
    blades = {type = "table", required = true, check = blade_list},
    scallop = {type = "number", check = positive},
    hub_stock = {type = "number", check = function(v) if not (v >= 0 and v < 10) then return "expected 0 <= hub_stock < 10 mm" end end},
    feed = {type = "number", check = positive},
  }, 2)
  return {kind = "widen", tool = o.tool, blades = o.blades, scallop = o.scallop or 0.01, hub_stock = o.hub_stock or 0,
          feed = o.feed or 1000, plan_flanks = function() return {} end}  -- its moves come with the notch's plan
end

-- A list of blade faces (job.flank_finish's and job.point_mill's `faces`).
local all_faces = {"main plus", "main minus", "splitter plus", "splitter minus"}
local function face_list(v)
  if #v == 0 then return "expected a list of faces" end
  for _, f in ipairs(v) do
    local known = false
    for _, name in ipairs(all_faces) do known = known or f == name end
    if not known then return "expected 'main plus', 'main minus', 'splitter plus', 'splitter minus'" end
  end
end

-- Flank finishing (§4.3) of blade faces with the side of a (tapered)
-- ball-end mill (bliskrun.flank_mill): faces = list of "main plus", "main
-- minus", "splitter plus", "splitter minus" (default all four).
function M.flank_finish(o)
  check_options("job.flank_finish", o, {
    tool = {type = "string", required = true},
    blades = {type = "table", required = true, check = blade_list},
    faces = {type = "table", check = face_list},
    chord_tol = {type = "number", check = positive},
    clearance = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
    mesh_tol = {type = "number", check = positive},
    balance = {type = "boolean"},
    optimise = {type = "boolean"},
    max_axis_correction = {type = "number", check = function(v)
      if not (v >= 0 and v <= 10) then return "expected 0..10 degrees" end end},
    overcut_weight = {type = "number", check = function(v) if not (v >= 1) then return "expected >= 1" end end},
    feed = {type = "number", check = positive},
  }, 2)
  local op = {kind = "flank_finish", tool = o.tool, blades = o.blades,
              faces = o.faces or {table.unpack(all_faces)},
              chord_tol = o.chord_tol or 0.005, clearance = o.clearance or 0.5, mesh_tol = o.mesh_tol or 0.05,
              balance = o.balance ~= false, optimise = o.optimise ~= false,
              max_axis_correction = o.max_axis_correction, overcut_weight = o.overcut_weight,
              feed = o.feed or 600, lift = 5}
  function op.plan_flanks(self, j, index)
    require_impeller(j, "job.flank_finish")
    local iw = require("impeller_world")
    local meshes = j:impeller_meshes(self.mesh_tol)
    local tool = j.tools[self.tool]
    local units = {}
    for _, name in ipairs(self.faces) do
      local kind, side = name:match("^(%a+) (%a+)$")
      if kind == "splitter" and not j.part:has_splitter() then
        error("job.flank_finish: the impeller has no splitters; faces = {'" .. name .. "'}", 0)
      end
      local world = iw.face_world(j.part, meshes, kind, side)
      local plan = bliskrun.flank_mill{face = j.part:face(1, side, kind), design = iw.design_face(j.part, 1, side, kind),
                                       hub = j.part:hub(), tool = tool.tool,
                                       ball_radius = tool.ball_radius, world = world,
                                       chord_tol = self.chord_tol, clearance = self.clearance, balance = self.balance,
                                       optimise = self.optimise, max_axis_correction = self.max_axis_correction,
                                       overcut_weight = self.overcut_weight, residual_points = 10}
      if #plan.refusals > 0 or not plan.lead_in.clear or not plan.lead_out.clear then
        error(string.format("job.flank_finish: %s face: %d poses refused%s; nothing of it is emitted", name,
                            #plan.refusals, (plan.lead_in.clear and plan.lead_out.clear) and ""
                              or ", lead not clear: " .. (plan.lead_in.reason or "") .. (plan.lead_out.reason or "")), 0)
      end
      -- The plan's leads slide the ball along the hub, off the face; the
      -- unit starts and ends up the tool axis from there, off the hub, so
      -- the job's links never touch the finished surfaces. Those two motions
      -- are proved here like the plan's own.
      local function lifted(pose) return {tip = add(pose.tip, pose.axis, self.lift), axis = pose.axis} end
      local start, finish = lifted(plan.lead_in.away), lifted(plan.lead_out.away)
      -- The lifts are leads too: their least margin (a lower bound within
      -- 0.01 mm, as the plan's lead_min_margin) joins the reported figures.
      local clearance = {cutter = 0, shank = self.clearance, holder = self.clearance}
      local lead_min, min_margin = plan.lead_min_margin or math.huge, plan.min_margin
      for _, leg in ipairs{{start, plan.lead_in.away}, {plan.lead_out.away, finish}} do
        local m = world:check_motion(tool.tool, leg[1], leg[2], {clearance = clearance})
        if not m.clear then
          error(string.format("job.flank_finish: %s face: the lift of %.1f mm off the hub at the %s is not clear "
                              .. "(margin %.3f mm)", name, self.lift, leg[1] == start and "lead-in" or "lead-out",
                              m.min_margin or 0 / 0), 0)
        end
        lead_min = math.min(lead_min, world:motion_min_margin(tool.tool, leg[1], leg[2], {clearance = clearance}))
      end
      min_margin = math.min(min_margin, lead_min)
      local moves = {{kind = "rapid", tip = start.tip, axis = start.axis, row = 1, motion = "start", operation = index},
                     {kind = "feed", tip = plan.lead_in.away.tip, axis = plan.lead_in.away.axis, row = 1,
                      motion = "approach", operation = index}}
      for _, p in ipairs(plan.poses) do
        moves[#moves + 1] = {kind = "feed", tip = p.tip, axis = p.axis, row = 1,
                             motion = #moves == 2 and "approach" or "cut", operation = index}
      end
      moves[#moves + 1] = {kind = "feed", tip = plan.lead_out.away.tip, axis = plan.lead_out.away.axis, row = 1,
                           motion = "retract", operation = index}
      moves[#moves + 1] = {kind = "feed", tip = finish.tip, axis = finish.axis, row = 1, motion = "retract",
                           operation = index}
      units[#units + 1] = {name = name, moves = moves,
                           report = {poses = #plan.poses, stations = plan.stations, tilted = plan.tilted,
                                     -- the emitted (fitted, with optimise) axes' residual; before the fit apart
                                     residual_max = plan.residual.max, residual_min = plan.residual.min,
                                     residual_mean = plan.residual.mean,
                                     residual_before_max = plan.residual_before.max,
                                     residual_before_min = plan.residual_before.min,
                                     residual_before_mean = plan.residual_before.mean,
                                     optimised = plan.optimised,
                                     -- apart from the residual: the corner the ball riding the hub leaves
                                     root_corner_max = plan.root_corner and plan.root_corner.max,
                                     min_margin = min_margin, lead_min_margin = lead_min}}
    end
    return per_blade(j, units, self.blades)
  end
  return op
end


-- Point milling (issue 40) of blade faces with the tip of a (tapered)
-- ball-end mill (bliskrun.point_mill) on the faces as designed (the lofted
-- faces where the part has them): rows along the flow spaced by the
-- scallop measured on the face, every pose, cutting motion, step, link and
-- lead proved against the blades either side and the hub (the face's own
-- world, as job.flank_finish's). faces = list as job.flank_finish's, or
-- "where flank milling misses": `instead_of_flank = tolerance` takes the
-- faces a job.flank_finish of the same job leaves beyond the tolerance (its
-- plans' residuals against the face as designed: the flank finish's own
-- figure), and the flank finish's units of those faces are dropped.
function M.point_mill(o)
  check_options("job.point_mill", o, {
    tool = {type = "string", required = true},
    blades = {type = "table", required = true, check = blade_list},
    faces = {type = "table", check = face_list},
    instead_of_flank = {type = "number", check = positive},
    scallop = {type = "number", check = positive},
    chord_tol = {type = "number", check = positive},
    rows = {type = "string", check = function(v) if v ~= "along" and v ~= "across" then return "expected 'along' or 'across'" end end},
    lean = {type = "number", check = positive},
    lead = {type = "number"},
    max_turn = {type = "number", check = positive},
    hub_stop = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
    follow_fillet = {type = "boolean"},
    clearance = {type = "number", check = function(v) if not (v >= 0) then return "expected >= 0 mm" end end},
    mesh_tol = {type = "number", check = positive},
    guard_spacing = {type = "number", check = positive},
    allowed_overcut = {type = "number", check = positive},
    simulate = {type = "table"},
    feed = {type = "number", check = positive},
  }, 2)
  local op = {kind = "point_mill", tool = o.tool, blades = o.blades,
              faces = o.faces or {table.unpack(all_faces)},
              instead_of_flank = o.instead_of_flank, scallop = o.scallop or 0.005, chord_tol = o.chord_tol or 0.002,
              rows = o.rows or "along", lean = o.lean or 10, lead = o.lead or 0, max_turn = o.max_turn or 2,
              hub_stop = o.hub_stop, follow_fillet = o.follow_fillet ~= false, clearance = o.clearance or 0.5, mesh_tol = o.mesh_tol or 0.05,
              guard_spacing = o.guard_spacing or 0.1, allowed_overcut = o.allowed_overcut or 0.005,
              simulate = o.simulate or {samples = {60, 240}},
              feed = o.feed or 600}
  -- The faces this operation mills in job j: its list, or those a flank
  -- finish planned before it leaves beyond `instead_of_flank`.
  function op.chosen_faces(self, j, planned_of)
    if not self.instead_of_flank then return self.faces end
    local out, allowed = {}, {}
    for _, f in ipairs(self.faces) do allowed[f] = true end
    self.decisions = {}
    for i, other in ipairs(j.operations) do
      if other.kind == "flank_finish" and planned_of[i] then
        for _, u in ipairs(planned_of[i]) do
          local r = u.report
          if u.blade == other.blades[1] and allowed[u.side] and r.residual_max then
            local worst = math.max(r.residual_max, -r.residual_min)
            local point = worst > self.instead_of_flank
            self.decisions[u.side] = {flank_residual_mm = worst, tolerance_mm = self.instead_of_flank,
                                      method = point and "point milling" or "flank milling"}
            if point then out[#out + 1] = u.side end
          end
        end
      end
    end
    return out
  end
  function op.plan_flanks(self, j, index, planned_of)
    require_impeller(j, "job.point_mill")
    local iw = require("impeller_world")
    local meshes = j:impeller_meshes(self.mesh_tol)
    local tool = j.tools[self.tool]
    local units = {}
    self.chosen = self:chosen_faces(j, planned_of or {})
    for _, name in ipairs(self.chosen) do
      local kind, side = name:match("^(%a+) (%a+)$")
      if kind == "splitter" and not j.part:has_splitter() then
        error("job.point_mill: the impeller has no splitters; faces = {'" .. name .. "'}", 0)
      end
      local other = side == "plus" and "minus" or "plus"
      local face, back = iw.design_face(j.part, 1, side, kind), iw.design_face(j.part, 1, other, kind)
      -- Out of the material: away from the blade's other face.
      local e = face:eval(0.5, 0.5)
      local q = back:point(0.5, 0.5)
      local d = {e.point[1] - q[1], e.point[2] - q[2], e.point[3] - q[3]}
      local flip = e.normal[1] * d[1] + e.normal[2] * d[2] + e.normal[3] * d[3] < 0
      -- Following the fillet the ball touches the hub by design: the
      -- planner guards the hub along the fillet line within
      -- allowed_overcut, and the world holds the hub for the cutter less
      -- the hub finish's allowance (a guard against gross errors, as the
      -- channel world's); stopping, the exact hub.
      local world = iw.face_world(j.part, meshes, kind, side,
                                  {hub_cutter = self.follow_fillet and iw.hub_finish_allowance or true})
      local plan = bliskrun.point_mill{face = {surface = face, flip = flip, name = "blade 1 " .. name},
                                       tool = tool.tool, world = world, rows = self.rows, scallop = self.scallop,
                                       chord_tol = self.chord_tol, lean = self.lean, lead = self.lead,
                                       max_turn = self.max_turn,
                                       -- The rows carried down to the fillet line (the ball touching
                                       -- face and hub); the band up to hub_stop measured as the root strip.
                                       hub = j.part:hub(), follow_fillet = self.follow_fillet,
                                       -- Default 3 r: the ball fits a root corner down to ~37 deg
                                       -- there (r / tan(theta / 2)); below is the fillet's.
                                       hub_stop = self.hub_stop or 3 * (tool.ball_radius or 1),
                                       clearance = self.clearance, holder_clearance = self.clearance,
                                       guard_spacing = self.guard_spacing, allowed_overcut = self.allowed_overcut}
      local rep = plan:report()
      if not rep.complete then
        local why = #rep.refusals > 0 and rep.refusals[1].reason or rep.refused[1]
        error(string.format("job.point_mill: %s face: %d poses refused, %d connections refused (first: %s); "
                            .. "nothing of it is emitted", name, #rep.refusals, #rep.refused, tostring(why)), 0)
      end
      -- Against the face as designed: the plan's own moves simulated.
      local sim = plan:simulate(self.simulate)
      -- The root strip the rows stop above (hub_stop): measured apart from
      -- the face's residual (which covers the rows' window only); no later
      -- operation of the job finishes it, and the verdict says so.
      local strip = plan:root_strip()
      local moves = {}
      for i, m in ipairs(plan:moves()) do
        moves[i] = {kind = m.kind, tip = m.tip, axis = m.axis, row = m.row, motion = m.motion, operation = index}
      end
      units[#units + 1] = {name = name, moves = moves,
                           report = {poses = rep.poses, rows = rep.rows, tilted = rep.tilted,
                                     scallop = rep.scallop, scallop_measured = rep.scallop_measured,
                                     scallop_closed_form = rep.scallop_closed_form, max_deviation = rep.max_deviation,
                                     max_turn = rep.max_turn, first_row_u = rep.first_row_u,
                                     residual_max = sim.left_max, residual_min = math.min(0, sim.overcut),
                                     untouched = sim.untouched, seconds = rep.seconds,
                                     strip_height = strip.height, strip_height_min = strip.height_min,
                                     strip_left_max = strip.left_max, strip_left_mean = strip.left_mean,
                                     strip_from_fillet = strip.from_fillet, root_corner_max = strip.corner_left_max,
                                     follows_fillet = rep.follows_fillet, allowed_overcut = self.allowed_overcut,
                                     strip_finished_by = rep.follows_fillet and "the rows carried down to the fillet"
                                                         or nil,
                                     decision = self.decisions and self.decisions[name]}}
    end
    return per_blade(j, units, self.blades)
  end
  return op
end

return M
