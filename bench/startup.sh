#!/usr/bin/env bash
# Start-up benchmark: the fixed cost of a steradian process. Runs `steradian --version`,
# `steradian --help` and a render of a trivial scene (bench/scenes/trivial.pbrt: one sphere,
# 16x16 pixels, 1 sample per pixel, written as EXR and as PNG) RUNS times each and prints
# the median and the maximum of wall time, CPU time (user + system) and peak RSS.
# The figures come from wait4(2) (microsecond CPU times, the child's own peak RSS) and a
# monotonic clock around fork and exec; nothing of the measuring process is counted.
# Targets (the reliability issue): --version under 30 ms and 20 MB, the trivial scene
# under 100 ms wall.
# Usage: [RUNS=N] bench/startup.sh [BINARY]     (default build/release/steradian, N = 20)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/release/steradian}
[ -x "$bin" ] || { echo "no executable $bin (build first: cmake --preset release && cmake --build --preset release)"; exit 1; }
runs=${RUNS:-20}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

python3 - "$bin" "$runs" "$tmp" <<'PY'
import os, statistics, sys, time

binary, runs, tmp = sys.argv[1], int(sys.argv[2]), sys.argv[3]
scene = "bench/scenes/trivial.pbrt"
cases = [
    ("--version", [binary, "--version"]),
    ("--help", [binary, "--help"]),
    ("render trivial -> exr", [binary, "render", scene, "-o", f"{tmp}/t.exr", "--quiet"]),
    ("render trivial -> png", [binary, "render", scene, "-o", f"{tmp}/t.png", "--quiet"]),
]

def run(argv):
    devnull = os.open(os.devnull, os.O_WRONLY)
    t0 = time.perf_counter()
    pid = os.fork()
    if pid == 0:
        os.dup2(devnull, 1)
        os.dup2(devnull, 2)
        os.execv(argv[0], argv)
    _, status, ru = os.wait4(pid, 0)
    wall = time.perf_counter() - t0
    os.close(devnull)
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"startup.sh: {' '.join(argv)} failed (status {status})")
    return wall, ru.ru_utime + ru.ru_stime, ru.ru_maxrss / 1024  # s, s, MiB

print(f"{binary}, {runs} runs each: median (max)")
print(f"{'':24s} {'wall ms':>16s} {'CPU ms':>16s} {'max RSS MiB':>16s}")
for name, argv in cases:
    run(argv)  # one warm-up run: the page cache holds the executable and its libraries
    samples = [run(argv) for _ in range(runs)]
    cols = []
    for k, scale in ((0, 1000), (1, 1000), (2, 1)):
        v = [s[k] * scale for s in samples]
        cols.append(f"{statistics.median(v):8.1f} ({max(v):5.1f})")
    print(f"{name:24s} {cols[0]:>16s} {cols[1]:>16s} {cols[2]:>16s}")
PY
