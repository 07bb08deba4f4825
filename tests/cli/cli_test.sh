#!/usr/bin/env bash
# End-to-end tests of the command line: exit codes, messages, output formats, --time.
# Usage: tests/cli/cli_test.sh path/to/steradian
set -u
bin=$(realpath "$1")
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0
fail=0
check() {  # check NAME CONDITION...
  local name=$1
  shift
  if "$@"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $name"; fi
}

cat > "$tmp/small.pbrt" <<'SCENE'
LookAt 0 0 -3  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 12 ] "string filename" "small.exr"
Sampler "independent" "integer pixelsamples" [ 4 ]
WorldBegin
LightSource "infinite" "rgb L" [ 1 1 1 ]
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
Shape "sphere" "float radius" [ 1 ]
SCENE

# --help and --version succeed and say what they are.
"$bin" --help > "$tmp/help.txt" 2>&1
check "--help exits 0" test $? -eq 0
check "--help names render" grep -q "render" "$tmp/help.txt"
"$bin" render --help > "$tmp/rhelp.txt" 2>&1
check "render --help lists --spp" grep -q -- "--spp" "$tmp/rhelp.txt"
"$bin" --version > "$tmp/version.txt" 2>&1
check "--version exits 0" test $? -eq 0
check "--version prints the version" grep -q "steradian [0-9]" "$tmp/version.txt"

# Every output type by extension; the default output is the Film's filename.
for ext in exr pfm png; do
  "$bin" render "$tmp/small.pbrt" -o "$tmp/out.$ext" --quiet
  check "render .$ext exits 0" test $? -eq 0
  check "render .$ext writes the file" test -s "$tmp/out.$ext"
done
check "PFM header" bash -c "head -c 2 '$tmp/out.pfm' | grep -q PF"
check "PNG signature" bash -c "head -c 4 '$tmp/out.png' | grep -q PNG"
(cd "$tmp" && "$bin" render small.pbrt --quiet)
check "default output is the Film filename" test -s "$tmp/small.exr"

# Several outputs from one render, options before the scene.
"$bin" render -o "$tmp/m1.exr" -o "$tmp/m2.png" "$tmp/small.pbrt" --quiet
check "two -o outputs exit 0" test $? -eq 0
check "two -o outputs both written" test -s "$tmp/m1.exr" -a -s "$tmp/m2.png"

# The summary reports the required figures.
"$bin" render "$tmp/small.pbrt" -o "$tmp/s.exr" > "$tmp/summary.txt" 2>&1
for key in "wall time" "CPU time" "samples/pixel" "camera paths/s" "rays/s" "peak memory" "NaN/Inf"; do
  check "summary has '$key'" grep -q "$key" "$tmp/summary.txt"
done

# --time stops early and says so (a budget far too small for 4096 spp).
"$bin" render "$tmp/small.pbrt" -o "$tmp/t.exr" --spp 100000 --time 0.5 > "$tmp/time.txt" 2>&1
check "--time exits 0" test $? -eq 0
check "--time says it stopped" grep -q "time budget" "$tmp/time.txt"
check "--time writes the image" test -s "$tmp/t.exr"

# Errors: non-zero exit, file:line:col and what was expected.
printf 'WorldBegin\nShape "sphere" "float radius" [ "big" ]\n' > "$tmp/bad.pbrt"
"$bin" render "$tmp/bad.pbrt" -o "$tmp/bad.exr" > "$tmp/bad.txt" 2>&1
check "bad scene exits non-zero" test $? -ne 0
check "bad scene names file:line:col" grep -q "bad.pbrt:2:" "$tmp/bad.txt"
"$bin" render "$tmp/missing.pbrt" > "$tmp/missing.txt" 2>&1
check "missing scene exits non-zero" test $? -ne 0
check "missing scene is named" grep -q "missing.pbrt" "$tmp/missing.txt"
printf 'WorldBegin\nShape "heightfield"\n' > "$tmp/unsup.pbrt"
"$bin" render "$tmp/unsup.pbrt" -o "$tmp/u.exr" > "$tmp/unsup.txt" 2>&1
check "unsupported shape exits non-zero" test $? -ne 0
check "unsupported shape says so" grep -q "not supported yet" "$tmp/unsup.txt"
"$bin" render "$tmp/small.pbrt" -o "$tmp/out.xyz" --quiet > "$tmp/ext.txt" 2>&1
check "unknown output extension exits non-zero" test $? -ne 0
"$bin" render "$tmp/small.pbrt" --spp -3 > /dev/null 2>&1
check "negative --spp is rejected" test $? -ne 0
"$bin" frobnicate > /dev/null 2>&1
check "unknown subcommand is rejected" test $? -ne 0

# measure: readings with standard errors, JSON (the documented keys), CSV, false colour;
# render writes <output>.meters.json, --luminance and --falsecolor.
cat > "$tmp/meters.pbrt" <<'SCENE'
Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ] "string filename" "m.exr"
Sampler "independent" "integer pixelsamples" [ 2 ]
WorldBegin
AttributeBegin
  Translate 0 0 2
  LightSource "point" "float scale" [ 100 ]
AttributeEnd
Meter "illuminance" "string name" "desk" "point3 p" [ 0 0 0  1 0 0 ] "normal n" [ 0 0 1 ]
Meter "illuminancegrid" "string name" "workplane" "point3 corner" [ -1 -1 0 ] "vector3 u" [ 2 0 0 ]
      "vector3 v" [ 0 2 0 ] "integer resolution" [ 4 3 ]
SCENE
"$bin" measure "$tmp/meters.pbrt" --json "$tmp/m.json" --csv "$tmp/m.csv" --falsecolor "$tmp/m.png" \
  --report "$tmp/m.html" > "$tmp/measure.txt" 2> "$tmp/measure.err"
check "measure exits 0" test $? -eq 0
desk=$(awk -F, '$1 == "desk" && $4 == 0 {print $8}' "$tmp/m.csv")
check "measure reports the desk reading (E = 100/2^2 = 25 lx to 0.1 %)" \
  awk -v v="$desk" 'BEGIN { exit !(v > 24.975 && v < 25.025) }'
