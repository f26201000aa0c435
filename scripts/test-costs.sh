#!/bin/bash
# Rewrites tests/test_costs.txt (the ctest COST of every test that takes a second or more) from
# the times ctest measured in a build tree's last runs (Testing/Temporary/CTestCostData.txt, the
# running average ctest keeps per test). Run it after a whole-suite ctest run on a quiet machine
# when tests were added or got much slower or faster; CI starts from a clean tree without that
# data, so these figures are what orders its ctest -j run (longest first).
#   scripts/test-costs.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
data="$build/Testing/Temporary/CTestCostData.txt"
[ -f "$data" ] || { echo "test-costs: $data not found (run ctest in $build first)" >&2; exit 1; }
out=tests/test_costs.txt
{
  echo "# ctest COST per test: measured seconds (ctest -j starts the costliest first)."
  echo "# Written by scripts/test-costs.sh from $(basename "$build")'s ctest runs on $(date +%F); tests under 1 s"
  echo "# are left out (cost 0: they fill the gaps at the end). Format: <seconds> <test name>."
  # Lines "name runs average" up to the '---' that starts the failed-tests list; names with
  # spaces or brackets (parameterised tests) are short and left out.
  awk '/^---/ { exit } NF == 3 && $3 >= 1 && $1 !~ /[][]/ { printf "%d %s\n", $3 + 0.999, $1 }' \
    "$data" | sort -k1,1nr -k2,2
} > "$out.tmp"
mv "$out.tmp" "$out"
echo "test-costs: $(grep -c '^[0-9]' "$out") tests in $out"
