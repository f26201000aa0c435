#!/usr/bin/env bash
# Checks that every C++ source of the repository is formatted as .clang-format says (Debian 12's
# clang-format 14; other versions may format differently). Lists the files that differ.
#   scripts/check-format.sh          check (exit 1 when a file differs)
#   scripts/check-format.sh --fix    format the files in place
# The test suite runs the check as the ctest test `clang_format` (label `format`).
set -euo pipefail
cd "$(dirname "$0")/.."
tool=${CLANG_FORMAT:-clang-format}
command -v "$tool" >/dev/null || { echo "check-format: $tool not found (apt install clang-format)" >&2; exit 2; }
mapfile -t files < <(git ls-files '*.cpp' '*.h' 2>/dev/null || find apps bench fuzz libs tests -name '*.cpp' -o -name '*.h')
if [ "${1:-}" = "--fix" ]; then
  "$tool" -i "${files[@]}"
  echo "check-format: formatted ${#files[@]} files"
  exit 0
fi
# One clang-format process for all files; it names each file that differs (first difference).
if ! report=$("$tool" --dry-run --Werror "${files[@]}" 2>&1); then
  mapfile -t differ < <(printf '%s\n' "$report" | sed -n 's/^\([^:]*\):[0-9]*:[0-9]*: error: .*/\1/p' | sort -u)
  printf 'check-format: not formatted as .clang-format says: %s\n' "${differ[@]}" >&2
  echo "check-format: ${#differ[@]} of ${#files[@]} files differ; scripts/check-format.sh --fix formats them" >&2
  exit 1
fi
echo "check-format: all ${#files[@]} files formatted ($("$tool" --version | head -1))"
