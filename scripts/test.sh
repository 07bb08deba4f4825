#!/usr/bin/env bash
# The whole test suite: a Release build with -Werror running every test (unit, stat, pbrt,
# scene), then the unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer.
# In CI (CI=true, set by .ci/run) it then fuzzes every input reader for 30 s each
# (scripts/fuzz.sh; FUZZ_SECONDS overrides, 0 skips).
# Usage: scripts/test.sh [--no-asan]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${JOBS:-2}

cmake --preset ci
cmake --build --preset ci -j "$jobs"
ctest --preset ci -j "$jobs"

if [ "${1:-}" != "--no-asan" ]; then
  cmake --preset asan
  cmake --build --preset asan -j "$jobs" --target steradian_unit_tests steradian_fuzz_replay
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --preset asan -j "$jobs" -L unit
fi

if [ "${CI:-}" = "true" ] && [ "${FUZZ_SECONDS:-30}" != 0 ]; then
  scripts/fuzz.sh "${FUZZ_SECONDS:-30}"
fi
