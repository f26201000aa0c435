#!/usr/bin/env bash
# Hard input bridged by the IMU (issue 14 point 2): for each profile, a clean run and runs with
# DURATION seconds of impaired frames from START (rgbdi-sim --blackout START:DURATION:KIND:
# black = covered lens, bare = no texture, blur = motion blur; KIND spin = rgbdi-sim --spin
# START:DURATION:SPIN_TURNS, an extra fast turn about the vertical), rgbdi-slam --gt on each, one
# markdown row per run: resets, frames with a pose, final / odometry ATE, the final ATE without
# the impaired frames and the impaired frames' own error (RMS, under the whole run's alignment).
#   [FPS=15] [SIM_DURATION=40] [START=19] [DURATION=2] [KINDS="black bare blur spin"] \
#   [SPIN_TURNS=1] [SLAM_ARGS=...] scripts/hard-input-table.sh [BUILD_DIR] [WORK_DIR] [PROFILES...]
set -euo pipefail
build=${1:-build}
work=${2:-out/hard-input}
shift 2 || shift $#
profiles=${*:-handheld wheeled_circle}
fps=${FPS:-15}
sim_duration=${SIM_DURATION:-40}
start=${START:-19}
duration=${DURATION:-2}
kinds=${KINDS:-black bare blur spin}
spin_turns=${SPIN_TURNS:-1}
read -r -a slam_args <<< "${SLAM_ARGS:-}"
for tool in rgbdi-sim rgbdi-slam; do
  [ -x "$build/bin/$tool" ] || { echo "hard-input-table: $build/bin/$tool not found (build first)" >&2; exit 1; }
done
/usr/bin/python3 -c 'import numpy' 2>/dev/null ||
  { echo "hard-input-table: needs numpy for /usr/bin/python3 (apt-get install python3-numpy)" >&2; exit 1; }
mkdir -p "$work"
echo "| profile | impairment | resets | frames with a pose | final ATE [m] | odometry ATE [m] | final ATE without the impaired frames [m] | impaired frames' error (RMS) [m] |"
echo "|---|---|---|---|---|---|---|---|"
for p in $profiles; do
  for kind in clean $kinds; do
    name="${p}_${fps}hz_${kind}"
    [ "$kind" != clean ] && name+="_${start}_${duration}"
    [ "$kind" = spin ] && name+="_${spin_turns}"
    seq="$work/$name"
    args=(--profile "$p" --duration "$sim_duration" --fps "$fps" --out "$seq")
    case "$kind" in
      clean) ;;
      spin) args+=(--spin "$start:$duration:$spin_turns") ;;
      *) args+=(--blackout "$start:$duration:$kind") ;;
    esac
    if [ ! -f "$seq/sequence.rawlog" ]; then
      "$build/bin/rgbdi-sim" "${args[@]}" > "$seq.gen.log" 2>&1
    fi
    "$build/bin/rgbdi-slam" --input "$seq/sequence.rawlog" --config "$seq/config.ini" \
      --gt "$seq/groundtruth.tum" --out "$seq.out" --quiet "${slam_args[@]}" > "$seq.slam.log" 2>&1 || true
    /usr/bin/python3 - "$seq" "$p" "$kind" "$start" "$duration" "$spin_turns" << 'PY'
import json, sys
import numpy as np
seq, profile, kind, start, duration = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4]), float(sys.argv[5])
label = kind if kind == "clean" else f"{kind} {duration:g} s"
if kind == "spin":
    label = f"spin {float(sys.argv[6]):g} turn in {duration:g} s (peak {2 * np.pi * float(sys.argv[6]) * 35 / 16 / duration:.1f} rad/s)"
try:
    s = json.load(open(seq + ".out/summary.json"))
except (OSError, ValueError):
    print(f"| {profile} | {kind} | run failed | - | - | - | - | - |")
    sys.exit(0)
gt = np.loadtxt(seq + "/groundtruth.tum")
est = np.loadtxt(seq + ".out/trajectory.tum")
t0 = gt[0, 0] + start
t1 = t0 + duration
idx = np.clip(np.searchsorted(gt[:, 0], est[:, 0]), 0, len(gt) - 1)
G, P, t = gt[idx, 1:4], est[:, 1:4], est[:, 0]
def aligned_errors(mask):
    # position + yaw alignment (as rgbdi-eval --align posyaw) on the masked poses
    mp, mg = P[mask].mean(0), G[mask].mean(0)
    H = (P[mask] - mp)[:, :2].T @ (G[mask] - mg)[:, :2]
    a = np.arctan2(H[0, 1] - H[1, 0], H[0, 0] + H[1, 1])
    R = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    return np.linalg.norm(P @ R.T + (mg - R @ mp) - G, axis=1)
inside = (t >= t0) & (t < t1)
e_all = aligned_errors(np.ones(len(t), bool))
e_out = aligned_errors(~inside)
rms = lambda e: float(np.sqrt(np.mean(e ** 2))) if len(e) else float("nan")
imp = f"{rms(e_all[inside]):.4f}" if kind != "clean" and inside.any() else "-"
excl = f"{rms(e_out[~inside]):.4f}" if kind != "clean" else "-"
print(f"| {profile} | {label} | {s.get('resets', '-')} | {len(t)} | "
      f"{s['evaluation']['ate_rmse']:.4f} | {s['evaluation_odometry']['ate_rmse']:.4f} | {excl} | {imp} |")
PY
  done
done
