#!/bin/bash
# Paper-style comparison table (Table 1 / Figures 7-8) on freshly generated simulator sequences:
# RGB-D-inertial vs monocular-inertial (--no-depth, with and without the static start) for every
# profile at 30 and 15 Hz. Prints a markdown table; needs a built tree (bench_vio).
#   [MODES="rgbd mono mono-moving-start"] scripts/vio-table.sh [BUILD_DIR] [PROFILES...]
set -euo pipefail
build=${1:-build}
shift || true
profiles=${*:-handheld wheeled_circle wheeled_slopes tracked_slopes}
bench="$build/bin/bench_vio"
[ -x "$bench" ] || { echo "vio-table: $bench not found (build first)" >&2; exit 1; }

echo "| profile | camera | mode | ATE posyaw [m] | scale error (sim3) [%] | coverage [%] | first pose [s] | resets | time offset [ms] |"
echo "|---|---|---|---|---|---|---|---|---|"
for p in $profiles; do
  for fps in 30 15; do
    for mode in ${MODES:-rgbd mono mono-moving-start}; do
      args=(--profile "$p" --fps "$fps")
      case $mode in
        mono) args+=(--no-depth) ;;
        mono-moving-start) args+=(--no-depth --set estimator.init_allow_static=false) ;;
      esac
      out=$("$bench" "${args[@]}" 2>/dev/null || true)
      /usr/bin/python3 - "$p" "$fps" "$mode" <<PY
import re, sys
out = """$out"""
p, fps, mode = sys.argv[1:4]
def grab(pat, default="-"):
    m = re.search(pat, out)
    return m.group(1) if m else default
ate = grab(r"posyaw: ATE rmse ([0-9.]+) m")
scale = grab(r"sim3: ATE rmse [0-9.]+ m, max [0-9.]+ m, scale ([0-9.]+)")
cov = grab(r"posyaw: .*coverage ([0-9.]+)")
first = grab(r"first pose at (-?[0-9.]+) s")
resets = grab(r"resets ([0-9]+)")
td = grab(r"time offset (-?[0-9.]+) ms")
if ate == "-":
    print(f"| {p} | {fps} Hz | {mode} | never initialised | - | - | - | {resets} | - |")
else:
    print(f"| {p} | {fps} Hz | {mode} | {float(ate):.4f} | {abs(float(scale)-1)*100:.2f} | "
          f"{float(cov)*100:.1f} | {float(first):.2f} | {resets} | {td} |")
PY
    done
  done
done
