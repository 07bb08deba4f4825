#include "steradian/media/nanovdb.h"

#include <zlib.h>

#include <cstring>
#include <unordered_set>
#include <vector>

#include <nanovdb/NanoVDB.h>
#include <nanovdb/util/IO.h>

#include "steradian/core/error.h"
#include "steradian/core/input_file.h"
#include "steradian/media/medium.h"

namespace sr {

namespace {

using GridT = nanovdb::NanoGrid<float>;
using TreeT = GridT::TreeType;
using RootT = TreeT::RootType;
using UpperT = RootT::ChildNodeType;
using LowerT = UpperT::ChildNodeType;
using LeafT = LowerT::ChildNodeType;
using RootTile = RootT::DataType::Tile;

/// Grid bytes as NanoVDB lays them out, 32-byte aligned as its node structures require.
struct alignas(NANOVDB_DATA_ALIGNMENT) Block {
    unsigned char bytes[NANOVDB_DATA_ALIGNMENT];
};

/// A box of index space holding values at most `max`: a leaf or a constant tile.
struct ValueBox {
    nanovdb::Coord lo;
    int size;
    float max;
};

/// The grid's index-to-world affine map, in double precision, and its inverse.
struct IndexMap {
    double world_from_index[12], index_from_world[12];
    static void apply(const double* m, const double* v, double* out) {
        for (int r = 0; r < 3; ++r)
            out[r] = m[4 * r] * v[0] + m[4 * r + 1] * v[1] + m[4 * r + 2] * v[2] + m[4 * r + 3];
    }
};

}  // namespace

struct NanoVdbGrid::Impl {
    std::unique_ptr<Block[]> buffer;
    uint64_t size = 0;
    const GridT* grid = nullptr;
    IndexMap map{};
    float background = 0;
    std::vector<ValueBox> boxes;  ///< every leaf and tile of a positive value
};

namespace {

[[noreturn]] void fail(const std::string& path, std::string_view why) {
    throw Error(fmt::format("NanoVDB file \"{}\": {}", path, why));
}

/// Reads little-endian values of the file's fixed-size records, every length checked.
class ByteReader {
  public:
    ByteReader(std::string_view bytes, const std::string& path) : m_b(bytes), m_path(path) {}
    size_t pos() const { return m_pos; }
    size_t left() const { return m_b.size() - m_pos; }
    bool done() const { return m_pos == m_b.size(); }
    void read(void* out, size_t n, std::string_view what) {
        if (left() < n)
            fail(m_path, fmt::format("truncated: {} needs {} bytes at byte {}, the file has {}",
                                     what, n, m_pos, m_b.size()));
        std::memcpy(out, m_b.data() + m_pos, n);
        m_pos += n;
    }
    std::string_view take(uint64_t n, std::string_view what) {
        if (left() < n)
            fail(m_path, fmt::format("truncated: {} needs {} bytes at byte {}, the file has {}",
                                     what, n, m_pos, m_b.size()));
        std::string_view v = m_b.substr(m_pos, size_t(n));
        m_pos += size_t(n);
        return v;
    }

