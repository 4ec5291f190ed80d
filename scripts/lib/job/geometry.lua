-- The little geometry the job library needs (scripts/lib/job.lua): points
-- and vectors as {x, y, z} lists, a plan's moves turned about Z, a point's
-- height over a meridian.
local M = {}

local function add(a, b, s) return {a[1] + s * b[1], a[2] + s * b[2], a[3] + s * b[3]} end
local function dot(a, b) return a[1] * b[1] + a[2] * b[2] + a[3] * b[3] end
local function unit(a)
  local n = math.sqrt(dot(a, a))
  return {a[1] / n, a[2] / n, a[3] / n}
end

-- A plan's moves turned about Z by `angle` (rad): a blisk's blades are one
-- blade turned by the pitch, so blade k's path is blade 1's turned.
local function turned_moves(list, angle)
  local c, s = math.cos(angle), math.sin(angle)
  local function rot(v) return {c * v[1] - s * v[2], s * v[1] + c * v[2], v[3]} end
  local out = {}
  for i, m in ipairs(list) do
    local t = {}
    for key, value in pairs(m) do t[key] = value end
    t.tip, t.axis = rot(m.tip), rot(m.axis)
    out[i] = t
  end
  return out
end

-- Heights over a meridian ({{z, r}, ...}, a polyline about Z): the signed
-- distance of p from it in p's meridian plane, + away from the axis — the
-- hub's radial offset, as the hub plan measures its rows' heights.
local function meridian_height(meridian, p)
  local r, z = math.sqrt(p.x * p.x + p.y * p.y), p.z
  local best, sign = math.huge, 1
  for i = 2, #meridian do
    local z0, r0, z1, r1 = meridian[i - 1][1], meridian[i - 1][2], meridian[i][1], meridian[i][2]
    local dz, dr = z1 - z0, r1 - r0
    local t = math.max(0, math.min(1, ((z - z0) * dz + (r - r0) * dr) / (dz * dz + dr * dr)))
    local ez, er = z - (z0 + t * dz), r - (r0 + t * dr)
    local d = math.sqrt(ez * ez + er * er)
    if d < best then
      -- The segment's normal away from the axis: (-dr, dz) or its opposite.
      local nz, nr = -dr, dz
      if nr < 0 then nz, nr = -nz, -nr end
      best, sign = d, (ez * nz + er * nr >= 0) and 1 or -1
    end
  end
  return sign * best
end

-- The blades of an operation planned once and turned (periodic) or each
-- planned: plan_blade(k) -> {{side =, plan =, report =, moves_list =}, ...}.

M.add, M.dot, M.unit, M.turned_moves, M.meridian_height = add, dot, unit, turned_moves, meridian_height
return M
