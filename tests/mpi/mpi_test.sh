#!/usr/bin/env bash
# steradian-mpi under mpirun (docs/distributed.md): renders and meter readings of 2 and 3
# processes are bit-identical to the one-process ones (the renderer's determinism rule: the
# same scene, seed and sample count give the same image and readings however the work is
# split) for the path tracer, the splatting integrators (bdpt, lightpath, mlt), sppm, vcm and the
# radiosity method, a reading keeps its closed form, a dying process fails the job in bounded time,
# and errors are reported once.
# Usage: tests/mpi/mpi_test.sh path/to/steradian path/to/steradian-mpi MPIEXEC
set -u
one=$(realpath "$1")
bin=$(realpath "$2")
mpiexec=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0
fail=0
check() {  # check NAME CONDITION...
  local name=$1
  shift
  if "$@"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $name"; fi
}
# This machine may have fewer cores than processes (--oversubscribe), and tests may run as
# root, which Open MPI refuses unless told.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
run() {  # run N ARGS... : steradian-mpi on N processes of one thread each, bounded in time
  local n=$1
  shift
  timeout 60 "$mpiexec" -n "$n" --oversubscribe "$bin" "$@"
}

# A diffuse sphere over a diffuse floor lit by a spherical area light: indirect light, a
# crop window (tiles that are not whole), 72 samples per pixel (two passes: 64 + 8).
cat > "$tmp/scene.pbrt" <<'SCENE'
LookAt 0 1 -4  0 0.5 0  0 1 0
Camera "perspective" "float fov" [ 45 ]
Film "rgb" "integer xresolution" [ 40 ] "integer yresolution" [ 30 ] "string filename" "s.pfm"
     "float cropwindow" [ 0.05 0.95 0 1 ]
Sampler "zsobol" "integer pixelsamples" [ 72 ]
WorldBegin
AttributeBegin
  Translate 1 3 -1
  AreaLightSource "diffuse" "rgb L" [ 8 8 8 ]
  Shape "sphere" "float radius" [ 0.4 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.6 0.5 0.4 ]
Shape "trianglemesh" "point3 P" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeBegin
  Translate 0 0.7 0
  Material "diffuse" "rgb reflectance" [ 0.2 0.7 0.3 ]
  Shape "sphere" "float radius" [ 0.7 ]
AttributeEnd
SCENE
# The meters measured below; and for `render`, whose meters aim at 0.1 % (too slow for a
# test), one that sees no light from under the floor (0 lx, 0 standard error after the pilot
# round), so that the render and then the measurement share one session of the processes.
cp "$tmp/scene.pbrt" "$tmp/meters.pbrt"
cat >> "$tmp/meters.pbrt" <<'SCENE'
Meter "illuminance" "string name" "floor" "point3 p" [ 1.5 0 0  -1.5 0 0 ] "normal n" [ 0 1 0 ]
Meter "illuminancegrid" "string name" "grid" "point3 corner" [ -2 0.01 -2 ] "vector3 u" [ 4 0 0 ]
      "vector3 v" [ 0 0 4 ] "integer resolution" [ 3 2 ]
SCENE
echo 'Meter "illuminance" "string name" "dark" "point3 p" [ 0 -0.01 0 ] "normal n" [ 0 -1 0 ]' >> "$tmp/scene.pbrt"

"$one" render "$tmp/scene.pbrt" -o "$tmp/ref.pfm" --threads 1 --quiet
check "one process renders" test -s "$tmp/ref.pfm"
for n in 2 3; do
  run "$n" render "$tmp/scene.pbrt" -o "$tmp/mpi$n.pfm" --threads 1 --quiet > "$tmp/r$n.txt" 2>&1
  check "mpirun -n $n render exits 0" test $? -eq 0
  check "mpirun -n $n render: the image is bit-identical to one process's" cmp -s "$tmp/ref.pfm" "$tmp/mpi$n.pfm"
  # The meters' readings written beside the image, compared value by value (every digit).
  check "mpirun -n $n render: the meters' readings equal one process's" python3 - "$tmp/ref.meters.json" "$tmp/mpi$n.meters.json" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
