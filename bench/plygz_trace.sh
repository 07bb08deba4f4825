#!/usr/bin/env bash
# What Embree's Morton build (LOW) costs in tracing against MEDIUM, on the 10-million-
# triangle height field of bench/plygz_load.sh (run that first: it makes DIR/grid.ply).
# accel.cpp builds a mesh of more than 2 M triangles with LOW when the render traces fewer
# camera paths than half the mesh's triangles (9,999,392 / 2), else with MEDIUM; renders just
# below and just above that threshold (390 x 390 and 400 x 400 pixels at 32 spp: 4.87 M and
# 5.12 M paths of the path tracer) get the two builds for nearly the same work. Prints the
# summary's scene load and render CPU time and the render CPU-microseconds per path.
# Usage: bench/plygz_trace.sh [BINARY] [DIR] [RUNS]
set -euo pipefail
bin=${1:-build/release/steradian}
dir=${2:-/tmp/steradian_plygz}
runs=${3:-1}
[ -s "$dir/grid.ply" ] || { echo "no $dir/grid.ply: run bench/plygz_load.sh first" >&2; exit 1; }
for side in 390 400; do
  cat > "$dir/trace-$side.pbrt" <<SCENE
LookAt 5 -8 12  5 5 0  0 0 1
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ $side ] "integer yresolution" [ $side ] "string filename" "trace.exr"
Sampler "independent" "integer pixelsamples" [ 32 ]
WorldBegin
LightSource "distant" "point3 from" [ 0 0 10 ] "point3 to" [ 0 0 0 ]
Shape "plymesh" "string filename" "grid.ply"
SCENE
  quality=$([ $((side * side * 32)) -lt $((9999392 / 2)) ] && echo LOW || echo MEDIUM)
  for _ in $(seq "$runs"); do
    out=$("$bin" render "$dir/trace-$side.pbrt" -o "$dir/trace-$side.exr" 2>&1)
    load=$(echo "$out" | awk '/scene load/ {print $3}')
    cpu=$(echo "$out" | awk '/CPU time/ {print $3}')
    echo "$side x $side, 32 spp ($quality): scene load $load s, render $cpu CPU-s," \
      "$(awk "BEGIN{printf \"%.3f\", $cpu * 1e6 / ($side * $side * 32)}") CPU-us per path"
  done
done