  private:
    std::string_view m_b;
    const std::string& m_path;
    size_t m_pos = 0;
};

std::unique_ptr<Block[]> allocate(uint64_t bytes) {
    return std::unique_ptr<Block[]>(new Block[size_t((bytes + sizeof(Block) - 1) / sizeof(Block))]);
}

/// A zlib stream ("ZIP" codec: a uint64 byte count, then the stream) inflated into exactly
/// `grid_size` bytes. The output buffer grows with what the stream produces (a small file
/// that claims a huge grid allocates little).
std::unique_ptr<Block[]> inflate_grid(std::string_view payload, uint64_t grid_size,
                                      const std::string& path, std::string_view name) {
    ByteReader r(payload, path);
    uint64_t n = 0;
    r.read(&n, sizeof n, "the ZIP-compressed grid's byte count");
    std::string_view in = r.take(n, "the ZIP-compressed grid");
    z_stream zs{};
    if (inflateInit(&zs) != Z_OK) fail(path, "zlib: inflateInit failed");
    uint64_t capacity = std::min<uint64_t>(grid_size, uint64_t(16) << 20), produced = 0;
    auto out = allocate(capacity);
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
    zs.avail_in = uInt(std::min<size_t>(in.size(), 1u << 30));
    int status = Z_OK;
    while (status == Z_OK) {
        if (produced == capacity) {
            if (capacity == grid_size) break;
            uint64_t bigger = std::min(grid_size, capacity * 2);
            auto grown = allocate(bigger);
            std::memcpy(grown.get(), out.get(), size_t(produced));
            out = std::move(grown);
            capacity = bigger;
        }
        zs.next_out = reinterpret_cast<Bytef*>(out.get()) + produced;
        zs.avail_out = uInt(std::min<uint64_t>(capacity - produced, 1u << 30));
        uInt before = zs.avail_out;
        status = inflate(&zs, Z_NO_FLUSH);
        produced += before - zs.avail_out;
    }
    inflateEnd(&zs);
    if (status != Z_STREAM_END || produced != grid_size)
        fail(path, fmt::format("grid \"{}\": the ZIP-compressed data {} ({} of {} bytes)", name,
                               status == Z_STREAM_END || status == Z_OK || status == Z_BUF_ERROR
                                   ? "has the wrong length"
                                   : "is corrupt",
                               produced, grid_size));
    return out;
}

/// NanoVDB's names of grid types and classes, for values the file may have made up.
std::string type_name(nanovdb::GridType t) {
    if (uint32_t(t) < uint32_t(nanovdb::GridType::End)) return nanovdb::toStr(t);
    return fmt::format("type-{}", uint32_t(t));
}
std::string class_name(nanovdb::GridClass c) {
    if (uint32_t(c) < uint32_t(nanovdb::GridClass::End)) return nanovdb::toStr(c);
    return fmt::format("class-{}", uint32_t(c));
}

bool finite_map(const double* m, int n) {
    for (int i = 0; i < n; ++i)
        if (!std::isfinite(m[i])) return false;
    return true;
}

/// Walks a grid's tree once, checking that every node lies inside the buffer, is aligned,
/// and is reached once (a tree, not a graph), that every value is finite, and collecting
/// the value boxes (for majorants) and the active voxels' index bounds.
class TreeChecker {
  public:
    TreeChecker(NanoVdbGrid::Impl& g, const std::string& path, std::string_view name)
        : m_g(g), m_path(path), m_name(name), m_base(reinterpret_cast<const char*>(g.buffer.get())) {}

    void check() {
        const GridT& grid = *m_g.grid;
        const auto* tree_data = reinterpret_cast<const nanovdb::TreeData<3>*>(&grid.tree());
        const int64_t tree_off = int64_t(sizeof(nanovdb::GridData));
        const int64_t root_off = node_offset(tree_off, tree_data->mNodeOffset[3],
                                             int64_t(sizeof(RootT::DataType)), "the root node");
        const auto* root = at<RootT>(root_off);
        const auto& rd = *reinterpret_cast<const RootT::DataType*>(root);
        uint64_t tiles_room = (m_g.size - uint64_t(root_off) - sizeof(RootT::DataType)) / sizeof(RootTile);
        if (rd.mTableSize > tiles_room)
            bad(fmt::format("the root node's {} tiles run past the end of the grid", rd.mTableSize));
        finite(rd.mBackground, "the background value");
        m_g.background = rd.mBackground;
        const auto* tiles = reinterpret_cast<const RootTile*>(&rd + 1);
        for (uint32_t i = 0; i < rd.mTableSize; ++i) {
            const RootTile& t = tiles[i];
            nanovdb::Coord o = t.origin();
            if (t.child != 0) {
                int64_t off = node_offset(root_off, t.child, int64_t(sizeof(UpperT)), "an upper node");
                upper(*at<UpperT>(off), o);
            } else {
                finite(t.value, "a root tile's value");
                tile(o, int(UpperT::DIM), t.value, t.state != 0);
            }
        }
        if (!m_any_active) bad("no active voxels");
    }
    nanovdb::Coord active_min() const { return m_min; }
    nanovdb::Coord active_max() const { return m_max; }

