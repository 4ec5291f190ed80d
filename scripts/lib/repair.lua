-- What the repair recipes share: the passes of a repair plan's finishing
-- layer for the simulation, sample counts for a (u, v) window of a blade
-- surface, and the finishing layer checked on bands around the region.
local M = {}

-- The moves of the finishing layer as simulation passes (a stop ends one).
function M.finishing_passes(plan, tool)
  local passes, cur = {}, {}
  for i = plan.first_finishing_move, #plan.moves do
    local m = plan.moves[i]
    if m.kind == "stop" then
      if #cur > 0 then passes[#passes + 1] = {tool = tool, poses = cur} end
      cur = {}
    else
      cur[#cur + 1] = m
    end
  end
  if #cur > 0 then passes[#passes + 1] = {tool = tool, poses = cur} end
  return passes
end

-- Samples of the window w = {u = {u0, u1}, v = {v0, v1}} of `surface`: 0.04
-- mm apart across the passes (u: the cusps between passes lie there), 0.25
-- mm along them (v), where the material left varies only with the chord.
-- Lengths measured along the u line at v_mid and around the v line at the
-- window's middle span.
function M.window_samples(surface, w, v_mid)
  local function dist(a, b) return math.sqrt((b.x - a.x) ^ 2 + (b.y - a.y) ^ 2 + (b.z - a.z) ^ 2) end
  local span_mm = dist(surface:point(w.u[1], v_mid), surface:point(w.u[2], v_mid))
  local around, um, n = 0, 0.5 * (w.u[1] + w.u[2]), 64
  for k = 0, n - 1 do
    local v0 = w.v[1] + (w.v[2] - w.v[1]) * k / n
    local v1 = w.v[1] + (w.v[2] - w.v[1]) * (k + 1) / n
    around = around + dist(surface:point(um, v0), surface:point(um, v1))
  end
  return math.max(8, math.ceil(span_mm / 0.04)), math.max(8, math.ceil(around / 0.25))
end

local function dist(a, b) return math.sqrt((b.x - a.x) ^ 2 + (b.y - a.y) ^ 2 + (b.z - a.z) ^ 2) end

-- The finishing layer simulated on bands of `surface` around the window
-- w = {u = {u0, u1}, v = {v0, v1}} on every side the tool reaches (issue 43:
-- 1 mm below the region only missed contacts above and beside it):
-- `band_mm` (default 1) of span below and above it, and around the profile
-- before and after its v range. Lengths are measured on the surface: along
-- the u line at the window's middle v, around the whole v line at its middle
-- u. A side at the surface's end (u 0 or 1) has no band, nor do before and
-- after when the window goes all the way round (v 0..1). Each band is
-- simulated with `passes` at window_samples' density, `search_below`
-- (default 0.05 mm) the deepest overcut measured. Returns {overcut = the
-- deepest over all bands (mm, <= 0), side = its band's name or nil,
-- sides = {below|above|before|after = {overcut, u, v, point, samples_u,
-- samples_v}}}: where each band was cut deepest (u, v on `surface`).
function M.band_check(surface, passes, w, opts)
  opts = opts or {}
  local band_mm = opts.band_mm or 1
  assert(w.v[1] < w.v[2], "band_check: the window's v range must not wrap through the seam")
  local vm, um = 0.5 * (w.v[1] + w.v[2]), 0.5 * (w.u[1] + w.u[2])
  local along, around, n = 0, 0, 256
  for k = 0, n - 1 do
    along = along + dist(surface:point(k / n, vm), surface:point((k + 1) / n, vm))
    around = around + dist(surface:point(um, k / n), surface:point(um, (k + 1) / n))
  end
  local du, dv = band_mm / along, band_mm / around
  local bands = {
    {name = "below", u = {math.max(0, w.u[1] - du), w.u[1]}, v = w.v},
    {name = "above", u = {w.u[2], math.min(1, w.u[2] + du)}, v = w.v},
    {name = "before", u = w.u, v = {math.max(0, w.v[1] - dv), w.v[1]}},
    {name = "after", u = w.u, v = {w.v[2], math.min(1, w.v[2] + dv)}},
  }
  local out = {overcut = 0, sides = {}}
  for _, band in ipairs(bands) do
    if band.u[2] - band.u[1] > 1e-9 and band.v[2] - band.v[1] > 1e-9 then
      local su, sv = M.window_samples(surface, band, 0.5 * (band.v[1] + band.v[2]))
      local b = bliskrun.simulate{surface = surface, passes = passes, u = band.u, v = band.v, samples_u = su,
                                  samples_v = sv, search_above = 0.05, search_below = opts.search_below or 0.05}
      out.sides[band.name] = {overcut = b.overcut, u = b.overcut_u, v = b.overcut_v, point = b.overcut_point,
                              samples_u = su, samples_v = sv}
      if b.overcut < out.overcut then
        out.overcut = b.overcut
        out.side = band.name
      end
    end
  end
  return out
end

return M