check "measure prints grid statistics" grep -q "E_avg" "$tmp/measure.txt"
check "measure --json writes the meters" grep -q '"meters"' "$tmp/m.json"
for key in '"name": "desk"' '"type": "illuminance"' '"unit": "lx"' '"values"' '"stderr"' '"uniformity"'; do
  check "JSON has $key" grep -q "$key" "$tmp/m.json"
done
check "CSV has a header and 14 rows" test "$(wc -l < "$tmp/m.csv")" -eq 15
# Nothing scatters: a point light's illuminance is I cos / r^2 and one shadow ray, exact.
check "measure computes direct light without sampling" grep -q '"estimator": "deterministic"' "$tmp/m.json"
check "a point light's reading is exact" \
  python3 -c "import json,sys; m=json.load(open(sys.argv[1]))['meters'][0]; sys.exit(0 if m['exact'][0] and m['stderr'][0] == 0 and abs(m['values'][0] - 25) < 1e-5 else 1)" "$tmp/m.json"
check "the table says exact" grep -q "(exact)" "$tmp/measure.txt"
"$bin" measure "$tmp/meters.pbrt" --sampled-direct --json "$tmp/ms.json" --quiet > /dev/null 2>&1
check "measure --sampled-direct samples" grep -q '"estimator": "monte carlo"' "$tmp/ms.json"
check "measure --falsecolor writes a PNG" test -s "$tmp/m.png"
check "measure --report writes an HTML page" grep -q "<h1>Lighting report: meters.pbrt</h1>" "$tmp/m.html"
check "the report has the grid's plans" test "$(grep -c "<svg" "$tmp/m.html")" -eq 2
"$bin" measure "$tmp/meters.pbrt" --report "$tmp/m.csv/r.html" > "$tmp/badreport.txt" 2>&1
check "measure --report to an unwritable place fails" test $? -ne 0
check "... naming the path, before measuring" \
  sh -c "grep -q 'm.csv/r.html' '$tmp/badreport.txt' && ! grep -q E_avg '$tmp/badreport.txt'"
"$bin" measure "$tmp/small.pbrt" > "$tmp/nometer.txt" 2>&1
check "measure without meters exits non-zero" test $? -ne 0
check "measure without meters says so" grep -q "no Meter" "$tmp/nometer.txt"
"$bin" render "$tmp/meters.pbrt" -o "$tmp/mr.exr" --luminance "$tmp/mr-y.exr" --falsecolor "$tmp/mr-fc.png" --quiet
check "render with meters exits 0" test $? -eq 0
check "render writes <output>.meters.json" grep -q '"workplane"' "$tmp/mr.meters.json"
check "render --luminance writes an EXR" test -s "$tmp/mr-y.exr"
check "render --falsecolor writes a PNG" test -s "$tmp/mr-fc.png"
printf 'Camera "perspective"\nWorldBegin\nMeter "illuminance" "point3 p" [ 0 0 0 ]\n' > "$tmp/badm.pbrt"
"$bin" measure "$tmp/badm.pbrt" > "$tmp/badm.txt" 2>&1
check "bad meter exits non-zero" test $? -ne 0
check "bad meter names file:line:col" grep -q "badm.pbrt:3:1" "$tmp/badm.txt"

# ---- reliability: outputs are checked before rendering, written atomically, and checked ----
# A slow scene (minutes at this spp), so that failing fast shows the check came first.
slow=(render "$tmp/small.pbrt" --spp 1000000)
start=$SECONDS
"$bin" "${slow[@]}" -o "$tmp/out.xyz" > "$tmp/ext2.txt" 2>&1
check "unknown extension fails before rendering" test $? -ne 0 -a $((SECONDS - start)) -lt 20
check "unknown extension is named" grep -q 'unknown image format ".xyz"' "$tmp/ext2.txt"
touch "$tmp/afile"
start=$SECONDS
"$bin" "${slow[@]}" -o "$tmp/afile/sub/x.exr" > "$tmp/dir.txt" 2>&1
check "impossible output directory fails before rendering" test $? -ne 0 -a $((SECONDS - start)) -lt 20
check "impossible output directory is named" grep -q "cannot create the directory" "$tmp/dir.txt"
"$bin" "${slow[@]}" -o "$tmp/ok.exr" --luminance "$tmp/y.png" > "$tmp/lum.txt" 2>&1
check "single-channel --luminance to PNG fails before rendering" test $? -ne 0
# A gbuffer or spectral film writes EXR only: another -o extension fails before rendering.
sed 's/Film "rgb"/Film "gbuffer"/' "$tmp/small.pbrt" > "$tmp/gbuffer.pbrt"
start=$SECONDS
"$bin" render "$tmp/gbuffer.pbrt" --spp 1000000 -o "$tmp/g.png" > "$tmp/g.txt" 2>&1
check "gbuffer film to PNG fails before rendering" test $? -ne 0 -a $((SECONDS - start)) -lt 20
check "gbuffer film to PNG says EXR only" grep -q "channels: .exr only" "$tmp/g.txt"
"$bin" render "$tmp/gbuffer.pbrt" -o "$tmp/g.exr" --quiet
check "gbuffer film writes an EXR" test -s "$tmp/g.exr"
"$bin" render "$tmp/gbuffer.pbrt" -o "$tmp/g1.exr" --threads 1 --quiet
check "gbuffer channels do not depend on the thread count" cmp -s "$tmp/g.exr" "$tmp/g1.exr"
sed 's/Film "rgb"/Film "spectral"/' "$tmp/small.pbrt" > "$tmp/spectral.pbrt"
"$bin" render "$tmp/spectral.pbrt" -o "$tmp/s2.exr" --threads 2 --quiet
"$bin" render "$tmp/spectral.pbrt" -o "$tmp/s1.exr" --threads 1 --quiet
check "spectral buckets do not depend on the thread count" cmp -s "$tmp/s1.exr" "$tmp/s2.exr"
"$bin" render "$tmp/small.pbrt" -o "$tmp/new/dir/x.exr" --quiet
check "a missing output directory is created" test -s "$tmp/new/dir/x.exr"
"$bin" measure "$tmp/meters.pbrt" --json "$tmp/afile/m.json" > "$tmp/mj.txt" 2>&1
check "measure --json into an impossible directory fails" test $? -ne 0
check "no temporary files are left behind" test -z "$(find "$tmp" -name '.*.tmp-*')"