  private:
    template <typename T>
    const T* at(int64_t off) const {
        return reinterpret_cast<const T*>(m_base + off);
    }
    [[noreturn]] void bad(std::string_view why) const {
        fail(m_path, fmt::format("grid \"{}\" is malformed: {}", m_name, why));
    }
    void finite(float v, std::string_view what) const {
        if (!std::isfinite(v)) bad(fmt::format("{} is {}", what, v));
    }
    /// from + rel, checked to start a node of `size` bytes inside the buffer, aligned, and
    /// not reached before.
    int64_t node_offset(int64_t from, int64_t rel, int64_t size, std::string_view what) {
        const int64_t n = int64_t(m_g.size);
        if (rel < -from || rel > n - size - from)
            bad(fmt::format("{} at offset {} lies outside the grid's {} bytes", what,
                            static_cast<long long>(from) + static_cast<long long>(rel), n));
        int64_t off = from + rel;
        if (off % NANOVDB_DATA_ALIGNMENT != 0)
            bad(fmt::format("{} at offset {} is not {}-byte aligned", what, off,
                            NANOVDB_DATA_ALIGNMENT));
        if (!m_seen.insert(off).second)
            bad(fmt::format("{} at offset {} is reached twice", what, off));
        return off;
    }
    void active(nanovdb::Coord lo, int size) {
        nanovdb::Coord hi = lo + nanovdb::Coord(size - 1);
        if (!m_any_active) {
            m_min = lo, m_max = hi, m_any_active = true;
            return;
        }
        m_min = m_min.minComponent(lo);
        m_max = m_max.maxComponent(hi);
    }
    void tile(nanovdb::Coord o, int size, float v, bool is_active) {
        if (v > 0) m_g.boxes.push_back({o, size, v});
        if (is_active) active(o, size);
    }
    template <typename NodeT, typename F>
    void internal(const NodeT& node, nanovdb::Coord origin, std::string_view what, F&& child) {
        const auto& d = *reinterpret_cast<const typename NodeT::DataType*>(&node);
        const int64_t self = reinterpret_cast<const char*>(&node) - m_base;
        constexpr int log2 = int(NodeT::LOG2DIM), cdim = int(NodeT::ChildNodeType::DIM);
        for (uint32_t n = 0; n < NodeT::SIZE; ++n) {
            nanovdb::Coord o = origin + nanovdb::Coord(int(n >> (2 * log2)) * cdim,
                                                       int((n >> log2) & ((1u << log2) - 1)) * cdim,
                                                       int(n & ((1u << log2) - 1)) * cdim);
            if (d.mChildMask.isOn(n)) {
                int64_t off = node_offset(self, d.mTable[n].child,
                                          int64_t(sizeof(typename NodeT::ChildNodeType)), what);
                child(*at<typename NodeT::ChildNodeType>(off), o);
            } else {
                finite(d.mTable[n].value, "a tile's value");
                tile(o, cdim, d.mTable[n].value, d.mValueMask.isOn(n));
            }
        }
    }
    void upper(const UpperT& node, nanovdb::Coord origin) {
        internal(node, origin, "a lower node",
                 [&](const LowerT& c, nanovdb::Coord o) { lower(c, o); });
    }
    void lower(const LowerT& node, nanovdb::Coord origin) {
        internal(node, origin, "a leaf", [&](const LeafT& c, nanovdb::Coord o) { leaf(c, o); });
    }
    void leaf(const LeafT& node, nanovdb::Coord origin) {
        const auto& d = *reinterpret_cast<const LeafT::DataType*>(&node);
        float mx = 0;
        for (uint32_t n = 0; n < LeafT::SIZE; ++n) {
            finite(d.mValues[n], "a voxel's value");
            mx = std::max(mx, d.mValues[n]);
            if (d.mValueMask.isOn(n))
                active(origin + nanovdb::Coord(int(n >> 6), int((n >> 3) & 7), int(n & 7)), 1);
        }
        if (mx > 0) m_g.boxes.push_back({origin, int(LeafT::DIM), mx});
    }

