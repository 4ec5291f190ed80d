-- The clearance surfaces a job's links run on (job/links.lua), each a table
-- {description, back_out(pose) -> pose or nil, travel(out, into) -> points,
-- contains(p) (optional)}: a can about a blisk, a surface of revolution
-- over an impeller's outline.
local geometry = require("job.geometry")

local add = geometry.add

local M = {}

-- The blisk's clearance surface: the cylinder of radius R about Z.
--   back_out(pose) -> the tool backed out along its axis until the tip is on
--   the cylinder (nil when the axis points along Z); travel(out, into) ->
--   points round the cylinder, into last, in steps short enough that every
--   chord stays within 0.5 mm of it.
-- The clearance surface of a blisk: the cylinder of radius R about Z and,
-- when z0 < z1 are given, its end planes z = z0 and z = z1 in front of and
-- behind the part (a can). A tool backs out along its axis to the can's
-- first wall: the cylinder, or the end plane it points at when it meets
-- that first (an edge tool's axis is nearly axial; without the planes such
-- an axis would meet the cylinder far beyond the machine's travel); it
-- travels out on the plane to the cylinder's rim, round the cylinder, and in
-- on the other's plane.
function M.cylinder(R, z0, z1)
  local can = z0 and z1
  local c = {description = can and string.format("the clearance can (r = %g mm, z %g .. %g mm)", R, z0, z1)
                               or string.format("the clearance cylinder (r = %g mm)", R)}
  -- Whether a point lies inside the clearance surface (strictly).
  function c.contains(p)
    return p[1] ^ 2 + p[2] ^ 2 < R * R - 1e-9 and (not can or (p[3] > z0 + 1e-9 and p[3] < z1 - 1e-9))
  end
  function c.back_out(pose)
    local p, a = pose.tip, pose.axis
    -- |xy(p + t a)| = R: (a.a) t^2 + 2 (p.a) t + (p.p - R^2) = 0 in xy.
    local A, B, C = a[1] ^ 2 + a[2] ^ 2, p[1] * a[1] + p[2] * a[2], p[1] ^ 2 + p[2] ^ 2 - R * R
    local disc = B * B - A * C
    local t = A >= 0.04 and disc >= 0 and math.max(0, (-B + math.sqrt(disc)) / A) or nil
    if can and math.abs(a[3]) >= 1e-6 then
      -- The can's first wall along the axis: an end plane before the cylinder.
      local tz = math.max(0, ((a[3] < 0 and z0 or z1) - p[3]) / a[3])
      local q = add(p, a, tz)
      if q[1] ^ 2 + q[2] ^ 2 <= R * R and (not t or tz < t) then t = tz end
    end
    if not t then return nil end
    return {tip = add(p, a, t), axis = a}
  end
  -- The point on the rim (radius R) a point on an end plane travels out
  -- to, or the point itself when it is on the cylinder.
  local function rim(q)
    local r = math.sqrt(q[1] ^ 2 + q[2] ^ 2)
    if r >= R - 1e-6 then return q, false end
    if r < 1e-9 then return {R, 0, q[3]}, true end
    return {R * q[1] / r, R * q[2] / r, q[3]}, true
  end
  function c.travel(out, into)
    local from, out_plane = rim(out.tip)
    local to, into_plane = rim(into.tip)
    local points = {}
    if out_plane then points[#points + 1] = from end
    local t1, t2 = math.atan(from[2], from[1]), math.atan(to[2], to[1])
    local dt = t2 - t1
    while dt > math.pi do dt = dt - 2 * math.pi end
    while dt < -math.pi do dt = dt + 2 * math.pi end
    local n = math.max(1, math.ceil(math.abs(dt) / (2 * math.acos((R - 0.5) / R))))
    for i = 1, n do
      local s, t = i / n, t1 + i / n * dt
      points[#points + 1] = i == n and to or {R * math.cos(t), R * math.sin(t), from[3] + s * (to[3] - from[3])}
    end
    if into_plane then points[#points + 1] = into.tip end
    return points
  end
  return c
end

-- An impeller's clearance surface: the surface of revolution `clearance` mm
-- over its meridional outline (impeller_world.envelope): its channels open
-- upward and outward, so a tool backed out along its axis meets it just
-- above the channel.
function M.over_impeller(part, clearance)
  local surface = require("impeller_world").envelope(part, clearance)
  surface.description = string.format("the clearance surface %g mm over the impeller", clearance)
  return surface
end

return M
