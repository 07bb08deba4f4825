#!/usr/bin/env python3
"""vcm against bdpt and volpath at equal CPU time on the foggy room (bench/scenes/foggy_room.pbrt:
a room filled with fog, lit only through a small opening; the measure of bench/caustic_bdpt.py).

Renders the scene with Integrator "path" (the volumetric path tracer, the scene having media),
"bdpt" and "vcm" (the scene's Integrator line replaced, "maxdepth" 6 for all; vcm with its
default radius), each RUNS times with different seeds, and measures each render's error
against a converged reference as the RMS over 16 x 16-pixel blocks of the blocks' relative
luminance errors. The error at equal CPU time scales as 1 / sqrt(time), so the ratio reported
for X over Y is sqrt(MSE_X x CPU_X / (MSE_Y x CPU_Y)). CPU seconds are the renderer's
user + system time (getrusage of the child). The image mean's relative error is reported too.

Usage: bench/foggy_vcm.py STERADIAN REFERENCE.exr [PATH_SPP] [BDPT_SPP] [VCM_ITERATIONS] [RUNS]
(REFERENCE.exr: e.g. steradian render bench/scenes/foggy_room.pbrt --spp 1024 --seed 99)
"""
import pathlib
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from caustic_bdpt import Y, blocks, read_exr, runs_of  # noqa: E402

SCENE = pathlib.Path(__file__).parent / "scenes" / "foggy_room.pbrt"
LINE = 'Integrator "bdpt" "integer maxdepth" [ 6 ]'


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    exe = str(pathlib.Path(sys.argv[1]).resolve())
    ref_img = read_exr(sys.argv[2]) @ Y
    ref = blocks(ref_img)
    count = {"path": int(sys.argv[3]) if len(sys.argv) > 3 else 64,
             "bdpt": int(sys.argv[4]) if len(sys.argv) > 4 else 16,
             "vcm": int(sys.argv[5]) if len(sys.argv) > 5 else 16}
    runs = int(sys.argv[6]) if len(sys.argv) > 6 else 3
    text = SCENE.read_text()
    if LINE not in text:
        sys.exit(f"{SCENE}: no line {LINE!r}")
    tmp = pathlib.Path(tempfile.mkdtemp())
    res = {}
    for name in ("path", "bdpt", "vcm"):
        scene = tmp / f"{name}.pbrt"
        scene.write_text(text.replace(LINE, f'Integrator "{name}" "integer maxdepth" [ 6 ]'))
        mses, secs, mean_err = runs_of(exe, scene, count[name], runs, ref, ref_img, tmp / name)
        res[name] = (np.mean(mses), np.mean(secs))
        print(f"{name:5s} {count[name]:4d} spp: CPU {np.mean(secs):7.2f} s, RMS relative block "
              f"error {np.sqrt(np.mean(mses)):.4f} (runs {', '.join(f'{np.sqrt(m):.4f}' for m in mses)}); "
              f"image mean's relative error RMS {np.sqrt(np.mean(np.square(mean_err))):.4f} "
              f"(runs {', '.join(f'{e:+.4f}' for e in mean_err)})")
    print(f"images in {tmp}")
    for x, y in (("bdpt", "path"), ("vcm", "path"), ("vcm", "bdpt")):
        (mx, tx), (my, ty) = res[x], res[y]
        print(f"error at equal CPU time, {x} / {y}: {np.sqrt(mx * tx / (my * ty)):.3f}")


if __name__ == "__main__":
    main()
