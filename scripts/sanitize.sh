#!/usr/bin/env bash
# Builds the test suite with a sanitizer into its own build directory and runs it.
#   scripts/sanitize.sh asan [TEST...]   AddressSanitizer + UndefinedBehaviorSanitizer, build-asan/,
#                                        every test executable (or the ones named)
#   scripts/sanitize.sh tsan [TEST...]   ThreadSanitizer, build-tsan/, the threaded parts:
#                                        test_stage_worker, test_slam_system, test_slam_outputs,
#                                        test_live_* (or the ones named)
# Environment:
#   JOBS (default 2)           build jobs
#   RGBDI_ASAN_LEAKS=0         LeakSanitizer off
#   RGBDI_ASAN_RSS_MB (4096)   ASan ends a test process whose memory grows beyond this
#   RGBDI_SAN_MAX_COST         skip the gtest tests whose Release run time in tests/test_costs.txt is
#                              above this many seconds (a sanitized run is 3-20x slower, and the
#                              end-to-end tests take minutes in Release); "all" runs every test.
#                              Default 10 for asan; 90 for tsan, so that the threaded-vs-sequential
#                              and reset runs of test_slam_system (84 s and 37 s) are checked.
#                              The skipped tests are listed in the summary. An explicit
#                              GTEST_FILTER replaces this (and the list below).
#   RGBDI_SAN_TIMEOUT (3600)   [s] limit per test executable (a hang counts as a failure)
#   BUILD_DIR                  instead of build-asan/ or build-tsan/ (e.g. to time a cold build
#                              with CCACHE_DISABLE=1)
# Suppressions (third-party reports only, each with its reason): fuzz/lsan.supp (the leaks of
# MRPT's readers on damaged input, shared with scripts/fuzz.sh), scripts/sanitize-tsan.supp.
# Exit status: 0 all passed, 1 a test failed or a sanitizer reported, 2 usage.
# Prints the wall time of the build, of each executable and of the run (doc/robustness.md).
set -euo pipefail
cd "$(dirname "$0")/.."
mode="${1:-}"
shift || true
jobs="${JOBS:-2}"
case "$mode" in
  asan)
    dir=${BUILD_DIR:-build-asan}
    flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
    ;;
  tsan)
    dir=${BUILD_DIR:-build-tsan}
    flags="-fsanitize=thread -fno-omit-frame-pointer"
    ;;
  *)
    echo "usage: scripts/sanitize.sh asan|tsan [TEST...]" >&2
    exit 2
    ;;
esac
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
# The optimisation and debug flags go into the build type's variable: CMAKE_CXX_FLAGS comes first
# on the command line, so RelWithDebInfo's own "-O2 -g" would override them there. -O1 as the
# sanitizers' documentation recommends; -g1 (line tables) is all a report's stack needs and
# compiles about a third faster than -g. NDEBUG: the code that ships, as the Release tests run it.
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DCMAKE_EXE_LINKER_FLAGS="$flags" -DCMAKE_SHARED_LINKER_FLAGS="$flags" \
  -DRGBDI_BUILD_BENCH=OFF >/dev/null

if [ $# -gt 0 ]; then
  tests=("$@")
elif [ "$mode" = tsan ]; then
  tests=(test_stage_worker test_slam_system test_slam_outputs)
  for f in tests/live/test_live_*.cpp; do tests+=("$(basename "$f" .cpp)"); done
else
  tests=()
  for f in tests/*/test_*.cpp; do tests+=("$(basename "$f" .cpp)"); done
  # The replays of the fuzz targets run under the sanitizer too (fuzz_support.cpp is no target).
  for f in fuzz/fuzz_*.cpp; do
    t="fuzz_replay_$(basename "$f" .cpp | sed 's/^fuzz_//')"
    ninja -C "$dir" -t query "$t" >/dev/null 2>&1 && tests+=("$t")
  done
fi
# The end-to-end tests in tests/apps/ run the apps (their targets depend on them), some others
# simulate their input with rgbdi-sim (test::cachedSimSequence): build it for those. Linking the
# apps costs minutes under a sanitizer, so a run of tests that need none leaves them out.
extra=()
for t in "${tests[@]}"; do
  src=$(ls tests/*/"$t".cpp 2>/dev/null || true)
  if [ -n "$src" ] && grep -q "cachedSimSequence" "$src"; then
    extra=(rgbdi-sim)
    break
  fi
