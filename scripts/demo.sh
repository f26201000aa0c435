#!/usr/bin/env bash
# README main job: installs dependencies, builds rgbdi (Release), generates a demo sequence with
# the simulator (wheeled robot over two ramps, D435i-like noise), runs rgbdi-slam on it and prints
# the accuracy against ground truth and where the outputs are.
#   bash scripts/demo.sh [PROFILE] [DURATION_S]     (defaults: wheeled_slopes, 40 s)
set -euo pipefail
cd "$(dirname "$0")/.."
PROFILE=${1:-wheeled_slopes}
DURATION=${2:-40}
BUILD_DIR=${BUILD_DIR:-build}
OUT=${OUT:-$PWD/out/demo_${PROFILE}}

bash scripts/setup-deps.sh
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD_DIR" -j "$(nproc)" --target rgbdi-sim rgbdi-slam rgbdi-eval

rm -rf "$OUT"
mkdir -p "$OUT"
echo "== Generating a ${DURATION} s '${PROFILE}' sequence in $OUT/sequence"
"$BUILD_DIR/bin/rgbdi-sim" --profile "$PROFILE" --duration "$DURATION" --out "$OUT/sequence"
echo "== Running rgbdi-slam"
"$BUILD_DIR/bin/rgbdi-slam" --input "$OUT/sequence/sequence.rawlog" \
  --config "$OUT/sequence/config.ini" --gt "$OUT/sequence/groundtruth.tum" --out "$OUT/result"
echo "== Results are in $OUT/result (summary.json has all figures)"