# Out-of-range and non-finite command-line values are errors.
for args in "--threads 100000" "--threads -1" "--time nan" "--time inf" "--time -1" \
            "--exposure nan" "--seed 18446744073709551616" "--seed -1"; do
  # shellcheck disable=SC2086
  "$bin" render "$tmp/small.pbrt" -o "$tmp/r.exr" $args --quiet > "$tmp/range.txt" 2>&1
  check "render $args is rejected" test $? -ne 0
done
for args in "--rel-error nan" "--rel-error 0" "--time nan" "--threads 100000"; do
  # shellcheck disable=SC2086
  "$bin" measure "$tmp/meters.pbrt" $args --quiet > "$tmp/range.txt" 2>&1
  check "measure $args is rejected" test $? -ne 0
done

# measure --time is a bound, not a suggestion: rounds grow up to 64-fold, and a round that
# would overrun is abandoned (within a few percent of the budget; its own clock, in the JSON).
# (--sampled-direct: this scene's light is direct, which is otherwise computed at once.)
"$bin" measure "$tmp/meters.pbrt" --rel-error 1e-12 --time 2 --sampled-direct --json "$tmp/tb.json" --quiet > "$tmp/tb.txt" 2>&1
check "measure --time exits 0" test $? -eq 0
check "measure --time 2 stops within 2.1 s" \
  python3 -c "import json,sys; r=json.load(open(sys.argv[1])); sys.exit(0 if r['time_limited'] and r['wall_seconds'] < 2.1 else 1)" "$tmp/tb.json"
check "measure --time reports unconverged values" grep -q '"converged": false' "$tmp/tb.json"

# SIGINT / SIGTERM: the first signal lets the pass in flight finish, the completed passes are
# written, and the exit status is 128 + the signal; a second signal exits at once.
# interrupted SIGNAL COMMAND...: runs the command, sends SIGNAL after 1.5 s, returns its status.
interrupted() {
  local sig=$1
  shift
  "$@" &
  local pid=$!
  sleep 1.5
  kill "-$sig" $pid
  wait $pid
}
interrupted INT "$bin" render "$tmp/small.pbrt" -o "$tmp/int.pfm" --spp 10000000 > "$tmp/int.txt" 2>&1
check "SIGINT during render exits 130" test $? -eq 130
check "SIGINT during render writes the completed passes" test -s "$tmp/int.pfm"
check "SIGINT during render says so" grep -q "interrupted" "$tmp/int.txt"
interrupted TERM "$bin" render "$tmp/small.pbrt" -o "$tmp/term.pfm" --spp 10000000 --quiet > "$tmp/term.txt" 2>&1
check "SIGTERM during render exits 143" test $? -eq 143
check "SIGTERM during render writes the completed passes" test -s "$tmp/term.pfm"
interrupted INT "$bin" measure "$tmp/meters.pbrt" --rel-error 1e-12 --sampled-direct --json "$tmp/int.json" --quiet > "$tmp/mint.txt" 2>&1
check "SIGINT during measure exits 130" test $? -eq 130
check "SIGINT during measure writes the readings" grep -q '"interrupted": true' "$tmp/int.json"
# A pass of minutes: the second signal must not wait for it.
"$bin" render "$ROOT/scenes/cornell-box.pbrt" -o "$tmp/int2.pfm" --spp 1000000 --quiet > /dev/null 2>&1 &
pid=$!
sleep 1
kill -INT $pid
sleep 0.3
start=$SECONDS
kill -INT $pid
wait $pid
status=$?
check "a second SIGINT exits at once with 130" test $status -eq 130 -a $((SECONDS - start)) -lt 3
check "a second SIGINT writes nothing" test ! -e "$tmp/int2.pfm"

# A 68-byte PNG whose header declares 16000 x 16000 RGB pixels is refused from its header
# (it took 4 GB and 85 s before), with the limit named.
python3 - "$tmp/huge.png" <<'PY'
import struct, sys, zlib
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 16000, 16000, 8, 2, 0, 0, 0))
png += chunk(b"IDAT", zlib.compress(b"\0" * 16)) + chunk(b"IEND", b"")
open(sys.argv[1], "wb").write(png)
PY
sed 's|Material "diffuse" "rgb reflectance" \[ 0.5 0.5 0.5 \]|Texture "t" "spectrum" "imagemap" "string filename" "huge.png"\nMaterial "diffuse" "texture reflectance" "t"|' "$tmp/small.pbrt" > "$tmp/huge.pbrt"
start=$SECONDS
"$bin" render "$tmp/huge.pbrt" -o "$tmp/huge.exr" --quiet > "$tmp/huge.txt" 2>&1
check "an image declaring 16000 x 16000 pixels is refused" test $? -ne 0 -a $((SECONDS - start)) -lt 5
check "the refusal names the limit" grep -q "more than the limit" "$tmp/huge.txt"
check "the refusal names the texture's line" grep -q "huge.pbrt:7:1" "$tmp/huge.txt"

