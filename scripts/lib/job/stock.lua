-- The job's stock (issue 41; scripts/lib/job.lua is the entry): with
-- job.new{..., blank = {profile = {{r, z}, ...}, resolution = 0.5}}, every
-- operation's moves — links included, in program order, each stretch with
-- its own tool — cut a bliskrun.stock (docs/lua_api/stock.md) after
-- planning, and the run reports per operation what it removed, the share of
-- its cutting path in air, and the stock left after it. A job without a
-- blank is unchanged.
local options = require("job.options")
local Job = require("job.model").Job

local check_options, positive = options.check, options.positive

local M = {}

-- job.new's `blank` option, checked at the recipe's line (level: as
-- options.check).
function M.check_blank(blank, level)
  check_options("job.new blank", blank, {
    profile = {type = "table", required = true, check = function(v)
      if #v < 3 then return "expected the blank's meridian, a closed polygon {{r, z}, ...} of at least 3 points" end
    end},
    resolution = {type = "number", check = positive},   -- ray spacing, mm (default 0.5)
    step = {type = "number", check = positive},         -- stock:cut's step, mm (default: the resolution)
    check_body = {type = "boolean"},                    -- shank and holder against the stock (default true)
  }, level + 1)
end

-- The pose a fraction t along the motion from pose a to move b, as
-- stock:cut and the machine move: the tip straight, the axis on the great
-- circle.
local function pose_at(a, b, t)
  local tip = {a.tip[1] + t * (b.tip[1] - a.tip[1]), a.tip[2] + t * (b.tip[2] - a.tip[2]),
               a.tip[3] + t * (b.tip[3] - a.tip[3])}
  local u, v = a.axis, b.axis
  local c = math.max(-1, math.min(1, u[1] * v[1] + u[2] * v[2] + u[3] * v[3]))
  local angle = math.acos(c)
  local wu, wv
  if angle < 1e-9 then wu, wv = 1 - t, t
  else wu, wv = math.sin((1 - t) * angle) / math.sin(angle), math.sin(t * angle) / math.sin(angle) end
  local axis = {wu * u[1] + wv * v[1], wu * u[2] + wv * v[2], wu * u[3] + wv * v[3]}
  local n = math.sqrt(axis[1] ^ 2 + axis[2] ^ 2 + axis[3] ^ 2)
  return {tip = tip, axis = {axis[1] / n, axis[2] / n, axis[3] / n}}
end

-- The feed starts this far (tip path, mm) before the tool first meets the
-- stock: the stock is exact along its rays only, and a machine takes a
-- little path to reach the feed rate from a rapid.
local FEED_BEFORE_STOCK_MM = 1
-- The first contact is bisected down to this much tip path, mm.
local ENTRY_TOL_MM = 0.01

-- The rapids of a stretch that removed stock (r, its first cut from the
-- stock `before` it) turned into feeds at their operation's feed rate from
-- where they meet the stock on: the largest fraction t of the motion from
-- the pose before along which the swept tool — cutter, shank and holder —
-- still cuts nothing of the stock as the moves before it left it (bisected
-- on copies), less FEED_BEFORE_STOCK_MM; the move gets rapid_to (that pose:
-- the program moves there at the rapid rate, then feeds on). A rapid in
-- material from its start (a retract) is fed whole. Records each in
-- out.fed.
local function fed_rapids(self, out, stretch, r, before, tool, opts, contact, first_index, op)
  local feed = self.operations[op].feed
  local work, done, prev = before:copy(), 0, opts.from
  for k, m in ipairs(stretch) do
    if m.kind == "rapid" and r.moves[k].removed_mm3 >= contact then
      if k - 1 > done then
        work:cut(table.move(stretch, done + 1, k - 1, 1, {}), tool,
                 {from = prev, step = opts.step, check_body = opts.check_body})
        done, prev = k - 1, stretch[k - 1]
      end
      local rapid_mm, length = 0, r.moves[k].length_mm
      if prev then
        local dx, dy, dz = m.tip[1] - prev.tip[1], m.tip[2] - prev.tip[2], m.tip[3] - prev.tip[3]
        length = math.sqrt(dx * dx + dy * dy + dz * dz)
      end
      if prev and length > FEED_BEFORE_STOCK_MM then
        local function clear(t)
          local p = pose_at(prev, m, t)
          local c = work:copy():cut({{kind = "rapid", tip = p.tip, axis = p.axis}}, tool,
                                    {from = prev, step = opts.step, check_body = opts.check_body})
          return c.removed_mm3 < contact and c.body_contact_moves == 0
        end
        local lo, hi = 0, 1
        while (hi - lo) * length > ENTRY_TOL_MM do
          local mid = 0.5 * (lo + hi)
          if clear(mid) then lo = mid else hi = mid end
        end
        local t = lo - FEED_BEFORE_STOCK_MM / length
        if t > 0 then
          m.rapid_to = pose_at(prev, m, t)
          rapid_mm = t * length
        end
      end
      m.kind, m.feed, m.in_stock = "feed", feed, true
      out.rapids_fed = (out.rapids_fed or 0) + 1
      out.fed = out.fed or {}
      out.fed[#out.fed + 1] = {move = first_index + k - 1, operation = op, motion = m.motion or "?",
                               removed_mm3 = r.moves[k].removed_mm3, length_mm = length, rapid_mm = rapid_mm}
    end
  end
