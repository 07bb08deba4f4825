#include "steradian/scene/mesh_io/ply.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/core/input_file.h"
#include "steradian/scene/mesh_io/mesh.h"

namespace sr {
namespace {

namespace fs = std::filesystem;

// ---- a small PLY writer for the tests
// ------------------------------------------------------------

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

const char* format_keyword(PlyFormat f) {
    switch (f) {
        case PlyFormat::Ascii:
            return "ascii";
        case PlyFormat::BinaryLittleEndian:
            return "binary_little_endian";
        case PlyFormat::BinaryBigEndian:
            return "binary_big_endian";
    }
    return "";
}

struct PlyProp {
    std::string type;  ///< scalar type, or the list's item type
    std::string name;
    std::string count_type;  ///< empty for a scalar property
};

/// rows[i][j]: the values of property j of item i (one value for a scalar property).
struct PlyElem {
    std::string name;
    std::vector<PlyProp> props;
    std::vector<std::vector<std::vector<double>>> rows;
};

template <typename T>
void put_binary(std::string& out, double v, bool big_endian) {
    const T t = static_cast<T>(v);
    char b[sizeof(T)];
    std::memcpy(b, &t, sizeof(T));
    if (big_endian != (std::endian::native == std::endian::big)) std::reverse(b, b + sizeof(T));
    out.append(b, sizeof(T));
}

void put_value(std::string& out, PlyFormat f, const std::string& type, double v) {
    const bool is_float = type == "float" || type == "float32";
    const bool is_double = type == "double" || type == "float64";
    if (f == PlyFormat::Ascii) {
        if (is_float) {
            out += fmt::format("{} ", static_cast<float>(v));
        } else if (is_double) {
            out += fmt::format("{} ", v);
        } else {
            out += fmt::format("{} ", static_cast<std::int64_t>(v));
        }
        return;
    }
    const bool be = f == PlyFormat::BinaryBigEndian;
    if (type == "char" || type == "int8") {
        put_binary<std::int8_t>(out, v, be);
    } else if (type == "uchar" || type == "uint8") {
        put_binary<std::uint8_t>(out, v, be);
    } else if (type == "short" || type == "int16") {
        put_binary<std::int16_t>(out, v, be);
    } else if (type == "ushort" || type == "uint16") {
        put_binary<std::uint16_t>(out, v, be);
    } else if (type == "int" || type == "int32") {
        put_binary<std::int32_t>(out, v, be);
    } else if (type == "uint" || type == "uint32") {
        put_binary<std::uint32_t>(out, v, be);
    } else if (is_float) {
        put_binary<float>(out, v, be);
    } else if (is_double) {
        put_binary<double>(out, v, be);
    } else {
        ADD_FAILURE() << "test writer: unknown type " << type;
    }
}

std::string write_header(PlyFormat f, const std::vector<PlyElem>& elems) {
    std::string out =
        fmt::format("ply\nformat {} 1.0\ncomment written by ply_test\n", format_keyword(f));
    for (const PlyElem& e : elems) {
        out += fmt::format("element {} {}\n", e.name, e.rows.size());
        for (const PlyProp& p : e.props) {
            if (p.count_type.empty()) {
                out += fmt::format("property {} {}\n", p.type, p.name);
            } else {
                out += fmt::format("property list {} {} {}\n", p.count_type, p.type, p.name);
            }
        }
    }
    out += "end_header\n";
    return out;
}

std::string write_ply(PlyFormat f, const std::vector<PlyElem>& elems) {
    std::string out = write_header(f, elems);
    for (const PlyElem& e : elems) {
        for (const auto& row : e.rows) {
            for (std::size_t j = 0; j < e.props.size(); ++j) {
                const PlyProp& p = e.props[j];
                if (!p.count_type.empty())
                    put_value(out, f, p.count_type, static_cast<double>(row[j].size()));
                for (double v : row[j]) put_value(out, f, p.type, v);
            }
            if (f == PlyFormat::Ascii) out += '\n';
        }
    }
    return out;
}

PlyElem vertex_element(const std::vector<Point3>& p, const std::string& type = "float") {
    PlyElem e{"vertex", {{type, "x", ""}, {type, "y", ""}, {type, "z", ""}}, {}};
    for (const Point3& q : p) e.rows.push_back({{q.x}, {q.y}, {q.z}});
    return e;
}

PlyElem face_element(const std::vector<std::vector<int>>& faces,
                     const std::string& count_type = "uchar", const std::string& type = "int",
                     const std::string& name = "vertex_indices") {
    PlyElem e{"face", {{type, name, count_type}}, {}};
    for (const auto& f : faces) e.rows.push_back({std::vector<double>(f.begin(), f.end())});
    return e;
}

const std::vector<Point3> kQuadP = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
const std::vector<std::vector<int>> kQuadTris = {{0, 1, 2}, {0, 2, 3}};
const std::vector<uint32_t> kQuadIndices = {0, 1, 2, 0, 2, 3};

// ---- files -------------------------------------------------------------------------------------

/// A per-test file path under the temp dir (tests may run as parallel processes).
std::string temp_path(const std::string& suffix = "") {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string n =
        fmt::format("steradian_ply_{}_{}{}", info->test_suite_name(), info->name(), suffix);
    std::replace(n.begin(), n.end(), '/', '_');
    return (fs::temp_directory_path() / (n + ".ply")).string();
}

std::string write_file(const std::string& bytes, const std::string& suffix = "") {
    const std::string path = temp_path(suffix);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    EXPECT_TRUE(out.good()) << path;
    return path;
}

/// Reads `bytes` from a file; gzip data from `concurrent` bytes on are inflated while parsed
/// (1: always; the default: only large files).
TriangleMeshData read_bytes(const std::string& bytes,
                            std::uint64_t concurrent = kPlyConcurrentGunzipBytes) {
    const std::string path = write_file(bytes);
    TriangleMeshData m = read_ply(path, concurrent);
    fs::remove(path);
    return m;
}

/// Reads `bytes` from a file and expects an sr::Error starting with "path:" and containing
/// `expected` (where "{path}" stands for the file's path).
void expect_error(const std::string& bytes, const std::string& expected,
                  std::uint64_t concurrent = kPlyConcurrentGunzipBytes) {
    const std::string path = write_file(bytes);
    std::string want = expected;
    if (auto pos = want.find("{path}"); pos != std::string::npos) want.replace(pos, 6, path);
    try {
        read_ply(path, concurrent);
        ADD_FAILURE() << "no error; expected: " << want;
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind(path + ":", 0), 0u) << msg;
        EXPECT_NE(msg.find(want), std::string::npos)
            << "message: " << msg << "\nexpected: " << want;
    }
    fs::remove(path);
}

void expect_points(const std::vector<Point3>& got, const std::vector<Point3>& want) {
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(got[i].x, want[i].x) << "vertex " << i;
        EXPECT_EQ(got[i].y, want[i].y) << "vertex " << i;
        EXPECT_EQ(got[i].z, want[i].z) << "vertex " << i;
    }
}

