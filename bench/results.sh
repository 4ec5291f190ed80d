#!/usr/bin/env bash
# Regenerates bench/RESULTS.md, the one place measured figures live:
# runs the recipes below with the Release build in build/, times each with
# /usr/bin/time, records the machine, then has scripts/tools/results.lua
# turn the recipes' JSON reports into the page.
#
#   bench/results.sh [--data ../shared/data] [--bench] [--threads N] [--runs DIR]
#
#   --data DIR   also run the cheap recipes on real part data
#   --bench      also run build/bench/bliskrun_bench (built if missing)
#   --runs DIR   where the runs' out folders go (default build/results)
#   --resume     keep the runs already finished in DIR (after an interrupted run)
# The built-in part's recipes take a few minutes on the 2-core machine.
set -euo pipefail
cd "$(dirname "$0")/.."

data=""
bench=0
resume=0
threads=2
runs=build/results
while [ $# -gt 0 ]; do
  case "$1" in
    --data) data="$(cd "$2" && pwd)"; shift 2 ;;
    --bench) bench=1; shift ;;
    --threads) threads="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --resume) resume=1; shift ;;
    *) echo "bench/results.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
done
[ -x build/bliskrun ] || { echo "bench/results.sh: build/bliskrun not found; build first (README)" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "bench/results.sh: needs GNU time (/usr/bin/time; apt-get install time)" >&2; exit 2; }
[ "$resume" = 1 ] || rm -rf "$runs"
mkdir -p "$runs"
runs="$(cd "$runs" && pwd)"

json_string() { printf '"%s"' "$(printf '%s' "$1" | sed 's/\\/\\\\/g; s/"/\\"/g')"; }

entries=()
# run NAME RECIPE [--set k=v]...: one recipe into $runs/NAME.
run() {
  local name="$1" recipe="$2"; shift 2
  local settings="" a skip=0
  for a in "$@"; do
    if [ "$skip" = 1 ]; then skip=0; continue; fi
    case "$a" in --set) ;; --data) skip=1; settings="${settings:+$settings }--data" ;; *) settings="${settings:+$settings }$a" ;; esac
  done
  local code=0
  if [ "$resume" = 1 ] && [ -f "$runs/$name.code" ]; then
    code="$(cat "$runs/$name.code")"
    echo "== $recipe $settings (kept: --resume)" >&2
  else
    echo "== $recipe $settings" >&2
    rm -rf "${runs:?}/$name"
    /usr/bin/time -o "$runs/$name.time" -f "%e %U %S %M" \
      build/bliskrun "scripts/recipes/$recipe" --out "$runs/$name" --threads "$threads" --quiet "$@" \
      > "$runs/$name.log" 2>&1 || code=$?
    echo "$code" > "$runs/$name.code"
  fi
  # GNU time appends "Command exited with non-zero status N" before its line on failure.
  read -r wall user sys rss < <(tail -n 1 "$runs/$name.time")
  entries+=("{\"recipe\": $(json_string "$recipe"), \"settings\": $(json_string "$settings"), \"out\": $(json_string "$name"), \"exit_code\": $code, \"wall_s\": $wall, \"user_s\": $user, \"sys_s\": $sys, \"max_rss_kb\": $rss}")
}

# When the runs started and how loaded the machine was then: kept across --resume.
if [ ! -f "$runs/started" ]; then
  { date -u '+%Y-%m-%d %H:%M UTC'; cut -d' ' -f1-3 /proc/loadavg;
    git rev-parse --short HEAD; git diff --quiet HEAD -- core lua_api scripts/recipes scripts/lib scripts/posts scripts/machines || echo dirty; } > "$runs/started"
fi
started_at="$(sed -n 1p "$runs/started")"
load="$(sed -n 2p "$runs/started")"
commit="$(sed -n 3p "$runs/started")$(grep -q '^dirty$' "$runs/started" && echo ' + local changes' || true)"
run wheel_design blisk_wheel_design.lua
run drum_finish blisk_drum_finish.lua
run drum_study blisk_drum_study.lua
run post blisk_post.lua
run hub_finish blisk_hub_finish.lua
run edges blade_edges.lua
run belt blade_belt_grinding.lua
run repair_tip blade_repair.lua
run repair_edge blade_repair.lua --set damage=edge
run repair_paths blade_repair_paths.lua
run impeller_flank impeller_flank_finish.lua
run channel_roughing impeller_channel_roughing.lua
run blisk_job blisk_job.lua --set blades=2
run impeller_job impeller_job.lua --set blades=2 --set channels=right --set "faces=main minus"
if [ -n "$data" ]; then
  run rotor67_wheel rotor67_wheel_design.lua --data "$data"
  run rotor37_wheel rotor37_wheel_design.lua --data "$data"
  run hecc_model hecc_impeller_model.lua --data "$data"
  run hecc_flank hecc_impeller_flank_finish.lua --data "$data"
fi

if [ "$bench" = 1 ]; then
  [ -x build/bench/bliskrun_bench ] || cmake --build build --target bliskrun_bench
  build/bench/bliskrun_bench --benchmark_format=json --benchmark_out="$runs/bench.json" > /dev/null
fi

{
  printf '{"date": %s, "commit": %s, "nproc": %d, "cpu": %s, "mem_total_kb": %d, "load": %s, "threads": %d, "runs": [\n' \
    "$(json_string "$started_at")" "$(json_string "$commit")" \
    "$(nproc)" \
    "$(json_string "$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -n 1)")" \
    "$(sed -n 's/^MemTotal: *\([0-9]*\) kB/\1/p' /proc/meminfo)" \
    "$(json_string "$load")" "$threads"
  sep=""
  for e in "${entries[@]}"; do printf '%s  %s' "$sep" "$e"; sep=$',\n'; done
  printf '\n]}\n'
} > "$runs/index.json"

build/bliskrun scripts/tools/results.lua --data "$runs" --out bench --quiet
echo "wrote bench/RESULTS.md" >&2
