#!/bin/bash
# Compares the CPU time of two rgbdi-slam binaries on the same sequences, run alternately
# (old, new, old, new, ...) so that the virtual machine's speed drift, which moves a single
# run by up to a fifth within minutes, hits both alike. Prints every run (CPU = user + sys [s],
# wall [s], peak RSS [MB]) and per sequence the median of the per-pair ratios new / old.
#   [PAIRS=3] [SEQ_DIR=out/bench-cpu/seq] scripts/cpu-pairs.sh OLD_BINARY NEW_BINARY NAME...
# NAME: a sequence directory under SEQ_DIR with sequence.rawlog and config.ini (the ones
# scripts/bench-cpu.sh generates, e.g. handheld_15hz).
set -euo pipefail
[ $# -ge 3 ] || { sed -n '2,9p' "$0" >&2; exit 2; }
old=$1 new=$2
shift 2
pairs=${PAIRS:-3}
seq_dir=${SEQ_DIR:-out/bench-cpu/seq}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for bin in "$old" "$new"; do
  [ -x "$bin" ] || { echo "cpu-pairs: $bin is not an executable" >&2; exit 1; }
done
run() {  # run BINARY SEQUENCE -> "cpu wall rss_mb"
  rm -rf "$work/out"
  /usr/bin/time -f "%U %S %e %M" -o "$work/time" "$1" --input "$2/sequence.rawlog" \
    --out "$work/out" --config "$2/config.ini" --quiet > /dev/null 2>&1 ||
    { echo "cpu-pairs: $1 failed on $2" >&2; exit 1; }
  awk '{printf "%.2f %.2f %.0f", $1 + $2, $3, $4 / 1024}' "$work/time"
}
for name in "$@"; do
  s="$seq_dir/$name"
  [ -f "$s/sequence.rawlog" ] || { echo "cpu-pairs: $s/sequence.rawlog not found" >&2; exit 1; }
  ratios=()
  for i in $(seq "$pairs"); do
    read -r c_old w_old m_old <<< "$(run "$old" "$s")"
    read -r c_new w_new m_new <<< "$(run "$new" "$s")"
    echo "$name pair $i: old CPU $c_old s wall $w_old s RSS $m_old MB | new CPU $c_new s wall $w_new s RSS $m_new MB"
    ratios+=("$(awk -v a="$c_new" -v b="$c_old" 'BEGIN {print a / b}')")
  done
  printf '%s\n' "${ratios[@]}" | sort -g |
    awk -v n="$name" '{r[NR] = $1} END {m = NR % 2 ? r[(NR + 1) / 2] : (r[NR / 2] + r[NR / 2 + 1]) / 2;
      printf "%s: median CPU new / old %.3f over %d pairs\n", n, m, NR}'
done
