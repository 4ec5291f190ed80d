-- hostile: values JSON cannot hold are named, not crashed on.
-- expect-exit: 1
-- expect: json_odd_values\.lua:7: write_json: value\.list\[2\] is not a finite number
assert(not pcall(bliskrun.write_json, "a.json", {f = print}))
assert(not pcall(bliskrun.write_json, "a.json", {c = coroutine.create(print)}))
assert(pcall(bliskrun.write_json, "a.json", {bytes = "\255\254 not utf-8"}))
bliskrun.write_json("b.json", {list = {1, 0/0}})