void expect_uvs(const std::vector<Point2>& got, const std::vector<Point2>& want) {
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(got[i].x, want[i].x) << "vertex " << i;
        EXPECT_EQ(got[i].y, want[i].y) << "vertex " << i;
    }
}

/// A w x h grid of vertices with random (exactly representable) float attributes.
struct RandomGrid {
    std::vector<Point3> p;
    std::vector<Normal3> n;
    std::vector<Point2> uv;
    std::vector<std::vector<int>> faces;  ///< triangles and quads mixed
    std::vector<uint32_t> tri_indices;    ///< expected triangulation
};

RandomGrid random_grid(int w, int h, bool quads, unsigned seed) {
    RandomGrid g;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-100.f, 100.f);
    for (int i = 0; i < w * h; ++i) {
        g.p.emplace_back(u(rng), u(rng), u(rng));
        g.n.emplace_back(u(rng), u(rng), u(rng));
        g.uv.emplace_back(u(rng), u(rng));
    }
    for (int y = 0; y + 1 < h; ++y) {
        for (int x = 0; x + 1 < w; ++x) {
            const int a = y * w + x, b = a + 1, c = a + w + 1, d = a + w;
            const auto ua = uint32_t(a), ub = uint32_t(b), uc = uint32_t(c), ud = uint32_t(d);
            if (quads && (x + y) % 2 == 0) {
                g.faces.push_back({a, b, c, d});
                g.tri_indices.insert(g.tri_indices.end(), {ua, ub, uc, ua, uc, ud});
            } else {
                g.faces.push_back({a, b, c});
                g.faces.push_back({a, c, d});
                g.tri_indices.insert(g.tri_indices.end(), {ua, ub, uc, ua, uc, ud});
            }
        }
    }
    return g;
}

PlyElem full_vertex_element(const RandomGrid& g, const std::string& type = "float") {
    PlyElem e{"vertex",
              {{type, "x", ""},
               {type, "y", ""},
               {type, "z", ""},
               {type, "nx", ""},
               {type, "ny", ""},
               {type, "nz", ""},
               {type, "u", ""},
               {type, "v", ""}},
              {}};
    for (std::size_t i = 0; i < g.p.size(); ++i)
        e.rows.push_back({{g.p[i].x},
                          {g.p[i].y},
                          {g.p[i].z},
                          {g.n[i].x},
                          {g.n[i].y},
                          {g.n[i].z},
                          {g.uv[i].x},
                          {g.uv[i].y}});
    return e;
}

// ---- round trips in every format ---------------------------------------------------------------

class PlyFormats : public ::testing::TestWithParam<PlyFormat> {};

