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

function P.header(self, job, out)
  out:line(self:comment(job.name))
  out:line(self:comment("machine " .. job.machine.name))
  out:line(self:comment(string.format("tool %d length %s", job.tool.number,
                                      self:number(job.tool.length, job.decimals.linear))))
  for _, note in ipairs(self:setup_notes(job)) do out:line(self:comment(note)) end
  self:emit(out, "G90 G17 G71 G40 " .. (job.feed_mode == "inverse_time" and "G93" or "G94"))
  self:emit(out, "G54")
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