done
# Set before the build: ctest's test discovery runs the test executables while building.
supp() { [ -f "scripts/sanitize-$1.supp" ] && echo ":suppressions=$PWD/scripts/sanitize-$1.supp"; }
# hard_rss_limit_mb: the fuzz replays run without their 1.5 GiB address-space limit under ASan
# (replay_main.cpp), and MRPT's allocation by a corrupt count (doc/robustness.md, finding 1) then
# grew fuzz_replay_rawlog to 22 GB until the kernel killed it: stop at 4 GB with a report instead.
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=${RGBDI_ASAN_LEAKS:-1}:abort_on_error=0:hard_rss_limit_mb=${RGBDI_ASAN_RSS_MB:-4096}"
export LSAN_OPTIONS="print_suppressions=0:suppressions=$PWD/fuzz/lsan.supp"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1$(supp tsan || true)"
export RGBDI_BIN_DIR="$PWD/$dir/bin"
t0=$(date +%s)
ninja -C "$dir" -j "$jobs" "${tests[@]}" "${extra[@]}"
t1=$(date +%s)
echo "sanitize.sh $mode: build took $((t1 - t0)) s"

# The tests too costly for a sanitized run (see RGBDI_SAN_MAX_COST above).
default_cost=10
[ "$mode" = tsan ] && default_cost=90
max_cost="${RGBDI_SAN_MAX_COST:-$default_cost}"
# Never under a sanitizer: it loads the sanitized sensor plugin into Debian's uninstrumented
# rawlog-grabber, which cannot load a sanitizer runtime late ("libtsan.so.2: cannot allocate
# memory in static TLS block", seen under TSan; ASan's runtime likewise has to be the process's
# first library).
unsanitizable=(RgbdiSensorPlugin.LoadsInRawlogGrabberAndRecordsFromTheSimulator)
skipped=()
if [ -z "${GTEST_FILTER:-}" ]; then
  skipped=("${unsanitizable[@]}")
  while read -r cost name; do
    case "$cost" in '#'* | '') continue ;; esac
    [ "$max_cost" = all ] && break
    # gtest names only (Suite.Test); the other entries are whole executables (fuzz replays).
    if [[ "$name" == *.* ]] && [ "$cost" -gt "$max_cost" ] &&
      [[ " ${unsanitizable[*]} " != *" $name "* ]]; then skipped+=("$name"); fi
  done <tests/test_costs.txt
  if [ ${#skipped[@]} -gt 0 ]; then
    GTEST_FILTER="-$(IFS=:; echo "${skipped[*]}")"
    export GTEST_FILTER
  fi
fi

declare -A is_skipped=()
for n in "${skipped[@]}"; do is_skipped[$n]=1; done
failed=()
not_run=()
for t in "${tests[@]}"; do
  # The skipped tests of this executable (the summary lists only those).
  if [ ${#skipped[@]} -gt 0 ] && [[ "$t" == test_* ]]; then
    suite=
    while IFS= read -r line; do
      case "$line" in
        "  "*) n="$suite${line#  }"; n="${n%%  #*}"
               [ -n "${is_skipped[$n]:-}" ] && not_run+=("$n ($t)") ;;
        *.) suite="$line" ;;
      esac
    done < <(env -u GTEST_FILTER "$dir/bin/$t" --gtest_list_tests 2>/dev/null || true)
  fi
  # A fuzz replay limits its address space to 1.5 GiB in the normal build (replay_main.cpp), so
  # that a size field from the input which makes a library malloc gigabytes (OpenCV's yaml reader:
  # cv::Mat::create of 48 GB in fuzz_replay_vins_yaml) fails as the reader's refusal. Under ASan
  # it cannot; the same from ASan's allocator: such a malloc returns null. (operator new still
  # aborts whatever these say: MRPT's allocation of finding 1 stops fuzz_replay_rawlog.)
  opts=$ASAN_OPTIONS
  [[ "$t" == fuzz_replay_* ]] && opts+=":allocator_may_return_null=1:max_allocation_size_mb=1536"
  s=$(date +%s)
  if ! ASAN_OPTIONS=$opts timeout "${RGBDI_SAN_TIMEOUT:-3600}" "$dir/bin/$t" >"$dir/$t.log" 2>&1; then
    failed+=("$t")
    echo "FAILED: $t, $(($(date +%s) - s)) s (log: $dir/$t.log)"
    # The first sanitizer report or failed assertion, to see at a glance what happened.
    grep -m 3 -E "ERROR: (Address|Leak)Sanitizer|runtime error|WARNING: ThreadSanitizer|\[  FAILED  \]" \
      "$dir/$t.log" | sed 's/^/    /' || true
  else
    ran=$(grep -o -m 1 -E '[0-9]+ tests? from [0-9]+ test suites? ran' "$dir/$t.log" || true)
    echo "passed: $t, $(($(date +%s) - s)) s${ran:+ ($ran)}"
  fi
done
t2=$(date +%s)
echo "sanitize.sh $mode: ${#tests[@]} executables, ${#failed[@]} failed, run took $((t2 - t1)) s"
if [ ${#not_run[@]} -gt 0 ]; then
  echo "not run: ${#not_run[@]} tests (${unsanitizable[*]}: not under a sanitizer; the others" \
    "over ${max_cost} s in Release, RGBDI_SAN_MAX_COST=all runs them):"
  printf '  %s\n' "${not_run[@]}"
fi
[ ${#failed[@]} -eq 0 ]
