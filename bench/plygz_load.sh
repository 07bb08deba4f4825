#!/usr/bin/env bash
# Load time of a 10-million-triangle gzip-compressed binary PLY (the issue "Real pbrt-v4
# scenes": under 3 s on a 2-core machine). Generates a height-field grid of 2237 x 2237
# vertices (9,999,392 triangles; float positions and normals, uchar/int faces) once into
# DIR, gzips it, and renders a 1-spp, 8 x 8 image of it with the compressed and the
# uncompressed mesh, printing the summary's "scene load" (parse + PLY + gunzip + Embree
# build) of each, best of RUNS, and each run's CPU seconds. The render traces 64 camera
# paths, fewer than the mesh's triangles, so the mesh gets Embree's Morton build (accel.cpp).
# Usage: bench/plygz_load.sh [BINARY] [DIR] [RUNS]
set -euo pipefail
bin=${1:-build/release/steradian}
dir=${2:-/tmp/steradian_plygz}
runs=${3:-3}
mkdir -p "$dir"
if [ ! -s "$dir/grid.ply.gz" ]; then
  python3 - "$dir/grid.ply" <<'PY'
import math, struct, sys
w = 2237
nv, nf = w * w, (w - 1) * (w - 1) * 2
with open(sys.argv[1], "wb") as f:
    f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\n"
             "property float x\nproperty float y\nproperty float z\n"
             "property float nx\nproperty float ny\nproperty float nz\n"
             "element face %d\nproperty list uchar int vertex_indices\nend_header\n"
             % (nv, nf)).encode())
    row = struct.Struct("<" + "ffffff" * w)
    for j in range(w):
        y = j / (w - 1) * 10.0
        vals = []
        for i in range(w):
            x = i / (w - 1) * 10.0
            dx, dy = math.cos(x) * math.cos(y), -math.sin(x) * math.sin(y)
            inv = 1.0 / math.sqrt(dx * dx + dy * dy + 1.0)
            vals += (x, y, math.sin(x) * math.cos(y), -dx * inv, -dy * inv, inv)
        f.write(row.pack(*vals))
    tri = struct.Struct("<" + "BIII" * (2 * (w - 1)))
    for j in range(w - 1):
        vals = []
        for i in range(w - 1):
            a = j * w + i
            vals += (3, a, a + 1, a + w + 1, 3, a, a + w + 1, a + w)
        f.write(tri.pack(*vals))
PY
  gzip -6 -k -f "$dir/grid.ply"
fi
ls -l "$dir/grid.ply" "$dir/grid.ply.gz"
for mesh in grid.ply.gz grid.ply; do
  cat > "$dir/scene-$mesh.pbrt" <<SCENE
LookAt 5 -8 12  5 5 0  0 0 1
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ] "string filename" "grid.exr"
Sampler "independent" "integer pixelsamples" [ 1 ]
WorldBegin
LightSource "distant" "point3 from" [ 0 0 10 ] "point3 to" [ 0 0 0 ]
Shape "plymesh" "string filename" "$mesh"
SCENE
  best=""
  cpus=""
  for _ in $(seq "$runs"); do
    # The whole process's CPU time (user + sys, from /usr/bin/time); the 64-pixel render
    # adds milliseconds.
    out=$(/usr/bin/time -f "cpu %U %S" "$bin" render "$dir/scene-$mesh.pbrt" -o "$dir/grid.pfm" 2>&1)
    t=$(echo "$out" | awk '/scene load/ {print $3}')
    cpus="$cpus $(echo "$out" | awk '/^cpu / {printf "%.2f", $2 + $3}')"
    if [ -z "$best" ] || awk "BEGIN{exit !($t < $best)}"; then best=$t; fi
  done
  echo "$mesh: scene load $best s (best of $runs); CPU-s of the runs:$cpus"
done
