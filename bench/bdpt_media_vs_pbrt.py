#!/usr/bin/env python3
"""steradian's bdpt against pbrt-v4's bdpt on a scene with participating media (default
bench/scenes/foggy_room.pbrt, whose Integrator line must be bdpt's): both are unbiased
estimators of the same image, so their 16 x 16-pixel block means and image means agree within
the standard errors of RUNS independent renders (seeds) each. Prints the image means with
their standard errors, the z-score of their difference, the mean square and largest |z| over
the blocks, and each renderer's CPU seconds per render (user + system of the child), and writes
the first render of each as PNG to OUTDIR. pbrt-v4 runs on one thread: on two its bdpt
crashes (SIGSEGV) on bench/scenes/foggy_room.pbrt (build of /work/pbrt-v4-build, 27 Nov 2026).

Usage: bench/bdpt_media_vs_pbrt.py STERADIAN PBRT [SPP] [RUNS] [OUTDIR] [SCENE] [FIRST_SEED]
"""
import pathlib
import resource
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from noise_vs_pbrt import read_exr, read_pfm  # noqa: E402

Y = np.array([0.2126, 0.7152, 0.0722])
SCENE = pathlib.Path(__file__).resolve().parent / "scenes" / "foggy_room.pbrt"


def cpu_run(cmd):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, check=True, capture_output=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def blocks(lum, b=16):
    h, w = lum.shape
    return lum[: h // b * b, : w // b * b].reshape(h // b, b, w // b, b).mean(axis=(1, 3)).ravel()


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    ours, pbrt = (str(pathlib.Path(p).resolve()) for p in sys.argv[1:3])
    spp = int(sys.argv[3]) if len(sys.argv) > 3 else 64
    runs = int(sys.argv[4]) if len(sys.argv) > 4 else 4
    outdir = pathlib.Path(sys.argv[5]) if len(sys.argv) > 5 else pathlib.Path(tempfile.mkdtemp())
    scene = pathlib.Path(sys.argv[6]).resolve() if len(sys.argv) > 6 else SCENE
    seed0 = int(sys.argv[7]) if len(sys.argv) > 7 else 1
    outdir.mkdir(parents=True, exist_ok=True)
    tmp = pathlib.Path(tempfile.mkdtemp())
    stats = {}
    for name in ("steradian", "pbrt-v4"):
        bl, means, secs = [], [], []
        for seed in range(runs):
            exr = tmp / f"{name}-{seed}.exr"
            if name == "steradian":
                out = tmp / f"{name}-{seed}.pfm"
                secs.append(cpu_run([ours, "render", str(scene), "-q", "--spp", str(spp), "--seed",
                                     str(seed + seed0), "--threads", "2", "-o", str(out)]))
                lum = read_pfm(out) @ Y
                if seed == 0:
                    subprocess.run([ours, "render", str(scene), "-q", "--spp", str(spp), "--seed",
                                    str(seed0), "--threads", "2", "-o", str(exr)], check=True)
            else:
                secs.append(cpu_run([pbrt, "--quiet", "--spp", str(spp), "--seed", str(seed + seed0),
                                     "--nthreads", "1", "--outfile", str(exr), str(scene)]))
                lum = read_exr(exr) @ Y
            if seed == 0:
                subprocess.run(["oiiotool", str(exr), "--tocolorspace", "sRGB", "-o",
                                str(outdir / f"{name}.png")], check=True)
            bl.append(blocks(lum))
            means.append(lum.mean())
        bl, means = np.array(bl), np.array(means)
        stats[name] = (bl.mean(axis=0), bl.std(axis=0, ddof=1) / np.sqrt(runs),
                       means.mean(), means.std(ddof=1) / np.sqrt(runs), np.mean(secs))
        s = stats[name]
        print(f"{name:9s} {spp} spp x {runs}: image mean {s[2]:.6f} +- {s[3]:.6f}, "
              f"CPU {s[4]:.1f} s per render")
    a, b = stats["steradian"], stats["pbrt-v4"]
    z = (a[0] - b[0]) / np.sqrt(a[1] ** 2 + b[1] ** 2)
    zm = (a[2] - b[2]) / np.hypot(a[3], b[3])
    print(f"image means: steradian / pbrt-v4 = {a[2] / b[2]:.4f}, z = {zm:.2f}")
    print(f"blocks ({z.size}): mean square z {np.mean(z * z):.2f}, largest |z| {np.abs(z).max():.2f}")
    print(f"PNGs in {outdir}")


if __name__ == "__main__":
    main()
