#!/usr/bin/env python3
"""bdpt against path on a caustic at equal CPU time (bench/scenes/caustic.pbrt: a small
spherical light above a glass sphere on a diffuse floor).

Renders the scene with Integrator "path" and "bdpt" (the scene's own line replaced), each
RUNS times with different seeds, and measures each render's error against a converged
reference as the RMS over 16 x 16-pixel blocks of the blocks' relative luminance errors
(block mean - reference block mean) / reference block mean: transport noise counts, the few
pixels on the edge of a directly seen light do not dominate it. The error at equal CPU time
scales as 1 / sqrt(time) for both, so the ratio reported is
    sqrt(MSE_bdpt x CPU_bdpt / (MSE_path x CPU_path)),
bdpt's error over path's when both are given the same CPU time (< 0.5: bdpt's error is at
most half). CPU seconds are the renderer's user + system time (getrusage of the child).

A second figure leaves out the blocks where the light itself is seen, directly or through
the glass (reflected or refracted): such pixels are lit by camera -> specular* -> light paths,
which both integrators can only sample from the camera side (bdpt's s = 0 is the path
tracer's BSDF sampling), so they measure samples per second, not transport. The blocks are
found by rendering the scene with the diffuse surfaces black (only those paths remain) and
leaving out each block where such a pixel exceeds the block's reference mean.

The reference is a high-spp render given on the command line (e.g. bdpt at 512 spp with
another seed); its own noise adds to both MSEs and pulls the ratio towards 1.

With a SCENE argument another scene is measured the same way (its Integrator line must be
bdpt's); bench/scenes/lampshade.pbrt is the room lit by a lamp in a closed diffuse-
transmission shade, bench/scenes/foggy_room.pbrt a foggy room lit through a small opening
(its "path" is the volumetric path tracer). The light-seen blocks are only looked for in bench/scenes/caustic.pbrt.

Usage: bench/caustic_bdpt.py STERADIAN REFERENCE.exr [PATH_SPP] [BDPT_SPP] [RUNS] [SCENE]
"""
import pathlib
import resource
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from noise_vs_pbrt import read_exr, read_pfm  # noqa: E402

SCENE = pathlib.Path(__file__).parent / "scenes" / "caustic.pbrt"
Y = np.array([0.2126, 0.7152, 0.0722])


