-- Heidenhain TNC (conversational) post: FUNCTION TCPM, so XYZ are the tool
-- tip in the part frame and the rotary words machine axis positions; linear
-- L blocks, FMAX for rapids, feed in mm/min. Numbers carry their sign
-- (X+10.000). Block numbers from 0 in steps of 1, as the TNC numbers them.
-- Older controls use M128 instead of FUNCTION TCPM: override tcp_on/tcp_off.
local P = extend "base"

P.name = "heidenhain"
P.tcp = true
P.block_numbers = true
P.block_start = 0
P.block_step = 1
P.comment_open = "; "
P.comment_close = ""
-- PATHCTRL AXIS: the rotary axes move linearly between blocks; every block
-- is split until the whole tool stays within tolerance of the proved motion
-- under that interpolation (P.orientation = "axis"). A post that writes
-- PATHCTRL VECTOR says P.orientation = "vector".
P.tcp_function = "FUNCTION TCPM F TCP AXIS POS PATHCTRL AXIS"
P.orientation = "axis"
-- The TNC takes rotary values up to +-99 999.9999 deg; M94 reduces a
-- continuous axis' display to [0, 360) deg without motion, written at links
-- where the axis has wound past a turn.
P.rotary_input_limit = 99999.9999
P.resets_rotary_display = true

function P.rotary_reset(self, job, move, out)
  for _, name in ipairs(move.reset) do
    self:emit(out, "M94 " .. name)
    self.last[name] = nil  -- the next block writes the axis again
  end
end

-- The TNC has no inverse-time feed; without TCPM a per-minute feed on a
-- rotary move is not the tip's speed. So TCPM only.
function P.check(self, job)
  if not job.tcp then error("heidenhain: this post writes TCPM programs only (tcp = true)", 0) end
end

function P.emit(self, out, text)
  self.block = self.block + self.block_step
  out:line(self.block .. " " .. text)
end

function P.word(self, address, value, decimals)
  local text = self:number(value, decimals)
  if text:sub(1, 1) ~= "-" then text = "+" .. text end
  return address .. text
end

-- The program's name, or its number when post.write gives program_number
-- (the TNC calls programs by name; a number is a name too).
P.writes_program_number = true
local function pgm_name(job)
  if job.program_number then return tostring(job.program_number) end
  return (job.name:upper():gsub("[^%w_]", "_"))
end

function P.program_start(self, job, out)
  self:emit(out, "BEGIN PGM " .. pgm_name(job) .. " MM")
end

-- Every line of a TNC program is a numbered block, comments too.
function P.comment_line(self, out, text)
  self:emit(out, self:comment(text))
end

-- The TNC has no G54: cycle 247 activates a row of the preset table (its
-- parameter continues the block on the next line, as the TNC writes it).
function P.work_offset_word(self, job)
  return "preset " .. job.work_offset
end

function P.work_offset(self, job, out)
  self:emit(out, "CYCL DEF 247 DATUM SETTING ~")
  out:line(string.format("    Q339=+%d    ;DATUM NUMBER", job.work_offset))
end

function P.tool_change(self, job, out)
  local call = string.format("TOOL CALL %d Z", job.tool.number)
  if job.tool.spindle_rpm then call = call .. string.format(" S%d", job.tool.spindle_rpm) end
  self:emit(out, call)
  self:emit(out, "M3")
end

function P.tcp_on(self, job, out) self:emit(out, self.tcp_function) end
function P.tcp_off(self, job, out) self:emit(out, "FUNCTION RESET TCPM") end

function P.rapid(self, job, move, out, words)
  words = words or self:axis_words(job, move)
  self.last.F = nil  -- FMAX holds for its block only: repeat F on the next feed block
  self:emit(out, "L " .. table.concat(words, " ") .. " R0 FMAX")
end

function P.feed_move(self, job, move, out)
  local parts = self:axis_words(job, move)
  parts[#parts + 1] = self:feed_word(job, move)
  self:emit(out, "L " .. table.concat(parts, " "))
end

function P.footer(self, job, out)
  self:emit(out, "M5")
  self:emit(out, "M30")
  self:emit(out, "END PGM " .. pgm_name(job) .. " MM")
end

return P
