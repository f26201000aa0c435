#!/bin/bash
# Rolling-shutter accuracy table (issue 37): for every profile, frame rate and seed, one simulator
# sequence rendered with a global shutter and the same one with a rolling-shutter colour camera
# ([sim] rolling_shutter_readout_s = READOUT, top to bottom, stamped at the middle row); rgbdi-slam
# on the global one, on the rolling one without compensation ([camera] rolling_shutter_readout_s
# = 0) and with it (= READOUT, the config.ini rgbdi-sim writes), and with the readout estimated
# online from 0 ([estimator] estimate_rolling_shutter_readout = true, [camera]
# rolling_shutter_readout_s = 0: the prior is wrong by the whole readout). ATE RMSE of
# trajectory.tum and the final readout estimate (summary.json). The sequences are deleted after
# each run; the per-run rows go to TSV.
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
        if len(f) != 9 or f[0] == "profile":
            continue
        p, fps, seed = f[0], int(f[1]), f[2]
        g, u, c, readout, e, r_est = map(float, f[3:9])
        rows.setdefault((p, fps), []).append((seed, g, u, c, e, r_est))
print("| profile | camera | seeds | global shutter [m] | rolling, not compensated [m] | "
      "rolling, compensated [m] | rolling, readout estimated from 0 [m] | "
      "not compensated / global | compensated / global | estimated / global | "
      "readout estimates [ms] |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for (p, fps), r in sorted(rows.items(), key=lambda k: (k[0][0], -k[0][1])):
    med = [statistics.median(x[i] for x in r) for i in (1, 2, 3, 4)]
    est = ", ".join(f"{1e3 * x[5]:.1f}" for x in sorted(r))
    print(f"| {p} | {fps} Hz | {len(r)} | {med[0]:.4f} | {med[1]:.4f} | {med[2]:.4f} | "
          f"{med[3]:.4f} | {med[1] / med[0]:.2f} | {med[2] / med[0]:.2f} | "
          f"{med[3] / med[0]:.2f} | {est} |")
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
[ -s "$tsv" ] ||
  echo "profile fps seed ate_global ate_uncompensated ate_compensated readout_s ate_estimated" \
    "readout_estimated_s" >"$tsv"

ate() {  # sequence dir, config, run name -> ATE RMSE of trajectory.tum [and the readout estimate]
  "$build/bin/rgbdi-slam" --input "$1/sequence.rawlog" --config "$2" --gt "$1/groundtruth.tum" \
    --out "$work/$3" --no-save-map --quiet >"$work/$3.log" 2>&1 || { echo nan nan; return; }
  /usr/bin/python3 -c 'import json,sys; d = json.load(open(sys.argv[1]))
print(d["evaluation"]["ate_rmse"], d.get("rolling_shutter_readout", {}).get("estimated_s", "nan"))' \
    "$work/$3/summary.json" 2>/dev/null || echo nan nan
}

for p in $profiles; do
  for fps in $rates; do
    for seed in $seeds; do
      sim=("$build/bin/rgbdi-sim" --profile "$p" --duration "$duration" --fps "$fps" --seed "$seed")
      "${sim[@]}" --out "$work/global" >/dev/null
      "${sim[@]}" --out "$work/rolling" --config "$work/rolling.ini" >/dev/null
      sed 's/^rolling_shutter_readout_s = .*/rolling_shutter_readout_s = 0/' \
        "$work/rolling/config.ini" >"$work/uncompensated.ini"
      printf '[estimator]\nestimate_rolling_shutter_readout = true\n' |
        cat "$work/uncompensated.ini" - >"$work/estimated.ini"
      g=$(ate "$work/global" "$work/global/config.ini" run_g | cut -d' ' -f1)
      u=$(ate "$work/rolling" "$work/uncompensated.ini" run_u | cut -d' ' -f1)
      c=$(ate "$work/rolling" "$work/rolling/config.ini" run_c | cut -d' ' -f1)
      e=$(ate "$work/rolling" "$work/estimated.ini" run_e)
      echo "$p $fps $seed $g $u $c $readout $e" | tee -a "$tsv"
      rm -rf "$work"/global "$work"/rolling "$work"/run_*
    done
  done
done
table "$tsv"
