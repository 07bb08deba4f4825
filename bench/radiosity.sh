#!/usr/bin/env bash
# Radiosity benchmark (issue 21): CIE 171:2006 case 5.8 at rho = 0.8 with a 50 x 50
# cell-averaged indirect illuminance grid on the floor (bench/scenes/cie171-5.8-rho0.8-grid50.pbrt).
# Runs `steradian measure ... --json` RUNS times and prints the median and maximum wall time
# from process start to JSON written, the CPU time (user + system, wait4) and the floor's
# average indirect illuminance against the closed form rho Phi / (S (1 - rho)) = 416.667 lx
# (target: within 0.2 %, under 2 s wall). With PATH_TOO=1 in the environment, the
# path tracer once on the same scene for comparison (about 30 CPU-s).
# With OFFICE=1, instead the proof scene scenes/office.pbrt: its 20 x 20 working-plane grid by
# radiosity (--rel-error OFFICE_RAD, default 0.003) RUNS times, then by the path tracer
# (--method path --rel-error OFFICE_PATH, default 0.001: about 270 CPU-s) in the same run,
# and the per-point and average deviations of radiosity from the path tracer with the
# combined standard errors (issue 21's criterion: 1 % at every point, 0.3 % on average).
# With CURVED=1, the same comparison on bench/scenes/curved-room.pbrt (a sphere, a column and
# a round table: curved shapes meshed by the radiosity pass), its meter "points".
# Usage: [RUNS=N] [PATH_TOO=1] [OFFICE=1 | CURVED=1] bench/radiosity.sh [BINARY]   (default build/release/steradian, N = 5)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/release/steradian}
[ -x "$bin" ] || { echo "no executable $bin (build first: cmake --preset release && cmake --build --preset release)"; exit 1; }
runs=${RUNS:-5}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

if [ "${OFFICE:-0}" = 1 ] || [ "${CURVED:-0}" = 1 ]; then
if [ "${CURVED:-0}" = 1 ]; then
  scene=bench/scenes/curved-room.pbrt meter=points
else
  scene=scenes/office.pbrt meter=working-plane
fi
python3 - "$bin" "$runs" "$tmp" "${OFFICE_RAD:-0.003}" "${OFFICE_PATH:-0.001}" "$scene" "$meter" <<'PY'
import json, math, os, statistics, sys, time

binary, runs, tmp, rad_err, path_err = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4], sys.argv[5]
scene, meter = sys.argv[6], sys.argv[7]

def run(extra):
    out = f"{tmp}/m.json"
    if os.path.exists(out):
        os.remove(out)
    argv = [binary, "measure", scene, "--json", out, "-q"] + extra
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
    if status != 0:
        sys.exit(f"failed: {' '.join(argv)}")
    d = json.load(open(out))
    grid = next(m for m in d["meters"] if m["name"] == meter)
    return wall, ru.ru_utime + ru.ru_stime, grid, d

walls, cpus = [], []
for _ in range(runs):
    wall, cpu, R, d = run(["--rel-error", rad_err])
    walls.append(wall)
    cpus.append(cpu)
print(f"radiosity: {binary} measure {scene} --rel-error {rad_err}: wall median {statistics.median(walls):.2f} s "
      f"max {max(walls):.2f} s, CPU median {statistics.median(cpus):.2f} s; {d.get('radiosity')}")
wall, cpu, P, _ = run(["--method", "path", "--rel-error", path_err])
print(f"path: {binary} measure {scene} --method path --rel-error {path_err}: wall {wall:.1f} s, CPU {cpu:.1f} s")
dev = [r / p - 1 for r, p in zip(R["values"], P["values"])]
z = [(r - p) / math.hypot(a, b) for r, p, a, b in zip(R["values"], P["values"], R["stderr"], P["stderr"])]
beyond = sum(1 for r, p, a, b in zip(R["values"], P["values"], R["stderr"], P["stderr"])
             if abs(r - p) > 0.01 * p + 3 * math.hypot(a, b))
if "avg" in R:
    print(f"E_avg radiosity {R['avg']:.3f} +- {R['avg_stderr']:.3f}, path {P['avg']:.3f} +- {P['avg_stderr']:.3f}: "
          f"{100 * (R['avg'] / P['avg'] - 1):+.3f} %")
print(f"per point: {100 * min(dev):+.2f} .. {100 * max(dev):+.2f} %, mean |dev| {100 * statistics.mean(map(abs, dev)):.2f} %, "
      f"|z| max {max(map(abs, z)):.1f}; beyond 1 % + 3 se: {beyond} of {len(dev)}")
PY
exit 0
fi

python3 - "$bin" "$runs" "$tmp" "${PATH_TOO:-0}" <<'PY'
import json, os, statistics, sys, time

binary, runs, tmp, path_too = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4] == "1"
scene = "bench/scenes/cie171-5.8-rho0.8-grid50.pbrt"
expected = 0.8 * 10000 / (96 * 0.2)

def run(extra):
    out = f"{tmp}/m.json"
    if os.path.exists(out):
        os.remove(out)
    argv = [binary, "measure", scene, "--json", out, "-q"] + extra
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
    if status != 0:
        sys.exit(f"failed: {' '.join(argv)}")
    d = json.load(open(out))
    m = d["meters"][0]
    return wall, ru.ru_utime + ru.ru_stime, m["avg"], m["avg_stderr"], d

opts = ["--rel-error", "0.02", "--replicas", "8", "--pilot-samples", "8"]
print(f"command: {binary} measure {scene} {' '.join(opts)} --json OUT.json")
walls, cpus = [], []
for _ in range(runs):
    wall, cpu, avg, se, d = run(opts)
    walls.append(wall)
    cpus.append(cpu)
print(f"radiosity: wall median {statistics.median(walls):.3f} s max {max(walls):.3f} s, "
      f"CPU median {statistics.median(cpus):.3f} s; E_avg {avg:.3f} +- {se:.3f} lx "
      f"({100 * (avg / expected - 1):+.3f} % of {expected:.3f}); {d.get('radiosity')}")
if path_too:
    wall, cpu, avg, se, _ = run(["--method", "path"])
    print(f"path (default options): wall {wall:.2f} s, CPU {cpu:.2f} s; E_avg {avg:.3f} +- {se:.3f} lx "
          f"({100 * (avg / expected - 1):+.3f} %)")
PY
