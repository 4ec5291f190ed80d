-- Line and bar charts as SVG text, for the figures the papers plot
-- (points per row, chord error along a row). Fixed number formatting, so
-- the same data gives the same bytes.
--
--   local chart = require("svg_chart")
--   bliskrun.write_text("fig.svg", chart.lines{title = "...", x_label = "v", y_label = "um",
--     series = {{name = "constant", points = {{x, y}, ...}}, ...}, limit = {y = 2, name = "tolerance"}})

local M = {}

local colours = {"#b2182b", "#2166ac", "#1b7837", "#762a83", "#e08214", "#404040"}

local function esc(s)
  return (tostring(s):gsub("&", "&amp;"):gsub("<", "&lt;"):gsub(">", "&gt;"))
end

local function f(x) return string.format("%.2f", x) end

-- A nice tick step for a range.
local function tick_step(span)
  if span <= 0 then return 1 end
  local raw = span / 5
  local mag = 10 ^ math.floor(math.log(raw, 10))
  for _, m in ipairs{1, 2, 5, 10} do
    if raw <= m * mag then return m * mag end
  end
  return 10 * mag
end

-- spec: title, x_label, y_label, series = {{name, points = {{x, y}, ...}, bars = bool}},
-- limit = {y =, name =} (a dashed horizontal line), width (720), height (360).
-- A series may give `lines = {{{x, y}, ...}, ...}` instead of `points`:
-- several polylines under one name (the paths on a face), and
-- `y_from_zero = false` lets the y axis start at the data.
function M.lines(spec)
  local W, H = spec.width or 720, spec.height or 360
  local left, top, right, bottom = 70, 40, 160, 50
  local xmin, xmax, ymin, ymax = math.huge, -math.huge, spec.y_from_zero == false and math.huge or 0, -math.huge
  for _, s in ipairs(spec.series) do
    for _, line in ipairs(s.lines or {s.points}) do
      for _, p in ipairs(line) do
        xmin, xmax = math.min(xmin, p[1]), math.max(xmax, p[1])
        ymin, ymax = math.min(ymin, p[2]), math.max(ymax, p[2])
      end
    end
  end
  if ymin == math.huge then ymin = 0 end
  if spec.limit then ymax = math.max(ymax, spec.limit.y) end
  if xmin == math.huge then xmin, xmax = 0, 1 end
  if xmax <= xmin then xmax = xmin + 1 end
  if ymax <= ymin then ymax = ymin + 1 end
  ymax = ymax + 0.05 * (ymax - ymin)
  local function X(x) return left + (x - xmin) / (xmax - xmin) * W end
  local function Y(y) return top + H - (y - ymin) / (ymax - ymin) * H end
  local out = {}
  local function add(s) out[#out + 1] = s end
  add(string.format('<?xml version="1.0" encoding="UTF-8"?>\n<svg xmlns="http://www.w3.org/2000/svg" '
                    .. 'width="%d" height="%d" font-family="sans-serif" font-size="12">', left + W + right,
                    top + H + bottom))
  add('<rect width="100%" height="100%" fill="white"/>')
  add(string.format('<text x="%d" y="24" font-size="15">%s</text>', left, esc(spec.title or "")))
  add(string.format('<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="black"/>', left, top, W, H))
  local sx, sy = tick_step(xmax - xmin), tick_step(ymax - ymin)
  for t = math.ceil(xmin / sx) * sx, xmax + 1e-9, sx do
    add(string.format('<text x="%s" y="%d" text-anchor="middle">%s</text>', f(X(t)), top + H + 16,
                      string.format("%g", tonumber(string.format("%.6g", t)))))
  end
  for t = math.ceil(ymin / sy) * sy, ymax + 1e-9, sy do
    add(string.format('<line x1="%d" x2="%d" y1="%s" y2="%s" stroke="#dddddd"/>', left, left + W, f(Y(t)), f(Y(t))))
    add(string.format('<text x="%d" y="%s" text-anchor="end">%s</text>', left - 6, f(Y(t) + 4),
                      string.format("%g", tonumber(string.format("%.6g", t)))))
  end
  add(string.format('<text x="%s" y="%d" text-anchor="middle">%s</text>', f(left + W / 2), top + H + 38,
                    esc(spec.x_label or "")))
  add(string.format('<text x="18" y="%s" text-anchor="middle" transform="rotate(-90 18 %s)">%s</text>',
                    f(top + H / 2), f(top + H / 2), esc(spec.y_label or "")))
  local n = #spec.series
  for i, s in ipairs(spec.series) do
    local c = colours[(i - 1) % #colours + 1]
    if s.bars then
      -- Grouped bars around each x.
      local bw = math.max(1, W / math.max(1, #s.points) / (n + 1))
      for _, p in ipairs(s.points) do
        add(string.format('<rect x="%s" y="%s" width="%s" height="%s" fill="%s"/>',
                          f(X(p[1]) + (i - 1 - n / 2) * bw), f(Y(p[2])), f(bw), f(Y(ymin) - Y(p[2])), c))
      end
    else
      for _, line in ipairs(s.lines or {s.points}) do
        local pts = {}
        for _, p in ipairs(line) do pts[#pts + 1] = f(X(p[1])) .. "," .. f(Y(p[2])) end
        add(string.format('<polyline fill="none" stroke="%s" stroke-width="1.5" points="%s"/>', c,
                          table.concat(pts, " ")))
      end
    end
    add(string.format('<rect x="%d" y="%d" width="12" height="12" fill="%s"/>', left + W + 12, top + 4 + 20 * (i - 1), c))
    add(string.format('<text x="%d" y="%d">%s</text>', left + W + 30, top + 14 + 20 * (i - 1), esc(s.name)))
  end
  if spec.limit then
    add(string.format('<line x1="%d" x2="%d" y1="%s" y2="%s" stroke="black" stroke-dasharray="6 4"/>', left,
                      left + W, f(Y(spec.limit.y)), f(Y(spec.limit.y))))
    add(string.format('<text x="%d" y="%s">%s</text>', left + 6, f(Y(spec.limit.y) - 4), esc(spec.limit.name or "")))
  end
  add("</svg>\n")
  return table.concat(out, "\n")
end

return M
