#!/usr/bin/env bash
# The checks a change must pass before review, short of the tests:
#   1. the C++ files it changed are clang-format clean (scripts/format.sh --check);
#   2. the include layers of docs/architecture.md hold (scripts/check_layers.py);
#   3. everything compiles without a warning: the ci preset builds with
#      -Wall -Wextra -Wpedantic -Wshadow -Werror (cmake/warnings.cmake).
# clang-tidy and cppcheck are not used: the Debian 12 versions (clang-tidy 14, cppcheck 2.10)
# cannot parse the GCC vector extensions of spectrum/sampled.h and the C++20 template lambdas
# of bsdf/bsdf.h, so they report errors in every file and check nothing beyond them.
# Usage: scripts/lint.sh [FILE...]   (files for the format check; default: the changed ones)
set -euo pipefail
cd "$(dirname "$0")/.."
status=0
scripts/format.sh --check "$@" || status=1
python3 scripts/check_layers.py || status=1
cmake --preset ci >/dev/null && cmake --build --preset ci -j "${JOBS:-2}" || status=1
[ $status -eq 0 ] && echo "lint: passed"
exit $status
