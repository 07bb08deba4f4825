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
import sys

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from caustic_bdpt import compare_third  # noqa: E402

if __name__ == "__main__":
    compare_third(__doc__, "mlt", 64, "mpp")
