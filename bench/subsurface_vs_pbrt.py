#!/usr/bin/env python3
"""steradian's subsurface random walk against pbrt-v4's tabulated BSSRDF, on the stand-ins of
pbrt-v4-scenes' head and sssdragon materials (bench/scenes/subsurface, written by its
make_scenes.py: a sphere and a thin slab on a grey floor, an area light and a dim sky).
Renders each scene with both at the same spp and prints the mean RGB and luminance of the
sphere, the slab and a patch of the floor beside the sphere (which the objects light), with
the ratio ours / pbrt-v4, and the CPU seconds of each render. Writes side-by-side PNGs
(ours left) next to the EXRs in the output directory.

Usage: bench/subsurface_vs_pbrt.py STERADIAN PBRT [SPP] [OUTDIR]
"""
import pathlib
import resource
import subprocess
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from noise_vs_pbrt import read_exr  # noqa: E402

# Regions of the 160 x 120 image (x0, y0, x1, y1), inside each object's silhouette.
REGIONS = {"sphere": (35, 42, 67, 74), "slab": (109, 42, 118, 78), "floor": (50, 95, 100, 110)}


def cpu_run(cmd):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, check=True, capture_output=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    ours_exe, pbrt_exe = sys.argv[1], sys.argv[2]
    spp = int(sys.argv[3]) if len(sys.argv) > 3 else 1024
    out = pathlib.Path(sys.argv[4] if len(sys.argv) > 4 else "subsurface-vs-pbrt")
    out.mkdir(parents=True, exist_ok=True)
    scenes = pathlib.Path(__file__).resolve().parent / "scenes" / "subsurface"
    for name in ("head", "dragon"):
        scene = scenes / f"{name}.pbrt"
        a, b = out / f"{name}-steradian.exr", out / f"{name}-pbrt-v4.exr"
        ta = cpu_run([ours_exe, "render", str(scene), "--spp", str(spp), "-o", str(a)])
        tb = cpu_run([pbrt_exe, "--spp", str(spp), "--outfile", str(b), str(scene)])
        ia, ib = read_exr(a), read_exr(b)
        print(f"{name} at {spp} spp: steradian {ta:.1f} CPU-s, pbrt-v4 {tb:.1f} CPU-s")
        for region, (x0, y0, x1, y1) in REGIONS.items():
            ma = ia[y0:y1, x0:x1].reshape(-1, 3).mean(axis=0)
            mb = ib[y0:y1, x0:x1].reshape(-1, 3).mean(axis=0)
            ya = 0.2126 * ma[0] + 0.7152 * ma[1] + 0.0722 * ma[2]
            yb = 0.2126 * mb[0] + 0.7152 * mb[1] + 0.0722 * mb[2]
            print(f"  {region:7s} steradian RGB {ma[0]:.4f} {ma[1]:.4f} {ma[2]:.4f} Y {ya:.4f} | "
                  f"pbrt-v4 RGB {mb[0]:.4f} {mb[1]:.4f} {mb[2]:.4f} Y {yb:.4f} | "
                  f"ratio RGB {ma[0] / mb[0]:.3f} {ma[1] / mb[1]:.3f} {ma[2] / mb[2]:.3f} "
                  f"Y {ya / yb:.3f}")
        subprocess.run(["oiiotool", str(a), "--tocolorspace", "sRGB", str(b), "--tocolorspace",
                        "sRGB", "--mosaic", "2x1", "-o", str(out / f"{name}.png")], check=True)


if __name__ == "__main__":
    main()
