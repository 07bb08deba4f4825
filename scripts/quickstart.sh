#!/usr/bin/env bash
# One command for a fresh Debian machine: install dependencies, build (Release), and render
# the bundled Cornell box to out/cornell-box.exr and out/cornell-box.png.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake --preset release
cmake --build --preset release --target steradian
mkdir -p out
build/release/steradian render scenes/cornell-box.pbrt -o out/cornell-box.exr -o out/cornell-box.png