TEST_P(PlyFormats, TrianglesPositionsOnly) {
    const std::vector<Point3> p = {{0.5f, -1.25f, 3}, {1e-3f, 2.5e7f, -0.1f}, {0, 0, 1}};
    const TriangleMeshData m =
        read_bytes(write_ply(GetParam(), {vertex_element(p), face_element({{0, 1, 2}})}));
    expect_points(m.p, p);
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_TRUE(m.n.empty());
    EXPECT_TRUE(m.uv.empty());
    EXPECT_TRUE(m.face_indices.empty());
}

TEST_P(PlyFormats, NormalsUvAndMixedQuads) {
    const RandomGrid g = random_grid(7, 5, /*quads=*/true, 1);
    const TriangleMeshData m =
        read_bytes(write_ply(GetParam(), {full_vertex_element(g), face_element(g.faces)}));
    expect_points(m.p, g.p);
    expect_points(m.n, g.n);
    expect_uvs(m.uv, g.uv);
    EXPECT_EQ(m.indices, g.tri_indices);
    // mesh.h: room for the builder's padding vertex, so that it costs no copy.
    EXPECT_GT(m.p.capacity(), m.p.size());
}

TEST_P(PlyFormats, GzipCompressedReadsAsTheUncompressed) {
    // pbrt-v4 reads ".ply.gz" through zlib; we decompress in memory.
    const RandomGrid g = random_grid(9, 4, /*quads=*/true, 3);
    const std::string bytes =
        write_ply(GetParam(), {full_vertex_element(g), face_element(g.faces)});
    const TriangleMeshData m = read_bytes(gzip_compress(bytes));
    expect_points(m.p, g.p);
    expect_points(m.n, g.n);
    expect_uvs(m.uv, g.uv);
    EXPECT_EQ(m.indices, g.tri_indices);
    const std::string gz = gzip_compress(bytes);
    expect_error(gz.substr(0, gz.size() - 12), "{path}: truncated gzip data");
}

TEST_P(PlyFormats, GzipParsedWhileInflatedReadsAsTheUncompressed) {
    // Binary: 90 000 vertices and 178 000 faces, 5.3 MB, more than one of the inflater's
    // 4 MiB pieces, so the reader waits for pieces. ASCII is waited for whole: smaller.
    const bool ascii = GetParam() == PlyFormat::Ascii;
    const RandomGrid g = random_grid(ascii ? 30 : 300, ascii ? 20 : 300, /*quads=*/true, 5);
    const std::string bytes =
        write_ply(GetParam(), {full_vertex_element(g), face_element(g.faces)});
    const std::string gz = gzip_compress(bytes, 1);
    const TriangleMeshData a = read_bytes(gz, 1);
    expect_points(a.p, g.p);
    expect_points(a.n, g.n);
    expect_uvs(a.uv, g.uv);
    EXPECT_EQ(a.indices, g.tri_indices);
    // Several members: the trailer's size is the last member's, so the concurrent reader
    // finds the data larger than promised and falls back to inflating the whole first.
    const std::size_t half = bytes.size() / 2;
    const TriangleMeshData b = read_bytes(
        gzip_compress(bytes.substr(0, half), 1) + gzip_compress(bytes.substr(half), 1), 1);
    EXPECT_EQ(b.p.size(), g.p.size());
    EXPECT_EQ(b.indices, g.tri_indices);
    // Truncated anywhere: the inflater's error, as when inflated before parsing.
    for (std::size_t cut : {gz.size() / 10, gz.size() - 12})
        expect_error(gz.substr(0, cut), "{path}: truncated gzip data", 1);
    // A face that is wrong in the data before a corrupt stretch: the data's own error is
    // reported first, as when the file is inflated whole before it is parsed.
    const RandomGrid small = random_grid(30, 20, /*quads=*/true, 6);
    std::vector<std::vector<int>> faces = small.faces;
    faces[0][1] = int(small.p.size());
    const std::string bad_bytes =
        write_ply(GetParam(), {full_vertex_element(small), face_element(faces)});
    std::string bad = gzip_compress(bad_bytes, 1);
    bad[bad.size() - 6] = char(bad[bad.size() - 6] ^ 0x10);  // the trailer's CRC-32
    expect_error(bad, "{path}: corrupt gzip data", 1);
    expect_error(bad, "{path}: corrupt gzip data");
    // Without the corrupt stretch, the face's own error.
    expect_error(gzip_compress(bad_bytes, 1), "references vertex", 1);
}

TEST_P(PlyFormats, DoublePositions) {
    const std::vector<double> coords = {0.1, -2.0 / 3.0, 1e10, 3.25, -7.0, 1e-9, 0, 5, 6};
    PlyElem v{"vertex", {{"double", "x", ""}, {"double", "y", ""}, {"double", "z", ""}}, {}};
    for (int i = 0; i < 3; ++i)
        v.rows.push_back({{coords[3 * i]}, {coords[3 * i + 1]}, {coords[3 * i + 2]}});
    const TriangleMeshData m = read_bytes(write_ply(GetParam(), {v, face_element({{2, 1, 0}})}));
    ASSERT_EQ(m.p.size(), 3u);
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) EXPECT_EQ(m.p[i][k], static_cast<Float>(coords[3 * i + k]));
    }
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{2, 1, 0}));
}

