#!/usr/bin/env python3
"""vcm against bdpt and path on the caustic at equal CPU time (bench/scenes/caustic.pbrt;
the measure of bench/caustic_bdpt.py).

Renders the scene with Integrator "path", "bdpt" and "vcm" (the scene's Integrator line
replaced, "maxdepth" 8 for all; vcm with its default radius, 0.003 x the scene's bounding
radius, and radiusalpha 0.75), each RUNS times with different seeds, and measures each
render's error against a converged reference as the RMS over 16 x 16-pixel blocks of the
blocks' relative luminance errors (block mean - reference block mean) / reference block mean.
The error at equal CPU time scales as 1 / sqrt(time) (for vcm's merged part nearly so: its
radius shrinks slowly), so the ratio reported for each integrator X is
    sqrt(MSE_X x CPU_X / (MSE_Y x CPU_Y)),
X's error over Y's when both are given the same CPU time. CPU seconds are the renderer's
user + system time (getrusage of the child). The image mean's relative error is reported
too (vcm's merging is biased: a bias would show there, beside the reference's own noise).

Usage: bench/caustic_vcm.py STERADIAN REFERENCE.exr [PATH_SPP] [BDPT_SPP] [VCM_SPP] [RUNS]
"""
import pathlib
import resource
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from caustic_bdpt import SCENE, Y, blocks  # noqa: E402
from noise_vs_pbrt import read_exr, read_pfm  # noqa: E402

INTEGRATORS = {
    "path": 'Integrator "path" "integer maxdepth" [ 8 ]',
    "bdpt": 'Integrator "bdpt" "integer maxdepth" [ 8 ]',
    "vcm": 'Integrator "vcm" "integer maxdepth" [ 8 ]',
}


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    exe = str(pathlib.Path(sys.argv[1]).resolve())
    ref_img = read_exr(sys.argv[2]) @ Y
    ref = blocks(ref_img)
    spp = {"path": int(sys.argv[3]) if len(sys.argv) > 3 else 64,
           "bdpt": int(sys.argv[4]) if len(sys.argv) > 4 else 16,
           "vcm": int(sys.argv[5]) if len(sys.argv) > 5 else 16}
    runs = int(sys.argv[6]) if len(sys.argv) > 6 else 3
    tmp = pathlib.Path(tempfile.mkdtemp())
    text = SCENE.read_text()
    res = {}
    for name, line in INTEGRATORS.items():
        scene = tmp / f"{name}.pbrt"
        scene.write_text(text.replace('Integrator "bdpt" "integer maxdepth" [ 8 ]', line))
        mses, secs, mean_err = [], [], []
        for seed in range(runs):
            out = tmp / f"{name}-{seed}.pfm"
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            subprocess.run([exe, "render", str(scene), "-q", "--spp", str(spp[name]), "--seed",
                            str(seed), "--threads", "2", "-o", str(out)], check=True)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            secs.append((after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime))
            img = read_pfm(out) @ Y
            rel = (blocks(img) - ref) / ref
            mses.append(float(np.mean(rel * rel)))
            mean_err.append(img.mean() / ref_img.mean() - 1)
        res[name] = (np.mean(mses), np.mean(secs))
        print(f"{name:5s} {spp[name]:4d} spp: CPU {np.mean(secs):7.2f} s, RMS relative block "
              f"error {np.sqrt(np.mean(mses)):.4f} (runs "
              f"{', '.join(f'{np.sqrt(m):.4f}' for m in mses)}); image mean's relative error "
              f"RMS {np.sqrt(np.mean(np.square(mean_err))):.4f}")
    for x, y in (("bdpt", "path"), ("vcm", "path"), ("vcm", "bdpt")):
        (mx, tx), (my, ty) = res[x], res[y]
        print(f"error at equal CPU time, {x} / {y}: {np.sqrt(mx * tx / (my * ty)):.3f}")


if __name__ == "__main__":
    main()