key = lambda d: [(m["name"], m["values"], m["stderr"], m["samples"]) for m in d["meters"]]
sys.exit(0 if key(a) == key(b) and a["paths"] == b["paths"] else 1)
PY
done
# Threads within processes change nothing either; nor does pacing the passes for checkpoints
# (8, 16, 32, 16 samples per pixel), with the coordinator writing the checkpoint.
run 2 render "$tmp/scene.pbrt" -o "$tmp/ck.pfm" --threads 2 --checkpoint "$tmp/ck.ckpt" --quiet > "$tmp/ck.txt" 2>&1
check "mpirun -n 2 render --checkpoint exits 0" test $? -eq 0
check "mpirun -n 2 render --checkpoint: the image is bit-identical" cmp -s "$tmp/ref.pfm" "$tmp/ck.pfm"
check "mpirun -n 2 render --checkpoint writes the checkpoint" test -s "$tmp/ck.ckpt"
# The summary comes from process 0 alone, with the CPU time of all processes.
run 3 render "$tmp/scene.pbrt" -o "$tmp/sum.pfm" --threads 1 > "$tmp/sum.txt" 2>&1
check "the summary is printed once" test "$(grep -c 'scene load' "$tmp/sum.txt")" -eq 1
check "the summary names the processes" grep -q "processes       3" "$tmp/sum.txt"

# measure: several rounds (a 2 % target), every replica of every round spread over the
# processes; the readings equal one process's to the last digit. By the path tracer (auto
# would pick radiosity for these diffuse surfaces: it is tested below).
"$one" measure "$tmp/meters.pbrt" --method path --rel-error 0.02 --threads 1 --json "$tmp/m1.json" -q > /dev/null
for n in 2 3; do
  run "$n" measure "$tmp/meters.pbrt" --method path --rel-error 0.02 --threads 1 --json "$tmp/m$n.json" -q > "$tmp/m$n.txt" 2>&1
  check "mpirun -n $n measure exits 0" test $? -eq 0
  check "mpirun -n $n measure: the readings equal one process's" python3 - "$tmp/m1.json" "$tmp/m$n.json" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
key = lambda d: [(m["name"], m["values"], m["stderr"], m["samples"], m["converged"]) for m in d["meters"]]
rounds = max(s for m in a["meters"] for s in m["samples"]) > 32 * 32  # more than the pilot
sys.exit(0 if key(a) == key(b) and rounds else 1)
PY
done
# A closed form through the distributed path: a point light of intensity 100 cd (scale 100)
# 2 m above the meter, nothing else: E = I / d^2 = 25 lx.
cat > "$tmp/point.pbrt" <<'SCENE'
Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]
WorldBegin
AttributeBegin
  Translate 0 0 2
  LightSource "point" "float scale" [ 100 ]
AttributeEnd
Meter "illuminance" "string name" "desk" "point3 p" [ 0 0 0  1 0 0 ] "normal n" [ 0 0 1 ]
SCENE
run 2 measure "$tmp/point.pbrt" --csv "$tmp/point.csv" -q > /dev/null 2>&1
desk=$(awk -F, '$1 == "desk" && $4 == 0 {print $8}' "$tmp/point.csv")
check "mpirun -n 2 measure: E = 100/2^2 = 25 lx (to 0.1 %)" \
  awk -v v="$desk" 'BEGIN { exit !(v > 24.975 && v < 25.025) }'

# The splatting integrators (bdpt, lightpath: light subpaths land in any pixel) and the
# radiosity method, on a room of triangles lit by a quad light (the radiosity system meshes
# triangles): each process renders its tiles as one process does, the splats are added in
# tile order, every process solves the same radiosity system. The one-process images at 1
# and 2 threads are the reference (the single-process rule), 72 samples per pixel (two
# passes: the second continues the first's splat sums).
cat > "$tmp/room.pbrt" <<'SCENE'
LookAt 0 1.5 -4  0 0.5 0  0 1 0
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ 40 ] "integer yresolution" [ 30 ] "string filename" "r.pfm"
Sampler "zsobol" "integer pixelsamples" [ 72 ]
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 6 6 6 ]
  Shape "trianglemesh" "point3 P" [ -0.5 2.5 -0.5  -0.5 2.5 0.5  0.5 2.5 0.5  0.5 2.5 -0.5 ] "integer indices" [ 0 2 1 0 3 2 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.6 0.5 0.4 ]
