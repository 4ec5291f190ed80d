-- hostile: unbounded Lua allocation, stopped by the Lua heap limit.
-- expect-exit: 1
-- expect: lua_heap_bomb\.lua:7: memory limit of 32 MB exceeded
-- args: --memory-limit 32
local t = {}
local i = 0
while true do i = i + 1; t[i] = {i} end
