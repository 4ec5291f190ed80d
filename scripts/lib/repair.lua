-- What the repair recipes share: the passes of a repair plan's finishing
-- layer for the simulation, and sample counts for a (u, v) window of a
-- blade surface.
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

return M
