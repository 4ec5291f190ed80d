-- ABB RAPID for a part-in-hand belt-grinding cell: the contact wheel is a
-- stationary tool (tooldata robhold FALSE, its frame in the world), the blade
-- a work object held by the robot (wobjdata robhold TRUE, its user frame on
-- the flange), every move a MoveL to a robtarget: the wheel's contact frame in
-- the blade frame, the quaternion, and confdata [cf1, cf4, cf6, cfx] from the
-- planned joints (cf = the quadrant of axes 1, 4, 6; cfx the branch of
-- core/machine/robot.h). Speeds are speeddata literals [tcp mm/s, ori deg/s,
-- 5000, 1000]; grinding moves use zone z1, lift-offs and approaches fine.
local P = extend "robot_base"

P.name = "abb_rapid"
P.dialect = "abb_rapid"
P.comment_open = "! "
P.comment_close = ""
P.orientation_speed = 30   -- deg/s
P.grinding_zone = "z1"

function P.pose(self, m)
  local o, q = m.origin, m.quaternion
  return string.format("[[%s,%s,%s],[%s,%s,%s,%s]]", self:position(o.x), self:position(o.y), self:position(o.z),
                       self:number(q[1], self.decimals.quaternion), self:number(q[2], self.decimals.quaternion),
                       self:number(q[3], self.decimals.quaternion), self:number(q[4], self.decimals.quaternion))
end

function P.header(self, job, out)
  out:line("MODULE " .. self:program_name(job))
  out:line("  ! " .. job.name)
  out:line("  ! cell " .. job.cell.name .. ", station " .. job.station.name .. " (" .. job.station.belt .. ")")
  out:line("  ! the wheel is a stationary TCP, the blade a work object held by the robot (robhold TRUE)")
end

function P.data(self, job, out)
  -- Stationary tool: robhold FALSE, tframe = the contact frame in the world.
  out:line(string.format("  PERS tooldata tWheel := [FALSE,%s,[1,[0,0,0],[1,0,0,0],0,0,0]];", self:pose(job.station)))
  -- Moving work object: robhold TRUE, uframe = the blade frame on the flange.
  out:line(string.format("  PERS wobjdata wBlade := [TRUE,TRUE,\"\",%s,[[0,0,0],[1,0,0,0]]];", self:pose(job.grip)))
end

function P.motion(self, job, out)
  out:line("  PROC main()")
  local path = nil
  for _, m in ipairs(job.moves) do
    if m.path ~= path then
      out:line(string.format("    ! path %d", m.path))
      path = m.path
    end
    out:line(string.format("    MoveL [%s,[%d,%d,%d,%d],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],[%s,%s,5000,1000],%s,tWheel\\WObj:=wBlade;",
                           self:pose(m):sub(2, -2), m.cf1, m.cf4, m.cf6, m.cfx, self:number(m.feed, 1),
                           self:number(self.orientation_speed, 1), m.link and "fine" or self.grinding_zone))
  end
  out:line("  ENDPROC")
end

function P.footer(self, job, out)
  out:line("ENDMODULE")
end

return P
