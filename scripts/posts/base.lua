-- The shape every post shares. A post is a table of small steps; a program
-- is written by running the steps `elements` lists, in order. A post file
-- starts from this one (`local P = extend "base"`) or from another post
-- (`extend "fanuc"`) and replaces only the steps it words differently; a
-- recipe can do the same to a loaded post before writing with it.
--
-- Each step is function(self, job, out). `job` carries what the program is
-- about (see docs/lua_api.md, post.write): job.name, job.machine (name,
-- linear = {"X","Y","Z"}, rotary = {"A","C"}, configuration, tool_length,
-- rotary_axes = {{name=, carrier = "part"|"tool", iso841 = bool}, ...}),
-- job.tool (number, length, spindle_rpm: the tool in the spindle), job.tools
-- (every tool of the program, in order), job.work_offset (1, 2, ...: G54,
-- G55, ... / the TNC's preset), job.coolant ("flood" | "mist" | "through" |
-- "off"; nil: no coolant words), job.program_number (nil: the post's
-- default), job.setup (name or nil, flip, clocking_deg),
-- job.notes (lines for the header), job.tcp, job.feed_mode
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
P.resets_rotary_display = false  -- the post writes a display reset (its step rotary_reset)
P.rotary_input_limit = nil     -- the controller's largest rotary value, deg

-- The motion step switches TCP control on before the first move that needs
-- it and off for the moves written in machine axes (the way in at the safe
-- height) and at the end.
function P.elements(self, job)
  return { self.header, self.tool_change, self.coolant_on, self.motion, self.coolant_off, self.footer }
end

