#!/usr/bin/env bash
# Installs every build and test dependency of steradian from Debian's package archive.
# Safe to run twice: apt-get install skips what is already installed.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  python3                # scripts/check_layers.py and check_doc_examples.py (ctest)
  libembree-dev          # Embree 3: all ray queries
  libtbb-dev             # oneTBB: parallel tiles
  libopenexr-dev         # OpenEXR 3: .exr read and written directly (film/image_exr.cpp)
  libpng-dev             # libpng 1.6: .png read and written directly (film/image_png.cpp)
  libjpeg-dev            # libjpeg-turbo: .jpg read directly (film/image_jpeg.cpp)
  libopenimageio-dev     # every other image format (TIFF, JPEG, HDR, ...), through the
                         # module steradian_oiio.so loaded only when such a file is used
  openimageio-tools      # oiiotool, for inspecting renders
  zlib1g-dev             # zlib: gzip-compressed scene files (.pbrt.gz) and meshes (.ply.gz)
  libnanovdb-dev         # NanoVDB headers: .nvdb grids of "nanovdb" media (media/nanovdb.cpp)
  libfmt-dev libcli11-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  clang-14 libclang-rt-14-dev  # scripts/fuzz.sh: libFuzzer and the sanitizers (preset fuzz)
  llvm-14                      # llvm-symbolizer: source lines in the fuzzers' stack traces
  pybind11-dev python3-dev     # the Python module (src/python/, docs/python.md)
  python3-numpy python3-pytest # its arrays, and its tests (tests/python/, ctest python)
  libopenmpi-dev openmpi-bin   # steradian-mpi and its test (docs/distributed.md, ctest mpi)
)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
