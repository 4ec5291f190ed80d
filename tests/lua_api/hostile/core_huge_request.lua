-- hostile: one core request far beyond the limit (400 million curvature
-- samples, ~16 GB): refused at its recipe line the moment the allocation is
-- asked for, instead of taking the machine's memory.
-- expect-exit: 1
-- expect: core_huge_request\.lua:8: memory limit of 128 MB exceeded \(--memory-limit\)
-- args: --memory-limit 128 --time-limit 60
local flank = bliskrun.blisk{}:flank(1, "pressure")
bliskrun.curvature_stats(flank, {samples_u = 20000, samples_v = 20000})