-- The header is steps too: what a setter must know before pressing start
-- (the verdict, the machine, the setup, the rotary senses, every tool, what
-- the program assumes, the recipe's notes), then the blocks that put the
-- controller in a known state and select the work offset.
function P.header_elements(self, job)
  return { self.program_start, self.program_number_line, self.verdict_line, self.machine_line, self.setup_lines, self.rotary_senses,
           self.tool_lines, self.assumption_lines, self.note_lines, self.modal_line, self.work_offset }
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

-- A comment around `text`. Where comments close with ")", a parenthesis
-- inside would end it early; a trailing "~" would continue the block on
-- the next line (Heidenhain): both go.
function P.comment(self, text)
  text = text:gsub("%s*~+%s*$", "")
  if self.comment_close == ")" then text = text:gsub("[()]", "") end
  return self.comment_open .. text .. self.comment_close
end

-- A header comment on a line of its own (a numbered block where every line
-- must be one: Heidenhain).
function P.comment_line(self, out, text)
  out:line(self:comment(text))
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

-- The block that selects job.work_offset, and how the header names it:
-- ISO G54-G59 for 1-6 (posts with more offsets override).
function P.work_offset_word(self, job)
  local n = job.work_offset
  if n > 6 then
    error(string.format("%s: work_offset %d: this post selects G54-G59 (work offsets 1-6)", self.name, n), 0)
  end
  return "G" .. (53 + n)
end

-- What the program assumes of the setup, as comment texts for the header:
-- where the work offset must be set, and how rapids are written.
function P.setup_notes(self, job)
  local o = job.machine.part_origin
  local at = string.format("X%s Y%s Z%s", self:number(o[1], 3), self:number(o[2], 3), self:number(o[3], 3))
  local offset = "work offset " .. self:work_offset_word(job)
  local notes = {}
  if job.tcp then
    notes[#notes + 1] = offset .. ": the part frame origin; it lies at " .. at ..
                        " from the machine zero of the machine file with all axes at 0"
  else
    notes[#notes + 1] = offset .. ": the machine zero of the machine file; the part frame origin must lie at " ..
                        at .. " from it with all axes at 0"
  end
  notes[#notes + 1] = string.format("rapids that turn a rotary axis%s are feed moves at F%d mm/min",
                                    job.machine.linear_rapids and "" or " or move more than one linear axis",
                                    math.floor(job.machine.rapid_feed + 0.5))
  if job.approach then
    notes[#notes + 1] = string.format("each tool comes in from the safe height Z%s: Z alone, then the rotary axes, "
                                      .. "then X and Y, then Z down; each tool leaves up Z to it",
                                      self:number(job.approach.safe_z, 3))
  else
    notes[#notes + 1] = "the first move positions from the tool change point: start with the tool clear of the part"
  end
  notes[#notes + 1] = "between blocks the controller moves " .. job.controller ..
                      ": the program was split and swept for that"
  return notes
end

-- ---- steps -------------------------------------------------------------

function P.header(self, job, out)
  for _, step in ipairs(self:header_elements(job)) do step(self, job, out) end
end

-- The program's first lines (tape start, program number or name): per post.
function P.program_start(self, job, out) end

-- The verdict of the program's proof. The post cannot know it: the job's
-- sweep of the written program replaces the token after proving it.
P.verdict_text = "VERDICT: @VERDICT@"
function P.verdict_line(self, job, out)
  self:comment_line(out, self.verdict_text)
end

function P.machine_line(self, job, out)
  self:comment_line(out, "machine " .. job.machine.name)
end

-- Which setup, and how the part sits in it. The program's X, Y, Z are in the
-- part frame; the model was turned into it as the job's setup says (turned
-- over: 180 deg about X; then clocked about Z), so the setter mounts the
-- part that way.
function P.setup_lines(self, job, out)
  local s = job.setup
  if s.name then self:comment_line(out, "setup: " .. s.name) end
  if s.flip then
    self:comment_line(out, "part turned over: 180 deg about X, model +Z along part frame -Z")
  else
    self:comment_line(out, "part not turned over: model +Z along part frame +Z")
  end
  local clocking = self:number(s.clocking_deg, 3)
  if s.clocking_deg == 0 then
    self:comment_line(out, "clocking 0.000 deg: model +X along part frame +X")
  else
    self:comment_line(out, "clocking " .. clocking .. " deg: model turned " .. clocking .. " deg about part frame +Z" ..
                           (s.flip and " after turning over" or ""))
  end
end

-- ISO 841: a positive A, B, C turns the tool relative to the part
-- right-handed about +X, +Y, +Z. A table that turns the part right-handed
-- turns the tool relative to it left-handed, so a table's sense is said as
-- both: what the setter sees the table do, and what that is against ISO 841.
local iso_axis = {A = "+X", B = "+Y", C = "+Z"}
function P.rotary_senses(self, job, out)
  for _, a in ipairs(job.machine.rotary_axes) do
    local about = iso_axis[a.name] or "its direction"
    local iso = a.iso841 and "as ISO 841" or "against ISO 841"
    if a.carrier == "part" then
      local part = a.iso841 and "left" or "right"
      local tool = a.iso841 and "right" or "left"
      self:comment_line(out, string.format("rotary %s table: %s+ turns the part %s-handed about %s, the tool relative "
                                           .. "to the part %s-handed: %s", a.name, a.name, part, about, tool, iso))
    else
      self:comment_line(out, string.format("rotary %s head: %s+ turns the tool %s-handed about %s: %s", a.name,
                                           a.name, a.iso841 and "right" or "left", about, iso))
    end
  end
end

-- Every tool of the program, in the order they are called.
function P.tool_lines(self, job, out)
  for _, t in ipairs(job.tools) do
    local text = string.format("tool %d length %s", t.number, self:number(t.length, job.decimals.linear))
    if t.spindle_rpm then text = text .. string.format(" S%d", t.spindle_rpm) end
    self:comment_line(out, text)
  end
end

function P.assumption_lines(self, job, out)
  for _, note in ipairs(self:setup_notes(job)) do self:comment_line(out, note) end
end

-- The recipe's own notes (post.write's `notes`), one comment each.
function P.note_lines(self, job, out)
  for _, note in ipairs(job.notes) do self:comment_line(out, note) end
end

-- job.program_number on a controller whose programs carry none (their
-- file name is the number): a header line. A post that writes it in the
-- program's own words (Fanuc's O-number, the TNC's PGM name) sets
-- P.writes_program_number and leaves this out.
P.writes_program_number = false
function P.program_number_line(self, job, out)
  if job.program_number and not self.writes_program_number then
    self:comment_line(out, "program number " .. job.program_number)
  end
end

-- Coolant (job.coolant): its code after every tool change (the spindle
-- is running) and the off code after the last move, before the footer
-- stops the spindle. Codes differ between machine builders, through-spindle
-- coolant most: a post (or a recipe, on a loaded post) replaces these
-- tables; a coolant with no code here is refused, naming the ones there are.
P.coolant_codes = {flood = "M8", mist = "M7", through = "M88"}
P.coolant_off_codes = {flood = "M9", mist = "M9", through = "M89", off = "M9"}

function P.coolant_code(self, job)
  local c = job.coolant
  if c == nil then return nil end
  local code = c == "off" and self.coolant_off_codes.off or self.coolant_codes[c]
  if not code then
    local have = {}
    for name, word in pairs(self.coolant_codes) do have[#have + 1] = name .. " (" .. word .. ")" end
    table.sort(have)
    error(string.format("%s: coolant '%s': this post has no code for it; it has %s", self.name, c,
                        #have > 0 and table.concat(have, ", ") or "none"), 0)
  end
  return code
end

function P.coolant_on(self, job, out)
  local code = self:coolant_code(job)
  if code then self:emit(out, code) end
end

function P.coolant_off(self, job, out)
  if job.coolant and job.coolant ~= "off" then self:emit(out, self.coolant_off_codes[job.coolant] or "M9") end
end

-- Modal words that put the controller in a known state: per post.
function P.modal_line(self, job, out) end

function P.work_offset(self, job, out)
  self:emit(out, self:work_offset_word(job))
end

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
      self:coolant_on(job, out)
    end
    if move.reset then self:rotary_reset(job, move, out) end
    if move.safe == "retract" or move.safe == "rotate" then
      -- Machine axes: under TCP with its control off (and what the
      -- controller needs for tip words then); without TCP with the length
      -- compensation tcp_on writes, which places the tip.
      if job.tcp then
        if on then
          set(false)
          self:machine_axes_on(job, out)
        end
      else
        set(true)
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
  error(self.name .. ": this post cannot reset a rotary axis' display (set P.resets_rotary_display and write the step rotary_reset)", 0)
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
