#!/usr/bin/env bash
# Strong scaling of steradian-mpi (docs/distributed.md): the Cornell box (512x512, maxdepth
# 16) at a fixed sample count, on 1 process of 1 thread (steradian, no MPI), then under
# mpirun on N = 1, 2, 3, 4 processes of one thread each (oversubscribed beyond the cores).
# Prints per run the wall seconds (the whole mpirun, start-up included, and the render
# alone as process 0 times it), the CPU seconds of all processes, the speed-up and the
# parallel efficiency against the one-process render, and checks that every image is
# bit-identical to the one-process image. INTEGRATOR=bdpt (or lightpath) renders with that
# integrator at MAXDEPTH (default 5) instead, and prints the splat reduction's figures
# (splats added in tile order, the coordinator's seconds adding them, the bytes of splat
# lists received from the other processes). INTEGRATOR=mlt or sppm work too (SPP is then
# the mutations per pixel, or the iterations; PARAMS adds parameters to the Integrator line,
# e.g. PARAMS='"float radius" [ 4 ]'); their summary line "splats" counts mlt's splats, or
# sppm's deposits from the workers' photons (and the bytes of their photon hits).
# Usage: [SPP=32] [RANKS="1 2 3 4"] [INTEGRATOR=bdpt [MAXDEPTH=5] [PARAMS=...]]
#        [BUILD=build/release] bench/mpi_scaling.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD:-build/release}
spp=${SPP:-32}
ranks=${RANKS:-1 2 3 4}
one=$build/steradian
bin=$build/steradian-mpi
[ -x "$bin" ] || { echo "build first: cmake --preset release && cmake --build --preset release (with Open MPI installed)"; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1  # harmless when not root
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scene=scenes/cornell-box.pbrt
if [ -n "${INTEGRATOR:-}" ]; then
  sed "s/^Integrator .*/Integrator \"$INTEGRATOR\" \"integer maxdepth\" [ ${MAXDEPTH:-5} ] ${PARAMS:-}/" "$scene" > "$tmp/scene.pbrt"
  scene=$tmp/scene.pbrt
fi
echo "cores: $(nproc); scene: scenes/cornell-box.pbrt (${INTEGRATOR:-path}) at $spp spp; one thread per process"
printf '%-22s %10s %10s %10s %8s %10s %s\n' run "wall(job)" "wall(rnd)" "CPU(all)" speedup efficiency image
t0=$(date +%s.%N)
"$one" render "$scene" --spp "$spp" --threads 1 -o "$tmp/ref.pfm" > "$tmp/ref.txt" 2>&1
t1=$(date +%s.%N)
base=$(awk '/wall time/ {print $3}' "$tmp/ref.txt")
cpu=$(awk '/CPU time/ {print $3}' "$tmp/ref.txt")
printf '%-22s %10.2f %10.2f %10.2f %8s %10s %s\n' "steradian (1 process)" "$(echo "$t1 - $t0" | bc)" "$base" "$cpu" 1.00 100% reference
for n in $ranks; do
  t0=$(date +%s.%N)
  mpirun -n "$n" --oversubscribe "$bin" render "$scene" --spp "$spp" --threads 1 -o "$tmp/mpi$n.pfm" > "$tmp/mpi$n.txt" 2>&1
  t1=$(date +%s.%N)
  wall=$(awk '/wall time/ {print $3}' "$tmp/mpi$n.txt")
  cpu=$(awk '/CPU time of all/ {print $7}' "$tmp/mpi$n.txt")
  [ -n "$cpu" ] || cpu=$(awk '/CPU time/ {print $3}' "$tmp/mpi$n.txt")
  same=$(cmp -s "$tmp/ref.pfm" "$tmp/mpi$n.pfm" && echo identical || echo DIFFERENT)
  speedup=$(echo "scale=2; $base / $wall" | bc)
  eff=$(echo "scale=0; 100 * $base / $wall / $n" | bc)
  printf '%-22s %10.2f %10.2f %10.2f %8s %9s%% %s\n' "mpirun -n $n" "$(echo "$t1 - $t0" | bc)" "$wall" "$cpu" "$speedup" "$eff" "$same"
  grep -h "^  splats\|^  processes" "$tmp/mpi$n.txt" || true
done
