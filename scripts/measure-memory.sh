#!/bin/bash
# Peak resident memory of rgbdi-slam on a generated sequence of the given length, with the RSS
# sampled every 5 s (to see whether it grows with frames) and the memory split of summary.json.
#   scripts/measure-memory.sh DURATION_S [PROFILE] [WORK_DIR] [BUILD_DIR]
# Needs a built tree; a 10-minute sequence takes ~16 GB of disk (external images).
set -euo pipefail
duration=${1:?usage: measure-memory.sh DURATION_S [PROFILE] [WORK_DIR] [BUILD_DIR]}
profile=${2:-wheeled_slopes}
work=${3:-out/memory}
build=${4:-build}
seq="$work/${profile}_${duration}s"
out="$seq.out"
mkdir -p "$work"
if [ ! -f "$seq/sequence.rawlog" ]; then
  "$build/bin/rgbdi-sim" --profile "$profile" --duration "$duration" --out "$seq" > "$seq.gen.log" 2>&1
fi
/usr/bin/time -v -o "$out.time" "$build/bin/rgbdi-slam" --input "$seq/sequence.rawlog" --out "$out" \
  --gt "$seq/groundtruth.tum" --config "$seq/config.ini" --quiet > "$out.log" 2>&1 &
time_pid=$!
sleep 1
slam_pid=$(pgrep -P "$time_pid" | head -1 || true)
: > "$out.rss"
while [ -n "$slam_pid" ] && kill -0 "$slam_pid" 2> /dev/null; do
  echo "$(date +%s) $(awk '/VmRSS/ {print $2}' /proc/$slam_pid/status 2> /dev/null)" >> "$out.rss"
  sleep 5
done
wait "$time_pid"
/usr/bin/python3 - "$out" "$duration" << 'PY'
import json, re, sys
out, duration = sys.argv[1], sys.argv[2]
peak = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", open(out + ".time").read()).group(1))
s = json.load(open(out + "/summary.json"))
m = s["map"]
mb = lambda b: b / 2**20
print(f"{duration} s: peak RSS {peak / 1024:.0f} MB; frames {s['frames']}, keyframes {m['keyframes']}, "
      f"map points {m['points']}, octree {mb(m.get('point_octree_bytes', 0)):.0f} MB, "
      f"keyframe store {mb(m.get('keyframe_store_bytes', 0)):.0f} MB, "
      f"occupancy {mb(m.get('occupancy_bytes', 0)):.0f} MB; "
      f"ATE {s['evaluation']['ate_rmse']:.3f} m, resets {s['resets']}")
PY
