#!/usr/bin/env bash
# Runs every libFuzzer target for SECONDS each (default 60), one after the other.
#   scripts/fuzz.sh [SECONDS] [TARGET...]     targets: rawlog bag ros_messages tum ini vins_yaml
#                                            keyframe_store map_files image_decode (default: all)
# Builds build-fuzz/ with clang (-DRGBDI_FUZZ=ON) and the seed writers (fuzz_replay_*) in build/,
# keeps the growing corpora in build-fuzz/corpus/<target>/ (not in git) and crashes in
# build-fuzz/findings/<target>/. A finding is replayed with build/bin/fuzz_replay_<target> FILE.
# Environment: JOBS (default 2); RGBDI_FUZZ_TMPDIR (default /dev/shm when writable, else TMPDIR):
# where the targets that read files write each input (fuzz_support.cpp: the temporary directory).
# On disk, ext4 writes a truncated file's data back before the next write (its replace-by-
# truncate heuristic), so a target spent most of its time waiting (fuzz_image_decode: 11 % of a
# core, state D) instead of fuzzing.
# Exit status: 0 no finding, 1 a target found a crash, 2 usage.
# Needs clang and libFuzzer (Debian 12: clang, libclang-rt-14-dev); installs them with apt-get
# when they are missing (setup-deps.sh does not: CI does not fuzz). LeakSanitizer reports inside
# MRPT/OpenCV are suppressed by fuzz/lsan.supp (each entry with its reason).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
case "$seconds" in ''|*[!0-9]*) echo "usage: scripts/fuzz.sh [SECONDS] [TARGET...]" >&2; exit 2;; esac
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(rawlog bag ros_messages tum ini vins_yaml keyframe_store map_files image_decode)
jobs="${JOBS:-2}"
fuzzer_lib() { clang++ -print-file-name=libclang_rt.fuzzer-x86_64.a 2>/dev/null || true; }
if ! command -v clang++ >/dev/null || [ ! -f "$(fuzzer_lib)" ] || ! command -v ccache >/dev/null; then
  sudo=()
  [ "$(id -u)" -eq 0 ] || sudo=(sudo)
  echo "fuzz.sh: installing clang, libFuzzer (libclang-rt-14-dev) and ccache" >&2
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends clang libclang-rt-14-dev ccache >/dev/null
fi
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" >/dev/null
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  "${launcher[@]}" -DRGBDI_FUZZ=ON >/dev/null
ninja -C build -j "$jobs" "${targets[@]/#/fuzz_replay_}"
ninja -C build-fuzz -j "$jobs" "${targets[@]/#/fuzz_}"

scratch="${RGBDI_FUZZ_TMPDIR:-}"
if [ -z "$scratch" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then scratch=/dev/shm; fi
[ -z "$scratch" ] || export TMPDIR="$scratch"

found=0
for t in "${targets[@]}"; do
  corpus="build-fuzz/corpus/$t"
  findings="build-fuzz/findings/$t"
  mkdir -p "$corpus" "$findings"
  [ -n "$(ls -A "$corpus")" ] || "build/bin/fuzz_replay_$t" --write-seeds "$corpus"
  echo "== fuzz_$t for $seconds s"
  # A corrupt size field makes MRPT / ROS allocate gigabytes (doc/robustness.md, open findings):
  # ASan returns null for allocations above 1 GiB, the readers turn the bad_alloc into their
  # refusal, and fuzzing goes on past it (libFuzzer's own malloc limit is set above ASan's).
  if ! ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1:max_allocation_size_mb=1024" \
      LSAN_OPTIONS="suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0" \
      UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1" "build-fuzz/bin/fuzz_$t" "$corpus" \
      -max_total_time="$seconds" -max_len=262144 -rss_limit_mb=2560 -malloc_limit_mb=2048 \
      -timeout=10 \
      -artifact_prefix="$findings/" -print_final_stats=1 2>"build-fuzz/fuzz_$t.log"; then
    found=1
    echo "fuzz_$t: FINDING, see $findings/ and build-fuzz/fuzz_$t.log"
  fi
  grep -E "^stat::(number_of_executed_units|new_units_added)|cov: " "build-fuzz/fuzz_$t.log" |
    tail -n 3 || true
  echo "corpus: $(find "$corpus" -type f | wc -l) inputs"
done
exit $found
