#!/usr/bin/env bash
# Formats C++ sources with clang-format (the repository's .clang-format; clang-format 14,
# Debian's clang-format package). Only the files you changed are touched, so that a
# change's diff holds its own lines: by default the C++ files that differ from the merge
# base with main (committed, staged or not) plus untracked ones; or the files given.
# Usage: scripts/format.sh [--check] [FILE...]
#   --check   change nothing; list the files that are not formatted and exit 1 if any
set -euo pipefail
cd "$(dirname "$0")/.."
check=0
if [ "${1:-}" = "--check" ]; then check=1; shift; fi
if [ $# -gt 0 ]; then
  files=("$@")
else
  base=$(git merge-base HEAD main 2>/dev/null || git rev-parse HEAD)
  mapfile -t files < <({ git diff --name-only --diff-filter=ACMR "$base" -- '*.cpp' '*.h';
                         git ls-files --others --exclude-standard -- '*.cpp' '*.h'; } | sort -u)
fi
[ ${#files[@]} -eq 0 ] && { echo "format: no changed C++ files"; exit 0; }
bad=0
for f in "${files[@]}"; do
  [ -f "$f" ] || continue
  if [ $check -eq 1 ]; then
    if ! clang-format --dry-run --Werror "$f" >/dev/null 2>&1; then echo "not formatted: $f"; bad=1; fi
  else
    clang-format -i "$f"
  fi
done
[ $check -eq 1 ] && [ $bad -eq 0 ] && echo "format: ${#files[@]} files formatted"
exit $bad