Shape "trianglemesh" "point3 P" [ -3 0 -3  3 0 -3  3 0 3  -3 0 3 ] "integer indices" [ 0 1 2 0 2 3 ]
Material "diffuse" "rgb reflectance" [ 0.2 0.7 0.3 ]
Shape "trianglemesh" "point3 P" [ -3 0 2  3 0 2  3 3 2  -3 3 2 ] "integer indices" [ 0 1 2 0 2 3 ]
Meter "illuminance" "string name" "floor" "point3 p" [ 1 0 0  -1 0 0.5 ] "normal n" [ 0 1 0 ]
SCENE
not_black() {  # not_black IMAGE.pfm : some pixel is positive (the splats reached the film)
  python3 - "$1" <<'PY'
import struct, sys
d = open(sys.argv[1], "rb").read()
parts = d.split(b"\n", 3)
w, h = map(int, parts[1].split()); scale = float(parts[2])
fmt = ("<" if scale < 0 else ">") + "f" * (3 * w * h)
v = struct.unpack(fmt, parts[3][: 12 * w * h])
sys.exit(0 if max(v) > 0 else 1)
PY
}
for integ in bdpt lightpath radiosity; do
  { echo "Integrator \"$integ\" \"integer maxdepth\" [ 4 ]"; cat "$tmp/room.pbrt"; } > "$tmp/$integ.pbrt"
  "$one" render "$tmp/$integ.pbrt" -o "$tmp/$integ-ref.pfm" --threads 1 --quiet
  "$one" render "$tmp/$integ.pbrt" -o "$tmp/$integ-t2.pfm" --threads 2 --quiet
  check "$integ: one process, 1 and 2 threads: the same image" cmp -s "$tmp/$integ-ref.pfm" "$tmp/$integ-t2.pfm"
  check "$integ: the image is not black" not_black "$tmp/$integ-ref.pfm"
  for n in 2 3; do
    run "$n" render "$tmp/$integ.pbrt" -o "$tmp/$integ-$n.pfm" --threads 1 --quiet > "$tmp/$integ-$n.txt" 2>&1
    check "mpirun -n $n render ($integ) exits 0" test $? -eq 0
    check "mpirun -n $n render ($integ): the image is bit-identical to one process's" cmp -s "$tmp/$integ-ref.pfm" "$tmp/$integ-$n.pfm"
  done
done
# Many tiles (9 x 6 = 54, more than the 32 whose splats the coordinator keeps apart at once
# with one thread a process): the window holds the hand-out back, the order stays.
sed -e 's/\[ 40 \]/[ 144 ]/; s/\[ 30 \]/[ 96 ]/; s/\[ 72 \]/[ 8 ]/' "$tmp/bdpt.pbrt" > "$tmp/wide.pbrt"
"$one" render "$tmp/wide.pbrt" -o "$tmp/wide-ref.pfm" --threads 1 --quiet
run 2 render "$tmp/wide.pbrt" -o "$tmp/wide-2.pfm" --threads 1 --quiet > "$tmp/wide-2.txt" 2>&1
check "mpirun -n 2 render (bdpt, 54 tiles) exits 0" test $? -eq 0
check "mpirun -n 2 render (bdpt, 54 tiles): the image is bit-identical" cmp -s "$tmp/wide-ref.pfm" "$tmp/wide-2.pfm"
# The radiosity method's readings: measure --method radiosity, --method auto (which takes it:
# every surface is a diffuse triangle), and the meters a radiosity render writes.
same_readings() {  # same_readings A.json B.json : every value, error and sample count
  python3 - "$1" "$2" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
key = lambda d: [(m["name"], m["values"], m["stderr"], m["samples"], m["converged"]) for m in d["meters"]]
sys.exit(0 if key(a) == key(b) and a["method"] == b["method"] == "radiosity" else 1)
PY
}
for method in radiosity auto; do
  "$one" measure "$tmp/room.pbrt" --method "$method" --rel-error 0.01 --threads 1 --json "$tmp/rad1-$method.json" -q > /dev/null 2>&1
  for n in 2 3; do
    run "$n" measure "$tmp/room.pbrt" --method "$method" --rel-error 0.01 --threads 1 --json "$tmp/rad$n-$method.json" -q > "$tmp/rad$n-$method.txt" 2>&1
    check "mpirun -n $n measure --method $method exits 0" test $? -eq 0
    check "mpirun -n $n measure --method $method: the readings equal one process's" same_readings "$tmp/rad1-$method.json" "$tmp/rad$n-$method.json"
  done
done
for n in 2 3; do
  check "mpirun -n $n render (radiosity): the meters' readings equal one process's" same_readings "$tmp/radiosity-ref.meters.json" "$tmp/radiosity-$n.meters.json"
