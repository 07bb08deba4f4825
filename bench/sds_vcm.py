#!/usr/bin/env python3
"""vcm against sppm and bdpt on the specular-diffuse-specular scene (scenes/sds-mirrors.pbrt;
the measure of bench/sds_sppm.py), as error against the closed form versus CPU time.

Each pixel that sees the lit floor through the mirror is compared with the closed form
(docs/sppm.md), as the RMS over the 8 x 8-pixel blocks wholly on the lit floor of the blocks'
relative luminance errors. bdpt cannot sample these paths (error 1: it renders the floor
black); sppm and vcm converge (vcm by merging, the only one of its strategies that can make
these paths, with MIS weight 1 there). Both use the initial radius 0.05 of the scene; sppm
traces the scene's 65536 photons per iteration, vcm one light path per pixel (4096, "vcm")
or as many as sppm's photons ("vcm-65536", "integer lightpathsperiteration" [ 65536 ]), so
iterations cost differently and the comparison is made at equal CPU time: for each run the
error times sqrt(CPU seconds) (the error of one CPU second, if the error falls as
1/sqrt(time)). CPU seconds are the renderer's user + system time (getrusage of the child).
Each configuration is rendered RUNS times with different seeds and the MSEs averaged.

Usage: bench/sds_vcm.py STERADIAN [RUNS] [SPPM_ITERATIONS] [VCM_ITERATIONS...]
"""
import math
import pathlib
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from noise_vs_pbrt import read_pfm  # noqa: E402
from sds_sppm import BLOCK, RES, SCENE, Y, expected_blocks, render  # noqa: E402


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    exe = str(pathlib.Path(sys.argv[1]).resolve())
    runs = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    sppm_iters = int(sys.argv[3]) if len(sys.argv) > 3 else 16
    vcm_iters = [int(a) for a in sys.argv[4:]] or [16, 64, 256]
    want = expected_blocks()
    keep = ~np.isnan(want)
    print(f"blocks on the lit floor: {keep.sum()} of {want.size}")
    text = SCENE.read_text()
    tmp = pathlib.Path(tempfile.mkdtemp())
    i0, i1 = text.index('Integrator "sppm"'), text.index("WorldBegin")
    runs_list = [("bdpt", 'Integrator "bdpt" "integer maxdepth" [ 5 ]', 16),
                 ("sppm", text[i0:i1], sppm_iters)]
    vcm = 'Integrator "vcm" "integer maxdepth" [ 5 ] "float radius" [ 0.05 ]'
    runs_list += [("vcm", vcm, n) for n in vcm_iters]
    runs_list += [("vcm-65536", vcm + ' "integer lightpathsperiteration" [ 65536 ]', n)
                  for n in vcm_iters]
    print(f"{'integrator':10} {'spp/iter':>8} {'CPU s':>8} {'RMS rel. block error':>22} "
          f"{'error x sqrt(CPU s)':>20}")
    for name, line, spp in runs_list:
        scene = text[:i0] + line + "\n" + text[i1:]
        mses, secs = [], []
        for seed in range(runs):
            out = tmp / f"{name}-{spp}-{seed}.pfm"
            secs.append(render(exe, scene, spp, 1 + seed, out))
            got = read_pfm(out) @ Y
            b = got.reshape(RES // BLOCK, BLOCK, RES // BLOCK, BLOCK).mean(axis=(1, 3))
            rel = (b - want) / want
            mses.append(float(np.mean(rel[keep] ** 2)))
        err, cpu = math.sqrt(np.mean(mses)), float(np.mean(secs))
        print(f"{name:10} {spp:8d} {cpu:8.2f} {err:22.5f} {err * math.sqrt(cpu):20.5f}")


if __name__ == "__main__":
    main()
