-- hostile: a pathological pattern keeps Lua inside string.find (C code, no
-- count hook) far past the time limit; the watchdog's hard stop ends it and
-- names the last recipe line the count hook saw (the loop runs it here).
-- expect-exit: 1
-- expect: string_find_backtracking\.lua:8: time limit of 1 s exceeded \(--time-limit\) \(stopped by the watchdog
-- args: --time-limit 1
local s = string.rep("a", 60)
for _ = 1, 30000 do end; string.find(s, string.rep("a?", 60) .. string.rep("a", 60) .. "b")
