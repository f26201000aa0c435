#!/bin/bash
# Rolling-shutter accuracy table (issue 37): for every profile, frame rate and seed, one simulator
# sequence rendered with a global shutter and the same one with a rolling-shutter colour camera
# ([sim] rolling_shutter_readout_s = READOUT, top to bottom, stamped at the middle row); rgbdi-slam
# on the global one, on the rolling one without compensation ([camera] rolling_shutter_readout_s
# = 0) and with it (= READOUT, the config.ini rgbdi-sim writes). ATE RMSE of trajectory.tum
# (summary.json). The sequences are deleted after each run; the per-run rows go to TSV.
#   [SEEDS="1 2 3"] [FPS="30 15"] [DURATION=20] [READOUT=0.033] [TSV=out/rs-table.tsv] \
#     scripts/rolling-shutter-table.sh [BUILD_DIR] [PROFILES...]
#   scripts/rolling-shutter-table.sh --table TSV...   (the table of rows already measured)
set -euo pipefail

table() {
  /usr/bin/python3 - "$@" <<'PY'
import statistics, sys
rows = {}
for path in sys.argv[1:]:
    for line in open(path):
        f = line.split()
        if len(f) != 7 or f[0] == "profile":
            continue
        p, fps, seed, g, u, c = f[0], int(f[1]), f[2], *map(float, f[3:6])
        rows.setdefault((p, fps), []).append((seed, g, u, c))
print("| profile | camera | seeds | global shutter [m] | rolling, not compensated [m] | "
      "rolling, compensated [m] | not compensated / global | compensated / global |")
print("|---|---|---|---|---|---|---|---|")
for (p, fps), r in sorted(rows.items(), key=lambda k: (k[0][0], -k[0][1])):
    med = [statistics.median(x[i] for x in r) for i in (1, 2, 3)]
    print(f"| {p} | {fps} Hz | {len(r)} | {med[0]:.4f} | {med[1]:.4f} | {med[2]:.4f} | "
          f"{med[1] / med[0]:.2f} | {med[2] / med[0]:.2f} |")
PY
}

if [ "${1:-}" = "--table" ]; then
  shift
  table "$@"
  exit 0
fi

build=${1:-build}
shift || true
profiles=${*:-handheld wheeled_circle wheeled_slopes tracked_slopes}
seeds=${SEEDS:-1 2 3}
rates=${FPS:-30 15}
duration=${DURATION:-20}
readout=${READOUT:-0.033}
tsv=${TSV:-out/rs-table.tsv}
for app in rgbdi-sim rgbdi-slam; do
  [ -x "$build/bin/$app" ] || { echo "rolling-shutter-table: $build/bin/$app not found" >&2; exit 1; }
done
mkdir -p "$(dirname "$tsv")"
work=$(mktemp -d "${TMPDIR:-/tmp}/rs-table.XXXXXX")
trap 'rm -rf "$work"' EXIT
printf '[sim]\nrolling_shutter_readout_s = %s\n' "$readout" >"$work/rolling.ini"
[ -s "$tsv" ] || echo "profile fps seed ate_global ate_uncompensated ate_compensated readout_s" >"$tsv"

ate() {  # sequence dir, config, run name -> ATE RMSE of trajectory.tum
  "$build/bin/rgbdi-slam" --input "$1/sequence.rawlog" --config "$2" --gt "$1/groundtruth.tum" \
    --out "$work/$3" --no-save-map --quiet >"$work/$3.log" 2>&1 || { echo nan; return; }
  /usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["evaluation"]["ate_rmse"])' \
    "$work/$3/summary.json" 2>/dev/null || echo nan
}

for p in $profiles; do
  for fps in $rates; do
    for seed in $seeds; do
      sim=("$build/bin/rgbdi-sim" --profile "$p" --duration "$duration" --fps "$fps" --seed "$seed")
      "${sim[@]}" --out "$work/global" >/dev/null
      "${sim[@]}" --out "$work/rolling" --config "$work/rolling.ini" >/dev/null
      sed 's/^rolling_shutter_readout_s = .*/rolling_shutter_readout_s = 0/' \
        "$work/rolling/config.ini" >"$work/uncompensated.ini"
      g=$(ate "$work/global" "$work/global/config.ini" run_g)
      u=$(ate "$work/rolling" "$work/uncompensated.ini" run_u)
      c=$(ate "$work/rolling" "$work/rolling/config.ini" run_c)
      echo "$p $fps $seed $g $u $c $readout" | tee -a "$tsv"
      rm -rf "$work"/global "$work"/rolling "$work"/run_*
    done
  done
done
table "$tsv"