end

-- Cuts the stock with the planned moves (Job:plan calls it when the job has
-- a blank). Returns {stock (the bliskrun.Stock), blank_mm3, blank_exact_mm3,
-- resolution, operations = {{operation, kind, removed_mm3, cut_mm,
-- air_cut_mm, air_share, rapid_removed_mm3, rapid_cut_moves,
-- body_contact_moves, body_contact_max_mm3, rate_max_mm2, axial_max_mm,
-- radial_max_mm, left_mm3, seconds}, ...}, memory_mb}.
function Job:cut_stock(planned)
  local b = self.blank
  local stock = bliskrun.stock{profile = b.profile, resolution = b.resolution or 0.5}
  local info = stock:info()
  local out = {stock = stock, blank_mm3 = info.blank_mm3, blank_exact_mm3 = info.blank_exact_mm3,
               resolution = info.resolution, operations = {}}
  local by_op = {}
  for i, op in ipairs(self.operations) do
    by_op[i] = {operation = i, kind = op.kind, removed_mm3 = 0, cut_mm = 0, air_cut_mm = 0, rapid_removed_mm3 = 0,
                rapid_cut_moves = 0, body_contact_moves = 0, body_contact_max_mm3 = 0, rate_max_mm2 = 0,
                axial_max_mm = 0, radial_max_mm = 0, seconds = 0}
    out.operations[i] = by_op[i]
  end
  local moves, last = planned.moves, nil
  -- What stock:cut calls rounding (its air default times the spacing).
  local contact = 0.001 * info.resolution
  local cpu0 = os.clock()
  local i = 1
  while i <= #moves do
    -- A stretch of one operation with one tool (a link's back-out is the
    -- old tool's), from the pose the one before it ended at.
    local op, tool = moves[i].operation, moves[i].tool
    local j = i
    while j < #moves and moves[j + 1].operation == op and moves[j + 1].tool == tool do j = j + 1 end
    local stretch = table.move(moves, i, j, 1, {})
    local opts = {from = last, step = b.step, check_body = b.check_body, per_move = true}
    local before = stock:copy()
    local tool_body = self:tool_entry(tool).tool
    local r = stock:cut(stretch, tool_body, opts)
    -- A rapid that removes stock — an approach, retract or link proved
    -- against the finished part, through the stock an earlier operation
    -- left — is a feed at the operation's feed rate from where it meets the
    -- stock on (fed_rapids); the stretch is cut again from the stock before
    -- it with those moves split (the posted program with them). One rule
    -- for every operation's rapids.
    local expanded, original = stretch, nil
    if r.rapid_cut_moves > 0 then
      fed_rapids(self, out, stretch, r, before, tool_body, opts, contact, i, op)
      expanded, original = {}, {}
      for k, m in ipairs(stretch) do
        if m.rapid_to then
          expanded[#expanded + 1] = {kind = "rapid", tip = m.rapid_to.tip, axis = m.rapid_to.axis}
          original[#expanded] = k
        end
        expanded[#expanded + 1] = m
        original[#expanded] = k
      end
      stock = before
      out.stock = stock
      r = stock:cut(expanded, tool_body, opts)
    end
    -- The verdict's moves: the rapid part of a split move is checked as the
    -- rapid it is.
    for x, m in ipairs(expanded) do
      local k = original and original[x] or x
      if r.moves[x].body_mm3 > 0 or (m.kind == "rapid" and r.moves[x].removed_mm3 >= contact) then
        out.offending = out.offending or {}
        out.offending[#out.offending + 1] = {move = i + k - 1, operation = op, kind = m.kind,
          motion = stretch[k].motion or stretch[k].operation_kind, body_mm3 = r.moves[x].body_mm3,
          removed_mm3 = r.moves[x].removed_mm3}
      end
    end
    local e = by_op[op]
    for _, k in ipairs({"removed_mm3", "cut_mm", "air_cut_mm", "rapid_removed_mm3", "rapid_cut_moves",
                        "body_contact_moves", "seconds"}) do
      e[k] = e[k] + r[k]
    end
    e.body_contact_max_mm3 = math.max(e.body_contact_max_mm3, r.body_contact_max_mm3)
    e.rate_max_mm2 = math.max(e.rate_max_mm2, r.engagement.rate_max_mm2)
    e.axial_max_mm = math.max(e.axial_max_mm, r.engagement.axial_max_mm)
    e.radial_max_mm = math.max(e.radial_max_mm, r.engagement.radial_max_mm)
    e.left_mm3 = r.volume_left_mm3
    last = {tip = moves[j].tip, axis = moves[j].axis}
    i = j + 1
  end
  for _, e in ipairs(out.operations) do
    e.air_share = e.cut_mm > 0 and e.air_cut_mm / e.cut_mm or 0
    e.left_mm3 = e.left_mm3 or (out.operations[e.operation - 1] or {left_mm3 = out.blank_mm3}).left_mm3
  end
  out.memory_mb = stock:info().memory_mb
  out.cpu_seconds = os.clock() - cpu0  -- every thread's, for the log
  return out
end

-- Printed lines and the JSON report's `stock` (timings to the log only).
function M.report(r)
  local s = r.planned.stock
  print(string.format("  stock: blank %.0f mm3 on %.2f mm rays (exact %.0f mm3), %.1f MB", s.blank_mm3, s.resolution,
                      s.blank_exact_mm3, s.memory_mb))
  local json = {blank_mm3 = s.blank_mm3, blank_exact_mm3 = s.blank_exact_mm3, resolution_mm = s.resolution,
                operations = {}}
  local seconds = 0
  for _, e in ipairs(s.operations) do
    seconds = seconds + e.seconds
    print(string.format("  stock after operation %d (%s): removed %.0f mm3, air %.0f of %.0f mm cut (%.0f %%), "
                        .. "left %.0f mm3%s%s", e.operation, e.kind, e.removed_mm3, e.air_cut_mm, e.cut_mm,
                        100 * e.air_share, e.left_mm3,
                        e.rapid_cut_moves > 0 and string.format("; %d rapids through material (%.1f mm3)",
                          e.rapid_cut_moves, e.rapid_removed_mm3) or "",
                        e.body_contact_moves > 0 and string.format("; shank or holder in the stock on %d moves "
                          .. "(up to %.2f mm3)", e.body_contact_moves, e.body_contact_max_mm3) or ""))
    json.operations[#json.operations + 1] = {operation = e.operation, kind = e.kind, removed_mm3 = e.removed_mm3,
      cut_mm = e.cut_mm, air_cut_mm = e.air_cut_mm, air_share = e.air_share, left_mm3 = e.left_mm3,
      rapid_removed_mm3 = e.rapid_removed_mm3, rapid_cut_moves = e.rapid_cut_moves,
      body_contact_moves = e.body_contact_moves, body_contact_max_mm3 = e.body_contact_max_mm3,
      rate_max_mm2 = e.rate_max_mm2, axial_max_mm = e.axial_max_mm, radial_max_mm = e.radial_max_mm}
  end
  print(string.format("  stock cut by %d moves in %.1f s (%.1f s CPU)", #r.planned.moves, seconds, s.cpu_seconds))
  if s.rapids_fed then
    print(string.format("  %d rapids through the stock turned into feeds at their operation's feed rate from %g mm "
                        .. "before the stock on", s.rapids_fed, FEED_BEFORE_STOCK_MM))
    for _, m in ipairs(s.fed) do
      print(string.format("    move %d, operation %d (%s): %.2f mm3 over %.1f mm, %s", m.move, m.operation, m.motion,
                          m.removed_mm3, m.length_mm, m.rapid_mm > 0
                            and string.format("rapid %.1f mm, fed %.1f mm", m.rapid_mm, m.length_mm - m.rapid_mm)
                            or "fed whole (in the stock from its start)"))
    end
  end
  -- The moves the verdict fails on, named (the first 20).
  for k, m in ipairs(s.offending or {}) do
    if k > 20 then print(string.format("  ... %d more", #s.offending - 20)) break end
    print(string.format("  move %d, operation %d (%s %s): %s", m.move, m.operation, m.kind, m.motion or "?",
                        m.body_mm3 > 0 and string.format("shank or holder %.2f mm3 in the stock", m.body_mm3)
                          or string.format("rapid removes %.2f mm3", m.removed_mm3)))
  end
  json.rapids_turned_to_feeds = s.rapids_fed or 0
  if s.fed then
    json.fed_rapids = {}
    for _, m in ipairs(s.fed) do
      json.fed_rapids[#json.fed_rapids + 1] = {move = m.move, operation = m.operation, motion = m.motion,
                                               removed_mm3 = m.removed_mm3, length_mm = m.length_mm,
                                               rapid_mm = m.rapid_mm}
    end
  end
  r.json.stock = json
end

-- What the verdict states of the stock (report.lua's common requirements):
-- per operation, no rapid removing stock and no shank or holder in it. A
-- rapid is proved against the finished part, not against the material an
-- earlier operation left, so a stock cut by one is a crash the part's
-- proofs cannot see; the report names the operation and the move count.
function M.requirements(r, q)
  local s = r.planned and r.planned.stock
  if not s then return q end
  for _, e in ipairs(s.operations) do
    local what = string.format("operation %d (%s)", e.operation, e.kind:gsub("_", " "))
    q[#q + 1] = {name = what .. ": rapids through the stock (moves)", unit = "count", measured = e.rapid_cut_moves,
                 at_most = 0, note = e.rapid_cut_moves > 0
                   and string.format("%d rapids remove %.1f mm3 of stock", e.rapid_cut_moves, e.rapid_removed_mm3)
                   or nil}
    q[#q + 1] = {name = what .. ": shank or holder in the stock (moves)", unit = "count",
                 measured = e.body_contact_moves, at_most = 0, note = e.body_contact_moves > 0
                   and string.format("%d moves, up to %.2f mm3 in the stock", e.body_contact_moves,
                                     e.body_contact_max_mm3) or nil}
  end
  return q
end

-- The report page's table: the stock after each operation.
function M.section(r)
  local s = r.planned.stock
  local rows = {}
  for _, e in ipairs(s.operations) do
    rows[#rows + 1] = {e.operation, e.kind:gsub("_", " "), e.removed_mm3, e.cut_mm, 100 * e.air_share, e.left_mm3,
                       e.rate_max_mm2, e.radial_max_mm, e.axial_max_mm, e.rapid_cut_moves, e.body_contact_moves}
  end
  return {title = "Stock after each operation", text = string.format(
    "The blank (%.0f mm³; %.0f mm³ exact) cut by every move in program order, links included, each with its tool, "
    .. "on rays %.2f mm apart along X, Y and Z (docs/lua_api/stock.md).", s.blank_mm3, s.blank_exact_mm3, s.resolution),
    table = {columns = {"operation", "kind", "removed (mm³)", "cutting path (mm)", "in air (%)", "stock left (mm³)",
                        "removal per mm, max (mm²)", "ae max (mm)", "ap max (mm)", "rapids through stock",
                        "moves with shank or holder in stock"}, rows = rows}}
end

return M