TEST_P(PlyFormats, QuadSplitAlongDiagonal02) {
    const TriangleMeshData m =
        read_bytes(write_ply(GetParam(), {vertex_element(kQuadP), face_element({{0, 1, 2, 3}})}));
    EXPECT_EQ(m.indices, kQuadIndices);
}

TEST_P(PlyFormats, SkipsUnknownElementsAndProperties) {
    // Vertex colours, an unknown float and an unknown list inside the vertex element; edge and
    // material elements around the vertex and face elements; extra face properties.
    const RandomGrid g = random_grid(4, 3, /*quads=*/true, 2);
    PlyElem v{"vertex",
              {{"uchar", "red", ""},
               {"uchar", "green", ""},
               {"uchar", "blue", ""},
               {"float", "x", ""},
               {"double", "confidence", ""},
               {"float", "y", ""},
               {"int", "tags", "uchar"},
               {"float", "z", ""},
               {"float", "nx", ""},
               {"float", "ny", ""},
               {"float", "nz", ""},
               {"short", "flags", ""}},
              {}};
    for (std::size_t i = 0; i < g.p.size(); ++i) {
        std::vector<double> tags(i % 3, 7.0);
        v.rows.push_back({{255},
                          {double(i)},
                          {3},
                          {g.p[i].x},
                          {0.25},
                          {g.p[i].y},
                          tags,
                          {g.p[i].z},
                          {g.n[i].x},
                          {g.n[i].y},
                          {g.n[i].z},
                          {-3}});
    }
    PlyElem f{"face",
              {{"uchar", "flags", ""},
               {"int", "vertex_indices", "uchar"},
               {"float", "texcoord", "uchar"},
               {"double", "weight", ""}},
              {}};
    for (const auto& face : g.faces) {
        std::vector<double> tc(2 * face.size(), 0.5);
        f.rows.push_back({{1}, std::vector<double>(face.begin(), face.end()), tc, {2.5}});
    }
    PlyElem edge{"edge", {{"int", "vertex1", ""}, {"int", "vertex2", ""}}, {}};
    for (int i = 0; i < 5; ++i) edge.rows.push_back({{double(i)}, {double(i + 1)}});
    PlyElem material{"material",
                     {{"float", "ambient", ""}, {"uchar", "name", "uint"}, {"int", "id", ""}},
                     {{{0.1}, {65, 66, 67}, {4}}, {{0.2}, {}, {5}}}};
    PlyElem empty{"nothing", {}, {}};
    const TriangleMeshData m =
        read_bytes(write_ply(GetParam(), {edge, v, material, f, edge, empty}));
    expect_points(m.p, g.p);
    expect_points(m.n, g.n);
    EXPECT_TRUE(m.uv.empty());
    EXPECT_EQ(m.indices, g.tri_indices);
    EXPECT_TRUE(m.face_indices.empty());
}

TEST_P(PlyFormats, FaceIndicesFollowQuadSplit) {
    PlyElem f{"face", {{"int", "vertex_indices", "uchar"}, {"int", "face_indices", ""}}, {}};
    f.rows.push_back({{0, 1, 2, 3}, {7}});
    f.rows.push_back({{3, 2, 1}, {-2}});
    const TriangleMeshData m = read_bytes(write_ply(GetParam(), {vertex_element(kQuadP), f}));
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 3, 2, 1}));
    EXPECT_EQ(m.face_indices, (std::vector<int>{7, 7, -2}));
}

TEST_P(PlyFormats, EveryScalarTypeForPositions) {
    const std::vector<Point3> p = {{1, 2, 3}, {100, 0, 50}, {7, 9, 11}};
    for (const char* type :
         {"char", "uchar", "short", "ushort", "int", "uint", "float", "double", "int8", "uint8",
          "int16", "uint16", "int32", "uint32", "float32", "float64"}) {
        SCOPED_TRACE(type);
        const TriangleMeshData m =
            read_bytes(write_ply(GetParam(), {vertex_element(p, type), face_element({{0, 1, 2}})}));
        expect_points(m.p, p);
    }
}

TEST_P(PlyFormats, FaceListTypes) {
    const std::pair<const char*, const char*> types[] = {
        {"uchar", "int"},     {"uchar", "uint"},  {"ushort", "uint"}, {"uint", "int"},
        {"char", "short"},    {"uchar", "uchar"}, {"int", "ushort"},  {"uint8", "int32"},
        {"uint16", "uint16"}, {"int32", "uint32"}};
    for (const auto& [count_type, index_type] : types) {
        SCOPED_TRACE(fmt::format("{} {}", count_type, index_type));
        const TriangleMeshData m = read_bytes(write_ply(
            GetParam(), {vertex_element(kQuadP),
                         face_element({{0, 1, 2, 3}, {3, 1, 2}}, count_type, index_type)}));
        EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 3, 1, 2}));
    }
}