    NanoVdbGrid::Impl& m_g;
    const std::string& m_path;
    std::string_view m_name;
    const char* m_base;
    std::unordered_set<int64_t> m_seen;
    bool m_any_active = false;
    nanovdb::Coord m_min, m_max;
};

}  // namespace

NanoVdbGrid::NanoVdbGrid(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
NanoVdbGrid::~NanoVdbGrid() = default;

Float NanoVdbGrid::value(int i, int j, int k) const {
    return m_impl->grid->tree().getValue(nanovdb::Coord(i, j, k));
}

Float NanoVdbGrid::sample(Point3 p) const {
    double w[3] = {p.x, p.y, p.z}, x[3];
    IndexMap::apply(m_impl->map.index_from_world, w, x);
    int c[3];
    double f[3];
    for (int a = 0; a < 3; ++a) {
        // Far outside any grid (|index| >= 2^30): the background (no int overflow).
        if (!(std::abs(x[a]) < double(1 << 30))) return m_impl->background;
        double fl = std::floor(x[a]);
        c[a] = int(fl);
        f[a] = x[a] - fl;
    }
    auto acc = m_impl->grid->getAccessor();
    auto v = [&](int dx, int dy, int dz) {
        return double(acc.getValue(nanovdb::Coord(c[0] + dx, c[1] + dy, c[2] + dz)));
    };
    auto lx = [&](int dy, int dz) { return v(0, dy, dz) * (1 - f[0]) + v(1, dy, dz) * f[0]; };
    double y0 = lx(0, 0) * (1 - f[1]) + lx(1, 0) * f[1];
    double y1 = lx(0, 1) * (1 - f[1]) + lx(1, 1) * f[1];
    return Float(y0 * (1 - f[2]) + y1 * f[2]);
}

void NanoVdbGrid::fill_majorants(MajorantGrid& g, Point3 lo, Point3 hi) const {
    const int n = g.res;
    g.cells.assign(size_t(n) * n * n, std::max(0.f, m_impl->background));
    auto cell_range = [&](double a, double b, int axis, int& c0, int& c1) {
        double ext = double(hi[axis]) - double(lo[axis]);
        double u0 = (a - lo[axis]) / ext * n, u1 = (b - lo[axis]) / ext * n;
        // A little slack: the DDA's float arithmetic may put a boundary point either side.
        c0 = int(std::clamp(std::floor(u0 - 1e-3), 0.0, double(n - 1)));
        c1 = int(std::clamp(std::floor(u1 + 1e-3), 0.0, double(n - 1)));
        return !(u1 < -1e-3 || u0 > n + 1e-3);
    };
    for (const ValueBox& b : m_impl->boxes) {
        // The points that interpolate from the box's lattice points: the open index box
        // (lo - 1, lo + size), mapped to world space (its 8 corners' bounds).
        double bmin[3] = {1e300, 1e300, 1e300}, bmax[3] = {-1e300, -1e300, -1e300};
        for (int corner = 0; corner < 8; ++corner) {
            double x[3], w[3];
            for (int a = 0; a < 3; ++a)
                x[a] = (corner >> a) & 1 ? double(b.lo[a]) + b.size : double(b.lo[a]) - 1;
            IndexMap::apply(m_impl->map.world_from_index, x, w);
            for (int a = 0; a < 3; ++a) {
                bmin[a] = std::min(bmin[a], w[a]);
                bmax[a] = std::max(bmax[a], w[a]);
            }
        }
        int c0[3], c1[3];
        bool inside = true;
        for (int a = 0; a < 3; ++a) inside &= cell_range(bmin[a], bmax[a], a, c0[a], c1[a]);
        if (!inside) continue;
        for (int z = c0[2]; z <= c1[2]; ++z)
            for (int y = c0[1]; y <= c1[1]; ++y)
                for (int x = c0[0]; x <= c1[0]; ++x) {
                    Float& m = g.cells[(size_t(z) * n + y) * n + x];
                    m = std::max(m, b.max);
                }
    }
}

NanoVdbFile NanoVdbFile::read(const std::string& path, std::string_view density_name,
                              std::string_view temperature_name, uint64_t limit) {
    std::string bytes = read_regular_file(path, limit, "NanoVDB file");
    return parse(bytes, path, density_name, temperature_name);
}

NanoVdbFile NanoVdbFile::parse(std::string_view bytes, const std::string& path,
                               std::string_view density_name, std::string_view temperature_name) {
    static_assert(sizeof(nanovdb::io::MetaData) == 176 && sizeof(nanovdb::io::Header) == 16);
    NanoVdbFile file;
    ByteReader r(bytes, path);
    if (bytes.empty()) fail(path, "the file is empty");
    while (!r.done()) {
        nanovdb::io::Header h;
        r.read(&h, sizeof h, "a segment header");
        if (h.magic != NANOVDB_MAGIC_NUMBER)
            fail(path, h.magic == nanovdb::io::reverseEndianness(NANOVDB_MAGIC_NUMBER)
                           ? "big-endian NanoVDB data are not supported"
                           : fmt::format("not a NanoVDB file (no \"NanoVDB0\" magic number at "
                                         "byte {})",
                                         r.pos() - sizeof h));
        if (h.version.getMajor() != NANOVDB_MAJOR_VERSION_NUMBER)
            fail(path, fmt::format("NanoVDB format version {}.{}.{}; only version {}.x is read",
                                   h.version.getMajor(), h.version.getMinor(),
                                   h.version.getPatch(), NANOVDB_MAJOR_VERSION_NUMBER));
        if (h.gridCount == 0) fail(path, "a segment has no grids");
        struct Meta {
            nanovdb::io::MetaData m;
            std::string name;
        };
        std::vector<Meta> metas(h.gridCount);
        for (Meta& m : metas) {
            r.read(&m.m, sizeof m.m, "a grid's metadata");
            if (m.m.nameSize == 0 || m.m.nameSize > 1u << 16)
                fail(path, fmt::format("a grid's name has {} bytes", m.m.nameSize));
            std::string_view name = r.take(m.m.nameSize, "a grid's name");
            m.name = std::string(name.substr(0, name.find('\0')));
        }
        for (const Meta& m : metas) {
            std::string_view payload = r.take(m.m.fileSize, fmt::format("grid \"{}\"", m.name));
            std::shared_ptr<const NanoVdbGrid>* slot = nullptr;
            if (m.name == density_name && !file.density)
                slot = &file.density;
            else if (!temperature_name.empty() && m.name == temperature_name && !file.temperature)
                slot = &file.temperature;
            if (!slot) continue;
            auto impl = std::make_unique<NanoVdbGrid::Impl>();
            uint64_t size = m.m.gridSize;
            if (size < sizeof(nanovdb::GridData) + sizeof(nanovdb::TreeData<3>))
                fail(path, fmt::format("grid \"{}\": {} bytes, too few for a grid", m.name, size));
            if (size > kMaxNanoVdbFileBytes)
                fail(path, fmt::format("grid \"{}\": {} bytes, more than the limit of {}", m.name,
                                       size, kMaxNanoVdbFileBytes));
            if (h.codec == nanovdb::io::Codec::NONE) {
                if (payload.size() != size)
                    fail(path, fmt::format("grid \"{}\": {} bytes stored for a grid of {} bytes",
                                           m.name, payload.size(), size));
                impl->buffer = allocate(size);
                std::memcpy(impl->buffer.get(), payload.data(), payload.size());
            } else if (h.codec == nanovdb::io::Codec::ZIP) {
                impl->buffer = inflate_grid(payload, size, path, m.name);
            } else if (h.codec == nanovdb::io::Codec::BLOSC) {
                fail(path, "BLOSC-compressed grids are not supported (uncompressed and ZIP are: "
                           "nanovdb_convert or NanoVDB's io::writeGrid can rewrite the file)");
            } else {
                fail(path, fmt::format("unknown compression codec {}", int(h.codec)));
            }
            impl->size = size;
            const auto* gd = reinterpret_cast<const nanovdb::GridData*>(impl->buffer.get());
            if (gd->mMagic != NANOVDB_MAGIC_NUMBER)
                fail(path, fmt::format("grid \"{}\" has no magic number", m.name));
            if (gd->mVersion.getMajor() != NANOVDB_MAJOR_VERSION_NUMBER)
                fail(path, fmt::format("grid \"{}\": NanoVDB version {}.x; only {}.x is read",
                                       m.name, gd->mVersion.getMajor(),
                                       NANOVDB_MAJOR_VERSION_NUMBER));
            if (gd->mGridType != nanovdb::GridType::Float)
                fail(path, fmt::format("grid \"{}\" holds {} values; a float grid is needed",
                                       m.name, type_name(gd->mGridType)));
            if (gd->mGridClass != nanovdb::GridClass::FogVolume &&
                gd->mGridClass != nanovdb::GridClass::Unknown)
                fail(path, fmt::format("grid \"{}\" is a {} grid; a fog volume is needed", m.name,
                                       class_name(gd->mGridClass)));
            // The index-to-world map: 3x3 matrix and translation (double precision).
            const nanovdb::Map& map = gd->mMap;
            double* wi = impl->map.world_from_index;
            for (int row = 0; row < 3; ++row) {
                for (int c = 0; c < 3; ++c) wi[4 * row + c] = map.mMatD[3 * row + c];
                wi[4 * row + 3] = map.mVecD[row];
            }
            const double* a = wi;
            double det = a[0] * (a[5] * a[10] - a[6] * a[9]) - a[1] * (a[4] * a[10] - a[6] * a[8]) +
                         a[2] * (a[4] * a[9] - a[5] * a[8]);
            double scale = 0;
            for (int i : {0, 1, 2, 4, 5, 6, 8, 9, 10}) scale = std::max(scale, std::abs(a[i]));
            if (!finite_map(wi, 12) || !(std::abs(det) > 1e-12 * scale * scale * scale))
                fail(path, fmt::format("grid \"{}\": its index-to-world map is not an invertible "
                                       "finite affine map",
                                       m.name));
            double* iw = impl->map.index_from_world;
            // Inverse: the adjugate over the determinant, then -inverse * translation.
            iw[0] = (a[5] * a[10] - a[6] * a[9]) / det;
            iw[1] = (a[2] * a[9] - a[1] * a[10]) / det;
            iw[2] = (a[1] * a[6] - a[2] * a[5]) / det;
            iw[4] = (a[6] * a[8] - a[4] * a[10]) / det;
            iw[5] = (a[0] * a[10] - a[2] * a[8]) / det;
            iw[6] = (a[2] * a[4] - a[0] * a[6]) / det;
            iw[8] = (a[4] * a[9] - a[5] * a[8]) / det;
            iw[9] = (a[1] * a[8] - a[0] * a[9]) / det;
            iw[10] = (a[0] * a[5] - a[1] * a[4]) / det;
            for (int row = 0; row < 3; ++row)
                iw[4 * row + 3] = -(iw[4 * row] * a[3] + iw[4 * row + 1] * a[7] +
                                    iw[4 * row + 2] * a[11]);
            impl->grid = reinterpret_cast<const GridT*>(impl->buffer.get());
            TreeChecker checker(*impl, path, m.name);
            checker.check();
            // World bounds: the active index box [min, max + 1] mapped (NanoVDB's worldBBox).
            nanovdb::Coord lo = checker.active_min(), hi = checker.active_max() + nanovdb::Coord(1);
            double bmin[3] = {1e300, 1e300, 1e300}, bmax[3] = {-1e300, -1e300, -1e300};
            for (int corner = 0; corner < 8; ++corner) {
                double x[3], w[3];
                for (int c = 0; c < 3; ++c) x[c] = double((corner >> c) & 1 ? hi[c] : lo[c]);
                IndexMap::apply(wi, x, w);
                for (int c = 0; c < 3; ++c) {
                    bmin[c] = std::min(bmin[c], w[c]);
                    bmax[c] = std::max(bmax[c], w[c]);
                }
            }
            for (int c = 0; c < 3; ++c)
                if (!(std::abs(bmin[c]) < 1e30 && std::abs(bmax[c]) < 1e30))
                    fail(path, fmt::format("grid \"{}\": its world bounds are not finite", m.name));
            auto grid = std::shared_ptr<NanoVdbGrid>(new NanoVdbGrid(std::move(impl)));
            grid->m_world_min = Point3(Float(bmin[0]), Float(bmin[1]), Float(bmin[2]));
            grid->m_world_max = Point3(Float(bmax[0]), Float(bmax[1]), Float(bmax[2]));
            *slot = std::move(grid);
        }
    }
    if (!file.density) fail(path, fmt::format("no grid named \"{}\"", density_name));
    return file;
}

}  // namespace sr
