#!/usr/bin/env bash
# Builds the test suite with a sanitizer into its own build directory and runs it.
#   scripts/sanitize.sh asan [TEST...]   AddressSanitizer + UndefinedBehaviorSanitizer, build-asan/,
#                                        every test executable (or the ones named)
#   scripts/sanitize.sh tsan [TEST...]   ThreadSanitizer, build-tsan/, the threaded parts:
#                                        test_stage_worker, test_slam_system, test_live_*
# Environment: JOBS (default 2), RGBDI_ASAN_LEAKS=0 to switch LeakSanitizer off.
# Exit status: 0 all passed, 1 a test failed or a sanitizer reported, 2 usage.
# Prints the wall time of the build and of the run (doc/robustness.md).
set -euo pipefail
cd "$(dirname "$0")/.."
mode="${1:-}"
shift || true
jobs="${JOBS:-2}"
case "$mode" in
  asan)
    dir=build-asan
    flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g -O1"
    ;;
  tsan)
    dir=build-tsan
    flags="-fsanitize=thread -fno-omit-frame-pointer -g -O1"
    ;;
  *)
    echo "usage: scripts/sanitize.sh asan|tsan [TEST...]" >&2
    exit 2
    ;;
esac
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="${flags%% -g*}" \
  -DCMAKE_SHARED_LINKER_FLAGS="${flags%% -g*}" -DRGBDI_BUILD_BENCH=OFF >/dev/null

if [ $# -gt 0 ]; then
  tests=("$@")
elif [ "$mode" = tsan ]; then
  tests=(test_stage_worker test_slam_system)
  for f in tests/live/test_live_*.cpp; do tests+=("$(basename "$f" .cpp)"); done
else
  tests=()
  for f in tests/*/test_*.cpp; do tests+=("$(basename "$f" .cpp)"); done
  # The replays of the fuzz targets run under the sanitizer too.
  for f in fuzz/fuzz_*.cpp; do tests+=("fuzz_replay_$(basename "$f" .cpp | sed 's/^fuzz_//')"); done
fi
# The end-to-end tests in tests/apps/ run the apps: build them too.
t0=$(date +%s)
ninja -C "$dir" -j "$jobs" "${tests[@]}" rgbdi-slam rgbdi-sim rgbdi-eval rawlog-convert
t1=$(date +%s)
echo "sanitize.sh $mode: build took $((t1 - t0)) s"

export ASAN_OPTIONS="halt_on_error=1:detect_leaks=${RGBDI_ASAN_LEAKS:-1}:abort_on_error=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1"
export RGBDI_BIN_DIR="$PWD/$dir/bin"
failed=()
for t in "${tests[@]}"; do
  if ! "$dir/bin/$t" >"$dir/$t.log" 2>&1; then
    failed+=("$t")
    echo "FAILED: $t (log: $dir/$t.log)"
  else
    echo "passed: $t"
  fi
done
t2=$(date +%s)
echo "sanitize.sh $mode: ${#tests[@]} executables, ${#failed[@]} failed, run took $((t2 - t1)) s"
[ ${#failed[@]} -eq 0 ]
