-- KUKA KRL (KSS 8.x) for a part-in-hand belt-grinding cell. External TCP:
-- with $IPO_MODE = #TCP the fixed tool — the contact wheel — is BASE data
-- relative to WORLD and the robot-guided workpiece — the blade — TOOL data
-- relative to FLANGE (the practitioners' and KSS inline forms' reading; KUKA's
-- own text on it was not reachable: docs/lua_api/robots.md); a position is
-- the wheel's contact frame in the blade frame, A, B, C its Z-Y-X angles
-- (deg). S and T are computed from the
-- planned joints by KUKA's definition (core/machine/robot_program.h): they
-- choose the solution of the first move, a PTP; the LINs after it keep that
-- configuration. The program starts like KUKA's template (the INI fold with
-- BAS #INITMOV), goes PTP to the cell's home axis position, sets the frames,
-- load, speeds and blending, grinds, restores $IPO_MODE = #BASE and goes
-- home. DEF names the file. A long program is a station program calling its
-- parts (plan:write_program's max_bytes); a part sets nothing but moves.
local P = extend "robot_base"

P.name = "kuka_krl"
P.dialect = "kuka_krl"
P.comment_open = "; "
P.comment_close = ""
P.acc_cp = 2.0       -- $ACC.CP, m/s²: well inside a KR QUANTEC's path acceleration
P.acc_ori = 100      -- $ACC.ORI1/ORI2, deg/s²

function P.frame(self, m)
  return string.format("{X %s,Y %s,Z %s,A %s,B %s,C %s}", self:position(m.origin.x), self:position(m.origin.y),
                       self:position(m.origin.z), self:number(m.a, self.decimals.angle),
                       self:number(m.b, self.decimals.angle), self:number(m.c, self.decimals.angle))
end

function P.axes(self, q)
  return string.format("{A1 %s,A2 %s,A3 %s,A4 %s,A5 %s,A6 %s}", self:number(q[1], 4), self:number(q[2], 4),
                       self:number(q[3], 4), self:number(q[4], 4), self:number(q[5], 4), self:number(q[6], 4))
end

function P.header(self, job, out)
  out:line("&ACCESS RVP")
  out:line("&REL 1")
  out:line("DEF " .. self:program_name(job) .. "( )")
  out:line("; " .. job.name .. (job.part and " (part)" or ""))
  out:line("; cell " .. job.cell.name .. ", station " .. job.station.name .. " (" .. job.station.belt .. ")")
  if job.part then return end
  out:line(";FOLD INI")
  out:line("  ;FOLD BASISTECH INI")
  out:line("    GLOBAL INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM ( )")
  out:line("    INTERRUPT ON 3")
  out:line("    BAS (#INITMOV,0 )")
  out:line("  ;ENDFOLD (BASISTECH INI)")
  out:line(";ENDFOLD (INI)")
end

function P.data(self, job, out)
  if job.part then return end
  out:line("; home: a known axis position before any Cartesian target")
  out:line("PTP " .. self:axes(job.cell.home))
  out:line("; external TCP: the wheel is BASE data (in WORLD), the blade TOOL data (on FLANGE)")
  out:line("$BASE = " .. self:frame(job.station))
  out:line("$TOOL = " .. self:frame(job.grip))
  -- $LOAD: the whole load on the flange — gripper and blade — its centre of
  -- gravity and principal axes in FLANGE (mm, Z-Y-X deg) and its principal
  -- moments (kg·m²), as KUKA's load data describe a payload.
  local p = job.payload
  out:line(string.format("; load: gripper %s kg + blade %s kg", self:number(p.gripper.mass, 3), self:number(p.blade.mass, 3)))
  out:line(string.format("$LOAD = {M %s,CM {X %s,Y %s,Z %s,A %s,B %s,C %s},J {X %s,Y %s,Z %s}}", self:number(p.mass, 3),
                         self:number(p.cog.x, 3), self:number(p.cog.y, 3), self:number(p.cog.z, 3),
                         self:number(p.a, 4), self:number(p.b, 4), self:number(p.c, 4), self:number(p.moments.x, 7),
                         self:number(p.moments.y, 7), self:number(p.moments.z, 7)))
  out:line("$IPO_MODE = #TCP")
  out:line("$ORI_TYPE = #VAR")
  out:line("$ACC.CP = " .. self:number(self.acc_cp, 2))
  out:line("$ACC.ORI1 = " .. self:number(self.acc_ori, 1))
  out:line("$ACC.ORI2 = " .. self:number(self.acc_ori, 1))
  out:line("; the orientation speed that lets every grinding move keep its feed")
  out:line("$VEL.ORI1 = " .. self:number(job.ori_speed, 1))
  out:line("$VEL.ORI2 = " .. self:number(job.ori_speed, 1))
  out:line("; blending within the chord tolerance")
  out:line("$APO.CDIS = " .. self:number(job.zone, 3))
end

function P.motion(self, job, out)
  for _, c in ipairs(job.calls) do out:line(c .. "()") end
  local speed = nil
  self:each_move(job, out, function(m)
    if m.feed ~= speed then
      out:line("$VEL.CP = " .. self:number(m.feed / 1000, 5))
      speed = m.feed
    end
    local f = self:frame(m):sub(2, -2)
    if m.first then
      -- The first Cartesian target: a PTP, whose S and T choose the arm's configuration.
      out:line(string.format("PTP {E6POS: %s,S %d,T %d}", f, m.s, m.t))
    else
      local blend = (not m.link and job.zone > 0) and " C_DIS" or ""
      out:line(string.format("LIN {E6POS: %s,S %d,T %d}%s", f, m.s, m.t, blend))
    end
  end)
end

function P.footer(self, job, out)
  if not job.part then
    out:line("$IPO_MODE = #BASE")
    out:line("PTP " .. self:axes(job.cell.home))
  end
  out:line("END")
end

-- The main program: the INI fold, then each station's program in turn.
function P.main_program(self, name, calls)
  local lines = {"&ACCESS RVP", "&REL 1", "DEF " .. name .. "( )", ";FOLD INI", "  ;FOLD BASISTECH INI",
                 "    GLOBAL INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM ( )", "    INTERRUPT ON 3",
                 "    BAS (#INITMOV,0 )", "  ;ENDFOLD (BASISTECH INI)", ";ENDFOLD (INI)"}
  for _, c in ipairs(calls) do lines[#lines + 1] = c .. "()" end
  lines[#lines + 1] = "END"
  return table.concat(lines, "\n") .. "\n"
end

return P
