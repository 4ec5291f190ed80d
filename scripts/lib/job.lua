-- A machining job (issue 13 item 1, issue 18 item 3): one part, a tool
-- table and an ordered list of operations, planned into one toolpath that
-- carries the operation, tool, blade and flank (or channel) of every move,
-- linked safely from one operation (or flank) to the next through a
-- clearance surface, simulated, and posted as one program per machine.
--
--   local job = require("job")
--   local j = job.new{
--     name = "blisk flanks", part = blisk, clearance_radius = 150,
--     tools = {wheel = {number = 5, length = 110, spindle_rpm = 8000, tool = wheel}},
--     operations = {job.drum_finish{tool = "wheel", blades = {1, 2}, residual = 0.014}},
--   }
--   j:run{name = "blisk", programs = {{machine = "dmg_like_ac_trunnion", post = "fanuc", file = "blisk.nc"}}}
--
-- or step by step: j:plan(), j:simulate{...}, j:post{...}.
--
-- Every option table is checked where the recipe writes it: an unknown key,
-- a wrong type or an impossible value is an error at that recipe line.
-- Nothing is emitted that was not proved: a plan with a refused pose or
-- link stops the job, and every link move is proved clear of every blade and
-- the hub (world:check_motion, the whole tool) before it joins the path.
--
-- The library, by part (scripts/lib/job/):
--   model.lua          the Job: job.new, its tools and tool life, j:plan
--   blisk_ops.lua      job.rough_channels, job.drum_finish, job.edge_finish, job.hub_finish
--   impeller_ops.lua   job.notch, job.widen, job.flank_finish, job.point_mill
--   clearance.lua      the clearance surfaces links run on
--   links.lua          the collision worlds, j:link and its proofs
--   simulate.lua       j:simulate (a blisk's units, an impeller's surfaces), the stops after it
--   seams.lua          blade 1 swept by every operation: j:simulate_seams, j:simulate_blade
--   post.lua           j:post, j:post_programs: program ends, setups, read back
--   stock.lua          the stock: a blank (job.new's `blank`) cut by every move after planning
--   report.lua         the printed summary, JSON and report.html of a run
--   run.lua            j:run: plan, simulate, post and report in one call
--   options.lua, geometry.lua   option checks; small vector helpers
local model = require("job.model")
local blisk_ops = require("job.blisk_ops")
local impeller_ops = require("job.impeller_ops")
local clearance = require("job.clearance")
local geometry = require("job.geometry")
local post = require("job.post")
local simulate = require("job.simulate")
require("job.links")
require("job.seams")
require("job.report")
require("job.run")
require("job.stock")

return {
  new = model.new, group_by_life = model.group_by_life, first_blades = model.first_blades,
  split_list = model.split_list,
  rough_channels = blisk_ops.rough_channels, drum_finish = blisk_ops.drum_finish, edge_finish = blisk_ops.edge_finish,
  hub_finish = blisk_ops.hub_finish,
  notch = impeller_ops.notch, widen = impeller_ops.widen, flank_finish = impeller_ops.flank_finish,
  point_mill = impeller_ops.point_mill,
  cylinder = clearance.cylinder, turned_moves = geometry.turned_moves, approach_length = post.approach_length,
  thinnest_blade = simulate.thinnest_blade,
}
