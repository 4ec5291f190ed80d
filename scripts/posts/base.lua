-- The shape every post shares. A post is a table of small steps; a program
-- is written by running the steps `elements` lists, in order. A post file
-- starts from this one (`local P = extend "base"`) or from another post
-- (`extend "fanuc"`) and replaces only the steps it words differently; a
-- recipe can do the same to a loaded post before writing with it.
--
-- Each step is function(self, job, out). `job` carries what the program is
-- about (see docs/lua_api.md, post.write): job.name, job.machine (name,
-- linear = {"X","Y","Z"}, rotary = {"A","C"}, configuration, tool_length),
-- job.tool (number, length, spindle_rpm: the tool in the spindle), job.tools
-- (every tool of the program, in order), job.tcp, job.feed_mode
-- ("per_minute" | "inverse_time"), job.decimals (linear, rotary, feed) and
-- job:moves(), an iterator over the machine moves. A move has kind ("rapid" |
-- "feed"), one field per machine axis (X, Y, Z in mm; the rotary names in
-- degrees; under TCP control X, Y, Z are the tool tip in the part frame), F
-- (the feed word, feed moves only), index, row, inserted, positioning (a
-- planned rapid written as a feed move at the rapid feed), tool (index into
-- job.tools), tip and axis; `safe` on the way in from the tool change
-- position and out ("retract": Z alone, "rotate": the rotary axes alone —
-- both with TCP control off, X, Y, Z then machine axes —, "position" X and
-- Y at the safe height, "descend" and "lift" along the tool axis); `reset`
-- the rotary axes whose display is reset before the move (step
-- rotary_reset). job.controller says how the controller moves between
-- blocks ("joint-linear", "TCP, rotaries linear", "TCP, vector
-- orientation"): what the program was split and swept for.
-- `out:line(text)` appends one line. `self` is a fresh instance per program:
-- modal state lives in it, never in the post table.
local P = {}

P.name = "base"
P.tcp = false             -- write with tool-centre-point control
P.tcp_always = false      -- the controller's kinematics are always TCP (LinuxCNC trt)
P.block_numbers = false
P.block_start = 10
P.block_step = 10
P.comment_open = "("
P.comment_close = ")"
-- How TCP moves the tool axis between blocks: "axis" (the rotary axes
-- linearly) or "vector" (the great circle). What the program is split and
-- swept for: it must be what the controller does (see tcp_on).
P.orientation = "axis"
P.rotary_reset = false         -- the post has a rotary_reset step (display reset)
P.rotary_input_limit = nil     -- the controller's largest rotary value, deg

-- The motion step switches TCP control on before the first move that needs
-- it and off for the moves written in machine axes (the way in at the safe
-- height) and at the end.
function P.elements(self, job)
  return { self.header, self.tool_change, self.motion, self.footer }
end

-- Runs the post: one instance per program, then every element in order.
function P.write(post, job, out)
  local self = setmetatable({ last = {}, block = post.block_start - post.block_step }, { __index = post })
  self:check(job)
  for _, step in ipairs(self:elements(job)) do
    step(self, job, out)
  end
end

-- Refuses jobs the controller cannot run; posts add their own checks.
function P.check(self, job) end

-- ---- formatting --------------------------------------------------------

-- Fixed decimals, never "-0.000". (Called five or six times a block:
-- `fixed`, which post files get beside `extend`, is string.format's "%.3f"
-- to the byte at a fraction of its cost.)
local concat = table.concat
local fixed = fixed
function P.number(self, value, decimals)
  return fixed(value, decimals)
end

function P.word(self, address, value, decimals)
  return address .. self:number(value, decimals)
end

function P.comment(self, text)
  return self.comment_open .. text .. self.comment_close
end

-- A block, numbered when the post numbers blocks.
function P.emit(self, out, text)
  if self.block_numbers then
    self.block = self.block + self.block_step
    text = "N" .. self.block .. " " .. text
  end
  out:line(text)
end

-- The axis words of a move that differ from the last ones written (modal
-- output). A move below the output resolution still gets a block: the
-- program has one block per planned move, which read-back relies on.
function P.axis_words(self, job, move)
  local words, n, last = {}, 0, self.last
  local machine, decimals = job.machine, job.decimals
  local names, d = machine.linear, decimals.linear
  for _ = 1, 2 do  -- the linear axes, then the rotary ones
    for i = 1, #names do
      local name = names[i]
      local text = self:word(name, move[name], d)
      if last[name] ~= text then
        n = n + 1
        words[n] = text
        last[name] = text
      end
    end
    names, d = machine.rotary, decimals.rotary
  end
  if n == 0 then
    -- Nothing changed: every word again (they are the last ones written).
    for _, group in ipairs({machine.linear, machine.rotary}) do
      for i = 1, #group do words[#words + 1] = last[group[i]] end
    end
  end
  return words
end

-- The motion word when it changes (G0/G1 are modal).
function P.motion_word(self, code)
  if self.last.motion == code then return nil end
  self.last.motion = code
  return code
end

-- Per-minute F is modal; inverse-time F belongs to each block.
function P.feed_word(self, job, move)
  local text = "F" .. self:number(move.F, job.decimals.feed)
  if job.feed_mode == "inverse_time" or self.last.F ~= text then
    self.last.F = text
    return text
  end
  return nil
end

-- What the program assumes of the setup, as comment texts for the header:
-- where the work offset must be set, and how rapids are written.
function P.setup_notes(self, job)
  local o = job.machine.part_origin
  local at = string.format("X%s Y%s Z%s", self:number(o[1], 3), self:number(o[2], 3), self:number(o[3], 3))
  local notes = {}
  if job.tcp then
    notes[#notes + 1] = "work offset: the part frame origin; it lies at " .. at ..
                        " from the machine zero of the machine file with all axes at 0"
  else
    notes[#notes + 1] = "work offset: the machine zero of the machine file; the part frame origin must lie at " ..
                        at .. " from it with all axes at 0"
  end
  notes[#notes + 1] = string.format("rapids that turn a rotary axis%s are feed moves at F%d mm/min",
                                    job.machine.linear_rapids and "" or " or move more than one linear axis",
                                    math.floor(job.machine.rapid_feed + 0.5))
  notes[#notes + 1] = "the first move positions from the tool change point: start with the tool clear of the part"
  return notes
end

-- ---- steps -------------------------------------------------------------

function P.header(self, job, out) end
function P.tool_change(self, job, out) end
function P.tcp_on(self, job, out) end
function P.tcp_off(self, job, out) end
-- After tcp_off, before blocks in machine axes (the way in at the safe
-- height) in a TCP program: what the controller needs for them (Fanuc:
-- length compensation again, which G49 cancelled).
function P.machine_axes_on(self, job, out) end
function P.footer(self, job, out) end

-- Every move in order; where the tool changes (move.tool indexes
-- job.tools), the tool-centre control goes off, the next tool is called
-- (job.tool is that tool from then on). TCP control (or, without TCP, the
-- length compensation tcp_on writes) is on for every move but the way in at
-- the safe height (move.safe "retract" and "rotate"), written in machine
-- axes with it off; modal words start over wherever it changes.
function P.motion(self, job, out)
  local current = 1
  local on = false
  local function set(want)
    if want == on then return end
    if want then self:tcp_on(job, out) else self:tcp_off(job, out) end
    on = want
    self.last = {}
  end
  for move in job:moves() do
    if move.tool ~= current then
      set(false)
      current = move.tool
      job.tool = job.tools[current]
      self.last = {}  -- modal words start over after a tool change
      self:tool_change(job, out)
    end
    if move.reset then self:rotary_reset(job, move, out) end
    if move.safe == "retract" or move.safe == "rotate" then
      -- Length compensation stays on without TCP (it places the tip).
      if job.tcp and on then
        set(false)
        self:machine_axes_on(job, out)
      end
      self:safe_block(job, move, out)
    else
      set(true)
      if move.kind == "rapid" then self:rapid(job, move, out) else self:feed_move(job, move, out) end
    end
  end
  set(false)
end

-- A display reset of the rotary axes move.reset names, before the move.
function P.rotary_reset(self, job, move, out)
  error(self.name .. ": this post cannot reset a rotary axis' display (set P.rotary_reset and write the step)", 0)
end

-- The way in at the safe height: Z alone ("retract") or the rotary axes
-- alone ("rotate"), as a rapid with only those words.
function P.safe_block(self, job, move, out)
  local names = move.safe == "retract" and {job.machine.linear[3]} or job.machine.rotary
  local d = move.safe == "retract" and job.decimals.linear or job.decimals.rotary
  local words = {}
  for i, name in ipairs(names) do
    words[i] = self:word(name, move[name], d)
    self.last[name] = words[i]
  end
  self:rapid(job, move, out, words)
end

-- A block: the motion word (when it changes), then `words`. (The words'
-- own table is joined: a million blocks made a million more tables.)
local function block(self, out, code, words)
  local g = self:motion_word(code)
  local text = concat(words, " ")
  if g then text = #words > 0 and g .. " " .. text or g end
  self:emit(out, text)
end

-- `words`: the axis words to write (default: those that changed).
function P.rapid(self, job, move, out, words)
  block(self, out, "G0", words or self:axis_words(job, move))
end

function P.feed_move(self, job, move, out)
  local words = self:axis_words(job, move)
  words[#words + 1] = self:feed_word(job, move)
  block(self, out, "G1", words)
end

return P