TEST_P(PlyFormats, VertexIndexAliasAndUvAliases) {
    for (const auto& [un, vn] : {std::pair{"s", "t"}, std::pair{"texture_u", "texture_v"},
                                 std::pair{"texture_s", "texture_t"}}) {
        SCOPED_TRACE(un);
        PlyElem v = vertex_element(kQuadP);
        v.props.push_back({"float", un, ""});
        v.props.push_back({"float", vn, ""});
        for (std::size_t i = 0; i < v.rows.size(); ++i) {
            v.rows[i].push_back({0.25 * double(i)});
            v.rows[i].push_back({1.0 - 0.125 * double(i)});
        }
        const TriangleMeshData m = read_bytes(
            write_ply(GetParam(), {v, face_element(kQuadTris, "uchar", "int", "vertex_index")}));
        EXPECT_EQ(m.indices, kQuadIndices);
        expect_uvs(m.uv, {{0, 1}, {0.25f, 0.875f}, {0.5f, 0.75f}, {0.75f, 0.625f}});
    }
}

TEST_P(PlyFormats, VertexElementAfterFaceElement) {
    const TriangleMeshData m =
        read_bytes(write_ply(GetParam(), {face_element(kQuadTris), vertex_element(kQuadP)}));
    expect_points(m.p, kQuadP);
    EXPECT_EQ(m.indices, kQuadIndices);
}

TEST_P(PlyFormats, EmptyMesh) {
    const TriangleMeshData m =
        read_bytes(write_ply(GetParam(), {vertex_element({}), face_element({})}));
    EXPECT_TRUE(m.p.empty());
    EXPECT_TRUE(m.indices.empty());
}

TEST_P(PlyFormats, LargerGridMatchesGenerator) {
    const RandomGrid g = random_grid(40, 30, /*quads=*/true, 3);
    // The plain layout takes the binary fast paths; adding a face property forces the generic
    // path; double attributes take the converting fixed-stride path.
    PlyElem faces_generic = face_element(g.faces);
    faces_generic.props.push_back({"uchar", "flags", ""});
    for (auto& row : faces_generic.rows) row.push_back({1});
    for (const auto& [vtype, faces] :
         {std::pair{"float", face_element(g.faces)}, std::pair{"double", faces_generic}}) {
        SCOPED_TRACE(vtype);
        const TriangleMeshData m =
            read_bytes(write_ply(GetParam(), {full_vertex_element(g, vtype), faces}));
        expect_points(m.p, g.p);
        expect_points(m.n, g.n);
        expect_uvs(m.uv, g.uv);
        EXPECT_EQ(m.indices, g.tri_indices);
    }
}

INSTANTIATE_TEST_SUITE_P(All, PlyFormats,
                         ::testing::Values(PlyFormat::Ascii, PlyFormat::BinaryLittleEndian,
                                           PlyFormat::BinaryBigEndian),
                         [](const auto& param_info) {
                             return std::string(format_keyword(param_info.param));
                         });

// ---- format details ----------------------------------------------------------------------------

TEST(PlyReader, AsciiWithCommentsObjInfoCrlfAndLooseWhitespace) {
    const std::string text =
        "ply\r\n"
        "format ascii 1.0\r\n"
        "comment made by hand\r\n"
        "obj_info some info\r\n"
        "element vertex 3\r\n"
        "property float x\r\n"
        "property  float\ty\r\n"
        "property float z\r\n"
        "comment between properties\r\n"
        "element face 1\r\n"
        "property list uchar int vertex_indices\r\n"
        "end_header\r\n"
        "0 0 0\r\n"
        "  +1.5   0 -0\r\n"
        "\r\n"
        "0 1e1 0\t\r\n"
        "3 0 1\n2\r\n";
    const TriangleMeshData m = read_bytes(text);
    expect_points(m.p, {{0, 0, 0}, {1.5f, 0, 0}, {0, 10, 0}});
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(PlyReader, ParsePlyFromMemoryUsesName) {
    const std::string bytes = write_ply(PlyFormat::BinaryLittleEndian,
                                        {vertex_element(kQuadP), face_element({{0, 1, 9}})});
    try {
        parse_ply(bytes, "memory.ply");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "memory.ply: face 0 references vertex 9 but there are 4 vertices");
    }
}

// ---- malformed input ---------------------------------------------------------------------------

const std::string kAsciiTriangle =
    "ply\n"
    "format ascii 1.0\n"
    "element vertex 3\n"
    "property float x\n"
    "property float y\n"
    "property float z\n"
    "element face 1\n"
    "property list uchar int vertex_indices\n"
    "end_header\n"
    "0 0 0\n"
    "1 0 0\n"
    "0 1 0\n"
    "3 0 1 2\n";

std::string replace(std::string s, const std::string& from, const std::string& to) {
    const auto pos = s.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    if (pos != std::string::npos) s.replace(pos, from.size(), to);
    return s;
}