done
# A worker dying mid-render of bdpt (the coordinator may be waiting for the splat window)
# still ends the job.
start=$SECONDS
STERADIAN_TEST_ABORT_AFTER_JOBS=1 run 2 render "$tmp/wide.pbrt" -o "$tmp/dead-bdpt.pfm" --threads 1 --quiet > "$tmp/dead-bdpt.txt" 2>&1
status=$?
check "bdpt: a dying process fails the job (status $status)" test "$status" -ne 0 -a "$status" -ne 124
check "... within 60 s" test $((SECONDS - start)) -lt 60
check "... and writes no image" test ! -e "$tmp/dead-bdpt.pfm"

# A process that dies mid-render ends the job: non-zero status, in bounded time, with a
# message naming it (Open MPI aborts the job when a process exits abnormally).
start=$SECONDS
STERADIAN_TEST_ABORT_AFTER_JOBS=1 run 2 render "$tmp/scene.pbrt" -o "$tmp/dead.pfm" --threads 1 --quiet > "$tmp/dead.txt" 2>&1
status=$?
check "a dying process fails the job (status $status)" test "$status" -ne 0 -a "$status" -ne 124
check "... within 60 s" test $((SECONDS - start)) -lt 60
check "... saying which process" grep -q "process 1 aborts" "$tmp/dead.txt"
check "... and writes no image" test ! -e "$tmp/dead.pfm"

# Integrator "mlt": the bootstrap's blocks and then, round by round, the chains (their
# states travel with them) are shared; each chain's splats are added in chain order, as one
# process adds them, in bands of rows with two threads. 400 chains in blocks of 25 (2
# processes), 16 (3) or 12 (2 of two threads), 3,000 bootstrap samples (3 blocks of 1,024),
# 4 rounds.
sed 's/^WorldBegin/Integrator "mlt" "integer bootstrapsamples" [ 500 ] "integer chains" [ 400 ]\nWorldBegin/' \
  "$tmp/scene.pbrt" > "$tmp/mlt.pbrt"
"$one" render "$tmp/mlt.pbrt" -o "$tmp/mlt1.pfm" --spp 4 --threads 1 --quiet
"$one" render "$tmp/mlt.pbrt" -o "$tmp/mlt1t2.pfm" --spp 4 --threads 2 --quiet
check "mlt: one process, 1 and 2 threads: the same image" cmp -s "$tmp/mlt1.pfm" "$tmp/mlt1t2.pfm"
check "mlt: the image is not black" not_black "$tmp/mlt1.pfm"
for n in 2 3; do
  run "$n" render "$tmp/mlt.pbrt" -o "$tmp/mlt$n.pfm" --spp 4 --threads 1 --quiet > "$tmp/mlt$n.txt" 2>&1
  check "mpirun -n $n render (mlt) exits 0" test $? -eq 0
  check "mpirun -n $n render (mlt): the image is bit-identical to one process's" cmp -s "$tmp/mlt1.pfm" "$tmp/mlt$n.pfm"
done
run 2 render "$tmp/mlt.pbrt" -o "$tmp/mlt2t2.pfm" --spp 4 --threads 2 --quiet > "$tmp/mlt2t2.txt" 2>&1
check "mpirun -n 2 render (mlt, 2 threads each): bit-identical" cmp -s "$tmp/mlt1.pfm" "$tmp/mlt2t2.pfm"
run 1 render "$tmp/mlt.pbrt" -o "$tmp/mlt1mpi.pfm" --spp 4 --threads 2 --quiet
check "mlt on 1 process of steradian-mpi: the same image" cmp -s "$tmp/mlt1.pfm" "$tmp/mlt1mpi.pfm"
# A worker dying while it holds chains ends the job.
start=$SECONDS
STERADIAN_TEST_ABORT_AFTER_JOBS=3 run 2 render "$tmp/mlt.pbrt" -o "$tmp/dead-mlt.pfm" --spp 4 --threads 1 --quiet > "$tmp/dead-mlt.txt" 2>&1
status=$?
check "mlt: a dying process fails the job (status $status)" test "$status" -ne 0 -a "$status" -ne 124
check "... within 60 s" test $((SECONDS - start)) -lt 60
check "... and writes no image" test ! -e "$tmp/dead-mlt.pfm"

# An error every process meets is reported once, by process 0.
run 3 render "$tmp/missing.pbrt" --quiet > "$tmp/missing.txt" 2>&1
check "a missing scene fails the job" test $? -ne 0
check "... reported once" test "$(grep -c '^error' "$tmp/missing.txt")" -eq 1

