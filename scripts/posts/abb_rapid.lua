-- ABB RAPID for a part-in-hand belt-grinding cell (RAPID reference manual:
-- tooldata, wobjdata, loaddata, confdata, speeddata, zonedata). The contact
-- wheel is a stationary tool (tooldata robhold FALSE, tframe in the world;
-- its tload the gripper on the flange), the blade a work object held by the
-- robot (wobjdata robhold TRUE, uframe on tool0) with its mass set by
-- GripLoad. Each program is a module with one procedure named after its file
-- and no `main`: a main module (P.main_program) calls the stations' procedures.
-- Its data are PERS named after the program, so two stations never share one
-- object. It runs with ConfL / ConfJ on: MoveAbsJ to the cell's home, a
-- MoveJ to the first target, MoveL to the others, each robtarget with the
-- confdata [cf1, cf4, cf6, cfx] of its planned joints; speeddata [feed,
-- orientation speed that keeps the feed, 5000, 1000]; a zone whose corner cut
-- stays within the chord tolerance while grinding, fine at lift-offs and
-- approaches. A long program is a station procedure calling parts
-- (plan:write_program's max_bytes), each part a module of moves only.
local P = extend "robot_base"

P.name = "abb_rapid"
P.dialect = "abb_rapid"
P.comment_open = "    ! "
P.comment_close = ""
P.home_speed = "v200"

local NINES = "[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]"

function P.pose(self, m)
  local o, q = m.origin, m.quaternion
  return string.format("[[%s,%s,%s],[%s,%s,%s,%s]]", self:position(o.x), self:position(o.y), self:position(o.z),
                       self:number(q[1], self.decimals.quaternion), self:number(q[2], self.decimals.quaternion),
                       self:number(q[3], self.decimals.quaternion), self:number(q[4], self.decimals.quaternion))
end

-- The station's data names: unique per program (RAPID keeps one PERS object per name).
function P.names(self, job)
  local station = job.part and job.program:gsub("_p%d+$", "") or job.program
  return {tool = "tw_" .. station, wobj = "wb_" .. station, load = "ld_" .. station, home = "jh_" .. station,
          zone = "zg_" .. station}
end

function P.header(self, job, out)
  out:line("MODULE " .. self:program_name(job))
  out:line("  ! " .. job.name .. (job.part and " (part)" or ""))
  out:line("  ! cell " .. job.cell.name .. ", station " .. job.station.name .. " (" .. job.station.belt .. ")")
end

function P.data(self, job, out)
  if job.part then return end
  local n, p = self:names(job), job.payload
  -- loaddata [mass, cog, aom, ix, iy, iz]: kg, mm, the principal axes as a
  -- quaternion, the principal moments in kg·m² to 1e-9 (a blade's are
  -- ~1e-6); the mass at least 1 g (RAPID refuses a load without one).
  local function load(m)
    local q = m.aom
    return string.format("[%s,[%s,%s,%s],[%s,%s,%s,%s],%s,%s,%s]", self:number(math.max(m.mass, 0.001), 3),
                         self:number(m.cog.x, 3), self:number(m.cog.y, 3), self:number(m.cog.z, 3),
                         self:number(q[1], self.decimals.quaternion), self:number(q[2], self.decimals.quaternion),
                         self:number(q[3], self.decimals.quaternion), self:number(q[4], self.decimals.quaternion),
                         self:number(m.moments.x, 9), self:number(m.moments.y, 9), self:number(m.moments.z, 9))
  end
  out:line("  ! the wheel: a stationary tool (robhold FALSE, tframe in the world); tload: the gripper that holds")
  out:line("  ! the work object, in the wrist coordinate system (tool0)")
  out:line(string.format("  PERS tooldata %s := [FALSE,%s,%s];", n.tool, self:pose(job.station), load(p.gripper)))
  out:line("  ! the blade: a work object held by the robot (robhold TRUE, uframe on tool0)")
  out:line(string.format("  PERS wobjdata %s := [TRUE,TRUE,\"\",%s,[[0,0,0],[1,0,0,0]]];", n.wobj, self:pose(job.grip)))
  out:line("  ! the blade, set by GripLoad: with a stationary tool a payload's centre of gravity and axes are in")
  out:line("  ! the object frame of the work object the robot moves (the blade frame)")
  out:line(string.format("  PERS loaddata %s := %s;", n.load, load(p.blade)))
  local h = job.cell.home
  out:line(string.format("  CONST jointtarget %s := [[%s,%s,%s,%s,%s,%s],%s];", n.home, self:number(h[1], 4),
                         self:number(h[2], 4), self:number(h[3], 4), self:number(h[4], 4), self:number(h[5], 4),
                         self:number(h[6], 4), NINES))
  if job.zone > 0 then
    out:line("  ! blend radius within the chord tolerance")
    out:line(string.format("  CONST zonedata %s := [FALSE,%s,%s,%s,0.1,%s,0.1];", n.zone, self:number(job.zone, 3),
                           self:number(job.zone, 3), self:number(job.zone, 3), self:number(job.zone, 3)))
  end
end

function P.motion(self, job, out)
  local n = self:names(job)
  out:line("  PROC " .. self:program_name(job) .. "()")
  if not job.part then
    out:line("    ConfJ \\On;")
    out:line("    ConfL \\On;")
    out:line(string.format("    MoveAbsJ %s,%s,fine,tool0;", n.home, self.home_speed))
    out:line("    GripLoad " .. n.load .. ";")
  end
  for _, c in ipairs(job.calls) do out:line("    " .. c .. ";") end
  local ori = self:number(job.ori_speed, 1)
  self:each_move(job, out, function(m)
    local zone = m.link and "fine" or (job.zone > 0 and n.zone or "fine")
    out:line(string.format("    %s [%s,[%d,%d,%d,%d],%s],[%s,%s,5000,1000],%s,%s\\WObj:=%s;", m.first and "MoveJ" or "MoveL",
                           self:pose(m):sub(2, -2), m.cf1, m.cf4, m.cf6, m.cfx, NINES, self:number(m.feed, 1), ori,
                           zone, n.tool, n.wobj))
  end)
  if not job.part then out:line(string.format("    MoveAbsJ %s,%s,fine,tool0;", n.home, self.home_speed)) end
  out:line("  ENDPROC")
end

function P.footer(self, job, out)
  out:line("ENDMODULE")
end

-- The main module: PROC main calling each station's procedure in turn.
function P.main_program(self, name, calls)
  local lines = {"MODULE " .. name, "  PROC main()"}
  for _, c in ipairs(calls) do lines[#lines + 1] = "    " .. c .. ";" end
  lines[#lines + 1] = "  ENDPROC"
  lines[#lines + 1] = "ENDMODULE"
  return table.concat(lines, "\n") .. "\n"
end

return P
