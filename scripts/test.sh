#!/usr/bin/env bash
# The whole test suite: a Release build with -Werror running every test (unit, stat, pbrt,
# scene), then the unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer.
# Usage: scripts/test.sh [--no-asan]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${JOBS:-2}

cmake --preset ci
cmake --build --preset ci -j "$jobs"
ctest --preset ci -j "$jobs"

if [ "${1:-}" != "--no-asan" ]; then
  cmake --preset asan
  cmake --build --preset asan -j "$jobs" --target steradian_unit_tests
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --preset asan -j "$jobs" -L unit
fi