# Integrator "sppm": every iteration's photon chunks are shared (20 chunks of 1,024 photons);
# a worker returns its photons' hits, the coordinator, which made the visible points, gathers
# them and adds the deposits in chunk order, as one process adds them. 3 iterations.
sed 's/^WorldBegin/Integrator "sppm" "float radius" [ 0.1 ] "integer photonsperiteration" [ 20000 ]\nWorldBegin/' \
  "$tmp/scene.pbrt" > "$tmp/sppm.pbrt"
"$one" render "$tmp/sppm.pbrt" --spp 3 -o "$tmp/sppm1.pfm" --threads 1 --quiet
"$one" render "$tmp/sppm.pbrt" --spp 3 -o "$tmp/sppm1t2.pfm" --threads 2 --quiet
check "sppm: one process, 1 and 2 threads: the same image" cmp -s "$tmp/sppm1.pfm" "$tmp/sppm1t2.pfm"
check "sppm: the image is not black" not_black "$tmp/sppm1.pfm"
for n in 2 3; do
  run "$n" render "$tmp/sppm.pbrt" --spp 3 -o "$tmp/sppm$n.pfm" --threads 1 --quiet > "$tmp/sppm$n.txt" 2>&1
  check "mpirun -n $n render (sppm) exits 0" test $? -eq 0
  check "mpirun -n $n render (sppm): the image is bit-identical to one process's" cmp -s "$tmp/sppm1.pfm" "$tmp/sppm$n.pfm"
done
run 2 render "$tmp/sppm.pbrt" --spp 3 -o "$tmp/sppm2t2.pfm" --threads 2 --quiet > "$tmp/sppm2t2.txt" 2>&1
check "mpirun -n 2 render (sppm, 2 threads each): bit-identical" cmp -s "$tmp/sppm1.pfm" "$tmp/sppm2t2.pfm"

# Integrator "vcm": every process traces each iteration's light paths (the merging grid needs
# them all), the coordinator adds their splats, and bands of film rows of the camera pass are
# shared; the image is bit-identical to one process's, with 1 or 2 threads a process. A crop
# window, a glass sphere (caustics: merging; the first scene's green sphere made glass), and
# then the same scene filled with fog (medium vertices on both subpaths, transmittance on
# every connection). 6 samples per pixel, and without the "dark" meter, which fog would
# light (render measures a scene's meters to 0.1 %: a minute more).
sed -e 's/"integer pixelsamples" \[ 72 \]/"integer pixelsamples" [ 6 ]/' \
  -e '/"string name" "dark"/d' \
  -e 's/^WorldBegin/Integrator "vcm" "integer maxdepth" [ 5 ] "float radius" [ 0.05 ]\nWorldBegin/' \
  -e 's/Material "diffuse" "rgb reflectance" \[ 0.2 0.7 0.3 \]/Material "dielectric" "float eta" [ 1.5 ]/' \
  "$tmp/scene.pbrt" > "$tmp/vcm.pbrt"
sed -e 's/^LookAt/MakeNamedMedium "fog" "string type" "homogeneous" "spectrum sigma_a" [ 300 0.05 900 0.05 ] "spectrum sigma_s" [ 300 0.3 900 0.3 ]\nMediumInterface "" "fog"\nLookAt/' \
  -e 's/^WorldBegin/WorldBegin\nMediumInterface "fog" "fog"/' "$tmp/vcm.pbrt" > "$tmp/vcm-fog.pbrt"
for v in vcm vcm-fog; do
  "$one" render "$tmp/$v.pbrt" -o "$tmp/$v-ref.pfm" --threads 1 --quiet
  check "$v: one process renders" test -s "$tmp/$v-ref.pfm"
  for n in 2 3; do
    for t in 1 2; do
      run "$n" render "$tmp/$v.pbrt" -o "$tmp/$v-$n-$t.pfm" --threads "$t" --quiet > "$tmp/$v-$n-$t.txt" 2>&1
      check "mpirun -n $n render ($v, $t threads) exits 0" test $? -eq 0
      check "mpirun -n $n render ($v, $t threads): the image is bit-identical" cmp -s "$tmp/$v-ref.pfm" "$tmp/$v-$n-$t.pfm"
    done
  done
done

echo "mpi: $pass passed, $fail failed"
test "$fail" -eq 0