TEST(PlyErrors, NotAPlyFile) {
    expect_error("solid cube\nfacet normal 0 0 1\n", "{path}: not a PLY file");
    expect_error("", "not a PLY file");
    expect_error("plyx\nformat ascii 1.0\n", "not a PLY file");
}

TEST(PlyErrors, UnsupportedFormatAndVersion) {
    expect_error(replace(kAsciiTriangle, "ascii 1.0", "binary_middle_endian 1.0"),
                 "{path}:2: unsupported format 'binary_middle_endian'");
    expect_error(replace(kAsciiTriangle, "ascii 1.0", "ascii 2.0"),
                 "{path}:2: unsupported PLY version '2.0'");
    expect_error(replace(kAsciiTriangle, "format ascii 1.0\n", ""),
                 ":2: 'element' before the 'format' line");
}

TEST(PlyErrors, BadHeaderKeyword) {
    expect_error(replace(kAsciiTriangle, "element face", "elemnt face"),
                 "{path}:7: unknown header keyword 'elemnt'");
}

TEST(PlyErrors, UnknownPropertyType) {
    expect_error(replace(kAsciiTriangle, "property float y", "property flaot y"),
                 "{path}:5: unknown property type 'flaot'");
    expect_error(replace(kAsciiTriangle, "list uchar int", "list float int"),
                 ":8: list count type 'float' is not an integer type");
    expect_error(replace(kAsciiTriangle, "list uchar int", "list uchar float"),
                 ":8: property 'vertex_indices' of element 'face' has non-integer type 'float'");
}

TEST(PlyErrors, MalformedHeaderLines) {
    expect_error(kAsciiTriangle.substr(0, kAsciiTriangle.find("end_header")),
                 "{path}: unexpected end of file in the header (no 'end_header' line)");
    expect_error(replace(kAsciiTriangle, "end_header\n", ""),
                 "{path}:9: unknown header keyword '0'");
    expect_error(replace(kAsciiTriangle, "element vertex 3", "element vertex -3"),
                 ":3: element 'vertex' has a negative count (-3)");
    expect_error(replace(kAsciiTriangle, "element vertex 3", "element vertex three"),
                 ":3: bad count 'three' for element 'vertex'");
    expect_error("ply\nformat ascii 1.0\nproperty float x\nend_header\n",
                 ":3: 'property' before any 'element'");
    expect_error(replace(kAsciiTriangle, "property float z", "property float y"),
                 ":6: duplicate property 'y' in element 'vertex'");
}

TEST(PlyErrors, MissingElementsAndProperties) {
    expect_error(
        "ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int "
        "vertex_indices\nend_header\n",
        "{path}: no 'vertex' element in the header");
    expect_error(replace(kAsciiTriangle, "property float z\n", ""),
                 "{path}:3: element 'vertex' has no property 'z'");
    expect_error(replace(kAsciiTriangle, "vertex_indices", "indices"),
                 ":7: element 'face' has no property 'vertex_indices'");
    expect_error(
        "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float "
        "y\nproperty float z\nend_header\n",
        "no 'face' element in the header");
    expect_error(replace(kAsciiTriangle, "property float z\n",
                         "property float z\nproperty float nx\nproperty float ny\n"),
                 ":3: element 'vertex' has only some of the properties nx, ny, nz");
}

TEST(PlyErrors, TruncatedBinary) {
    const std::vector<Point3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (PlyFormat f : {PlyFormat::BinaryLittleEndian, PlyFormat::BinaryBigEndian}) {
        const std::string full =
            write_ply(f, {vertex_element(p), face_element({{0, 1, 2}, {2, 1, 0}})});
        // 3 vertices of 12 bytes, then 2 faces of 13 bytes.
        expect_error(full.substr(0, full.size() - 26 - 20),
                     "{path}: unexpected end of file in element 'vertex' (read 1 of 3)");
        expect_error(full.substr(0, full.size() - 1),
                     "{path}: unexpected end of file in element 'face' (read 1 of 2)");
        expect_error(full.substr(0, full.size() - 13),
                     "{path}: unexpected end of file in element 'face' (read 1 of 2)");
        // Generic paths: a vertex list property and an extra face property.
        PlyElem v = vertex_element(p);
        v.props.push_back({"int", "tags", "uchar"});
        for (auto& row : v.rows) row.push_back({1, 2});
        PlyElem fe = face_element({{0, 1, 2}, {2, 1, 0}});
        fe.props.push_back({"int", "face_indices", ""});
        for (auto& row : fe.rows) row.push_back({0});
        const std::string generic = write_ply(f, {v, fe});
        expect_error(generic.substr(0, generic.size() - 34 - 10),
                     "unexpected end of file in element 'vertex' (read 2 of 3)");
        expect_error(generic.substr(0, generic.size() - 2),
                     "unexpected end of file in element 'face' (read 1 of 2)");
    }
}

