#!/usr/bin/env python3
"""Block-mean agreement of two renders of one scene (e.g. ours against pbrt-v4's): for blocks
of 8 x 8 and 16 x 16 pixels, how many block means of luminance agree within 2 %, the largest
and the median relative deviation, and the ratio of the whole images' mean luminance.

Usage: bench/block_means.py OURS.exr REFERENCE.exr
(for the grid-medium scene: render tests/data/reference/grid-medium/scene.pbrt with --spp 4096
and compare with tests/data/reference/grid-medium/pbrt-v4-4096spp.exr)
"""
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from noise_vs_pbrt import read_exr  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    w = np.array([0.2126, 0.7152, 0.0722])
    ya, yb = read_exr(sys.argv[1]) @ w, read_exr(sys.argv[2]) @ w
    if ya.shape != yb.shape:
        sys.exit(f"the images differ in size: {ya.shape} and {yb.shape}")
    h, wd = ya.shape
    for b in (8, 16):
        ny, nx = h // b, wd // b
        ra = ya[:ny * b, :nx * b].reshape(ny, b, nx, b).mean(axis=(1, 3))
        rb = yb[:ny * b, :nx * b].reshape(ny, b, nx, b).mean(axis=(1, 3))
        d = np.abs(ra / rb - 1)
        print(f"{b}x{b}-pixel blocks: {int((d <= 0.02).sum())} of {nx * ny} within 2 %, "
              f"largest deviation {d.max():.4f}, median {np.median(d):.4f}")
    print(f"whole image: mean luminance ratio {ya.mean() / yb.mean():.5f}")


if __name__ == "__main__":
    main()
