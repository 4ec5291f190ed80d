-- hostile: a tessellation at a tolerance far below the part's size: refused
-- before allocating, with the estimate (it ran on past both limits before).
-- expect-exit: 1
-- expect: tessellate_absurd_tolerance\.lua:8: tessellate: a \d+ x \d+ grid mesh for .* needs an estimated [0-9.]+ MB, more than the memory limit of 64 MB
-- args: --memory-limit 64 --time-limit 30
local surface = bliskrun.surface_of_revolution{meridian = {{0, 100}, {20, 110}, {40, 130}, {60, 160}}}
local mesh = surface:tessellate(1)
surface:tessellate(1e-9)
