-- hostile: write_json on a table that contains itself (crashed before).
-- expect-exit: 1
-- expect: json_self_cycle\.lua:7: write_json: value\.inner\.back is value again \(a cycle\)
local t = {name = "loop"}
t.inner = {}
t.inner.back = t
bliskrun.write_json("cycle.json", t)
