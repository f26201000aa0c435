#!/usr/bin/env bash
# Installs dependencies, builds rgbdi (Release) and runs the whole test suite with ctest, then the
# sanitizer runs that fit CI's time (issue 14 point 4): AddressSanitizer + UndefinedBehaviorSanitizer
# on the unit tests of the readers of outside data (tests/io, tests/common, tests/eval) and three
# fuzz replays, ThreadSanitizer on the stage worker that joins the pipeline's threads. The full
# sanitizer runs: scripts/sanitize.sh asan|tsan (doc/robustness.md "Sanitizers").
# Environment: BUILD_DIR (build), JOBS (nproc), RGBDI_TEST_SANITIZERS=0 skips the sanitizer runs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup-deps.sh
BUILD_DIR=${BUILD_DIR:-build}
JOBS=${JOBS:-$(nproc)}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD_DIR" -j "$JOBS"
(cd "$BUILD_DIR" && ctest --output-on-failure -j "$JOBS" --timeout 1500)
if [ "${RGBDI_TEST_SANITIZERS:-1}" != 0 ]; then
  asan=()
  for f in tests/io/test_*.cpp tests/common/test_*.cpp tests/eval/test_*.cpp; do
    asan+=("$(basename "$f" .cpp)")
  done
  JOBS=$JOBS bash scripts/sanitize.sh asan "${asan[@]}" fuzz_replay_rawlog fuzz_replay_tum \
    fuzz_replay_image_decode
  JOBS=$JOBS bash scripts/sanitize.sh tsan test_stage_worker
fi
