#pragma once
/// Small NanoVDB files (.nvdb) made with NanoVDB's own API (GridBuilder, io::writeGrids of
/// Debian's libnanovdb-dev), for the tests of "nanovdb" media and the stand-ins that
/// scripts/pbrt_corpus.py has tests/tools/nvdb_standin.cpp write.
#ifndef NANOVDB_USE_ZIP
#define NANOVDB_USE_ZIP  // ZIP-compressed files too (zlib, which steradian links)
#endif
#include <nanovdb/util/GridBuilder.h>
#include <nanovdb/util/IO.h>

#include <functional>
#include <string>
#include <vector>

namespace sr::test {

/// A float grid: value(i, j, k) at every index of the box [lo, hi] (values equal to the
/// background 0 stay unset), index (i, j, k) at world point origin + voxel x (i, j, k).
struct NvdbGridSpec {
    std::string name = "density";
    std::function<float(int, int, int)> value;
    nanovdb::Coord lo{0, 0, 0}, hi{0, 0, 0};
    double voxel = 1;
    nanovdb::Vec3d origin{0, 0, 0};
    nanovdb::GridClass grid_class = nanovdb::GridClass::FogVolume;
};

inline nanovdb::GridHandle<> nvdb_grid(const NvdbGridSpec& s) {
    nanovdb::GridBuilder<float> b(0.0f, s.grid_class);
    auto acc = b.getAccessor();
    for (int i = s.lo[0]; i <= s.hi[0]; ++i)
        for (int j = s.lo[1]; j <= s.hi[1]; ++j)
            for (int k = s.lo[2]; k <= s.hi[2]; ++k) {
                float v = s.value(i, j, k);
                if (v != 0) acc.setValue(nanovdb::Coord(i, j, k), v);
            }
    return b.getHandle<>(s.voxel, s.origin, s.name);
}

/// Writes the grids to one .nvdb file (one segment), uncompressed or ZIP-compressed.
inline void write_nvdb(const std::string& path, const std::vector<NvdbGridSpec>& grids,
                       nanovdb::io::Codec codec = nanovdb::io::Codec::NONE) {
    std::vector<nanovdb::GridHandle<>> handles;
    for (const NvdbGridSpec& s : grids) handles.push_back(nvdb_grid(s));
    nanovdb::io::writeGrids(path, handles, codec);
}

/// A cube of n^3 voxels of constant `value` (index [0, n - 1]^3).
inline NvdbGridSpec nvdb_box(std::string name, int n, float value, double voxel,
                             nanovdb::Vec3d origin) {
    NvdbGridSpec s;
    s.name = std::move(name);
    s.value = [value](int, int, int) { return value; };
    s.hi = nanovdb::Coord(n - 1);
    s.voxel = voxel;
    s.origin = origin;
    return s;
}

}  // namespace sr::test
