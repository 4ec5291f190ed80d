-- What the robot posts share (abb_rapid.lua, kuka_krl.lua): a part-in-hand
-- belt-grinding program where the wheel is a fixed TCP and the blade a work
-- object on the flange, so every target is the station's contact frame in
-- the blade frame (core/machine/robot_program.h). A robot post is written
-- like a CNC post — small steps run in order — from a job:
--   job.name, job.cell = {name, home}, job.station = {name, belt, speed,
--   origin, quaternion = {w, x, y, z}, a, b, c}, job.grip (the blade in the
--   flange frame, same fields), job.moves = {{origin, quaternion, a, b, c,
--   cf1, cf4, cf6, cfx, s, t, link, path, feed (mm/s), joints (deg)}, ...}.
-- `dialect` tells plan:write_program which reader replays the program before
-- it is written; a post that changes the syntax must keep it readable.
local P = extend "base"

P.name = "robot_base"
P.dialect = nil
P.decimals = { position = 4, quaternion = 9, angle = 6 }

function P.elements(self, job)
  return { self.header, self.data, self.motion, self.footer }
end

-- A program name the controllers accept: letters, digits, underscores.
function P.program_name(self, job)
  local name = job.name:gsub("[^%w_]", "_")
  if not name:match("^%a") then name = "P_" .. name end
  return name:sub(1, 24)
end

function P.position(self, v)
  return self:number(v, self.decimals.position)
end

return P
