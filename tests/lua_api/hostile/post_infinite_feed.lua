-- hostile: a toolpath with an infinite feed: refused where the path is
-- checked, naming the move, before anything is planned or written (it used
-- to be posted as "Finf" and caught only by the read-back).
-- expect-exit: 1
-- expect: post_infinite_feed\.lua:8: path\[2\]\.feed: expected a finite feed > 0 mm/min
-- args: --time-limit 30
local m = bliskrun.machine.load("dmg_like_ac_trunnion")
bliskrun.post.write{machine = m, post = "fanuc", file = "x.nc", tool = {number = 1, length = 80},
                    path = {{kind = "rapid", tip = {0, 0, 10}, axis = {0, 0, 1}},
                            {kind = "feed", tip = {1, 0, 1}, axis = {0, 0, 1}, feed = 1 / 0}}}