# Non-finite or unrepresentable cameras, lights, meters and transforms are errors at their
# file:line:col (they aborted inside Embree, exit 134, or rendered nothing).
bad_scene() {  # bad_scene NAME "CAMERA LINES" "WORLD LINES"
  printf '%b\nCamera "perspective"\nFilm "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]\nWorldBegin\n%b\nShape "sphere"\n' "$2" "$3" > "$tmp/$1.pbrt"
}
bad_scene zero-up "LookAt 0 0 -3  0 0 0  0 0 0" 'LightSource "point"'
bad_scene far-camera "LookAt 3e38 0 -3  0 0 0  0 1 0" 'LightSource "point"'
bad_scene far-light "LookAt 0 0 -3  0 0 0  0 1 0" 'AttributeBegin\nTranslate 3e38 0 0\nLightSource "point"\nAttributeEnd'
bad_scene far-meter "LookAt 0 0 -3  0 0 0  0 1 0" 'LightSource "point"\nMeter "illuminance" "point3 p" [ 3e38 0 0 ] "normal n" [ 0 0 1 ]'
bad_scene huge-sphere "LookAt 0 0 -3  0 0 0  0 1 0" 'AreaLightSource "diffuse"\nShape "sphere" "float radius" [ 1e20 ]'
for case in zero-up:1:1 far-camera:2:1 far-light:7:1 far-meter:6:1 huge-sphere:6:1; do
  name=${case%%:*}
  "$bin" render "$tmp/$name.pbrt" -o "$tmp/$name.exr" --quiet > "$tmp/$name.txt" 2>&1
  status=$?
  check "$name: exits 1 (not an abort)" test $status -eq 1
  check "$name: error at its file:line:col" grep -q "$name.pbrt:${case#*:}" "$tmp/$name.txt"
done

# Counts and sizes that are multiplied are checked, with a located error: a stratified
# 65536 x 65536 overflowed int and rendered black with exit 0; a 2e9-pixel-wide film failed
# with "cannot create std::vector larger than max_size()" and no location.
sed 's|Sampler "independent" "integer pixelsamples" \[ 4 \]|Sampler "stratified" "integer xsamples" [ 65536 ] "integer ysamples" [ 65536 ]|' "$tmp/small.pbrt" > "$tmp/strat.pbrt"
"$bin" render "$tmp/strat.pbrt" -o "$tmp/strat.exr" --quiet > "$tmp/strat.txt" 2>&1
check "stratified 65536 x 65536 is an error" test $? -eq 1
check "stratified overflow names its line" grep -q "strat.pbrt:4:1" "$tmp/strat.txt"
sed 's|"integer xresolution" \[ 16 \]|"integer xresolution" [ 2000000000 ]|' "$tmp/small.pbrt" > "$tmp/wide.pbrt"
"$bin" render "$tmp/wide.pbrt" -o "$tmp/wide.exr" --quiet > "$tmp/wide.txt" 2>&1
check "a 2e9-pixel-wide film is an error" test $? -eq 1
check "the film size error names its line" grep -q "wide.pbrt:3:1: film resolution" "$tmp/wide.txt"
"$bin" render "$tmp/small.pbrt" -o "$tmp/s.exr" --spp 2000000000 --quiet > "$tmp/spp.txt" 2>&1
check "--spp 2e9 is rejected" test $? -ne 0

# Only regular files are read, up to a size limit the error names: Include "/dev/zero" read
# until memory ran out.
truncate -s 5G "$tmp/huge-sparse.pbrt"
ln -s /dev/zero "$tmp/zero.ies"
for inc in 'Include "/dev/zero"' "Include \"$tmp\"" "Include \"$tmp/huge-sparse.pbrt\"" \
           'Shape "plymesh" "string filename" "/dev/zero"' \
           "LightSource \"goniometric\" \"string filename\" \"$tmp/zero.ies\""; do
  printf 'Camera "perspective"\nWorldBegin\n%s\n' "$inc" > "$tmp/inc.pbrt"
  start=$SECONDS
  timeout 60 "$bin" render "$tmp/inc.pbrt" -o "$tmp/inc.exr" --quiet > "$tmp/inc.txt" 2>&1
  status=$?
  check "$inc: refused at once" test $status -eq 1 -a $((SECONDS - start)) -lt 5
  check "$inc: located" grep -q "inc.pbrt:3:" "$tmp/inc.txt"
done
printf 'Camera "perspective"\nWorldBegin\nInclude "%s"\n' "$tmp/huge-sparse.pbrt" > "$tmp/inc.pbrt"
"$bin" render "$tmp/inc.pbrt" -o "$tmp/inc.exr" --quiet > "$tmp/inc.txt" 2>&1
check "a file over the size limit is refused, naming the limit" grep -q "more than the limit" "$tmp/inc.txt"
rm -f "$tmp/huge-sparse.pbrt"

# Out-of-float-range numbers are errors (1e39 became inf), and a binary file's bytes are
# escaped in messages, never echoed raw to the terminal.
printf 'Camera "perspective"\nWorldBegin\nShape "sphere" "float radius" [ 1e39 ]\n' > "$tmp/range.pbrt"
"$bin" render "$tmp/range.pbrt" -o "$tmp/range.exr" --quiet > "$tmp/range.txt" 2>&1
check "float radius 1e39 is an error" test $? -eq 1
check "float radius 1e39 is located" grep -q "range.pbrt:3:33: .*32-bit float" "$tmp/range.txt"
printf 'Camera "perspective"\nWorldBegin\nLightSource "point" "spectrum I" [ 400 1  500 1e39 ]\n' > "$tmp/range2.pbrt"
"$bin" render "$tmp/range2.pbrt" -o "$tmp/range.exr" --quiet > "$tmp/range.txt" 2>&1
check "an inline spectrum value of 1e39 is located" grep -q "range2.pbrt:3:" "$tmp/range.txt"
printf '400 1\n500 1\n450 1\n' > "$tmp/bad.spd"
printf 'Camera "perspective"\nWorldBegin\nLightSource "point" "spectrum I" "bad.spd"\n' > "$tmp/spd.pbrt"
"$bin" render "$tmp/spd.pbrt" -o "$tmp/range.exr" --quiet > "$tmp/range.txt" 2>&1
check "a spectrum file out of order names the scene line and the file line" \
  grep -q "spd.pbrt:3:.*bad.spd:3: wavelengths must increase" "$tmp/range.txt"
