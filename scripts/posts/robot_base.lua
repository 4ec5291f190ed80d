-- What the robot posts share (abb_rapid.lua, kuka_krl.lua): a part-in-hand
-- belt-grinding program where the wheel is a fixed TCP and the blade a work
-- object on the flange, so every target is the station's contact frame in
-- the blade frame (core/machine/robot_program.h). A robot post is written
-- like a CNC post — small steps run in order — from a job:
--   job.name (a title), job.program (the program's name = its file's name),
--   job.part (true: a part called by job.program's station program, moves
--   only), job.calls (the parts a station program calls instead of moves),
--   job.cell = {name, home (deg)}, job.station = {name, belt, speed, origin,
--   quaternion = {w, x, y, z}, a, b, c}, job.grip (the blade in the flange
--   frame, same fields), job.ori_speed (deg/s: every grinding move keeps its
--   feed), job.zone (blend radius, mm, within the chord tolerance; 0 exact),
--   job.payload = the whole load on the flange {mass (kg), cog (mm), aom
--   (principal axes, quaternion {w, x, y, z}), a, b, c (the same axes as
--   Z-Y-X deg), moments (principal, kg·m²), gripper = {same fields, flange
--   frame}, blade = {same fields, blade frame}}, job.moves = {{origin, quaternion, a, b, c, cf1,
--   cf4, cf6, cfx, s, t, link, first, path, feed (mm/s), joints (deg)}, ...}.
-- `dialect` tells plan:write_program which reader replays the program before
-- it is written; a post that changes the syntax must keep it readable.
local P = extend "base"

P.name = "robot_base"
P.dialect = nil
P.decimals = { position = 4, quaternion = 9, angle = 6 }

function P.elements(self, job)
  return { self.header, self.data, self.motion, self.footer }
end

function P.program_name(self, job)
  return job.program
end

function P.position(self, v)
  return self:number(v, self.decimals.position)
end

-- The moves grouped by path, with a comment at each path's start.
function P.each_move(self, job, out, fn)
  local path = nil
  for _, m in ipairs(job.moves) do
    if m.path ~= path then
      out:line(string.format("%spath %d%s", self.comment_open, m.path, self.comment_close))
      path = m.path
    end
    fn(m)
  end
end

return P
