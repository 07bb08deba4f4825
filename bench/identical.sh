#!/usr/bin/env bash
# Checks that two builds compute the same thing: renders every bundled and reference scene
# with both binaries (4 threads vs 1 thread too, for determinism) and compares the images
# byte for byte (PFM: raw floats, no metadata), then runs the photometric test cases through
# `measure` with both and compares the readings. Meant for refactors that must not change
# behaviour (the issue's "images bit-identical before and after").
# Usage: bench/identical.sh OLD_BINARY NEW_BINARY [SPP]
set -euo pipefail
cd "$(dirname "$0")/.."
old=${1:?usage: bench/identical.sh OLD_BINARY NEW_BINARY [SPP]}
new=${2:?usage: bench/identical.sh OLD_BINARY NEW_BINARY [SPP]}
spp=${3:-8}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

scenes=(scenes/*.pbrt tests/data/reference/*/scene.pbrt tests/data/identical/*.pbrt)
same=0
differ=0
for s in "${scenes[@]}"; do
  name=$(echo "$s" | tr '/' '_')
  "$old" render "$s" -o "$tmp/$name.old.pfm" --spp "$spp" --quiet
  "$new" render "$s" -o "$tmp/$name.new.pfm" --spp "$spp" --quiet --threads 1
  if cmp -s "$tmp/$name.old.pfm" "$tmp/$name.new.pfm"; then
    echo "identical  $s ($spp spp)"
    same=$((same + 1))
  else
    echo "DIFFERENT  $s ($spp spp)"
    differ=$((differ + 1))
  fi
done

# Readings: the meters' values and standard errors (the JSON's timing fields removed).
for s in tests/data/cie171/*.pbrt; do
  name=$(basename "$s" .pbrt)
  "$old" measure "$s" --rel-error 0.02 --json "$tmp/$name.old.json" --quiet --seed 1 >/dev/null
  "$new" measure "$s" --rel-error 0.02 --json "$tmp/$name.new.json" --quiet --seed 1 --threads 1 >/dev/null
  strip='del(.wall_seconds, .cpu_seconds)'
  if command -v jq >/dev/null; then
    jq -S "$strip" "$tmp/$name.old.json" >"$tmp/$name.old.norm" 2>/dev/null || cp "$tmp/$name.old.json" "$tmp/$name.old.norm"
    jq -S "$strip" "$tmp/$name.new.json" >"$tmp/$name.new.norm" 2>/dev/null || cp "$tmp/$name.new.json" "$tmp/$name.new.norm"
  else
    grep -v -E '"(wall_seconds|cpu_seconds|seconds)"' "$tmp/$name.old.json" >"$tmp/$name.old.norm" || true
    grep -v -E '"(wall_seconds|cpu_seconds|seconds)"' "$tmp/$name.new.json" >"$tmp/$name.new.norm" || true
  fi
  if cmp -s "$tmp/$name.old.norm" "$tmp/$name.new.norm"; then
    echo "identical  $s (measure readings)"
    same=$((same + 1))
  else
    echo "DIFFERENT  $s (measure readings)"
    diff "$tmp/$name.old.norm" "$tmp/$name.new.norm" | head -20 || true
    differ=$((differ + 1))
  fi
done
echo "$same identical, $differ different"
[ "$differ" -eq 0 ]