for seed in 1 2 3 4 5 6 7 8; do
  python3 -c "import random,sys; random.seed($seed); sys.stdout.buffer.write(bytes(random.randrange(256) for _ in range(3000)))" > "$tmp/binary.pbrt"
  "$bin" render "$tmp/binary.pbrt" -o "$tmp/range.exr" --quiet > "$tmp/binary.txt" 2>&1
  check "binary scene $seed: an error, printed as text" \
    python3 -c "import sys; t=open(sys.argv[1],'rb').read().decode('utf-8'); sys.exit(0 if t.startswith('error: ') and all(c=='\n' or ' '<=c!='\x7f' for c in t) else 1)" "$tmp/binary.txt"
done

# A --time shorter than one pass still renders the first pass (1 spp): not a black image.
"$bin" render "$tmp/small.pbrt" -o "$tmp/short.pfm" --spp 1000 --time 0.000001 > "$tmp/short.txt" 2>&1
check "--time shorter than a pass exits 0" test $? -eq 0
check "--time shorter than a pass says 1 sample per pixel" grep -q "samples/pixel   1 " "$tmp/short.txt"
check "--time shorter than a pass writes a lit image" \
  python3 -c "import sys,struct; d=open(sys.argv[1],'rb').read(); h=d.split(b'\n',3); v=struct.unpack('<%df'%((len(h[3]))//4), h[3]); sys.exit(0 if max(v)>0 else 1)" "$tmp/short.pfm"

# Disk full: on a 64 KiB tmpfs an image that does not fit is an error, and the file that was
# there before is intact (needs mount rights; skipped where there are none).
mkdir -p "$tmp/small-fs"
if mount -t tmpfs -o size=64k tmpfs "$tmp/small-fs" 2>/dev/null; then
  "$bin" render "$tmp/small.pbrt" -o "$tmp/small-fs/keep.pfm" --quiet
  cp "$tmp/small-fs/keep.pfm" "$tmp/keep-before.pfm"
  dd if=/dev/zero of="$tmp/small-fs/filler" bs=1k count=60 2>/dev/null
  printf 'LookAt 0 0 -3  0 0 0  0 1 0\nCamera "perspective"\nFilm "rgb" "integer xresolution" [ 64 ] "integer yresolution" [ 64 ]\nSampler "independent" "integer pixelsamples" [ 1 ]\nWorldBegin\nLightSource "infinite"\n' > "$tmp/big.pbrt"
  "$bin" render "$tmp/big.pbrt" -o "$tmp/small-fs/keep.pfm" --quiet > "$tmp/full.txt" 2>&1
  check "disk full exits non-zero" test $? -ne 0
  check "disk full says it could not write" grep -q "cannot write\|write failed\|No space" "$tmp/full.txt"
  check "disk full leaves the old file intact" cmp -s "$tmp/small-fs/keep.pfm" "$tmp/keep-before.pfm"
  check "disk full leaves no temporary file" test -z "$(find "$tmp/small-fs" -name '.*.tmp-*')"
  umount "$tmp/small-fs"
else
  echo "SKIP: disk-full tests (cannot mount a tmpfs here)"
fi

# Checkpoint and resume. A render killed with SIGKILL at random moments and resumed each time
# (from scratch when no checkpoint exists yet) ends with the image of an uninterrupted render,
# bit for bit; so does a measurement.
"$bin" render "$tmp/small.pbrt" -o "$tmp/ck-ref.pfm" --spp 20000 --quiet
# Passes paced by a time budget or checkpoints leave the image as one pass would: each
# pixel sums its samples in order whatever the passes.
"$bin" render "$tmp/small.pbrt" -o "$tmp/ck-paced.pfm" --spp 20000 --time 1000 --quiet
check "a time-budgeted render that completes equals the unbudgeted one" cmp -s "$tmp/ck-paced.pfm" "$tmp/ck-ref.pfm"
kills=0
resumes=0
rm -f "$tmp/ck.ckpt" "$tmp/ck.pfm"
for i in 1 2 3 4 5 6 7 8; do
  if [ -e "$tmp/ck.ckpt" ]; then
    "$bin" render --resume "$tmp/ck.ckpt" --threads 1 --quiet > /dev/null 2>&1 &
    resumes=$((resumes + 1))
  else
    # One thread (the image is the same on any number): the render lasts long enough for
    # the kills to land in it on a fast, idle machine too.
    "$bin" render "$tmp/small.pbrt" -o "$tmp/ck.pfm" --spp 20000 --checkpoint "$tmp/ck.ckpt" \
      --checkpoint-every 0 --threads 1 --quiet > /dev/null 2>&1 &
  fi
  pid=$!
  sleep "0.$((RANDOM % 8 + 1))"
  kill -KILL $pid 2> /dev/null && kills=$((kills + 1))
  wait $pid 2> /dev/null
done
if [ -e "$tmp/ck.ckpt" ]; then
  "$bin" render --resume "$tmp/ck.ckpt" --quiet > "$tmp/ck-final.txt" 2>&1
else
  "$bin" render "$tmp/small.pbrt" -o "$tmp/ck.pfm" --spp 20000 --checkpoint "$tmp/ck.ckpt" --quiet
