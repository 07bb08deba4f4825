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
import sys

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from caustic_bdpt import compare_third  # noqa: E402

if __name__ == "__main__":
    compare_third(__doc__, "vcm", 16, "spp")
