#!/usr/bin/env bash
# The benchmark suite (doc/benchmark-suite.md): rows of bench/suite/suite.json run on cached
# generated sequences, per-condition tables, and the paired comparison of two builds.
#   scripts/suite.sh plan [--tier quick|full]
#   scripts/suite.sh run [--tier quick|full] [--label NAME] [--build DIR] [--sim-build DIR]
#                        [--jobs 1|2] [--only REGEX] [--duration S] [--resume]
#   scripts/suite.sh report LABEL
#   scripts/suite.sh compare OLD_LABEL NEW_LABEL
# SUITE_OUT (default out/suite) holds runs/<label>/; SUITE_CACHE (default SUITE_OUT/cache) the
# generated sequences; SUITE_CACHE_MAX_GB bounds the cache (least recently used entries go).
set -euo pipefail
[ -x /usr/bin/time ] || {
  echo "suite: /usr/bin/time not found (apt-get install time, or scripts/setup-deps.sh)" >&2
  exit 1
}
exec /usr/bin/python3 "$(dirname "$0")/../bench/suite/suite.py" "$@"
