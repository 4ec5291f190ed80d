-- Links and their proofs (Job methods; scripts/lib/job.lua is the entry):
-- the collision worlds a motion is proved in — around a blade, the whole
-- part, an impeller's blade-1 neighbourhood — and the link from one unit's
-- last pose to the next's first through the job's clearance surface
-- (job/clearance.lua), every motion proved clear of the part with the
-- whole tool before it joins the path.
local geometry = require("job.geometry")
local Job = require("job.model").Job

local add, unit = geometry.add, geometry.unit

-- The impeller's faces and hub tessellated once per tolerance, shared by
-- every operation and the links.
function Job:impeller_meshes(tol)
  self.meshes = self.meshes or {}
  if not self.meshes[tol] then self.meshes[tol] = require("impeller_world").meshes(self.part, tol) end
  return self.meshes[tol]
end

-- The check surfaces around blade k (neighbours, hub, the blade itself for
-- the shank), built once per blade.
function Job:world_around(k)
  if not self.worlds[k] then
    -- Beyond a few blades, tessellate every flank once and share the meshes.
    local blisk_world = require("blisk_world")
    if self.part:blade_count() > 4 and self:blade_count_used() > 3 then
      self.worlds = blisk_world.all_blades(self.part)
    else
      self.worlds[k] = blisk_world.around_blade(self.part, k)
    end
  end
  return self.worlds[k]
end

-- A blisk's flank as the part has it, for the links' proofs: between the
-- hub and the casing. The flank's grid reaches past the casing (up to 7 mm
-- at the built-in blisk's inlet), where no material is: a roughing tool's
-- flute stands there when it leaves its channel.
function Job:link_flank(b, side)
  self.link_flanks = self.link_flanks or {}
  local key = b .. side
  if not self.link_flanks[key] then
    self.link_flanks[key] = bliskrun.trim_flank{flank = self.part:flank(b, side), hub = self.part:hub(),
                                                casing = self.part:casing()}
  end
  return self.link_flanks[key]
end

