-- Figures of runs bench/results.sh does not repeat (too long or too large for
-- every regeneration, or needing ../shared/data), as last measured on the
-- 2-core CI machine (quiet unless said). scripts/tools/results.lua carries
-- each into bench/RESULTS.md until a run of the same recipe with the same
-- settings replaces it. Moved here from the README on 2026-11-27 (commit
-- 418ef99); their history is in git. "Left" is material left on the design
-- surface (undercut, > 0); "overcut" the deepest cut below it (< 0).
return {
  {recipe = "blisk_drum_finish.lua", settings = "all_blades=true", measured = "before 2026-11-27",
   figures = "both flanks of all 22 blades planned on 2 threads in 18.4 s wall; the whole recipe, blade 1 "
             .. "simulated too, 27 s"},
  {recipe = "blisk_job.lua", settings = "blades=22", measured = "2026-11-28, 16b0d70 + channel roughing (issue 41)",
   figures = "from the blank: 132 plans, 743 248 moves, 131 links; the roughing's channel 1 (blade 1 suction to "
             .. "blade 2 pressure) 36 levels 0.81 mm apart, 382 passes 1.99 mm apart at most, 9 249 poses, every "
             .. "one proved, the other 21 channels its path turned; the stock it leaves, simulated: flanks "
             .. "0.492–0.516 mm, hub 0.499–0.540 mm (0.5 ± 0.05). Fanuc 2 151 663 + 1 844 345 blocks, "
             .. "Heidenhain 673 615 + 423 898, machine simulation PASS for all four; blade 1's map as without the "
             .. "roughing; verdict PASS. 8:27 wall (507 s), 473 s user, 5.3 GB peak on the 2-core machine with "
             .. "another 1-core job beside it for part of the run. The same job from a roughed part (`rough=false`) "
             .. "on the same machine the same hour: 6:23 wall, 366 s user, 4.8 GB — both far past issue 41's "
             .. "3-minute target, the machine simulation of the four programs alone 330–400 s CPU of either "
             .. "(since the 71 s below); the roughing's own share ~107 s CPU: planning and proving its channel "
             .. "~60 s, its stock sweep ~25 s, posting its 203 k moves the rest"},
  {recipe = "blisk_job.lua", settings = "blades=1 edges=false hub=false samples_u=40 samples_v=200",
   measured = "2026-11-28, 6b52e04 (from the blank of revolution)",
   figures = "the blank (disc 0.5 mm over the hub, blade ring to the casing cone and 1 mm beyond the edges) "
             .. "1 000 854 mm3 on 0.5 mm rays (Pappus 1 000 807), 3.6 MB; channels 1 and 22 roughed (36 levels, "
             .. "8 515 poses proved, 0 refused): removed 31 835 mm3, 6 % of 33 509 mm cutting path in air; the drum "
             .. "finish of blade 1 removed 1 233 mm3, 10 % in air, 6 of its rapids through 22 mm3 of stock and the "
             .. "shank or holder in the stock on 78 moves (up to 1.8 mm3) — the leads at the blade's edges, to be "
             .. "looked at; the stock cut by all 20 101 moves 6.9 s CPU. The roughing's stock by the independent "
             .. "sweep: flanks 0.492–0.516 mm, hub 0.499–0.540 mm (target 0.5 ± 0.05). 112 s CPU, 376 MB peak "
             .. "(machine simulation 16 + 17 s of it); wall not comparable (11 min on a machine shared by five "
             .. "engineers' builds and runs). With blank_top=8 (the test's): the stock cut of 8 613 moves 1.3 s "
             .. "CPU on 0.5 mm rays (2.2 MB), 0.2 s on 1 mm rays (0.6 MB; the job's default since), the figures "
             .. "within 1 %: the roughing removed 7 137 / 7 112 mm3, 4 / 5 % in air, the finish 399 / 395 mm3, 73 / "
             .. "76 % in air (the flanks over the 8 mm ring), its 4 rapids through 18.5 / 19.2 mm3"},
  {recipe = "blisk_job.lua", settings = "blades=22 rough=false", measured = "2026-11-27, 418ef99",
   figures = "110 plans, 517 374 moves, 109 links; Fanuc 1 331 008 + 1 492 124 blocks (tip within 3.1 µm "
             .. "of the plan), Heidenhain 285 955 + 231 413 blocks (0.9 µm); blade 1's map: nothing unreached, "
             .. "left ≤ 13.3 µm on the flanks (LE 12.9, TE 12.6, root strip 5.6, floor 4.8 µm), overcut "
             .. "≥ −1.68 µm; the fillet in the design's sharp corner, which the r 1.5 ball cannot enter, up to "
             .. "1.44 mm left (122 of 2565 samples more than 2 mm off), reported apart. 71 s wall, 115 s CPU, "
             .. "4.2 GB peak; posting ~20 s of it, the four programs at once (the longest, the trunnion's "
             .. "turned-over setup, 17.5 s: machine motion 8.3, post 7.2, read-back 1.6 s). With another "
             .. "1-core job beside it: 132 s wall, 169 s CPU, 4.8 GB"},
  {recipe = "impeller_job.lua", measured = "before 2026-11-27",
   figures = "all 17 blades: 119 plans, 214 435 moves (notch 28 526, widen 167 552, flank finish 15 895, "
             .. "links 2462 over 118 links); Heidenhain 214 435 / Fanuc 1 111 412 blocks, tip within 0.9 / "
             .. "3.3 µm; simulated: hub least left −1.1 µm (the sweep's resolution), measured cusp ≤ 9.9 µm "
             .. "for h = 10 µm, faces ≥ 0.30 mm left after widening; after the job the ruled cutter's own "
             .. "overcut of the design −115 / −115 / −55 / −73 µm (main plus / minus, splitter plus / minus; "
             .. "the plan's residual prediction within 2 µm), nothing from roughing or links. Planning 24 s "
             .. "CPU, simulation 57 s CPU, 80 s wall, 1.0 GB; `--set simulate=false` 44.6 s wall; posting "
             .. "Heidenhain 4.1 s, Fanuc 20.9 s (its Lua post 14.3 s for 1.1 M blocks, machine motion 5.1 s)"},
  {recipe = "hecc_impeller_job.lua", settings = "--data", measured = "before 2026-11-27",
   figures = "NASA HECC, all 15 blades: 105 plans, 223 560 poses, none refused, 224 916 moves (notch "
             .. "22 530, widen 182 625, flank finish 18 735, links 1026 over 104 links), finishers on 4 + 4 "
             .. "+ 4 + 3 blades (T2/T12/T22/T32); ruled fits 0.94 / 0.72 / 0.92 / 0.98 mm from the lofted "
             .. "faces, so roughing leaves 1.5 mm stock; hub least left −1.7 µm, faces ≥ 0.72 mm left after "
             .. "widening; after the job overcut 0.152 / 0.230 / ≥ 0.688 / 0.639 mm, all by the flank finish "
             .. "on the ruled fits (flagged: these faces need point milling), up to 1.99 mm left in the root "
             .. "corner (the r 2 ball's fillet); Heidenhain 224 916 / Fanuc 767 143 blocks, tip within 0.9 / "
             .. "2.8 µm; 72 s wall, 102 s CPU (planning 15, simulation 71, posting 19 s), 2.0 GB"},
  {recipe = "rotor67_finish.lua", settings = "--data", measured = "before 2026-11-27",
   figures = "NASA Rotor 67 blade 1 with its own extended wheel (D_t 18, R_c 50): suction flank 68 rows, "
             .. "7012 poses, none refused, left ≤ 14.05 µm, overcut 1.83 µm; pressure flank (default) 266 "
             .. "rows, 37 555 poses, left ≤ 17.3 µm, overcut 1.93 µm (chord tolerance 2 µm); about a minute"},
  {recipe = "blade_edges.lua", settings = "--data", measured = "2026-11-27, 418ef99",
   figures = "NASA Rotor 67 (R 3, a 120 mm shank): LE 70 rows against 84 side-edge rows, + 310 partial "
             .. "(13 416 poses); TE 55 against 81, + 259 partial (9459 poses); no contact and no link refused; "
             .. "overcut −1.12 / −1.08 µm on the edge, −1.16 / −0.96 µm on the flanks; left ≤ 17.0 µm (LE) / "
             .. "18.7 µm (TE), within the (−1, 20) µm band. 52 / 43 s CPU per edge, 1 min 16 s wall for both "
             .. "with the simulation, 4.8 GB peak (target 2 s per edge not met)"},
  {recipe = "blade_belt_grinding.lua", settings = "--data part=rotor67", measured = "before 2026-11-27",
   figures = "NASA Rotor 67: 113–328 paths per station and flank, programs up to 15 528 moves, 507 000 "
             .. "wheel poses checked, 12 s"},
  {recipe = "blade_repair.lua", settings = "--data part=rotor37", measured = "before 2026-11-27",
   figures = "NASA Rotor 37 tip: measured points within mean 1.57 µm, max 33 µm of the rebuilt blade; "
             .. "Gaussian curvature −0.395…0.137 rebuilt against −0.467…0.187 design; damaged region "
             .. "963 mm³, up to 11.4 mm thick; 5.6 s with `--set paths=false`; with the toolpaths 13 layers, "
             .. "16 440 poses, none refused (23 finishing contacts beside the lofted edges' ripples lifted "
             .. "off by ≤ 4.04 µm instead of refused), left ≤ 6.75 µm, overcut 1.99 / 1.79 µm (region / band); "
             .. "16.8 s wall"},
  {recipe = "bench", measured = "2026-11-28, blisk channel roughing (issue 41)",
   figures = "BM_BliskChannelLevelsProved: channel 1 of the built-in blisk roughed in levels (6 mm tapered ball end, "
             .. "0.5 mm stock, step-down 1, step-over 2, scallop 0.03, 41 stations), every pose, motion, step and "
             .. "link proved against both blades (flanks to the casing, edge rounds) and the hub, 2 threads: 36 "
             .. "levels, 9 249 poses, 0 refused, 28.3 s wall, 55.5 s CPU: 3.1 ms wall (6.0 ms CPU) per pose; 97 MB "
             .. "peak (with two other 1-core jobs on the machine: 60.7 s wall)"},
  {recipe = "bench", measured = "before 2026-11-27; CPU time unless said",
   figures = "interpolate a 100 × 500 / 200 × 1000 grid 3.6 / 14.7 ms; curvature statistics over 100 × 500 "
             .. "/ 200 × 1000 samples 24.6 / 102 ms; narrowest passage of the built-in blisk 98 ms; read and "
             .. "rebuild NASA Rotor 67 (lofted flanks with the fit of every point, hub, casing) 7.2 ms (Rotor "
             .. "37 7.9, HECC main blade 8.4 ms); FCL clear/not-clear query, drum wheel against 2 blades + "
             .. "hub (~100k triangles each) 35 µs; swept check per motion 36 µs; drum-finish one built-in "
             .. "flank, every link, lead and near-tolerance segment proved, pressure / suction 4.9 / 2.5 s "
             .. "(machine loaded ~3×); undercut simulation of the pressure plan at 200 × 1000 samples, 1 / 2 "
             .. "threads 2.9 / 1.7 s wall; drum-finish both flanks of all 22 blades, 2 threads 18.4 s wall; "
             .. "impeller: build the 17-blade model 1.05 ms, plan one main face with interference (149 poses) "
             .. "0.20 s, residual map of one face (100 × 400) 0.36 s; inverse kinematics 0.43 µs per pose; "
             .. "post + read-back of 100k moves (Fanuc, Lua post) 1.2 s; edge finish: strip width of one pose "
             .. "8.4 µs, one contact's strip sampling 1.5 ms, one row of the built-in LE (38 poses) 136 ms "
             .. "wall / 109 ms CPU, the whole built-in LE 8.7 / 4.7 s wall on 1 / 2 threads; rebuilding a "
             .. "measured blade from 30 × 2000 points 0.41 s on 2 threads, 0.60 s on 1"},
}
