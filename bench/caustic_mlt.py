#!/usr/bin/env python3
"""mlt against bdpt and path on the caustic at equal CPU time (bench/scenes/caustic.pbrt;
the measure of bench/caustic_bdpt.py).

Renders the scene with Integrator "path", "bdpt" and "mlt" (the scene's Integrator line
replaced; mlt with pbrt-v4's defaults but "maxdepth" 8 as the others), each RUNS times with
different seeds, and measures each render's error against a converged reference as the RMS
over 16 x 16-pixel blocks of the blocks' relative luminance errors. The error at equal CPU
time scales as 1 / sqrt(time), so the ratio reported for each integrator X is
    sqrt(MSE_X x CPU_X / (MSE_path x CPU_path)),
X's error over path's when both are given the same CPU time. For mlt the CPU time includes
its bootstrap (100000 x 9 paths), which does not shrink with the mutations; its error is
measured at the given mutation count. CPU seconds are the renderer's user + system time.
mlt's error also has a part that does not average out within one render: the bootstrap's
estimate of the normalisation b scales the whole image; it is reported apart (the RMS over
the runs of the relative error of the image mean).

Usage: bench/caustic_mlt.py STERADIAN REFERENCE.exr [PATH_SPP] [BDPT_SPP] [MLT_MPP] [RUNS]
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
    "mlt": 'Integrator "mlt" "integer maxdepth" [ 8 ]',
}


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    exe = str(pathlib.Path(sys.argv[1]).resolve())
    ref_img = read_exr(sys.argv[2]) @ Y
    ref = blocks(ref_img)
    spp = {"path": int(sys.argv[3]) if len(sys.argv) > 3 else 64,
           "bdpt": int(sys.argv[4]) if len(sys.argv) > 4 else 16,
           "mlt": int(sys.argv[5]) if len(sys.argv) > 5 else 64}
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
        print(f"{name:5s} {spp[name]:4d} {'mpp' if name == 'mlt' else 'spp'}: CPU "
              f"{np.mean(secs):7.2f} s, RMS relative block error {np.sqrt(np.mean(mses)):.4f} "
              f"(runs {', '.join(f'{np.sqrt(m):.4f}' for m in mses)}); image mean's relative "
              f"error RMS {np.sqrt(np.mean(np.square(mean_err))):.4f}")
    mp, tp = res["path"]
    for name in ("bdpt", "mlt"):
        m, t = res[name]
        print(f"error at equal CPU time, {name} / path: {np.sqrt(m * t / (mp * tp)):.3f}")
    mb, tb = res["bdpt"]
    m, t = res["mlt"]
    print(f"error at equal CPU time, mlt / bdpt: {np.sqrt(m * t / (mb * tb)):.3f}")


if __name__ == "__main__":
    main()
