#!/bin/bash
# The 10-minute wheeled_slopes racetrack with loop closure (issue 10 acceptance, not in ctest):
# final ATE (target <= 3 cm), points each lap adds to the map once loops close vs the first lap
# (target < 10 %), peak RSS of rgbdi-slam (target < 300 MB, measured as scripts/measure-memory.sh
# does: /usr/bin/time -v).
#   [FPS=15] [DURATION=600] scripts/loop-long.sh [BUILD_DIR] [WORK_DIR]
# The sequence (~8 GB at 15 Hz) is generated once into WORK_DIR and reused.
set -euo pipefail
build=${1:-build}
work=${2:-out/loop-long}
fps=${FPS:-15}
duration=${DURATION:-600}
profile=wheeled_slopes
for tool in rgbdi-sim rgbdi-slam bench_slam; do
  [ -x "$build/bin/$tool" ] || { echo "loop-long: $build/bin/$tool not found (build first)" >&2; exit 1; }
done
seq="$work/${profile}_${duration}s"
mkdir -p "$work"
if [ ! -f "$seq/sequence.rawlog" ]; then
  echo "loop-long: generating $seq ($duration s at $fps Hz)" >&2
  "$build/bin/rgbdi-sim" --profile "$profile" --duration "$duration" --fps "$fps" --out "$seq" \
    > "$seq.gen.log" 2>&1
fi
# 1. The SlamSystem in-process (offline mode, as fast as it goes: the result rgbdi-slam gets)
# for the ATE of the three trajectories and the points each lap added (Mapper::insertions
# grouped by the ground-truth lap), with its peak RSS (no output files written).
/usr/bin/time -v -o "$seq.bench.time" "$build/bin/bench_slam" --rawlog "$seq/sequence.rawlog" \
  --gt "$seq/groundtruth.tum" --config "$seq/config.ini" --profile "$profile" --duration "$duration" \
  --loop on --speed 0 --offline > "$seq.bench.log" 2>&1
# 2. rgbdi-slam as a user runs it (all outputs), for its peak RSS; BENCH_ONLY=1 skips it.
if [ "${BENCH_ONLY:-0}" != 1 ]; then
  /usr/bin/time -v -o "$seq.slam.time" "$build/bin/rgbdi-slam" --input "$seq/sequence.rawlog" \
    --out "$seq.out" --config "$seq/config.ini" --gt "$seq/groundtruth.tum" --quiet \
    > "$seq.slam.log" 2>&1
fi
/usr/bin/python3 - "$seq" << 'PY'
import json, os, re, sys
seq = sys.argv[1]
rss = lambda f: int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", open(f).read()).group(1)) / 1024
bench = open(seq + ".bench.log").read()
grab = lambda pat: re.search(pat, bench)
ate = grab(r"ATE posyaw: final ([0-9.]+) m, online ([0-9.]+) m, odometry ([0-9.]+) m")
kf = grab(r"keyframes (\d+), map points (\d+)")
loops = grab(r"loops (\d+), rolled back (\d+), solves (\d+), solve max ([0-9.]+) ms; map corrections (\d+), max ([0-9.]+) ms")
frames = grab(r"on \(offline mode, speed 0.00x\): (\d+) frames, wall ([0-9.]+) s")
laps = grab(r"points added per lap \(([0-9.]+) m\):(.*)")
print("| figure | value | target |")
print("|---|---|---|")
if frames and kf:
    print(f"| frames / keyframes / wall time | {frames.group(1)} / {kf.group(1)} / {float(frames.group(2)):.0f} s | |")
if ate:
    print(f"| ATE final / online / odometry [m] | {ate.group(1)} / {ate.group(2)} / {ate.group(3)} | final <= 0.03 |")
if loops:
    print(f"| loops accepted / rolled back / solves, solve max | {loops.group(1)} / {loops.group(2)} / {loops.group(3)}, {loops.group(4)} ms | |")
    print(f"| map corrections, max | {loops.group(5)}, {loops.group(6)} ms | |")
if kf:
    print(f"| map points at the end | {kf.group(2)} | |")
if laps:
    counts = [int(x) for x in re.findall(r"(\d+)(?: \(\d+ %\))?", laps.group(2))]
    first = counts[0] if counts else 0
    later = ", ".join(f"{c} ({100 * c / first:.0f} %)" for c in counts[1:]) if first else "-"
    print(f"| points added in lap 1 (lap {float(laps.group(1)):.1f} m) | {first} | |")
    print(f"| points added in later laps (share of lap 1) | {later} | each < 10 % |")
print(f"| peak RSS bench_slam (same system, no outputs) [MB] | {rss(seq + '.bench.time'):.0f} | |")
# With BENCH_ONLY=1 rgbdi-slam did not run: the files of an earlier run are not this run's.
if os.environ.get("BENCH_ONLY", "0") != "1" and os.path.exists(seq + ".slam.time") \
        and os.path.exists(seq + ".out/summary.json"):
    s = json.load(open(seq + ".out/summary.json"))
    print(f"| rgbdi-slam: ATE final / odometry [m] | {s['evaluation']['ate_rmse']:.4f} / {s['evaluation_odometry']['ate_rmse']:.4f} | |")
    print(f"| peak RSS rgbdi-slam [MB] | {rss(seq + '.slam.time'):.0f} | < 300 |")
PY
