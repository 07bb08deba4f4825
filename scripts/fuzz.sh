#!/usr/bin/env bash
# Fuzzes every input reader: builds the libFuzzer harnesses of fuzz/ (cmake preset `fuzz`,
# clang-14 with ASan + UBSan) if needed, then runs each harness for SECONDS (default 60),
# JOBS (default 2) harnesses at a time. Prints per harness the executions run and whether it
# crashed (a crash, sanitizer report, timeout or out-of-memory); exits 1 if any did. Inputs that crash are written to
# fuzz/regressions/<harness>/, which the normal test build replays (ctest fuzz_regressions):
# fix the reader, then commit the input with the fix.
#
# Usage: scripts/fuzz.sh [SECONDS] [HARNESS...]     (default: every harness)
# The corpus each harness grows is kept in build/fuzz/corpus/<harness>/ between runs; the
# seeds are assembled at run time in build/fuzz/seeds/<harness>/ from the project's scenes,
# test data and fuzz/seeds/.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
seconds=${1:-60}
shift || true
jobs=${JOBS:-2}

all=(pbrt_tokenizer pbrt_parser scene_build ply ies eulumdat spectrum_file measured_brdf nanovdb)
harnesses=("$@")
[ ${#harnesses[@]} -eq 0 ] && harnesses=("${all[@]}")

if ! command -v clang++-14 >/dev/null; then
  echo "fuzz.sh: clang++-14 not found (scripts/install-deps.sh installs it)" >&2
  exit 2
fi
[ -f build/fuzz/build.ninja ] || cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$jobs" --target fuzz_harnesses

# Per harness: the largest input (bytes) and the files the seeds come from.
max_len() {
  case $1 in
    pbrt_tokenizer) echo 4096 ;;
    pbrt_parser | scene_build) echo 12000 ;;  # the test scenes are up to 9 kB
    ply | ies | eulumdat | measured_brdf) echo 4096 ;;
    spectrum_file) echo 1024 ;;
    nanovdb) echo 700000 ;;  # an uncompressed grid has a 270 kB upper node
  esac
}
seed_files() {
  case $1 in
    pbrt_tokenizer | pbrt_parser | scene_build)
      find scenes tests/data fuzz/seeds/pbrt -name '*.pbrt' ;;
    ply) find tests/data fuzz/seeds/ply -name '*.ply' ;;
    ies) find tests/data fuzz/seeds/ies -name '*.ies' ;;
    eulumdat) find tests/data fuzz/seeds/eulumdat -name '*.ldt' ;;
    spectrum_file) find tests/data fuzz/seeds/spectrum_file -name '*.spd' ;;
    measured_brdf) find fuzz/seeds/measured_brdf -name '*.bsdf' ;;
    nanovdb) ;;  # written below by steradian_nvdb_standin
  esac
}

# The NanoVDB seeds' writer is built before the harnesses run (they run side by side).
if printf '%s\n' "${harnesses[@]}" | grep -qx nanovdb; then
  cmake --build --preset fuzz -j "$jobs" --target steradian_nvdb_standin >/dev/null
fi
for h in "${harnesses[@]}"; do
  if [ ! -x "build/fuzz/fuzz/fuzz_$h" ]; then
    echo "fuzz.sh: no harness $h (have: ${all[*]})" >&2
    exit 2
  fi
done

# One harness: its report goes to build/fuzz/<h>.out, its summary line to <h>.summary;
# exits 1 if it crashed.
fuzz_one() {
  local h=$1
  local bin=build/fuzz/fuzz/fuzz_$h
  local seeds=build/fuzz/seeds/$h corpus=build/fuzz/corpus/$h regressions=fuzz/regressions/$h
  rm -rf "$seeds"
  mkdir -p "$seeds" "$corpus" "$regressions"
  seed_files "$h" | while read -r f; do cp "$f" "$seeds/$(echo "$f" | tr / _)"; done
  if [ "$h" = nanovdb ]; then
    # Stand-in grids (uncompressed, ZIP; with a temperature grid) from NanoVDB's own writer.
    build/fuzz/steradian_nvdb_standin "$seeds/ball.nvdb"
    build/fuzz/steradian_nvdb_standin "$seeds/ball_zip.nvdb" --zip
    build/fuzz/steradian_nvdb_standin "$seeds/fire_zip.nvdb" --temperature --zip
  fi
  if [ "$h" = scene_build ]; then
    # The harness skips scenes with a "spectrum" "imagemap" texture (fuzz/scene_build.cpp):
    # the seeds get a constant texture in its place.
    sed -i -E 's/^(Texture +"[^"]*" +"spectrum") +"imagemap".*/\1 "constant"/' "$seeds"/*
  fi
  local dict=()
  case $h in pbrt_*| scene_build) dict=(-dict=fuzz/pbrt.dict) ;; esac
  local log=build/fuzz/$h.log
  echo "== $h: ${seconds}s"
  # -timeout: one input taking longer is a hang (scene_build's first image texture builds
  # the RGB-to-spectrum table, ~15 s under ASan). -rss_limit_mb / -malloc_limit_mb: more
  # memory than this for a few kB of input is an unbounded allocation.
  local timeout=10
  [ "$h" = scene_build ] && timeout=60
  local rc=0
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$bin" "$corpus" "$seeds" "$regressions" "${dict[@]}" \
    -max_total_time="$seconds" -max_len="$(max_len "$h")" -timeout=$timeout \
    -rss_limit_mb=2048 -malloc_limit_mb=1024 -report_slow_units=$timeout -print_final_stats=1 \
    -artifact_prefix="$regressions/" >"$log" 2>&1 || rc=$?
  local execs result
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  if [ $rc -eq 0 ]; then
    result="ok"
  else
    local artifact kind
    artifact=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -1)
    kind=$(grep -m1 -oE 'ERROR: (libFuzzer|AddressSanitizer|UndefinedBehaviorSanitizer|LeakSanitizer): [a-z-]+|runtime error: .*|fuzz_check failed: .*|error without .*|build error without .*' "$log" || true)
    result="CRASH (${kind:-exit $rc}) -> ${artifact:-no input written}; log $log"
    # The failing input in the log too (CI keeps only the log), when it is small.
    if [ -n "$artifact" ] && [ "$(stat -c %s "$artifact")" -le 4096 ]; then
      echo "-- $h: crashing input, base64:"
      base64 "$artifact"
    fi
    grep -A25 -m1 -E '==ERROR|runtime error|fuzz_check failed|error without|deadly signal' "$log" || true
  fi
  echo "   executions: ${execs:-?}  $result"
  printf '%-15s %12s  %s\n' "$h" "${execs:-?}" "$result" >"build/fuzz/$h.summary"
  [ $rc -eq 0 ]
}

# The harnesses are single-threaded: JOBS of them run at a time, each report printed whole
# when it ends.
status=0
running=0
for h in "${harnesses[@]}"; do
  if [ "$running" -ge "$jobs" ]; then
    wait -n || status=1
    running=$((running - 1))
  fi
  (rc=0; fuzz_one "$h" >"build/fuzz/$h.out" 2>&1 || rc=$?; cat "build/fuzz/$h.out"; exit $rc) &
  running=$((running + 1))
done
while [ "$running" -gt 0 ]; do
  wait -n || status=1
  running=$((running - 1))
done

echo
echo "fuzz.sh: ${seconds}s per harness, ${jobs} at a time"
printf '%-15s %12s  %s\n' harness executions result
for h in "${harnesses[@]}"; do cat "build/fuzz/$h.summary"; done
exit $status