TEST(PlyErrors, IndexOutOfRange) {
    const std::vector<Point3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (PlyFormat f :
         {PlyFormat::Ascii, PlyFormat::BinaryLittleEndian, PlyFormat::BinaryBigEndian}) {
        SCOPED_TRACE(format_keyword(f));
        expect_error(write_ply(f, {vertex_element(p), face_element({{0, 1, 2}, {0, 7, 1}})}),
                     "{path}: face 1 references vertex 7 but there are 3 vertices");
        expect_error(write_ply(f, {vertex_element(p), face_element({{0, 1, 2}, {0, 1, 2, -1}})}),
                     "{path}: face 1 references vertex -1 but there are 3 vertices");
        PlyElem huge = face_element({{0, 0, 1}}, "uchar", "uint");
        huge.rows[0][0][1] = 4294967295.0;
        expect_error(write_ply(f, {vertex_element(p), huge}),
                     "{path}: face 0 references vertex 4294967295 but there are 3 vertices");
        expect_error(write_ply(f, {vertex_element(p),
                                   face_element({{0, 1, 2}, {3, 0, 1}}, "ushort", "int")}),
                     "{path}: face 1 references vertex 3 but there are 3 vertices");
    }
}

TEST(PlyErrors, FacesThatAreNotTrianglesOrQuads) {
    const std::vector<Point3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 2, 0}};
    for (PlyFormat f :
         {PlyFormat::Ascii, PlyFormat::BinaryLittleEndian, PlyFormat::BinaryBigEndian}) {
        SCOPED_TRACE(format_keyword(f));
        expect_error(write_ply(f, {vertex_element(p), face_element({{0, 1, 2}, {0, 1, 2, 3, 4}})}),
                     "{path}: face 1 has 5 vertices; only triangles and quads are supported");
        expect_error(write_ply(f, {vertex_element(p), face_element({{0, 1}}, "short", "int")}),
                     "{path}: face 0 has 2 vertices");
        expect_error(write_ply(f, {vertex_element(p), face_element({{}}, "char", "int")}),
                     "{path}: face 0 has 0 vertices");
    }
}

TEST(PlyErrors, AsciiNotANumber) {
    expect_error(replace(kAsciiTriangle, "1 0 0\n", "1 abc 0\n"),
                 "{path}:11: element 'vertex' 1, property 'y': expected a number, got 'abc'");
    expect_error(replace(kAsciiTriangle, "3 0 1 2", "3 0 1.5 2"),
                 ":13: element 'face' 0, property 'vertex_indices': expected an integer of type "
                 "'int', got '1.5'");
    expect_error(replace(kAsciiTriangle, "3 0 1 2", "300 0 1 2"),
                 "expected an integer of type 'uchar', got '300'");
    expect_error(replace(kAsciiTriangle, "0 1 0\n", "0 1 0x1\n"), "got '0x1'");
}

TEST(PlyErrors, AsciiCountMismatch) {
    // The face line becomes a fourth vertex; the face then starts at the "2".
    expect_error(replace(kAsciiTriangle, "element vertex 3", "element vertex 4"),
                 "{path}: face 0 has 2 vertices");
    expect_error(replace(kAsciiTriangle, "element face 1", "element face 2"),
                 "unexpected end of file in element 'face' (read 1 of 2)");
    expect_error(replace(kAsciiTriangle, "element vertex 3", "element vertex 5"),
                 "unexpected end of file in element 'vertex' (read 4 of 5)");
    expect_error(replace(kAsciiTriangle, "element vertex 3", "element vertex 2"),
                 "{path}: face 0 has 0 vertices");
    expect_error(replace(kAsciiTriangle, "element face 1", "element face 0"),
                 "{path}:13: unexpected data after the last element: '3'");
}

TEST(PlyErrors, NonFinitePosition) {
    expect_error(replace(kAsciiTriangle, "1 0 0\n", "1 nan 0\n"),
                 "{path}: vertex 1 has a non-finite position (1, nan, 0)");
    const std::vector<Point3> p = {
        {0, 0, 0}, {1, std::numeric_limits<float>::quiet_NaN(), 0}, {0, 1, 0}};
    expect_error(
        write_ply(PlyFormat::BinaryLittleEndian, {vertex_element(p), face_element({{0, 1, 2}})}),
        "vertex 1 has a non-finite position");
    PlyElem v = vertex_element({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, "double");
    v.rows[2][0] = {1e300};
    expect_error(write_ply(PlyFormat::BinaryBigEndian, {v, face_element({{0, 1, 2}})}),
                 "vertex 2 has a non-finite position (inf, 1, 0)");
}

TEST(PlyErrors, NegativeListLengthOfUnknownProperty) {
    PlyElem v = vertex_element(kQuadP);
    v.props.push_back({"int", "tags", "char"});
    for (auto& row : v.rows) row.push_back({});
    std::string bytes = write_ply(PlyFormat::Ascii, {v, face_element(kQuadTris)});
    bytes = replace(bytes, "0 0 0 0 \n", "0 0 0 -1 \n");
    expect_error(bytes, "element 'vertex' 0, property 'tags': negative list length -1");
}

TEST(PlyErrors, MissingFile) {
    const std::string path = temp_path("_does_not_exist");
    try {
        read_ply(path);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path + ": cannot read file", 0), 0u) << e.what();
    }
    try {
        read_ply(fs::temp_directory_path().string());
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("cannot"), std::string::npos) << e.what();
    }
}

