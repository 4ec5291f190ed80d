-- ISO / Fanuc (30i-class) 5-axis post. Two modes:
--   machine axes (default): XYZ are machine positions computed by bliskrun's
--     kinematics, length compensation G43 (when the machine's XYZ denote the
--     tip), feed per the machine (G93 inverse time or G94);
--   TCP (tcp = true): G43.4 tool centre point control, XYZ are the tool tip
--     in the part frame, rotary words are machine positions, feed G94.
-- Block numbers N10, N20, ...; comments in parentheses, upper case.
local P = extend "base"

P.name = "fanuc"
P.block_numbers = true
-- G43.4 (TCP type 1) moves the rotary axes linearly between blocks.
P.orientation = "axis"
P.rotary_input_limit = 99999.999
P.program_number = 1000  -- the O-number unless post.write's program_number says another
P.writes_program_number = true

-- Fanuc comments cannot hold parentheses and are read upper case.
function P.comment(self, text)
  return "(" .. text:upper():gsub("[()]", "") .. ")"
end

function P.program_start(self, job, out)
  out:line("%")
  out:line(string.format("O%04d %s", job.program_number or self.program_number, self:comment(job.name)))
end

-- O-numbers run from 1 to 9999.
function P.check(self, job)
  local n = job.program_number
  if n and n > 9999 then error(string.format("fanuc: program_number %d: O-numbers are 1-9999", n), 0) end
end

-- G54-G59 are offsets 1-6; 7 on are the additional work offsets G54.1 P1,
-- P2, ... (48 standard, 300 with the option).
function P.work_offset_word(self, job)
  local n = job.work_offset
  return n <= 6 and "G" .. (53 + n) or "G54.1 P" .. (n - 6)
end

function P.modal_line(self, job, out)
  self:emit(out, "G90 G17 G21 G40 G49 G80 " .. (job.feed_mode == "inverse_time" and "G93" or "G94"))
end

function P.tool_change(self, job, out)
  self:emit(out, string.format("T%d M6", job.tool.number))
  if job.tool.spindle_rpm then self:emit(out, string.format("S%d M3", job.tool.spindle_rpm)) end
end

function P.tcp_on(self, job, out)
  if job.tcp then
    self:emit(out, string.format("G43.4 H%d", job.tool.number))
  elseif job.machine.tool_length == "tip" then
    self:emit(out, string.format("G43 H%d", job.tool.number))
  end
end

function P.tcp_off(self, job, out)
  if job.tcp or job.machine.tool_length == "tip" then self:emit(out, "G49") end
end

-- Under TCP, G49 also cancels the length compensation that the way in at
-- the safe height (machine axes, tip words) needs: it comes back as G43.
function P.machine_axes_on(self, job, out)
  if job.machine.tool_length == "tip" then self:emit(out, string.format("G43 H%d", job.tool.number)) end
end

function P.footer(self, job, out)
  self:emit(out, "M5")
  self:emit(out, "M30")
  out:line("%")
end

return P
