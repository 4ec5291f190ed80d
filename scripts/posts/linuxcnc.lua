-- LinuxCNC post for an A/C trunnion run with the xyzac-trt kinematics
-- module. Those kinematics make XYZ the tool tip in the part (table) frame
-- at all times, so the program is written under TCP control without a
-- switch word, rotary words are joint positions, feed per minute (G94).
-- No block numbers; comments in parentheses.
local P = extend "base"

P.name = "linuxcnc"
P.tcp = true
P.tcp_always = true

-- LinuxCNC has flood (M8) and mist (M7), both off by M9; coolant through
-- the spindle is a machine's own M code (an M1xx user command): set
-- P.coolant_codes.through on a loaded post.
P.coolant_codes = {flood = "M8", mist = "M7"}

function P.check(self, job)
  local r = job.machine.rotary
  if job.machine.configuration ~= "table-table" or r[1] ~= "A" or r[2] ~= "C" then
    error("linuxcnc: xyzac-trt kinematics need an A/C table-table machine, got " ..
          job.machine.configuration .. " " .. table.concat(r, "/"), 0)
  end
end

function P.program_start(self, job, out)
  out:line("%")
  out:line(self:comment(job.name))
end

function P.machine_line(self, job, out)
  out:line(self:comment("machine " .. job.machine.name .. ", kinematics xyzac-trt"))
end

function P.modal_line(self, job, out)
  out:line("G21 G90 G17 G40 G49 G94")
end

-- G54-G59 are offsets 1-6, G59.1-G59.3 are 7-9 (LinuxCNC has nine).
function P.work_offset_word(self, job)
  local n = job.work_offset
  if n > 9 then error(string.format("linuxcnc: work_offset %d: LinuxCNC has work offsets 1-9 (G54-G59.3)", n), 0) end
  return n <= 6 and "G" .. (53 + n) or "G59." .. (n - 6)
end

function P.tool_change(self, job, out)
  out:line(string.format("T%d M6", job.tool.number))
  out:line(string.format("G43 H%d", job.tool.number))
  if job.tool.spindle_rpm then out:line(string.format("S%d M3", job.tool.spindle_rpm)) end
end

function P.footer(self, job, out)
  out:line("G49")
  out:line("M5")
  out:line("M30")
  out:line("%")
end

return P
