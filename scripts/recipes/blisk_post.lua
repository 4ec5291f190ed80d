-- Posts one blade flank of a blisk-scale part for two machines and proves
-- both programs by read-back (issue 5, SPEC §7):
--   the A/C trunnion (dmg_like_ac_trunnion) with the Fanuc post, in machine
--   axes (G93, moves split to the chord tolerance), and
--   the B head / C table (monoblock_like_head_table) with the Heidenhain post
--   (FUNCTION TCPM).
-- Until the blisk-finishing strategy is bound to Lua, the path is a planned
-- test path at the blisk paper's scale: rows along the chord at spans from
-- the hub (r = 100 mm) to the tip (r = 130 mm, blade height 30 mm), the
-- blade twisting 14 deg from hub to tip, the tool axis along the span leaning
-- 10 deg against the feed.
--
--   bliskrun scripts/recipes/blisk_post.lua --out out [--set rows=16]
local rows = args.rows or 16         -- rows from hub to tip
local steps = 120                    -- feed moves per row
local hub_r, tip_r = 100, 130        -- mm
local chord = 36                     -- mm along the rotor axis
local feed = 900                     -- mm/min
local clearance = 20                 -- radial retract between rows, mm

local function flank_point(span, along)
  local r = hub_r + (tip_r - hub_r) * span
  local theta = math.rad(-8 + 16 * along + 14 * span * (along - 0.5))  -- twist
  local z = -chord / 2 + chord * along
  return r, theta, z
end

local function pose(r, theta, z, lean_deg)
  local c, s = math.cos(theta), math.sin(theta)
  local lean = math.rad(lean_deg)
  -- along the span (radial), leaning towards -Z by `lean`
  local axis = {c * math.cos(lean), s * math.cos(lean), -math.sin(lean)}
  return {r * c, r * s, z}, axis
end

local path = {}
for row = 0, rows - 1 do
  local span = row / (rows - 1)
  local r0, t0, z0 = flank_point(span, 0)
  local tip, axis = pose(r0 + clearance, t0, z0, 10)
  path[#path + 1] = {kind = "rapid", tip = tip, axis = axis, row = row + 1}
  for k = 0, steps do
    local r, theta, z = flank_point(span, k / steps)
    tip, axis = pose(r, theta, z, 10)
    path[#path + 1] = {kind = "feed", tip = tip, axis = axis, feed = feed, row = row + 1}
  end
  local r1, t1, z1 = flank_point(span, 1)
  tip, axis = pose(r1 + clearance, t1, z1, 10)
  path[#path + 1] = {kind = "feed", tip = tip, axis = axis, feed = 2 * feed, row = row + 1}
end

local tool = {number = 7, length = 95, spindle_rpm = 18000}
local report = {}
for _, job in ipairs({
  {machine = "dmg_like_ac_trunnion", post = "fanuc", file = "blade_ac_fanuc.nc"},
  {machine = "monoblock_like_head_table", post = "heidenhain", file = "blade_bc_heidenhain.h"},
}) do
  local m = bliskrun.machine.load(job.machine)
  local r = bliskrun.post.write{machine = m, post = job.post, path = path, file = job.file,
                                tool = tool, name = "blisk blade 1", chord_tol = 0.002}
  bliskrun.log(string.format("%s on %s: %d blocks (%d inserted), tip within %.4f mm of the plan, axis within %.5f deg",
                             job.file, m:name(), r.moves, r.inserted, r.max_position, r.max_angle))
  report[#report + 1] = {file = job.file, machine = m:name(), post = job.post, blocks = r.moves,
                         inserted = r.inserted, max_position_mm = r.max_position,
                         max_angle_deg = r.max_angle, max_departure_mm = r.max_deviation}
end
bliskrun.write_json("blisk_post.json", {planned_moves = #path, programs = report})
