#!/usr/bin/env bash
# Paired comparison of two steradian builds on the Cornell box: each round renders with both
# binaries at the same time, one thread each (one per core of a 2-core machine), so that both
# see the same machine load; the ratio of their CPU seconds is then far steadier than that of
# runs made one after the other on a shared machine.
# Usage: bench/ab.sh OLD_BINARY NEW_BINARY [ROUNDS (5)] [SPP (64)]
# Prints each round's CPU seconds and the new/old ratio, then the mean ratio and its standard
# error over the rounds.
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { sed -n 2,8p "$0"; exit 2; }
old=$1 new=$2 rounds=${3:-5} spp=${4:-64}
for b in "$old" "$new"; do [ -x "$b" ] || { echo "not an executable: $b"; exit 2; }; done
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
for ((i = 0; i < rounds; ++i)); do
  "$old" render scenes/cornell-box.pbrt -o "$dir/old.exr" --spp "$spp" --threads 1 >"$dir/old.txt" 2>&1 &
  "$new" render scenes/cornell-box.pbrt -o "$dir/new.exr" --spp "$spp" --threads 1 >"$dir/new.txt" 2>&1 &
  wait
  echo "$(awk '/CPU time/ {print $3}' "$dir/old.txt") $(awk '/CPU time/ {print $3}' "$dir/new.txt")"
done | awk '{ r = $2 / $1; s += r; ss += r * r; printf "  old %6.2f s   new %6.2f s   new/old %.3f\n", $1, $2, r }
  END { m = s / NR; se = NR > 1 ? sqrt((ss / NR - m * m) * NR / (NR - 1) / NR) : 0;
        printf "  mean new/old %.3f (standard error %.3f, %d rounds, CPU seconds, 1 thread each)\n", m, se, NR }'
