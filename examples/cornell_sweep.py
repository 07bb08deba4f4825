#!/usr/bin/env python3
"""Notebook-style example of the Python module (docs/python.md): render the Cornell box, show
it, sweep the reflectance of the tall block and plot the mean luminance of a region on it.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/cornell_sweep.py --spp 16

Each cell below is what one would type into a notebook; run as a script it saves the figure
(--out) instead of showing it. Needs numpy and matplotlib (Debian: python3-matplotlib).
"""
import argparse
import pathlib

import numpy as np

import steradian

ROOT = pathlib.Path(__file__).resolve().parents[1]

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--spp", type=int, default=16, help="samples per pixel of each render")
parser.add_argument("--out", default="cornell_sweep.png", help="the figure to write")
args = parser.parse_args()

# %% Load the bundled Cornell box and render it (a numpy array, linear RGB).
text = (ROOT / "scenes" / "cornell-box.pbrt").read_text()
scene = steradian.loads(text, base_dir=str(ROOT / "scenes"))
image = scene.render(spp=args.spp, progress=True)
print("rendered", image.shape, "mean", float(image.mean()))


def luminance(rgb):
    """Relative luminance of linear sRGB (ITU-R BT.709 weights)."""
    return rgb @ np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)


# %% The tall block gets its own grey material, swept from dark to white. Its front face
# covers this region of the 512 x 512 image (rows, columns).
region = (slice(200, 330), slice(170, 250))
reflectances = np.linspace(0.1, 0.9, 5)
means = []
for rho in reflectances:
    swept = text.replace(
        "    # tall block\n",
        f'    Material "diffuse" "rgb reflectance" [ {rho} {rho} {rho} ]\n    # tall block\n', 1)
    img = steradian.loads(swept, base_dir=str(ROOT / "scenes")).render(spp=args.spp)
    means.append(float(luminance(img[region]).mean()))
    print(f"reflectance {rho:.2f}: region luminance {means[-1]:.4f}")

# %% Show the image and the sweep.
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    raise SystemExit("matplotlib is not installed (Debian: python3-matplotlib); numbers above")
fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.5))
left.imshow(np.clip(image, 0, 1) ** (1 / 2.2))
r, c = region
left.add_patch(plt.Rectangle((c.start, r.start), c.stop - c.start, r.stop - r.start,
                             fill=False, edgecolor="yellow"))
left.set_title(f"Cornell box, {args.spp} spp")
left.axis("off")
right.plot(reflectances, means, "o-")
right.set_xlabel("reflectance of the tall block")
right.set_ylabel("mean luminance of the region (relative)")
right.grid(True)
fig.tight_layout()
fig.savefig(args.out, dpi=100)
print("wrote", args.out)
