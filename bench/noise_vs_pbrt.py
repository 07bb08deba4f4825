#!/usr/bin/env python3
"""Noise at equal CPU time against pbrt-v4: renders a scene with steradian and with a pbrt-v4
binary at the same samples per pixel, several times each with different seeds, and compares
their efficiency, 1 / (MSE x CPU seconds), where the MSE of each render is taken against a
high-spp reference image (for the scenes of ../shared/reference: pbrt-v4's own 512- or
1024-spp render). Equal efficiency means equal noise at equal time; a ratio above 1 means
steradian's noise at equal time is lower. CPU seconds are the renderer process's user + system
time (getrusage of the child), which includes scene loading for both.

The reference has noise of its own: it adds the same amount to both MSEs, which pulls the ratio
towards 1; that bias is small when the reference has many times the spp of the renders
(512 vs 16: the reference's variance is 1/32 of a render's).

pbrt-v4 is built outside the project (see docs/performance.md, "pbrt-v4 side by side"); images
are read with oiiotool (Debian's openimageio-tools).

Usage: bench/noise_vs_pbrt.py STERADIAN PBRT SCENE.pbrt REFERENCE.exr [SPP] [RUNS]
"""
import os
import pathlib
import resource
import subprocess
import sys
import tempfile

import numpy as np


def read_pfm(path):
    data = pathlib.Path(path).read_bytes()
    header, rest = [], data
    while len(header) < 3:
        line, rest = rest.split(b"\n", 1)
        header.append(line.strip())
    w, h = (int(v) for v in header[1].split())
    scale = float(header[2])
    ch = 3 if header[0] == b"PF" else 1
    a = np.frombuffer(rest, dtype="<f4" if scale < 0 else ">f4", count=w * h * ch)
    return a.reshape(h, w, ch)[::-1].astype(np.float64)


def read_exr(path):
    """An EXR's R, G, B as an H x W x 3 array, through `oiiotool --dumpdata` (Debian's
    OpenImageIO writes no PFM)."""
    out = subprocess.run(["oiiotool", "--dumpdata", str(path)], check=True, capture_output=True,
                         text=True).stdout.splitlines()
    w, h = (int(v) for v in out[0].split(":")[1].split(",")[0].split("x"))
    px = np.array([[float(v) for v in line.split(":")[1].split()[:3]] for line in out[1:]
                   if line.strip().startswith("Pixel")])
    return px.reshape(h, w, 3)


def run(cmd, cwd):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, cwd=cwd, check=True, capture_output=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    ours, pbrt = (str(pathlib.Path(p).resolve()) for p in sys.argv[1:3])
    scene = pathlib.Path(sys.argv[3]).resolve()
    reference = pathlib.Path(sys.argv[4]).resolve()
    spp = int(sys.argv[5]) if len(sys.argv) > 5 else 16
    runs = int(sys.argv[6]) if len(sys.argv) > 6 else 3
    tmp = pathlib.Path(tempfile.mkdtemp())
    ref = read_exr(reference)
    y = np.array([0.2126, 0.7152, 0.0722])
    results = {}
    for name in ("steradian", "pbrt-v4"):
        mses, secs, trimmed = [], [], []
        for seed in range(runs):
            out = tmp / f"{name}-{seed}.pfm"
            if name == "steradian":
                cmd = [ours, "render", str(scene), "-q", "--spp", str(spp), "--seed", str(seed),
                       "--threads", "2", "-o", str(out)]
            else:
                exr = tmp / f"{name}-{seed}.exr"
                cmd = [pbrt, "--nthreads", "2", "--spp", str(spp), "--seed", str(seed),
                       "--quiet", "--outfile", str(exr), str(scene)]
            secs.append(run(cmd, scene.parent))
            img = read_exr(exr) if name == "pbrt-v4" else read_pfm(out)
            d = (img - ref) @ y  # luminance error
            mses.append(float(np.mean(d * d)))
            trimmed.append(float(np.mean(np.sort((d * d).ravel())[: int(d.size * 0.999)])))
        results[name] = (np.mean(mses), np.mean(secs), float(np.mean(trimmed)))
        print(f"  per-run MSE {', '.join(f'{m:.4g}' for m in mses)}; without the 0.1 % largest "
              f"squared errors (fireflies) {np.mean(trimmed):.4g}")
        print(f"{name:10s} {spp} spp: CPU {np.mean(secs):7.2f} s (runs {', '.join(f'{s:.2f}' for s in secs)}),"
              f" luminance MSE {np.mean(mses):.4g}, efficiency 1/(MSE s) {1 / (np.mean(mses) * np.mean(secs)):.4g}")
    (m_s, t_s, r_s), (m_p, t_p, r_p) = results["steradian"], results["pbrt-v4"]
    print(f"CPU time ratio steradian / pbrt-v4: {t_s / t_p:.3f}")
    print(f"MSE ratio at equal spp, steradian / pbrt-v4: {m_s / m_p:.3f}")
    print(f"efficiency ratio steradian / pbrt-v4 (>1: less noise at equal time): "
          f"{(m_p * t_p) / (m_s * t_s):.3f}; without fireflies {(r_p * t_p) / (r_s * t_s):.3f}")


if __name__ == "__main__":
    main()
