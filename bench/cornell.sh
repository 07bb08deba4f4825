#!/usr/bin/env bash
# Whole-scene benchmark: the Cornell box at 512x512, 64 spp, maxdepth 16 (the scene's own
# settings), on all cores. Prints wall seconds, CPU seconds, camera paths/s, rays/s, and the
# RMSE against pbrt-v4's 1024-spp render (pbrt-v4's own 64-spp image: 0.01103).
# Usage: [RUNS=N] bench/cornell.sh [extra steradian options]
# With RUNS=N (default 1) the render runs N times and the CPU seconds of every run and their
# minimum are printed too: on a shared machine single runs vary by up to 20 %.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/release/steradian
[ -x "$bin" ] || { echo "build first: cmake --preset release && cmake --build --preset release"; exit 1; }
runs=${RUNS:-1}
out=$(mktemp -d)/cornell.exr
cpu=()
for ((i = 0; i < runs; ++i)); do
  summary=$("$bin" render scenes/cornell-box.pbrt -o "$out" "$@" 2>&1 | sed -n '/wall time/,$p')
  cpu+=("$(echo "$summary" | awk '/CPU time/ {print $3}')")
done
echo "$summary"
if ((runs > 1)); then
  echo "  CPU seconds of $runs runs: ${cpu[*]} (minimum $(printf '%s\n' "${cpu[@]}" | sort -g | head -1))"
fi
if command -v oiiotool >/dev/null; then
  ref=tests/data/reference/cornell-box/pbrt-v4-1024spp.exr
  # oiiotool --diff reports the RMS error of the difference over all channels.
  oiiotool "$out" --ch R,G,B "$ref" --ch R,G,B --diff 2>/dev/null | grep -i "rms" | sed 's/^ */  RMSE vs pbrt-v4 1024 spp: /' || true
fi
