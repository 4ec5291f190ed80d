-- hostile: an endless Lua loop, stopped by the count hook at its line.
-- expect-exit: 1
-- expect: endless_loop\.lua:6: time limit of 0\.5 s exceeded
-- args: --time-limit 0.5
local i = 0
while true do i = i + 1 end
