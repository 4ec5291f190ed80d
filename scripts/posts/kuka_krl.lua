-- KUKA KRL for a part-in-hand belt-grinding cell: external TCP mode
-- ($IPO_MODE = #TCP) with $TOOL the contact wheel's frame in the world and
-- $BASE the blade on the flange; every move a LIN to an E6POS: the wheel's
-- contact frame in the blade frame, A, B, C its Z-Y-X angles in degrees, S
-- the configuration (bit 0 wrist centre behind axis 1, bit 1 elbow, bit 2
-- axis 5 negative: the branch of core/machine/robot.h) and T the turn (bit i
-- set when axis i+1 is negative). Speeds in $VEL.CP (m/s); C_DIS while
-- grinding, exact stops at lift-offs and approaches.
local P = extend "robot_base"

P.name = "kuka_krl"
P.dialect = "kuka_krl"
P.comment_open = "; "
P.comment_close = ""

function P.frame(self, m)
  return string.format("{X %s,Y %s,Z %s,A %s,B %s,C %s}", self:position(m.origin.x), self:position(m.origin.y),
                       self:position(m.origin.z), self:number(m.a, self.decimals.angle),
                       self:number(m.b, self.decimals.angle), self:number(m.c, self.decimals.angle))
end

function P.header(self, job, out)
  out:line("DEF " .. self:program_name(job) .. "()")
  out:line("; " .. job.name)
  out:line("; cell " .. job.cell.name .. ", station " .. job.station.name .. " (" .. job.station.belt .. ")")
  out:line("; external TCP: the wheel is $TOOL (in the world), the blade $BASE (on the flange)")
end

function P.data(self, job, out)
  out:line("$IPO_MODE = #TCP")
  out:line("$TOOL = " .. self:frame(job.station))
  out:line("$BASE = " .. self:frame(job.grip))
end

function P.motion(self, job, out)
  local speed, path = nil, nil
  for _, m in ipairs(job.moves) do
    if m.path ~= path then
      out:line(string.format("; path %d", m.path))
      path = m.path
    end
    if m.feed ~= speed then
      out:line("$VEL.CP = " .. self:number(m.feed / 1000, 5))
      speed = m.feed
    end
    local f = self:frame(m)
    out:line(string.format("LIN {E6POS: %s, S %d, T %d}%s", f:sub(2, -2), m.s, m.t, m.link and "" or " C_DIS"))
  end
end

function P.footer(self, job, out)
  out:line("END")
end

return P
