#!/bin/bash
# ATE of the odometry, online and final (loop-closed) trajectories on every simulator profile
# (the profiles rgbdi-sim --help lists, default duration and noise), markdown table. Runs
# bench_slam: the SlamSystem rgbdi-slam runs (threaded, offline mode: the same result), fed by
# the simulator in-process with its exact ground truth, loop closure on, as fast as it goes.
#   [FPS=15] [DURATION=S] scripts/loop-table.sh [BUILD_DIR] [PROFILES...]
set -euo pipefail
build=${1:-build}
shift || true
fps=${FPS:-15}
bench="$build/bin/bench_slam"
for tool in rgbdi-sim bench_slam; do
  [ -x "$build/bin/$tool" ] || { echo "loop-table: $build/bin/$tool not found (build first)" >&2; exit 1; }
done
profiles=${*:-$("$build/bin/rgbdi-sim" --help | awk '$1 == "--profile" {gsub(/\|/, " "); for (i = 2; i <= NF; ++i) printf "%s ", $i}')}
echo "| profile | camera | duration [s] | keyframes | loops accepted (rolled back) | ATE odometry [m] | ATE online [m] | ATE final [m] | final / odometry |"
echo "|---|---|---|---|---|---|---|---|---|"
for p in $profiles; do
  args=(--profile "$p" --fps "$fps" --loop on --speed 0 --offline)
  [ -n "${DURATION:-}" ] && args+=(--duration "$DURATION")
  out=$("$bench" "${args[@]}" 2>&1 || true)
  /usr/bin/python3 - "$p" "$fps" <<PY
import re, sys
out = """$out"""
p, fps = sys.argv[1:3]
dur = re.search(r"simulated \S+, ([0-9.]+) s", out)
ate = re.search(r"ATE posyaw: final ([0-9.]+) m, online ([0-9.]+) m, odometry ([0-9.]+) m", out)
kf = re.search(r"keyframes (\d+), map points", out)
lp = re.search(r"loops (\d+), rolled back (\d+)", out)
if not ate:
    print(f"| {p} | {fps} Hz | - | - | - | run failed | - | - | - |")
    sys.exit(0)
fin, onl, odo = (float(x) for x in ate.groups())
print(f"| {p} | {fps} Hz | {float(dur.group(1)):.0f} | {kf.group(1) if kf else '-'} | "
      f"{lp.group(1) + ' (' + lp.group(2) + ')' if lp else '0'} | {odo:.4f} | {onl:.4f} | {fin:.4f} | "
      f"{100 * fin / odo:.0f} % |")
PY
done
