#!/usr/bin/env python3
"""sppm against bdpt and path on a specular-diffuse-specular scene (scenes/sds-mirrors.pbrt:
a spot light lights a diffuse floor only through a mirror, and the camera sees the floor only
through a second mirror), as error against the closed form versus CPU time.

The floor's luminance there has a closed form (docs/sppm.md): each pixel that sees the lit
floor through the mirror is compared with it, as the RMS over 8 x 8-pixel blocks of the
blocks' relative luminance errors (block mean - closed form) / closed form, taking only the
blocks wholly on the lit floor (the same blocks as tests/analytic/sppm_test.cpp; the closed
form is computed here by the same ray construction: the camera's pinhole rays through 8 x 8
points of each pixel). path and bdpt cannot sample these paths at all (error 1: they render
the floor black); sppm's error falls with its iterations. CPU seconds are the renderer's
user + system time (getrusage of the child).

Usage: bench/sds_sppm.py STERADIAN [ITERATIONS...]
"""
import math
import pathlib
import resource
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from noise_vs_pbrt import read_pfm  # noqa: E402

SCENE = pathlib.Path(__file__).parent.parent / "scenes" / "sds-mirrors.pbrt"
Y = np.array([0.2126, 0.7152, 0.0722])
RES, BLOCK = 64, 8


def fresnel_conductor(c, eta=0.2, k=5.0):
    # Unpolarised reflectance of a conductor of complex IOR eta + i k (the Fresnel equations).
    n = complex(eta, k)
    s2 = 1 - c * c
    ct = np.sqrt(1 - s2 / (n * n))
    rs = (c - n * ct) / (c + n * ct)
    rp = (n * c - ct) / (n * c + ct)
    return (abs(rs) ** 2 + abs(rp) ** 2) / 2


def camera_ray(px, py):
    # The scene's pinhole camera: LookAt 0.25 -1 4 -> 0.25 2.5 1.6667, up z, fov 12 (square).
    eye = np.array([0.25, -1.0, 4.0])
    look = np.array([0.25, 2.5, 1.6667]) - eye
    f = look / np.linalg.norm(look)
    # pbrt's LookAt (right = up x dir, up' = dir x right) and its screen window [-1, 1]^2,
    # raster (0, 0) at screen (-1, 1).
    right = np.cross([0, 0, 1.0], f)
    right /= np.linalg.norm(right)
    up = np.cross(f, right)
    t = math.tan(math.radians(6))
    sx = (-1 + 2 * px / RES) * t
    sy = (1 - 2 * py / RES) * t
    d = f + sx * right + sy * up
    return eye, d / np.linalg.norm(d)


def expected(px, py, margin=0.1):
    o, d = camera_ray(px, py)
    if d[1] <= 0:
        return None
    t = (2.5 - o[1]) / d[1]
    m = o + t * d
    if m[2] < 0 or m[2] > 5 or abs(m[0]) > 3:
        return None
    c2 = d[1]
    d = d * np.array([1, -1, 1])
    if d[2] >= 0:
        return None
    s = -m[2] / d[2]
    x, y = m[0] + s * d[0], m[1] + s * d[1]
    if x < -1.4 + margin or x > 2.5 - margin or abs(y) > 2 - margin:
        return None
    v = np.array([x + 2.5, y, -3.0])
    dist = np.linalg.norm(v)
    if (v[0] - v[2]) / (math.sqrt(2) * dist) < math.cos(math.radians(18)):
        return None
    u = 1 / v[0]
    if not (0.3 <= 3 + u * v[2] <= 4 and abs(u * v[1]) <= 2):
        return None
    return fresnel_conductor(c2) * 0.5 / math.pi * fresnel_conductor(v[0] / dist) * 1000 * 3 / dist ** 3


def expected_blocks():
    nb = RES // BLOCK
    out = np.full((nb, nb), np.nan)
    for by in range(nb):
        for bx in range(nb):
            vals = []
            for py in range(by * BLOCK, (by + 1) * BLOCK):
                for px in range(bx * BLOCK, (bx + 1) * BLOCK):
                    for j in range(4):
                        for i in range(4):
                            v = expected(px + (i + 0.5) / 4, py + (j + 0.5) / 4)
                            if v is None:
                                break
                            vals.append(v)
            if len(vals) == BLOCK * BLOCK * 16:
                out[by, bx] = np.mean(vals)
    return out


def render(exe, text, spp, seed, out):
    scene = out.with_suffix(".pbrt")
    scene.write_text(text)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([exe, "render", str(scene), "-q", "--spp", str(spp), "--seed", str(seed),
                    "--threads", "2", "-o", str(out)], check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    exe = str(pathlib.Path(sys.argv[1]).resolve())
    iters = [int(a) for a in sys.argv[2:]] or [4, 16, 64]
    want = expected_blocks()
    keep = ~np.isnan(want)
    print(f"blocks on the lit floor: {keep.sum()} of {want.size}")
    text = SCENE.read_text()
    tmp = pathlib.Path(tempfile.mkdtemp())
    i0, i1 = text.index('Integrator "sppm"'), text.index("WorldBegin")
    runs = [("path", 'Integrator "path" "integer maxdepth" [ 5 ]', 64),
            ("bdpt", 'Integrator "bdpt" "integer maxdepth" [ 5 ]', 16)]
    runs += [("sppm", text[i0:i1], n) for n in iters]
    print(f"{'integrator':10} {'spp/iter':>8} {'CPU s':>8} {'RMS rel. block error':>22}")
    for name, line, spp in runs:
        scene = text[:i0] + line + "\n" + text[i1:]
        out = tmp / f"{name}-{spp}.pfm"
        cpu = render(exe, scene, spp, 1, out)
        got = read_pfm(out) @ Y
        b = got.reshape(RES // BLOCK, BLOCK, RES // BLOCK, BLOCK).mean(axis=(1, 3))
        rel = (b - want) / want
        print(f"{name:10} {spp:8d} {cpu:8.2f} {math.sqrt(np.mean(rel[keep] ** 2)):22.5f}")


if __name__ == "__main__":
    main()
