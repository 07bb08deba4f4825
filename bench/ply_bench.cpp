/// PLY loading benchmarks: a 1M-triangle binary little-endian mesh with normals (the layout of
/// most scanned and exported meshes) and a 100k-triangle ASCII mesh. Files are generated once
/// into the temp dir and removed at exit.
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "steradian/core/input_file.h"
#include "steradian/scene/mesh_io/ply.h"

namespace {

/// A temp file removed when the program exits.
struct TempFile {
    std::string path;
    std::uintmax_t size = 0;
    ~TempFile() {
        std::error_code ec;
        std::filesystem::remove(path, ec);
    }
};

void put_u32_le(std::string& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xff);
}
void put_f32_le(std::string& out, float f) {
    std::uint32_t u;
    static_assert(sizeof(u) == sizeof(f));
    std::memcpy(&u, &f, sizeof(u));
    put_u32_le(out, u);
}

/// A w x w vertex height field z = sin(x) cos(y) with analytic normals: (w-1)^2 * 2 triangles.
std::string make_grid_ply(int w, bool binary) {
    const int nv = w * w;
    const int nf = (w - 1) * (w - 1) * 2;
    std::string out = fmt::format(
        "ply\nformat {} 1.0\ncomment steradian ply_bench grid\nelement vertex {}\n"
        "property float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        binary ? "binary_little_endian" : "ascii", nv, nf);
    out.reserve(out.size() + std::size_t(nv) * 24 + std::size_t(nf) * 13);
    for (int j = 0; j < w; ++j) {
        for (int i = 0; i < w; ++i) {
            const float x = float(i) / float(w - 1) * 10.f, y = float(j) / float(w - 1) * 10.f;
            const float z = std::sin(x) * std::cos(y);
            const float dx = std::cos(x) * std::cos(y), dy = -std::sin(x) * std::sin(y);
            const float inv = 1.f / std::sqrt(dx * dx + dy * dy + 1.f);
            const float v[6] = {x, y, z, -dx * inv, -dy * inv, inv};
            if (binary) {
                for (float f : v) put_f32_le(out, f);
            } else {
                out += fmt::format("{} {} {} {} {} {}\n", v[0], v[1], v[2], v[3], v[4], v[5]);
            }
        }
    }
    for (int j = 0; j + 1 < w; ++j) {
        for (int i = 0; i + 1 < w; ++i) {
            const std::uint32_t a = std::uint32_t(j * w + i), b = a + 1,
                                c = a + std::uint32_t(w) + 1, d = a + std::uint32_t(w);
            const std::uint32_t tris[2][3] = {{a, b, c}, {a, c, d}};
            for (const auto& t : tris) {
                if (binary) {
                    out += char(3);
                    for (std::uint32_t k : t) put_u32_le(out, k);
                } else {
                    out += fmt::format("3 {} {} {}\n", t[0], t[1], t[2]);
                }
            }
        }
    }
    return out;
}

const TempFile& grid_file(int w, bool binary) {
    auto make = [](int width, bool bin) {
        TempFile f;
        f.path = (std::filesystem::temp_directory_path() /
                  fmt::format("steradian_ply_bench_{}_{}_{}.ply", ::getpid(), width,
                              bin ? "binary" : "ascii"))
                     .string();
        const std::string bytes = make_grid_ply(width, bin);
        std::FILE* fp = std::fopen(f.path.c_str(), "wb");
        if (!fp || std::fwrite(bytes.data(), 1, bytes.size(), fp) != bytes.size()) {
            std::fprintf(stderr, "cannot write %s\n", f.path.c_str());
            std::abort();
        }
        std::fclose(fp);
        f.size = bytes.size();
        return f;
    };
    if (binary) {
        static const TempFile binary_file = make(w, true);
        return binary_file;
    }
    static const TempFile ascii_file = make(w, false);
    return ascii_file;
}

void run(benchmark::State& state, const TempFile& file) {
    std::size_t triangles = 0;
    for (auto _ : state) {
        sr::TriangleMeshData mesh = sr::read_ply(file.path);
        triangles = mesh.triangle_count();
        benchmark::DoNotOptimize(mesh.indices.data());
    }
    state.counters["triangles"] = double(triangles);
    state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(file.size));
}

// 708 x 708 vertices (501,264) -> 999,698 triangles; float xyz + normals; uchar/int faces.
void BM_ReadPly_BinaryLE_1M(benchmark::State& state) { run(state, grid_file(708, true)); }
BENCHMARK(BM_ReadPly_BinaryLE_1M)->Unit(benchmark::kMillisecond);

// The same 1M-triangle mesh gzip-compressed (zlib level 6, as gzip's default): decompression
// in memory plus the binary read. bench/plygz_load.sh times a 10M-triangle one end to end.
void BM_ReadPly_BinaryLE_1M_Gzip(benchmark::State& state) {
    static const TempFile gz = [] {
        const TempFile& plain = grid_file(708, true);
        std::FILE* in = std::fopen(plain.path.c_str(), "rb");
        std::string bytes(plain.size, '\0');
        if (!in || std::fread(bytes.data(), 1, bytes.size(), in) != bytes.size()) std::abort();
        std::fclose(in);
        TempFile f;
        f.path = plain.path + ".gz";
        const std::string z = sr::gzip_compress(bytes);
        std::FILE* out = std::fopen(f.path.c_str(), "wb");
        if (!out || std::fwrite(z.data(), 1, z.size(), out) != z.size()) std::abort();
        std::fclose(out);
        f.size = plain.size;  // bytes processed: the decompressed PLY
        return f;
    }();
    run(state, gz);
}
BENCHMARK(BM_ReadPly_BinaryLE_1M_Gzip)->Unit(benchmark::kMillisecond);

// 225 x 225 vertices (50,625) -> 100,352 triangles.
void BM_ReadPly_Ascii_100k(benchmark::State& state) { run(state, grid_file(225, false)); }
BENCHMARK(BM_ReadPly_Ascii_100k)->Unit(benchmark::kMillisecond);

}  // namespace