fi
check "resume after SIGKILL exits 0" test $? -eq 0
check "temporary files of killed writers are cleaned up" test -z "$(find "$tmp" -name '.ck.tmp-*')"
check "the render was killed at least twice and resumed" test $kills -ge 2 -a $resumes -ge 1
check "killed and resumed render is identical to an uninterrupted one" cmp -s "$tmp/ck.pfm" "$tmp/ck-ref.pfm"
echo "  (checkpoint: $kills kills, $resumes resumes)"
# A checkpoint is refused for another sample count, seed or scene, or when damaged.
"$bin" render --resume "$tmp/ck.ckpt" --spp 100 --quiet > "$tmp/ck-spp.txt" 2>&1
check "resume with another --spp is refused" test $? -ne 0
check "resume with another --spp says why" grep -q "samples per pixel" "$tmp/ck-spp.txt"
"$bin" render --resume "$tmp/ck.ckpt" --seed 3 --quiet > "$tmp/ck-seed.txt" 2>&1
check "resume with another --seed is refused" grep -q "seed" "$tmp/ck-seed.txt"
cp "$tmp/small.pbrt" "$tmp/small2.pbrt"
echo 'Shape "sphere" "float radius" [ 0.1 ]' >> "$tmp/small2.pbrt"
"$bin" render "$tmp/small2.pbrt" --resume "$tmp/ck.ckpt" --quiet > "$tmp/ck-scene.txt" 2>&1
check "resume on a changed scene is refused" grep -q "changed" "$tmp/ck-scene.txt"
head -c 300 "$tmp/ck.ckpt" > "$tmp/ck-cut.ckpt"
"$bin" render --resume "$tmp/ck-cut.ckpt" --quiet > "$tmp/ck-cut.txt" 2>&1
check "a truncated checkpoint is refused" grep -q "damaged or incomplete" "$tmp/ck-cut.txt"
"$bin" render --resume "$tmp/small.pbrt" --quiet > "$tmp/ck-not.txt" 2>&1
check "a file that is no checkpoint is refused" grep -q "not a steradian checkpoint" "$tmp/ck-not.txt"

cat > "$tmp/room.pbrt" <<'SCENE'
Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 4 4 4 ]
  Translate 0 0 2
  Shape "sphere" "float radius" [ 0.3 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.7 0.7 0.7 ]
Shape "trianglemesh" "point3 P" [ -3 -3 -0.01  3 -3 -0.01  3 3 -0.01  -3 3 -0.01 ]
      "integer indices" [ 0 1 2  0 2 3 ]
Shape "trianglemesh" "point3 P" [ -3 -3 3  -3 3 3  3 3 3  3 -3 3 ]
      "integer indices" [ 0 1 2  0 2 3 ]
Meter "illuminancegrid" "string name" "floor" "point3 corner" [ -1 -1 0 ] "vector3 u" [ 2 0 0 ]
      "vector3 v" [ 0 2 0 ] "integer resolution" [ 4 4 ]
SCENE
"$bin" measure "$tmp/room.pbrt" --method path --rel-error 0.0005 --json "$tmp/mck-ref.json" --quiet > /dev/null
mkills=0
rm -f "$tmp/mck.ckpt"
for i in 1 2 3 4 5 6; do
  if [ -e "$tmp/mck.ckpt" ]; then
    "$bin" measure --resume "$tmp/mck.ckpt" --threads 1 --quiet > /dev/null 2>&1 &
  else
    "$bin" measure "$tmp/room.pbrt" --method path --rel-error 0.0005 --json "$tmp/mck.json" \
      --checkpoint "$tmp/mck.ckpt" --threads 1 --quiet > /dev/null 2>&1 &
  fi
  pid=$!
  sleep "0.$((RANDOM % 5 + 3))"
  kill -KILL $pid 2> /dev/null && mkills=$((mkills + 1))
  wait $pid 2> /dev/null
done
if [ -e "$tmp/mck.ckpt" ]; then
  "$bin" measure --resume "$tmp/mck.ckpt" --quiet > /dev/null
else
  "$bin" measure "$tmp/room.pbrt" --method path --rel-error 0.0005 --json "$tmp/mck.json" --quiet > /dev/null
fi
same_readings() {  # the readings of two JSON files, times aside
  python3 -c '
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
for j in (a, b):
    j.pop("wall_seconds"); j.pop("cpu_seconds")
    for k in [k for k in j.get("radiosity", {}) if k.endswith("_seconds")]:
        j["radiosity"].pop(k)
sys.exit(0 if a == b else 1)' "$1" "$2"
}
check "the measurement was killed at least twice" test $mkills -ge 2
check "killed and resumed measurement gives the uninterrupted readings" same_readings "$tmp/mck.json" "$tmp/mck-ref.json"
echo "  (measure checkpoint: $mkills kills)"
"$bin" measure --resume "$tmp/mck.ckpt" --rel-error 0.01 --quiet > "$tmp/mck-rel.txt" 2>&1
check "measure resume with another --rel-error is refused" grep -q "rel-error" "$tmp/mck-rel.txt"
"$bin" render --resume "$tmp/mck.ckpt" --quiet > "$tmp/mck-kind.txt" 2>&1
check "render refuses a measurement's checkpoint" grep -q "not a render" "$tmp/mck-kind.txt"

# Two renders writing one path at once: the file is one of the two images, never a mix.
"$bin" render "$tmp/small.pbrt" -o "$tmp/a.pfm" --spp 64 --seed 1 --quiet
"$bin" render "$tmp/small.pbrt" -o "$tmp/b.pfm" --spp 64 --seed 2 --quiet
mixed=0
for i in 1 2 3 4 5 6; do
  "$bin" render "$tmp/small.pbrt" -o "$tmp/same.pfm" --spp 64 --seed 1 --quiet &
  p1=$!
  "$bin" render "$tmp/small.pbrt" -o "$tmp/same.pfm" --spp 64 --seed 2 --quiet &
  p2=$!
  wait $p1 $p2
  cmp -s "$tmp/same.pfm" "$tmp/a.pfm" || cmp -s "$tmp/same.pfm" "$tmp/b.pfm" || mixed=$((mixed + 1))
done
check "concurrent writers never leave a mixed file" test $mixed -eq 0

# OpenImageIO is a module loaded for other formats only: without it, EXR, PNG and PFM
# still work, and a TIFF output is refused before rendering with the reason.
for ext in exr png pfm; do
  STERADIAN_OIIO_MODULE=/nonexistent/steradian_oiio.so "$bin" render "$tmp/small.pbrt" \
    -o "$tmp/nomodule.$ext" --quiet
  check "without the OpenImageIO module: .$ext written" test $? -eq 0 -a -s "$tmp/nomodule.$ext"
