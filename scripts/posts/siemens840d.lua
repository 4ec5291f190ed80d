-- Siemens SINUMERIK 840D post. With tcp = true (the default here) the
-- program runs under TRAORI: XYZ are the tool tip in the part frame, the
-- rotary words are machine axis positions (ORIAXES interpolation), feed G94.
-- With tcp = false it writes machine axes with the machine's feed mode.
-- Block numbers N10, N20, ...; comments after ';'.
local P = extend "base"

P.name = "siemens840d"
P.tcp = true
P.block_numbers = true
P.comment_open = "; "
P.comment_close = ""

function P.program_start(self, job, out)
  out:line(self:comment(job.name))
end

function P.modal_line(self, job, out)
  self:emit(out, "G90 G17 G71 G40 " .. (job.feed_mode == "inverse_time" and "G93" or "G94"))
end

-- The settable frames: G54-G57 are offsets 1-4, G505-G599 are 5-99.
function P.work_offset_word(self, job)
  local n = job.work_offset
  return n <= 4 and "G" .. (53 + n) or "G" .. (500 + n)
end

function P.tool_change(self, job, out)
  self:emit(out, string.format("T%d D1", job.tool.number))
  self:emit(out, "M6")
  if job.tool.spindle_rpm then self:emit(out, string.format("S%d M3", job.tool.spindle_rpm)) end
end

function P.tcp_on(self, job, out)
  if job.tcp then self:emit(out, "TRAORI") end
end

function P.tcp_off(self, job, out)
  if job.tcp then self:emit(out, "TRAFOOF") end
end

function P.footer(self, job, out)
  self:emit(out, "M5")
  self:emit(out, "M30")
end

return P
