-- hostile: core objects kept alive until the C++ heap outgrows the limit
-- (each flank grid holds ~1.2 MB of points outside the Lua heap). Before the
-- budget counted the C++ heap, --memory-limit saw only the few bytes of each
-- Lua handle and the run grew until the machine ran out.
-- expect-exit: 1
-- expect: core_heap_bomb\.lua:10: memory limit of 256 MB exceeded \(--memory-limit\)
-- args: --memory-limit 256 --time-limit 60
local blisk = bliskrun.blisk{}
local keep = {}
for i = 1, 100000 do keep[i] = blisk:flank_grid(1, "pressure") end