/// Every prefix and many random corruptions of valid files either read or throw sr::Error.
TEST(PlyErrors, NeverCrashesOnCorruptInput) {
    const RandomGrid g = random_grid(4, 3, /*quads=*/true, 4);
    PlyElem fe = face_element(g.faces);
    PlyElem fe_generic = face_element(g.faces, "uchar", "int");
    fe_generic.props.push_back({"int", "face_indices", ""});
    for (auto& row : fe_generic.rows) row.push_back({3});
    PlyElem v = full_vertex_element(g);
    v.props.push_back({"uchar", "tags", "int"});
    for (auto& row : v.rows) row.push_back({1, 2});
    std::vector<std::string> files;
    for (PlyFormat f :
         {PlyFormat::Ascii, PlyFormat::BinaryLittleEndian, PlyFormat::BinaryBigEndian}) {
        files.push_back(write_ply(f, {full_vertex_element(g), fe}));
        files.push_back(write_ply(f, {v, fe_generic}));
    }
    set_warnings_quiet(true);  // trailing bytes in corrupted binary files are only warned about
    std::mt19937 rng(5);
    int errors = 0, successes = 0;
    auto attempt = [&](const std::string& bytes) {
        try {
            const TriangleMeshData m = parse_ply(bytes, "fuzz.ply");
            validate(m, "fuzz.ply");
            ++successes;
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind("fuzz.ply:", 0), 0u) << e.what();
            ++errors;
        }
    };
    for (const std::string& file : files) {
        for (std::size_t n = 0; n < file.size(); ++n) attempt(file.substr(0, n));
        for (int trial = 0; trial < 2000; ++trial) {
            std::string bytes = file;
            const int flips = 1 + int(rng() % 4);
            for (int k = 0; k < flips; ++k) {
                const std::size_t at = rng() % bytes.size();
                switch (rng() % 4) {
                    case 0:
                        bytes[at] = static_cast<char>(rng());
                        break;
                    case 1:
                        bytes[at] = static_cast<char>(0xff);
                        break;
                    case 2:
                        bytes[at] = "0123456789-. \n"[rng() % 14];
                        break;
                    default:
                        bytes.erase(at, 1 + rng() % 8);
                        break;
                }
                if (bytes.empty()) break;
            }
            attempt(bytes);
        }
    }
    set_warnings_quiet(false);
    EXPECT_GT(errors, 0);
    EXPECT_GT(successes, 0);
}

// ---- validate ----------------------------------------------------------------------------------

TEST(MeshValidate, AcceptsGoodMesh) {
    TriangleMeshData m;
    m.p = kQuadP;
    m.indices = kQuadIndices;
    m.n.assign(4, Normal3(0, 0, 1));
    m.uv.assign(4, Point2(0, 0));
    m.face_indices = {1, 1};
    EXPECT_NO_THROW(validate(m, "quad"));
    EXPECT_EQ(m.triangle_count(), 2u);
}

TEST(MeshValidate, RejectsBrokenMeshes) {
    auto expect_msg = [](const TriangleMeshData& m, const std::string& want) {
        try {
            validate(m, "mesh");
            ADD_FAILURE() << "no error; expected " << want;
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()), "mesh: " + want);
        }
    };
    TriangleMeshData good;
    good.p = kQuadP;
    good.indices = kQuadIndices;
    TriangleMeshData m = good;
    m.indices[4] = 4;
    expect_msg(m, "triangle 1 references vertex 4 but there are 4 vertices");
    m = good;
    m.indices[0] = 4294967295u;
    expect_msg(m, "triangle 0 references vertex 4294967295 but there are 4 vertices");
    m = good;
    m.indices.push_back(0);
    expect_msg(m, "index count 7 is not a multiple of 3");
    m = good;
    m.n.assign(3, Normal3(0, 0, 1));
    expect_msg(m, "3 normals for 4 vertices");
    m = good;
    m.uv.assign(5, Point2(0, 0));
    expect_msg(m, "5 texture coordinates for 4 vertices");
    m = good;
    m.face_indices = {1};
    expect_msg(m, "1 face indices for 2 triangles");
    m = good;
    m.n.assign(4, Normal3(0, 0, 1));
    m.n[2].y = std::numeric_limits<Float>::infinity();
    expect_msg(m, "vertex 2 has a non-finite normal (0, inf, 1)");
    m = good;
    m.uv.assign(4, Point2(0, 0));
    m.uv[3].x = std::numeric_limits<Float>::quiet_NaN();
    expect_msg(m, "vertex 3 has a non-finite texture coordinate (nan, 0)");
}

}  // namespace
}  // namespace sr
