#!/usr/bin/env bash
# The whole test suite: a Release build with -Werror running every test (unit, stat, pbrt,
# scene), then the unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer.
# The sanitizer build is the fuzz preset's (clang-14, ASan + UBSan + libFuzzer's coverage
# instrumentation): one build serves both the sanitized unit tests and the fuzz harnesses,
# instead of a separate gcc ASan build of the whole library (the `asan` preset, kept for
# gcc's sanitizers by hand). The fuzz preset compiles with -ffp-contract=off: clang fuses
# a*b+c into FMAs in other places than gcc does, and the unit tests that compare two code
# paths bit for bit (a spectrum sampled against evaluated, the cloud density against its
# definition term by term) hold for uncontracted arithmetic.
# In CI (CI=true, set by .ci/run) it then fuzzes every input reader for 20 s each
# (scripts/fuzz.sh, reusing that build; FUZZ_SECONDS overrides, 0 skips).
# Usage: scripts/test.sh [--no-asan]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${JOBS:-2}

cmake --preset ci
cmake --build --preset ci -j "$jobs"
ctest --preset ci -j "$jobs"

if [ "${1:-}" != "--no-asan" ]; then
  cmake --preset fuzz
  cmake --build --preset fuzz -j "$jobs" --target steradian_unit_tests steradian_fuzz_replay
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --preset fuzz -j "$jobs" -L unit
fi

if [ "${CI:-}" = "true" ] && [ "${FUZZ_SECONDS:-20}" != 0 ]; then
  scripts/fuzz.sh "${FUZZ_SECONDS:-20}"
fi
