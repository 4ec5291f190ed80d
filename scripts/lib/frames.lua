-- Rigid frames in recipes: {R = 3 x 3 rows, t = {x, y, z}}, and the
-- {origin, x, z} tables the Lua API takes and gives (y = z x x).
local M = {}

local function cross(a, b) return {a[2] * b[3] - a[3] * b[2], a[3] * b[1] - a[1] * b[3], a[1] * b[2] - a[2] * b[1]} end
local function xyz(v) return {v.x or v[1], v.y or v[2], v.z or v[3]} end

-- Rotation by `deg` about `axis` (Rodrigues), then the translation `t`.
function M.from_axis_angle(axis, deg, t)
  local n = math.sqrt(axis[1] ^ 2 + axis[2] ^ 2 + axis[3] ^ 2)
  local x, y, z = axis[1] / n, axis[2] / n, axis[3] / n
  local a = math.rad(deg)
  local c, s, C = math.cos(a), math.sin(a), 1 - math.cos(a)
  return {R = {{c + x * x * C, x * y * C - z * s, x * z * C + y * s},
               {y * x * C + z * s, c + y * y * C, y * z * C - x * s},
               {z * x * C - y * s, z * y * C + x * s, c + z * z * C}}, t = {t[1], t[2], t[3]}}
end

function M.from_table(f)
  local x, z = xyz(f.x), xyz(f.z)
  local y = f.y and xyz(f.y) or cross(z, x)
  local o = xyz(f.origin)
  return {R = {{x[1], y[1], z[1]}, {x[2], y[2], z[2]}, {x[3], y[3], z[3]}}, t = o}
end

function M.to_table(f)
  local R = f.R
  return {origin = {f.t[1], f.t[2], f.t[3]}, x = {R[1][1], R[2][1], R[3][1]}, z = {R[1][3], R[2][3], R[3][3]}}
end

function M.apply(f, p)
  local R = f.R
  return {R[1][1] * p[1] + R[1][2] * p[2] + R[1][3] * p[3] + f.t[1],
          R[2][1] * p[1] + R[2][2] * p[2] + R[2][3] * p[3] + f.t[2],
          R[3][1] * p[1] + R[3][2] * p[2] + R[3][3] * p[3] + f.t[3]}
end

function M.compose(a, b)  -- a * b
  local R = {}
  for i = 1, 3 do
    R[i] = {}
    for j = 1, 3 do R[i][j] = a.R[i][1] * b.R[1][j] + a.R[i][2] * b.R[2][j] + a.R[i][3] * b.R[3][j] end
  end
  return {R = R, t = M.apply(a, b.t)}
end

function M.inverse(f)
  local R = f.R
  local Rt = {{R[1][1], R[2][1], R[3][1]}, {R[1][2], R[2][2], R[3][2]}, {R[1][3], R[2][3], R[3][3]}}
  local t = f.t
  return {R = Rt, t = {-(Rt[1][1] * t[1] + Rt[1][2] * t[2] + Rt[1][3] * t[3]),
                       -(Rt[2][1] * t[1] + Rt[2][2] * t[2] + Rt[2][3] * t[3]),
                       -(Rt[3][1] * t[1] + Rt[3][2] * t[2] + Rt[3][3] * t[3])}}
end

function M.offset(f) return math.sqrt(f.t[1] ^ 2 + f.t[2] ^ 2 + f.t[3] ^ 2) end

function M.angle(f)
  local tr = f.R[1][1] + f.R[2][2] + f.R[3][3]
  return math.deg(math.acos(math.max(-1, math.min(1, (tr - 1) / 2))))
end

return M
