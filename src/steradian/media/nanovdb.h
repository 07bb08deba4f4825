#pragma once
/// Float grids of NanoVDB files (.nvdb), for pbrt-v4's "nanovdb" medium. A file is an input
/// like any other: it is read whole within a size limit, its segments and grid metadata are
/// parsed with every length checked, and the tree of each grid it returns is walked once,
/// every node offset checked to lie inside the grid's buffer, before NanoVDB's own accessor
/// (Debian's libnanovdb-dev headers) reads it. Uncompressed and zlib ("ZIP") files are read;
/// BLOSC-compressed ones are refused with a message that says so.
#include <memory>
#include <string>
#include <string_view>

#include "steradian/core/math.h"

namespace sr {

struct MajorantGrid;

/// One float grid of a .nvdb file, checked (see above). Values sit at integer index
/// coordinates; index and world space are related by the grid's affine map.
class NanoVdbGrid {
  public:
    ~NanoVdbGrid();
    NanoVdbGrid(const NanoVdbGrid&) = delete;
    NanoVdbGrid& operator=(const NanoVdbGrid&) = delete;

    /// The value at world point p: the trilinear interpolation of the values at the eight
    /// index-space lattice points around it (NanoVDB's SampleFromVoxels of order 1, which
    /// pbrt-v4 uses); voxels the tree does not store read the tiles' or background value.
    Float sample(Point3 p) const;
    /// The stored value at index (i, j, k).
    Float value(int i, int j, int k) const;
    /// The world-space bounds of the active voxels: the corners of the index box
    /// [min, max + 1] mapped to world space (NanoVDB's worldBBox, which pbrt-v4 bounds the
    /// medium with).
    Point3 world_min() const { return m_world_min; }
    Point3 world_max() const { return m_world_max; }
    /// Fills g (g.res^3 cells over the world box [lo, hi]) with, per cell, the largest value
    /// (negative ones count as 0) that sample() can interpolate from at points of the cell: a
    /// true upper bound, made from every leaf's largest value, every tile's value and the
    /// background, spread over the world box of the points that can read them.
    void fill_majorants(MajorantGrid& g, Point3 lo, Point3 hi) const;

    struct Impl;

  private:
    friend struct NanoVdbFile;
    explicit NanoVdbGrid(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m_impl;
    Point3 m_world_min, m_world_max;
};

/// The grids pbrt-v4's "nanovdb" medium reads from one file.
struct NanoVdbFile {
    std::shared_ptr<const NanoVdbGrid> density;      ///< never null
    std::shared_ptr<const NanoVdbGrid> temperature;  ///< null if the file has none

    /// Reads the float grid named `density_name` (which must exist) and the one named
    /// `temperature_name` (optional) of the .nvdb file `path`, at most `limit` bytes. Throws
    /// sr::Error with a message naming the file (the caller adds the scene location): a
    /// missing file, a wrong magic number or version, a truncated segment, a grid that is
    /// not a float fog volume, a tree whose offsets leave its buffer, non-finite values.
    static NanoVdbFile read(const std::string& path, std::string_view density_name,
                            std::string_view temperature_name, uint64_t limit);
    /// The same from the bytes of a file (the fuzz harness).
    static NanoVdbFile parse(std::string_view bytes, const std::string& path,
                             std::string_view density_name, std::string_view temperature_name);
};

/// The largest .nvdb file read (a grid is kept in memory whole, as NanoVDB lays it out).
inline constexpr uint64_t kMaxNanoVdbFileBytes = uint64_t(4) << 30;

}  // namespace sr