-- What a link's back-out from, or approach to, blade k's flanks is proved
-- against: the neighbours and the hub as the plans see them (0.01 mm), and
-- blade k itself for every tool part, the cutter included (0.01 mm, added as
-- margin): the back-out and approach slide the wheel along its own blade,
-- where the plan's lead-in/out left it, and must not touch it. Each blade
-- with its edge rounds (blisk_world.edge_round_mesh, up to the casing as the
-- flanks are): the flanks end where the rounds begin, and a round stands up
-- to its radius in front of the line between their ends.
function Job:link_world(k)
  self.link_worlds = self.link_worlds or {}
  if not self.link_worlds[k] then
    local n, tol = self.part:blade_count(), 0.01
    local blisk_world = require("blisk_world")
    local surfaces = {}
    for _, b in ipairs{(k - 2) % n + 1, k % n + 1} do
      for _, side in ipairs{"pressure", "suction"} do
        surfaces[#surfaces + 1] = {name = string.format("blade %d %s", b, side), surface = self:link_flank(b, side),
                                   chord_tol = tol}
      end
      for _, edge in ipairs{"leading", "trailing"} do
        surfaces[#surfaces + 1] = {name = string.format("blade %d %s edge", b, edge),
                                   mesh = blisk_world.edge_round_mesh(self.part, b, edge, tol)}
      end
    end
    surfaces[#surfaces + 1] = {name = "hub", surface = self.part:hub(), chord_tol = tol}
    for _, side in ipairs{"pressure", "suction"} do
      surfaces[#surfaces + 1] = {name = string.format("blade %d %s (own)", k, side), surface = self:link_flank(k, side),
                                 chord_tol = tol, margin = tol}
    end
    for _, edge in ipairs{"leading", "trailing"} do
      surfaces[#surfaces + 1] = {name = string.format("blade %d %s edge (own)", k, edge),
                                 mesh = blisk_world.edge_round_mesh(self.part, k, edge, tol), margin = tol}
    end
    self.link_worlds[k] = bliskrun.collision_world{surfaces = surfaces}
  end
  return self.link_worlds[k]
end

-- Every blade (flanks and edge rounds) and the hub, coarser (0.05 mm, added
-- as margin): what a link between two flanks, which may pass any blade, is
-- proved against. With the margin, clearance 0 for the cutter still keeps it
-- 0.05 mm off every surface: a link never cuts.
function Job:part_world()
  if not self.whole then
    local blisk_world = require("blisk_world")
    local surfaces = {}
    for b = 1, self.part:blade_count() do
      for _, side in ipairs{"pressure", "suction"} do
        surfaces[#surfaces + 1] = {name = string.format("blade %d %s", b, side), surface = self:link_flank(b, side),
                                   chord_tol = 0.05, margin = 0.05}
      end
      for _, edge in ipairs{"leading", "trailing"} do
        surfaces[#surfaces + 1] = {name = string.format("blade %d %s edge", b, edge),
                                   mesh = blisk_world.edge_round_mesh(self.part, b, edge, 0.05), margin = 0.05}
      end
    end
    surfaces[#surfaces + 1] = {name = "hub", surface = self.part:hub(), chord_tol = 0.05, margin = 0.05}
    self.whole = bliskrun.collision_world{surfaces = surfaces}
  end
  return self.whole
end

-- Where a link leg is proved, and the turn that brings it there: the first
-- leg leaves blade a, the last reaches blade b, the ones between travel over
-- the part. An impeller's legs near blade k are turned back onto blade 1
-- (its model is symmetric under the blade pitch) and proved against blade
-- 1's neighbourhood.
function Job:leg_world(leg, legs, blade_a, blade_b)
  if self.part_kind == "blisk" then
    return leg == 1 and blade_a and self:link_world(blade_a) or leg == legs and blade_b and self:link_world(blade_b)
               or self:part_world(), 0
  end
  local iw = require("impeller_world")
  if (leg == 1 and blade_a) or (leg == legs and blade_b) then
    self.neighbourhood = self.neighbourhood or iw.neighbourhood(self.part, self:impeller_meshes(0.05))
    return self.neighbourhood, -iw.pitch_angle(self.part, leg == 1 and blade_a or blade_b)
  end
  self.impeller_whole = self.impeller_whole or iw.whole(self.part, self:impeller_meshes(0.5))
  return self.impeller_whole, 0
end

-- Link from pose `a` to pose `b` through the clearance surface: back out
-- along a's axis, travel over the surface (the axis turning from a's to
-- b's), then in along b's axis. Each motion is proved clear of the part with
-- the whole tool.
-- cutter_a / cutter_b (mm, optional): the cutter's clearance on the first
-- and the last leg, where a or b stands in a roughed channel over its stock.
-- tool_a (optional): the tool that ends at a, when it is another: the
-- back-out is its last move (the tool change happens out on the clearance
-- surface), so the first leg is proved with it.
function Job:link(a, b, tool, what, blade_a, blade_b, cutter_a, cutter_b, tool_a)
  local surface = self.clearance_surface
  local function back_out(pose, which)
    local p = surface.back_out(pose)
    if not p then
      error(string.format("job: %s (%s): backed out along its axis (%.3f, %.3f, %.3f) the tool does not reach %s",
                          what, which, pose.axis[1], pose.axis[2], pose.axis[3], surface.description), 0)
    end
    return p
  end
  local out, into = back_out(a, "back out"), back_out(b, "approach")
  local travel = surface.travel(out, into)
  local poses = {out}
  for i, tip in ipairs(travel) do
    local s = i / #travel
    local axis = unit(add(out.axis, {into.axis[1] - out.axis[1], into.axis[2] - out.axis[2], into.axis[3] - out.axis[3]}, s))
    poses[#poses + 1] = {tip = tip, axis = i == #travel and into.axis or axis}
  end
  poses[#poses + 1] = b
  local from = a
  for i, to in ipairs(poses) do
    local cutter = math.max(i == 1 and cutter_a or 0, i == #poses and cutter_b or 0)
    self:prove_motion(from, to, i == 1 and tool_a or tool, i, #poses, blade_a, blade_b,
                      string.format("%s: link motion %d of %d", what, i, #poses), cutter > 0 and cutter or nil)
    from = to
  end
  table.remove(poses)  -- b itself is the next plan's first move
  return poses
end

-- Proves the motion from pose `a` to pose `b` clear of the part with the
-- whole tool, in the world of link leg `leg` of `legs` (Job:leg_world);
-- an error naming `what` otherwise.
-- `cutter`: the cutter's clearance there instead of the job's link clearance.
function Job:prove_motion(a, b, tool, leg, legs, blade_a, blade_b, what, cutter)
  a, b = {tip = a.tip, axis = a.axis}, {tip = b.tip, axis = b.axis}
  local world, angle = self:leg_world(leg, legs, blade_a, blade_b)
  if angle ~= 0 then
    local iw = require("impeller_world")
    a, b = iw.turn(a, angle), iw.turn(b, angle)
  end
  local clearance = self.link_clearance
  if cutter then
    clearance = {cutter = math.max(cutter, clearance.cutter or 0), shank = clearance.shank, holder = clearance.holder}
  end
  local m = world:check_motion(tool, a, b, {clearance = clearance})
  if not m.clear then
    error(string.format("job: %s is not proved clear of the part (margin %.3f mm at t = %.3f)", what,
                        m.min_margin or 0 / 0, m.t or 0 / 0), 0)
  end
end

return {}