def blocks(lum, b=16):
    h, w = lum.shape
    return lum[: h // b * b, : w // b * b].reshape(h // b, b, w // b, b).mean(axis=(1, 3))


def render_timed(exe, scene, spp, seed, out):
    """Renders `scene` at `spp` with `seed` on 2 threads to `out` (a .pfm); returns its luminance
    and the render's CPU seconds (user + system, getrusage of the child)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([exe, "render", str(scene), "-q", "--spp", str(spp), "--seed", str(seed),
                    "--threads", "2", "-o", str(out)], check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return read_pfm(out) @ Y, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def runs_of(exe, scene, count, runs, ref, ref_img, out_prefix):
    """`runs` renders of `scene` at `count` samples with seeds 0 .. runs - 1 (outputs
    `out_prefix`-SEED.pfm): per run the mean square of the blocks' relative errors against the
    reference blocks `ref`, the CPU seconds, and the image mean's relative error against
    `ref_img`'s."""
    mses, secs, mean_err = [], [], []
    for seed in range(runs):
        img, cpu = render_timed(exe, scene, count, seed, f"{out_prefix}-{seed}.pfm")
        secs.append(cpu)
        rel = (blocks(img) - ref) / ref
        mses.append(float(np.mean(rel * rel)))
        mean_err.append(img.mean() / ref_img.mean() - 1)
    return mses, secs, mean_err


def compare_third(doc, third, default_count, unit="spp"):
    """path, bdpt and `third` on the caustic (maxdepth 8 for all), each RUNS times: the RMS
    relative block error, the image mean's relative error, and the errors' ratios at equal CPU
    time (bdpt / path, third / path, third / bdpt). The command line of caustic_mlt.py and
    caustic_vcm.py: STERADIAN REFERENCE.exr [PATH_SPP] [BDPT_SPP] [THIRD_COUNT] [RUNS]."""
    if len(sys.argv) < 3:
        sys.exit(doc)
    exe = str(pathlib.Path(sys.argv[1]).resolve())
    ref_img = read_exr(sys.argv[2]) @ Y
    ref = blocks(ref_img)
    spp = {"path": int(sys.argv[3]) if len(sys.argv) > 3 else 64,
           "bdpt": int(sys.argv[4]) if len(sys.argv) > 4 else 16,
           third: int(sys.argv[5]) if len(sys.argv) > 5 else default_count}
    runs = int(sys.argv[6]) if len(sys.argv) > 6 else 3
    tmp = pathlib.Path(tempfile.mkdtemp())
    text = SCENE.read_text()
    res = {}
    for name in ("path", "bdpt", third):
        scene = tmp / f"{name}.pbrt"
        scene.write_text(text.replace('Integrator "bdpt" "integer maxdepth" [ 8 ]',
                                      f'Integrator "{name}" "integer maxdepth" [ 8 ]'))
        mses, secs, mean_err = runs_of(exe, scene, spp[name], runs, ref, ref_img, tmp / name)
        res[name] = (np.mean(mses), np.mean(secs))
        print(f"{name:5s} {spp[name]:4d} {unit if name == third else 'spp'}: CPU "
              f"{np.mean(secs):7.2f} s, RMS relative block error {np.sqrt(np.mean(mses)):.4f} "
              f"(runs {', '.join(f'{np.sqrt(m):.4f}' for m in mses)}); image mean's relative "
              f"error RMS {np.sqrt(np.mean(np.square(mean_err))):.4f}")
    for x, y in (("bdpt", "path"), (third, "path"), (third, "bdpt")):
        (mx, tx), (my, ty) = res[x], res[y]
        print(f"error at equal CPU time, {x} / {y}: {np.sqrt(mx * tx / (my * ty)):.3f}")


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    exe = str(pathlib.Path(sys.argv[1]).resolve())
    ref = blocks(read_exr(sys.argv[2]) @ Y)
    spp = {"path": int(sys.argv[3]) if len(sys.argv) > 3 else 64,
           "bdpt": int(sys.argv[4]) if len(sys.argv) > 4 else 16}
    runs = int(sys.argv[5]) if len(sys.argv) > 5 else 3
    scene_file = pathlib.Path(sys.argv[6]) if len(sys.argv) > 6 else SCENE
    tmp = pathlib.Path(tempfile.mkdtemp())
    text = scene_file.read_text()
    # The blocks where the light is seen directly or through the glass.
    black = tmp / "black.pbrt"
    black.write_text(text.replace('Integrator "bdpt"', 'Integrator "path"')
                     .replace('"rgb reflectance" [ 0.6 0.6 0.6 ]', '"rgb reflectance" [ 0 0 0 ]'))
    if scene_file.resolve() == SCENE.resolve():
        subprocess.run([exe, "render", str(black), "-q", "--spp", "64", "-o",
                        str(tmp / "black.pfm")], check=True)
        seen = read_pfm(tmp / "black.pfm") @ Y
        h, w = seen.shape
        seen_max = seen[: h // 16 * 16, : w // 16 * 16].reshape(h // 16, 16, w // 16, 16).max(axis=(1, 3))
        keep = seen_max <= ref
    else:
        keep = np.ones(ref.shape, dtype=bool)
    print(f"blocks: {ref.size}; without the light seen directly or through the glass: {keep.sum()}")
    res, res_kept, res_median = {}, {}, {}
    for name in ("path", "bdpt"):
        scene = tmp / f"{name}.pbrt"
        scene.write_text(text.replace('Integrator "bdpt"', f'Integrator "{name}"'))
        mses, secs, kept = [], [], []
        for seed in range(runs):
            img, cpu = render_timed(exe, scene, spp[name], seed, tmp / f"{name}-{seed}.pfm")
            secs.append(cpu)
            rel = (blocks(img) - ref) / ref
            mses.append(float(np.mean(rel * rel)))
            kept.append(float(np.mean(rel[keep] ** 2)))
        res[name] = (np.mean(mses), np.mean(secs))
        res_kept[name] = (np.mean(kept), np.mean(secs))
        res_median[name] = (float(np.median(mses)), np.mean(secs))
        print(f"{name:5s} {spp[name]:4d} spp: CPU {np.mean(secs):7.2f} s, RMS relative block error "
              f"{np.sqrt(np.mean(mses)):.4f} (runs {', '.join(f'{np.sqrt(m):.4f}' for m in mses)}); "
              f"without the light's blocks {np.sqrt(np.mean(kept)):.4f} "
              f"(runs {', '.join(f'{np.sqrt(m):.4f}' for m in kept)})")
    (mp, tp), (mb, tb) = res["path"], res["bdpt"]
    print(f"error at equal CPU time, bdpt / path: {np.sqrt(mb * tb / (mp * tp)):.3f}")
    (mp, tp), (mb, tb) = res_kept["path"], res_kept["bdpt"]
    print(f"the same without the blocks where the light is seen: {np.sqrt(mb * tb / (mp * tp)):.3f}")
    # The runs' errors have heavy tails (a rare firefly makes a block's error alone): the
    # ratio of the median runs' errors shows the typical run.
    (mp, tp), (mb, tb) = res_median["path"], res_median["bdpt"]
    print(f"the same from the median runs (all blocks): {np.sqrt(mb * tb / (mp * tp)):.3f}")


if __name__ == "__main__":
    main()
