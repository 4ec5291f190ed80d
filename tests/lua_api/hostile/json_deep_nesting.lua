-- hostile: write_json on a table nested 200000 deep (crashed before: the
-- recursion overran the Lua stack).
-- expect-exit: 1
-- expect: json_deep_nesting\.lua:9: write_json: value(\.a){64} nests deeper than 64 tables
local t = {}
local top = t
for _ = 1, 200000 do local n = {}; t.a = n; t = n end
t.a = 1
bliskrun.write_json("deep.json", top)