done
STERADIAN_OIIO_MODULE=/nonexistent/steradian_oiio.so "$bin" render "$tmp/small.pbrt" \
  -o "$tmp/nomodule.tif" --quiet > "$tmp/nomodule.txt" 2>&1
check "without the OpenImageIO module: .tif refused" test $? -eq 1 -a ! -e "$tmp/nomodule.tif"
check "without the OpenImageIO module: the reason is given" grep -q "nomodule.tif: .*OpenImageIO.*could not be loaded" "$tmp/nomodule.txt"
"$bin" render "$tmp/small.pbrt" -o "$tmp/with-module.tif" --quiet
check "with the OpenImageIO module: .tif written" test $? -eq 0 -a -s "$tmp/with-module.tif"

# pbrt compatibility: gzip inputs render as their text; unsupported things are all listed.
mkdir -p "$tmp/gz"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n-1 -1 0\n1 -1 0\n0 1 0\n3 0 1 2\n' > "$tmp/gz/t.ply"
gzip -c "$tmp/gz/t.ply" > "$tmp/gz/t.ply.gz"
sed 's/Shape "sphere".*/Shape "plymesh" "string filename" "t.ply"/' "$tmp/small.pbrt" > "$tmp/gz/s.pbrt"
sed 's/"t.ply"/"t.ply.gz"/' "$tmp/gz/s.pbrt" | gzip -c > "$tmp/gz/s.pbrt.gz"
"$bin" render "$tmp/gz/s.pbrt" -o "$tmp/gz/a.pfm" --seed 3 --quiet
"$bin" render "$tmp/gz/s.pbrt.gz" -o "$tmp/gz/b.pfm" --seed 3 --quiet
check "a .pbrt.gz with a .ply.gz renders as the uncompressed scene" cmp -s "$tmp/gz/a.pfm" "$tmp/gz/b.pfm"
head -c 100 "$tmp/gz/t.ply.gz" > "$tmp/gz/cut.ply.gz"
sed 's/"t.ply"/"cut.ply.gz"/' "$tmp/gz/s.pbrt" > "$tmp/gz/cut.pbrt"
"$bin" render "$tmp/gz/cut.pbrt" -o "$tmp/gz/c.pfm" --quiet > "$tmp/gz/cut.txt" 2>&1
check "a truncated .ply.gz is an error at its Shape" grep -q "cut.pbrt:8:1: .*cut.ply.gz: truncated gzip data" "$tmp/gz/cut.txt"
sed -e 's/Camera "perspective"/Camera "realistic"/' -e 's/\(Shape "sphere"\)/\1 "float radus" 1/' \
  -e 's/^LightSource.*/LightSource "projection"/' "$tmp/small.pbrt" > "$tmp/gz/three.pbrt"
"$bin" render "$tmp/gz/three.pbrt" -o "$tmp/gz/t.pfm" --quiet > "$tmp/gz/three.txt" 2>&1
check "unsupported things: non-zero exit" test $? -ne 0
check "unsupported things: all three located" bash -c "grep -q 'three.pbrt:2:1: Camera \"realistic\"' '$tmp/gz/three.txt' && grep -q 'three.pbrt:6:1: light type \"projection\"' '$tmp/gz/three.txt' && grep -q 'three.pbrt:8:.*unused parameter \"float radus\"' '$tmp/gz/three.txt'"

# check: parse and build without rendering; every problem located; a summary; JSON.
"$bin" check "$tmp/small.pbrt" > "$tmp/check-ok.txt" 2>&1
check "check of a good scene exits 0" test $? -eq 0
check "check summarises the scene" grep -q "small.pbrt: ok: 1 shapes (0 triangles), 0 instances, 1 lights, 1 materials, 1 textures; parsed and built in" "$tmp/check-ok.txt"
mkdir -p "$tmp/chk" && cp "$tmp/small.pbrt" "$tmp/chk/"
(cd "$tmp/chk" && "$bin" check small.pbrt > /dev/null 2>&1)
check "check renders nothing (no Film output written)" test ! -e "$tmp/chk/small.exr"
"$bin" check "$tmp/small.pbrt" "$tmp/gz/three.pbrt" "$tmp/gz/s.pbrt" --json "$tmp/check.json" > "$tmp/check3.txt" 2>&1
check "check with one bad scene of three exits 1" test $? -eq 1
check "check lists the bad scene's three problems" bash -c "grep -q 'three.pbrt: FAILED: 3 errors (3 unsupported' '$tmp/check3.txt' && grep -q 'unsupported: .*three.pbrt:2:1: Camera \"realistic\"' '$tmp/check3.txt' && grep -q 'unsupported: .*three.pbrt:8:.*unused parameter \"float radus\"' '$tmp/check3.txt'"
check "check counts the scenes that build" grep -q "^2 of 3 scenes parse and build$" "$tmp/check3.txt"
check "check --json: per scene ok, errors located, warnings" python3 -c "
import json, sys
j = json.load(open('$tmp/check.json'))
r = j['results']
assert j['scenes'] == 3 and j['scenes_ok'] == 2, j
assert [x['ok'] for x in r] == [True, False, True]
e = {(x['line'], x['column'], x['unsupported']) for x in r[1]['errors']}
assert (2, 1, True) in e and (6, 1, True) in e and len(e) == 3, e
assert all(x['file'].endswith('three.pbrt') for x in r[1]['errors'])
assert r[0]['summary']['shapes'] == 1 and r[0]['summary']['lights'] == 1
assert r[2]['summary']['triangles'] == 1
assert all(isinstance(x['warnings'], list) for x in r)
"
printf 'WorldBegin\nShape "sphere" "float radius" [ 1\n' > "$tmp/syntax.pbrt"
"$bin" check "$tmp/syntax.pbrt" > "$tmp/check-syntax.txt" 2>&1
check "check: a syntax error exits 1" test $? -eq 1
check "check: a syntax error is located" bash -c "grep -q 'syntax.pbrt: FAILED: 1 error ' '$tmp/check-syntax.txt' && grep -q 'error: .*syntax.pbrt:[0-9]*:[0-9]*: ' '$tmp/check-syntax.txt'"
printf 'WorldBegin\nActiveTransform EndTime\nShape "sphere"\n' > "$tmp/warn.pbrt"
"$bin" check "$tmp/warn.pbrt" --json "$tmp/warn.json" > "$tmp/check-warn.txt" 2>&1
check "check reports warnings with their location" grep -q "warning: .*warn.pbrt:2:1: ActiveTransform" "$tmp/check-warn.txt"
check "check --json keeps the warnings" python3 -c "
import json; w = json.load(open('$tmp/warn.json'))['results'][0]['warnings']
assert w and w[0]['line'] == 2 and 'ActiveTransform' in w[0]['message'], w"
"$bin" check "$tmp/missing.pbrt" > "$tmp/check-missing.txt" 2>&1
check "check of a missing file exits 1" test $? -eq 1
check "check of a missing file says so" grep -q "missing.pbrt: FAILED" "$tmp/check-missing.txt"

