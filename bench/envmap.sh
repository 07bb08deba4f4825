#!/usr/bin/env bash
# Cost of an environment map against a constant infinite light: the bundled materials scene
# (its area light kept) lit once by a 512 x 256 lat-long sky with a sun (made here, resampled
# at load to a 512^2 equal-area map) and once by a constant "rgb L", at equal samples per
# pixel; prints the render CPU seconds (load excluded) of each and their ratio.
# Usage: bench/envmap.sh [BINARY] [SPP] [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/release/steradian}
spp=${2:-32}
runs=${3:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 - "$tmp/sky.pfm" <<'PY'
import math, struct, sys
w, h = 512, 256
sun = [0.3, 0.6, 0.74]
n = math.sqrt(sum(c * c for c in sun)); sun = [c / n for c in sun]
cos_sun = math.cos(math.radians(2))
with open(sys.argv[1], "wb") as f:
    f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
    for y in reversed(range(h)):  # PFM rows go bottom to top
        th = (y + 0.5) / h * math.pi
        row = []
        for x in range(w):
            ph = (x + 0.5) / w * 2 * math.pi
            d = (math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th))
            if sum(a * b for a, b in zip(d, sun)) > cos_sun:
                p = (3000, 2800, 2500)
            elif d[2] > 0:
                p = (0.3 + 0.5 * (1 - d[2]), 0.5 + 0.4 * (1 - d[2]), 1.0)
            else:
                p = (0.25, 0.2, 0.15)
            row.append(struct.pack("<3f", *p))
        f.write(b"".join(row))
PY
light='LightSource "infinite" "blackbody L" \[ 6500 \] "float scale" \[ 0.35 \]'
sed -e "s|$light|LightSource \"infinite\" \"string filename\" \"$tmp/sky.pfm\"|" \
    -e 's|"integer xresolution" \[ 800 \] "integer yresolution" \[ 500 \]|"integer xresolution" [ 320 ] "integer yresolution" [ 200 ]|' \
    scenes/materials.pbrt > "$tmp/env.pbrt"
sed -e "s|$light|LightSource \"infinite\" \"rgb L\" [ 0.5 0.6 0.9 ]|" \
    -e 's|"integer xresolution" \[ 800 \] "integer yresolution" \[ 500 \]|"integer xresolution" [ 320 ] "integer yresolution" [ 200 ]|' \
    scenes/materials.pbrt > "$tmp/const.pbrt"
grep -q "sky.pfm" "$tmp/env.pbrt" || { echo "envmap.sh: could not edit scenes/materials.pbrt"; exit 1; }
cpu() { "$bin" render "$1" -o "$tmp/out.exr" --spp "$spp" --threads 1 2>&1 | awk '/CPU time/ {print $3}'; }
env_total=0; const_total=0
for r in $(seq "$runs"); do
  e=$(cpu "$tmp/env.pbrt"); c=$(cpu "$tmp/const.pbrt")
  echo "run $r: environment map $e s, constant $c s (render CPU, 1 thread, $spp spp)"
  env_total=$(awk "BEGIN {print $env_total + $e}"); const_total=$(awk "BEGIN {print $const_total + $c}")
done
echo "ratio environment / constant: $(awk "BEGIN {printf \"%.3f\", $env_total / $const_total}")"
