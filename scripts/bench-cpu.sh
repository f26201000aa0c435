#!/bin/bash
# What a user pays for the whole rgbdi-slam path: CPU seconds per second of data (user + sys of
# the process, all threads), wall-clock rate, peak RSS and the CPU split by stage, next to the ATE,
# for every profile at 15 and 30 Hz. Sequences are generated once with rgbdi-sim and cached.
#   [SEQ_DIR=out/bench-cpu/seq] [RUN_DIR=out/bench-cpu/run] [RATES="15 30"] [DURATION=S] \
#     [SLAM_ARGS=...] [EXTRA_CONFIG=FILE] scripts/bench-cpu.sh [BUILD_DIR] [PROFILES...]
# DURATION (seconds of data) shortens the sequences; unset = each profile's default length.
# EXTRA_CONFIG: INI text appended to each sequence's config.ini for the run (e.g. a [stream]
# section with image_rate_limit_hz = 15).
# LAYOUT=files (default): images in sequence_Images/ (a PNG and a compressed range file per frame
# to decode, MRPT's layout for large datasets); LAYOUT=embedded: raw images inside the rawlog
# (rgbdi-sim --embedded-images: nothing to decode, as from a live camera or a bag; 1.5 MB per
# frame on disk).
# Prints a markdown table (doc/performance.md explains the columns). On a shared machine compare
# CPU seconds, not wall time: the wall-clock rate depends on what else runs.
set -euo pipefail
build=${1:-build}
shift || true
profiles=${*:-handheld wheeled_circle wheeled_slopes tracked_slopes}
seq_dir=${SEQ_DIR:-out/bench-cpu/seq}
run_dir=${RUN_DIR:-out/bench-cpu/run}
rates=${RATES:-15 30}
duration=${DURATION:-}
layout=${LAYOUT:-files}
case $layout in
  files) sim_layout=() ;;
  embedded) sim_layout=(--embedded-images) ;;
  *) echo "bench-cpu: LAYOUT must be files or embedded, got '$layout'" >&2; exit 1 ;;
esac
for tool in rgbdi-sim rgbdi-slam; do
  [ -x "$build/bin/$tool" ] || { echo "bench-cpu: $build/bin/$tool not found (build first)" >&2; exit 1; }
done
mkdir -p "$seq_dir" "$run_dir"

echo "| profile | camera | frames | data [s] | CPU [s] | CPU-s per s | x real time | frames/s | peak RSS [MB] | decode | tracking | pre-int | optimisation | marginalisation | mapping | output | other | ATE [m] |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for p in $profiles; do
  for fps in $rates; do
    name="${p}_${fps}hz${duration:+_${duration}s}"
    [ "$layout" = files ] || name="${name}_$layout"
    seq="$seq_dir/$name"
    if [ ! -f "$seq/sequence.rawlog" ]; then
      rm -rf "$seq.tmp"
      "$build/bin/rgbdi-sim" --profile "$p" --fps "$fps" ${duration:+--duration "$duration"} \
        "${sim_layout[@]}" --out "$seq.tmp" > /dev/null
      mv "$seq.tmp" "$seq"
    fi
    out="$run_dir/$name"
    rm -rf "$out"
    config="$seq/config.ini"
    if [ -n "${EXTRA_CONFIG:-}" ]; then
      config="$out.ini"
      cat "$seq/config.ini" "$EXTRA_CONFIG" > "$config"
    fi
    # shellcheck disable=SC2086  # SLAM_ARGS is a list of extra arguments
    /usr/bin/time -v -o "$out.time" "$build/bin/rgbdi-slam" --input "$seq/sequence.rawlog" \
      --out "$out" --config "$config" --gt "$seq/groundtruth.tum" --quiet ${SLAM_ARGS:-} \
      > "$out.log" 2>&1 || { echo "| $p | $fps Hz | rgbdi-slam failed: see $out.log |"; continue; }
    /usr/bin/python3 - "$p" "$fps" "$out" << 'PY'
import json, re, sys
p, fps, out = sys.argv[1:4]
t = open(out + ".time").read()
def num(pat):
    return float(re.search(pat, t).group(1))
cpu = num(r"User time \(seconds\): ([0-9.]+)") + num(r"System time \(seconds\): ([0-9.]+)")
w = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (?:(\d+):)?(\d+):([0-9.]+)", t)
wall = int(w.group(1) or 0) * 3600 + int(w.group(2)) * 60 + float(w.group(3))
rss_mb = num(r"Maximum resident set size \(kbytes\): (\d+)") / 1024
s = json.load(open(out + "/summary.json"))
frames = s["frames"]
data_s = s["stream_duration_s"]
tm = s["timing_ms_per_frame"]
diag = s.get("stream_diagnostics", {})
# Everything as CPU ms per input frame, so that the stages add up to the total.
stage = {
    "decode": 1e3 * diag.get("read_cpu_s", 0.0) / frames,
    "tracking": tm.get("tracking", 0.0),
    "pre-int": tm.get("preintegration", 0.0),
    "optimisation": tm.get("optimisation", 0.0),
    "marginalisation": tm.get("marginalisation", 0.0),
    # occupancy ray casting happens once, at the end (Mapper::finish), outside mapping_ms_total
    "mapping": (s["map"].get("mapping_ms_total", 0.0) +
                s["map"].get("occupancy_rebuild_ms", 0.0)) / frames,
    "output": s.get("timing_ms_total", {}).get("output", 0.0) / frames,
}
# Stages added later (e.g. loop closing) are listed after the known ones, inside "other".
extra = {k: v for k, v in tm.items()
         if k not in ("tracking", "preintegration", "optimisation", "marginalisation")}
total_ms = 1e3 * cpu / frames
other = total_ms - sum(stage.values())
ate = s.get("evaluation", {}).get("ate_rmse")
cells = [p, f"{fps} Hz", str(frames), f"{data_s:.1f}", f"{cpu:.1f}", f"{cpu / data_s:.3f}",
         f"{data_s / wall:.2f}", f"{frames / wall:.1f}", f"{rss_mb:.0f}"]
cells += [f"{v:.2f}" for v in stage.values()]
cells.append(f"{other:.2f}" + "".join(f" ({k} {v:.2f})" for k, v in extra.items()))
cells.append("-" if ate is None else f"{ate:.4f}")
print("| " + " | ".join(cells) + " |")
PY
  done
done