# measure --method: auto picks radiosity for an all-diffuse scene and says so; the JSON
# names the method; --radiosity-mesh writes a PLY; path is forced by --method path; a mesh
# without the radiosity method is an error; render with Integrator "radiosity".
cie58="$ROOT/tests/data/cie171/case-5.8-rho0.5.pbrt"
"$bin" measure "$cie58" --rel-error 0.05 --replicas 4 --pilot-samples 4 --json "$tmp/rad.json" \
  --radiosity-mesh "$tmp/rad.ply" > "$tmp/rad.txt" 2>&1
check "measure --method auto on diffuse surfaces exits 0" test $? -eq 0
check "auto says radiosity and why" grep -q "method radiosity (auto: every surface is diffuse)" "$tmp/rad.txt"
check "the JSON names the method" python3 -c "
import json; d = json.load(open('$tmp/rad.json'))
assert d['method'] == 'radiosity' and d['radiosity']['unknowns'] > 0, d.get('method')
assert all(s > 0 for m in d['meters'] for s in m['stderr'])"
check "--radiosity-mesh writes a binary PLY with colours" bash -c "head -c 600 '$tmp/rad.ply' | grep -q 'property uchar red'"
"$bin" measure "$cie58" --method path --rel-error 0.2 > "$tmp/radp.txt" 2>&1
check "--method path says so" grep -q "method path (--method path)" "$tmp/radp.txt"
"$bin" measure "$cie58" --method path --radiosity-mesh "$tmp/x.ply" > "$tmp/radx.txt" 2>&1
check "--radiosity-mesh without radiosity fails" test $? -ne 0
check "--radiosity-mesh without radiosity says why" grep -q "not radiosity" "$tmp/radx.txt"
{ cat "$tmp/small.pbrt"; echo 'Meter "illuminance" "string name" "p" "point3 p" [ 0 0 -2 ] "normal n" [ 0 0 -1 ]'; } > "$tmp/radsphere.pbrt"
"$bin" measure "$tmp/radsphere.pbrt" --rel-error 0.2 > "$tmp/radm.txt" 2>&1
check "auto picks radiosity for a diffuse sphere (meshed)" grep -q "method radiosity (auto: " "$tmp/radm.txt"
sed 's/Material "diffuse" "rgb reflectance" \[ 0.5 0.5 0.5 \]/Material "conductor"/' "$tmp/radsphere.pbrt" > "$tmp/radglossy.pbrt"
"$bin" measure "$tmp/radglossy.pbrt" --rel-error 0.2 > "$tmp/radg.txt" 2>&1
check "auto keeps the path tracer for a metal sphere" grep -q "method path (auto: " "$tmp/radg.txt"
"$bin" measure "$cie58" --pilot-samples 3 > "$tmp/radps.txt" 2>&1
check "--pilot-samples must be a power of two" grep -q "not a power of two" "$tmp/radps.txt"
# measure --method light: the cell-averaged grids by light tracing (their estimator says so,
# the JSON's method is "light"); checkpoints are refused with it.
"$bin" measure "$cie58" --method light --rel-error 0.05 --json "$tmp/light.json" > "$tmp/light.txt" 2>&1
check "measure --method light exits 0" test $? -eq 0
check "--method light says so" grep -q "method light (--method light)" "$tmp/light.txt"
check "the light-traced grids say light tracing" python3 -c "
import json; d = json.load(open('$tmp/light.json'))
assert d['method'] == 'light', d['method']
assert all(m['estimator'] == 'light tracing' and m['stderr'][0] > 0 for m in d['meters']), d['meters']"
"$bin" measure "$cie58" --method light --checkpoint "$tmp/light.ckpt" > "$tmp/lightc.txt" 2>&1
check "--method light with a checkpoint fails" test $? -ne 0
check "--method light with a checkpoint says why" grep -q "checkpoints are not supported with light tracing" "$tmp/lightc.txt"
sed 's/^Integrator .*/Integrator "radiosity" "integer maxpatches" [ 200 ]/' "$cie58" > "$tmp/rad-int.pbrt"
"$bin" render "$tmp/rad-int.pbrt" -o "$tmp/rad.exr" --spp 4 --radiosity-mesh "$tmp/rad2.ply" --quiet
check "render with Integrator radiosity exits 0" test $? -eq 0
check "render with Integrator radiosity writes image and mesh" test -s "$tmp/rad.exr" -a -s "$tmp/rad2.ply"
printf 'Integrator "radiosity" "integer maxpatches" [ 0 ]\nWorldBegin\n' > "$tmp/radbad.pbrt"
"$bin" render "$tmp/radbad.pbrt" -o "$tmp/radbad.exr" > "$tmp/radbad.txt" 2>&1
check "a bad radiosity parameter is located" grep -q "radbad.pbrt:1:1.*maxpatches" "$tmp/radbad.txt"

echo "cli: $pass passed, $fail failed"
test "$fail" -eq 0
