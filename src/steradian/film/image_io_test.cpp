#include "steradian/film/image_io.h"

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <gtest/gtest.h>
#include <png.h>
// jpeglib.h needs FILE and size_t declared first.
#include <cstdio>
#include <jpeglib.h>

#include <unistd.h>

#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/film/image_formats.h"
#include "steradian/sampling/rng.h"
#include "steradian/spectrum/color.h"

namespace sr {
namespace {

namespace fs = std::filesystem;

/// A fresh directory per test, removed afterwards.
class ImageIo : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_dir = fs::temp_directory_path() /
                (std::string("steradian_image_io_") + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }
    fs::path m_dir;
};

Image make_image(int w, int h) {
    Image img;
    img.width = w;
    img.height = h;
    img.channels = 3;
    img.data.resize(size_t(w) * h * 3);
    return img;
}

/// Floats of all magnitudes and signs, including ones no 8- or 16-bit format can hold.
Image random_float_image(int w, int h, uint64_t seed) {
    Image img = make_image(w, h);
    Pcg32 rng(seed, 3);
    for (float& v : img.data) {
        float m = std::ldexp(rng.next_float() + 0.5f, int(rng.next_u32(40)) - 20);
        v = rng.next_u32(2) ? m : -m;
    }
    img.data[0] = 0;
    img.data[1] = 1e-30f;
    img.data[2] = 3.0e7f;
    return img;
}

void expect_bitwise_equal(const Image& a, const Image& b) {
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    ASSERT_EQ(a.channels, b.channels);
    ASSERT_EQ(a.data.size(), b.data.size());
    for (size_t i = 0; i < a.data.size(); ++i)
        ASSERT_EQ(a.data[i], b.data[i]) << "value " << i << " (pixel " << i / 3 << ")";
}

TEST_F(ImageIo, PfmRoundTripIsExact) {
    Image img = random_float_image(7, 5, 1);
    write_image(path("a.pfm"), img);
    expect_bitwise_equal(read_image(path("a.pfm")), img);
    // srgb_decode does not touch float formats.
    expect_bitwise_equal(read_image(path("a.pfm"), false), img);
}

TEST_F(ImageIo, PfmFileLayoutFollowsTheFormat) {
    // PFM: "PF\n<w> <h>\n<scale>\n", a negative scale meaning little-endian, then rows from
    // the bottom of the image to the top, RGB floats.
    Image img = make_image(2, 3);
    for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(i);
    write_image(path("l.pfm"), img);
    std::ifstream f(path("l.pfm"), std::ios::binary);
    std::string magic;
    int w = 0, h = 0;
    double scale = 0;
    f >> magic >> w >> h >> scale;
    f.get();
    EXPECT_EQ(magic, "PF");
    EXPECT_EQ(w, 2);
    EXPECT_EQ(h, 3);
    EXPECT_LT(scale, 0);
    float first[3];
    f.read(reinterpret_cast<char*>(first), sizeof first);
    // The first stored pixel is the bottom-left one: (x, y) = (0, 2), values 12, 13, 14.
    EXPECT_EQ(first[0], img.at(0, 2, 0));
    EXPECT_EQ(first[1], img.at(0, 2, 1));
    EXPECT_EQ(first[2], img.at(0, 2, 2));
}

TEST_F(ImageIo, PfmReaderHandlesBigEndianAndGreyscale) {
    // A 2 x 1 big-endian ("scale" +1) colour file and a 1 x 2 greyscale ("Pf") file, by hand.
    auto be = [](float v) {
        uint32_t u;
        std::memcpy(&u, &v, 4);
        u = __builtin_bswap32(u);
        return u;
    };
    {
        std::ofstream f(path("be.pfm"), std::ios::binary);
        f << "PF\n2 1\n1.0\n";
        for (float v : {1.5f, -2.0f, 0.25f, 4.0f, 8.0f, -16.0f}) {
            uint32_t u = be(v);
            f.write(reinterpret_cast<const char*>(&u), 4);
        }
    }
    Image a = read_image(path("be.pfm"));
    ASSERT_EQ(a.width, 2);
    ASSERT_EQ(a.height, 1);
    ASSERT_EQ(a.channels, 3);
    EXPECT_EQ(a.at(0, 0, 0), 1.5f);
    EXPECT_EQ(a.at(0, 0, 1), -2.0f);
    EXPECT_EQ(a.at(1, 0, 2), -16.0f);
    {
        std::ofstream f(path("g.pfm"), std::ios::binary);
        f << "Pf\n1 2\n-1.0\n";
        for (float v : {3.0f, 5.0f}) f.write(reinterpret_cast<const char*>(&v), 4);
    }
    Image g = read_image(path("g.pfm"));
    ASSERT_EQ(g.channels, 1);
    ASSERT_EQ(g.height, 2);
    EXPECT_EQ(g.at(0, 1, 0), 3.0f);  // first stored row is the bottom one
    EXPECT_EQ(g.at(0, 0, 0), 5.0f);
}

TEST_F(ImageIo, ExrRoundTripIsExact) {
    Image img = random_float_image(9, 4, 2);
    write_image(path("a.exr"), img);
    expect_bitwise_equal(read_image(path("a.exr")), img);
    expect_bitwise_equal(read_image(path("a.exr"), true), img);  // linear float: as stored
}

TEST_F(ImageIo, HalfExrKeepsHalfPrecision) {
    Image img = make_image(3, 1);
    // Exactly representable in half: kept bit for bit. Others: within half's 2^-11 relative
    // rounding error.
    float exact[] = {0.5f, 1.25f, -3.0f, 1024.0f, 0.0f, 0.0009765625f};
    float inexact[] = {0.1f, 3.14159265f, -123.456f};
    for (int i = 0; i < 6; ++i) img.data[i] = exact[i];
    for (int i = 0; i < 3; ++i) img.data[6 + i] = inexact[i];
    WriteOptions o;
    o.half_float = true;
    write_image(path("h.exr"), img, o);
    Image r = read_image(path("h.exr"));
    ASSERT_EQ(r.data.size(), img.data.size());
    for (int i = 0; i < 6; ++i) EXPECT_EQ(r.data[i], exact[i]);
    for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(r.data[6 + i], inexact[i], std::abs(inexact[i]) * std::ldexp(1.0, -11));
}

TEST_F(ImageIo, PngIsEightBitSrgb) {
    Image img = make_image(4, 2);
    const float in[8] = {0.0f, 1.0f, 0.5f, 2.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(),
                         0.002f, 0.2f};
    for (int p = 0; p < 8; ++p)
        for (int c = 0; c < 3; ++c) img.data[size_t(p) * 3 + c] = in[p];
    img.data[1] = 1.0f;  // a colour pixel: (0, 1, 0)
    write_image(path("a.png"), img);

    // Raw codes: round(255 * srgb_encode(v)) with v clamped to [0, 1] and NaN -> 0.
    // sRGB(0.5) = 1.055 * 0.5^(1/2.4) - 0.055 = 0.73536, 255 * 0.73536 = 187.5 -> 188.
    // sRGB(0.002) = 12.92 * 0.002 = 0.02584 -> 6.59 -> 7.
    // sRGB(0.2) = 1.055 * 0.2^(1/2.4) - 0.055 = 0.48453 -> 123.55 -> 124.
    const int codes[8] = {0, 255, 188, 255, 0, 0, 7, 124};
    Image raw = read_image(path("a.png"), false);
    ASSERT_EQ(raw.width, 4);
    ASSERT_EQ(raw.height, 2);
    ASSERT_EQ(raw.channels, 3);
    for (int p = 0; p < 8; ++p)
        for (int c = (p == 0 ? 2 : 0); c < 3; ++c)
            EXPECT_NEAR(raw.data[size_t(p) * 3 + c], codes[p] / 255.0, 1e-6) << "pixel " << p;
    EXPECT_NEAR(raw.data[1], 1.0, 1e-6);

    // Decoded: 0 -> 0, 1 -> 1, and each value within 1/255 of the input: rounding to a code
    // errs by at most half a code, and the decode's slope 2.4/1.055 ((e + 0.055)/1.055)^1.4 is
    // below 1.6 for encoded values e <= 0.75 (linear <= 0.52), so the error is < 0.8/255.
    Image dec = read_image(path("a.png"));
    EXPECT_EQ(dec.at(0, 0, 0), 0.0f);
    EXPECT_NEAR(dec.at(1, 0, 0), 1.0f, 1e-6);
    EXPECT_NEAR(dec.at(2, 0, 0), srgb_decode(188 / 255.0f), 1e-6);
    EXPECT_NEAR(dec.at(2, 0, 0), 0.5f, 1 / 255.0f);
    EXPECT_NEAR(dec.at(2, 1, 0), 0.002f, 1 / 255.0f);
    EXPECT_NEAR(dec.at(3, 1, 0), 0.2f, 1 / 255.0f);
}

TEST_F(ImageIo, PngExposureScalesByPowersOfTwo) {
    Image img = make_image(1, 1);
    img.data = {0.25f, 0.125f, 1.0f};
    WriteOptions o;
    o.exposure = 1;  // x2: 0.5, 0.25, 2 -> clamped 1
    write_image(path("e.png"), img, o);
    Image raw = read_image(path("e.png"), false);
    EXPECT_NEAR(raw.data[0], 188 / 255.0, 1e-6);                                  // sRGB(0.5)
    EXPECT_NEAR(raw.data[1], std::lround(255 * srgb_encode(0.25f)) / 255.0, 1e-6);  // 137
    EXPECT_NEAR(raw.data[2], 1.0, 1e-6);
}

TEST_F(ImageIo, SingleChannelExrRoundTrips) {
    Image y;
    y.width = 3;
    y.height = 2;
    y.channels = 1;
    y.data = {0.5f, 1e3f, 2.25f, 0, 7.125f, 1e-3f};
    write_image(path("y.exr"), y);
    Image back = read_image(path("y.exr"));
    ASSERT_EQ(back.channels, 1);
    ASSERT_EQ(back.width, 3);
    ASSERT_EQ(back.height, 2);
    for (size_t i = 0; i < y.data.size(); ++i) EXPECT_EQ(back.data[i], y.data[i]);
}

TEST_F(ImageIo, ErrorsAreReported) {
    Image img = make_image(2, 2);
    EXPECT_THROW(write_image(path("a.unknownext"), img), Error);
    EXPECT_THROW(read_image(path("missing.exr")), Error);
    EXPECT_THROW(read_image(path("missing.pfm")), Error);
    EXPECT_THROW(read_image(path("missing.png")), Error);
    Image grey = img;
    grey.channels = 1;
    grey.data.resize(4);
    EXPECT_THROW(write_image(path("g.png"), grey), Error);  // single channel: .exr only
    EXPECT_THROW(write_image(path("g.pfm"), grey), Error);
    grey.channels = 2;
    EXPECT_THROW(write_image(path("g2.exr"), grey), Error);
    // Not a PFM, and a truncated one.
    {
        std::ofstream f(path("bad.pfm"), std::ios::binary);
        f << "P6\n2 2\n255\n";
    }
    EXPECT_THROW(read_image(path("bad.pfm")), Error);
    {
        std::ofstream f(path("short.pfm"), std::ios::binary);
        f << "PF\n2 2\n-1.0\n";
        float v = 1;
        f.write(reinterpret_cast<const char*>(&v), 4);
    }
    EXPECT_THROW(read_image(path("short.pfm")), Error);
    // A file with an image extension that holds no image.
    {
        std::ofstream f(path("junk.exr"), std::ios::binary);
        f << "this is not an OpenEXR file";
    }
    EXPECT_THROW(read_image(path("junk.exr")), Error);
}

TEST_F(ImageIo, WriteCreatesMissingDirectories) {
    Image img = random_float_image(2, 2, 3);
    std::string p = path("sub/dir/x.pfm");
    write_image(p, img);
    expect_bitwise_equal(read_image(p), img);
}

// ---- the direct readers and writers against OpenImageIO ---------------------------------
// EXR and PNG are read and written without OpenImageIO, which is loaded (as a module) only for
// other formats and layouts. These tests pin that both ways give the same values: each file
// is read directly and through OpenImageIO (image_formats::force_openimageio), and files
// written either way are compared.

/// Runs `f` with every format but PFM going through OpenImageIO.
template <typename F>
auto through_openimageio(F f) {
    struct Reset {
        ~Reset() { image_formats::force_openimageio(false); }
    } reset;
    image_formats::force_openimageio(true);
    return f();
}

void expect_same_bits(const Image& a, const Image& b) {
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    ASSERT_EQ(a.channels, b.channels);
    ASSERT_EQ(a.data.size(), b.data.size());
    for (size_t i = 0; i < a.data.size(); ++i) {
        uint32_t x, y;
        std::memcpy(&x, &a.data[i], 4);
        std::memcpy(&y, &b.data[i], 4);
        ASSERT_EQ(x, y) << "value " << i << ": " << a.data[i] << " vs " << b.data[i];
    }
}

/// Reads `p` directly and through OpenImageIO (raw and sRGB-decoded) and expects the same
/// bits; returns the direct (raw) read.
Image read_both_ways(const std::string& p) {
    Image direct = read_image(p, false);
    expect_same_bits(direct, through_openimageio([&] { return read_image(p, false); }));
    expect_same_bits(read_image(p, true), through_openimageio([&] { return read_image(p, true); }));
    return direct;
}

/// Values that exercise half conversion: ties, denormals, overflow, infinities, NaN.
Image half_edge_image() {
    Image img = make_image(6, 2);
    const float v[] = {1.0f + std::ldexp(1.0f, -11),          // tie: to even (1.0)
                       1.0f + 3 * std::ldexp(1.0f, -11),      // tie: to even (up)
                       std::ldexp(1.0f, -24),                 // smallest denormal
                       std::ldexp(1.0f, -25),                 // half of it: tie to 0
                       std::ldexp(1.5f, -25),                 // rounds up to the denormal
                       65504.0f,                              // largest half
                       65520.0f,                              // rounds to infinity
                       1e9f, -1e9f,
                       std::numeric_limits<float>::infinity(),
                       -std::numeric_limits<float>::infinity(),
                       std::numeric_limits<float>::quiet_NaN(),
                       -0.0f, 0.1f, 1.0f / 3, 2.0f / 3, 1e-5f, -7.3e-6f};
    for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = v[i % std::size(v)];
    return img;
}

TEST_F(ImageIo, ExrDirectAndOpenImageIoAgree) {
    const Image img = random_float_image(11, 7, 4);
    const Image edges = half_edge_image();
    Image y;
    y.width = 4;
    y.height = 3;
    y.channels = 1;
    for (int i = 0; i < 12; ++i) y.data.push_back(std::ldexp(float(i) + 0.3f, i - 6));
    WriteOptions half;
    half.half_float = true;
    struct Case {
        const char* name;
        const Image* image;
        WriteOptions opts;
    } cases[] = {{"float", &img, {}}, {"half", &img, half}, {"edges", &edges, {}},
                 {"edges-half", &edges, half}, {"y", &y, {}}, {"y-half", &y, half}};
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const std::string direct = path(std::string(c.name) + "-direct.exr");
        const std::string oiio = path(std::string(c.name) + "-oiio.exr");
        write_image(direct, *c.image, c.opts);
        through_openimageio([&] { write_image(oiio, *c.image, c.opts); return 0; });
        const Image a = read_both_ways(direct);
        const Image b = read_both_ways(oiio);
        expect_same_bits(a, b);
        if (!c.opts.half_float && c.image != &edges) expect_bitwise_equal(a, *c.image);
    }
}

TEST_F(ImageIo, HalfExrValuesFollowTheHalfFormat) {
    // IEEE 754 binary16: 10 fraction bits, round to nearest even; 65504 the largest finite
    // value; 2^-24 the smallest denormal.
    Image img = make_image(2, 1);
    img.data = {1.0f + std::ldexp(1.0f, -11), 1.0f + 3 * std::ldexp(1.0f, -11), std::ldexp(1.0f, -24),
                65504.0f, 65520.0f, std::ldexp(1.0f, -26)};
    WriteOptions o;
    o.half_float = true;
    write_image(path("h.exr"), img, o);
    Image r = read_image(path("h.exr"));
    EXPECT_EQ(r.data[0], 1.0f);
    EXPECT_EQ(r.data[1], 1.0f + std::ldexp(1.0f, -9));
    EXPECT_EQ(r.data[2], std::ldexp(1.0f, -24));
    EXPECT_EQ(r.data[3], 65504.0f);
    EXPECT_TRUE(std::isinf(r.data[4]));
    EXPECT_EQ(r.data[5], 0.0f);
}

/// Writes an EXR with the given channels (all of `type`) directly with OpenEXR; channel k
/// of pixel p holds 0.25 * k + p, and the data window starts at (x0, y0).
void write_exr_channels(const std::string& p, const std::vector<std::string>& names,
                        Imf::PixelType type, int x0 = 0, int y0 = 0) {
    const int w = 3, h = 2, n = int(names.size());
    Imf::Header header(Imath::Box2i({0, 0}, {w - 1, h - 1}),
                       Imath::Box2i({x0, y0}, {x0 + w - 1, y0 + h - 1}));
    std::vector<float> f(size_t(w) * h * n);
    std::vector<Imath::half> hf(f.size());
    for (int px = 0; px < w * h; ++px)
        for (int k = 0; k < n; ++k) {
            f[size_t(px) * n + k] = 0.25f * k + float(px);
            hf[size_t(px) * n + k] = f[size_t(px) * n + k];
        }
    const size_t vs = type == Imf::HALF ? 2 : 4;
    char* base = type == Imf::HALF ? reinterpret_cast<char*>(hf.data()) : reinterpret_cast<char*>(f.data());
    Imf::FrameBuffer fb;
    for (int k = 0; k < n; ++k) {
        header.channels().insert(names[size_t(k)], Imf::Channel(type));
        fb.insert(names[size_t(k)],
                  Imf::Slice::Make(type, base + vs * size_t(k), header.dataWindow(), vs * n, vs * n * w));
    }
    Imf::OutputFile out(p.c_str(), header);
    out.setFrameBuffer(fb);
    out.writePixels(h);
}

TEST_F(ImageIo, ExrLayoutsReadAsOpenImageIoReadsThem) {
    // Read directly: RGB, RGBA, Y, in half or float, with a data window away from the origin.
    // Left to OpenImageIO (same result by construction): other channel sets.
    struct Case {
        std::vector<std::string> names;
        Imf::PixelType type;
        int x0, y0;
    } cases[] = {{{"R", "G", "B"}, Imf::FLOAT, 0, 0},    {{"B", "G", "R"}, Imf::HALF, 0, 0},
                 {{"A", "B", "G", "R"}, Imf::FLOAT, 0, 0}, {{"R", "G", "B", "A"}, Imf::HALF, 5, -3},
                 {{"Y"}, Imf::HALF, -2, 4},               {{"Y", "A"}, Imf::FLOAT, 0, 0},
                 {{"Z"}, Imf::FLOAT, 0, 0},               {{"diffuse.R", "diffuse.G", "diffuse.B"}, Imf::HALF, 0, 0},
                 {{"R", "G", "B", "Z"}, Imf::FLOAT, 1, 1}};
    int i = 0;
    for (const Case& c : cases) {
        SCOPED_TRACE(i);
        const std::string p = path("layout" + std::to_string(i++) + ".exr");
        write_exr_channels(p, c.names, c.type, c.x0, c.y0);
        Image r = read_both_ways(p);
        EXPECT_EQ(r.width, 3);
        EXPECT_EQ(r.height, 2);
        EXPECT_EQ(r.channels, int(c.names.size()));
    }
    // R, G, B, A in that order whatever the file's order (it stores them alphabetically).
    write_exr_channels(path("rgba.exr"), {"A", "R", "G", "B"}, Imf::FLOAT);
    Image rgba = read_image(path("rgba.exr"));
    ASSERT_EQ(rgba.channels, 4);
    EXPECT_EQ(rgba.at(1, 0, 0), 1.25f);  // R: written as channel 1
    EXPECT_EQ(rgba.at(1, 0, 3), 1.0f);   // A: channel 0
}

TEST_F(ImageIo, PbrtV4ExrFilesReadAsBefore) {
    // The reference images pbrt-v4 wrote (float and half RGB, ZIP): the same bits directly and
    // through OpenImageIO.
    const std::string dir = std::string(STERADIAN_SOURCE_DIR) + "/tests/data/reference/";
    for (const char* f : {"cornell-box/pbrt-v4-1024spp.exr", "cornell-box/pbrt-v4-64spp.exr",
                          "cornell-box-glass-metal/pbrt-v4-1024spp.exr"}) {
        SCOPED_TRACE(f);
        Image img = read_both_ways(dir + f);
        EXPECT_EQ(img.width, 512);
        EXPECT_EQ(img.channels, 3);
    }
}

/// Writes a PNG with libpng: `codes` row-major (8- or 16-bit values, one per sample; for
/// depths below 8, one per pixel), with an optional gAMA of 1.0 and Adam7 interlacing.
void write_test_png(const std::string& p, int w, int h, int color_type, int depth,
                    const std::vector<int>& codes, bool gamma1 = false, bool interlace = false,
                    const std::vector<png_color>& palette = {}) {
    std::FILE* f = std::fopen(p.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    ASSERT_EQ(setjmp(png_jmpbuf(png)), 0);
    png_init_io(png, f);
    png_set_IHDR(png, info, png_uint_32(w), png_uint_32(h), depth, color_type,
                 interlace ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (!palette.empty()) png_set_PLTE(png, info, palette.data(), int(palette.size()));
    if (gamma1) png_set_gAMA(png, info, 1.0);
    png_write_info(png, info);
    const int samples = color_type == PNG_COLOR_TYPE_RGB ? 3 : 1;
    std::vector<png_byte> bytes;
    for (int y = 0; y < h; ++y) {
        std::vector<png_byte> row;
        if (depth == 16) {
            for (int i = 0; i < w * samples; ++i) {
                int v = codes[size_t(y) * w * samples + i];
                row.push_back(png_byte(v >> 8));
                row.push_back(png_byte(v & 255));
            }
        } else if (depth == 8) {
            for (int i = 0; i < w * samples; ++i) row.push_back(png_byte(codes[size_t(y) * w * samples + i]));
        } else {
            row.assign(size_t((w * depth + 7) / 8), 0);
            for (int x = 0; x < w; ++x) {
                int bit = x * depth;
                row[size_t(bit / 8)] |= png_byte(codes[size_t(y) * w + x] << (8 - depth - bit % 8));
            }
        }
        bytes.insert(bytes.end(), row.begin(), row.end());
    }
    std::vector<png_bytep> rows;
    const size_t stride = bytes.size() / size_t(h);
    for (int y = 0; y < h; ++y) rows.push_back(bytes.data() + stride * size_t(y));
    png_write_image(png, rows.data());
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    ASSERT_EQ(std::fclose(f), 0);
}

TEST_F(ImageIo, PngDirectAndOpenImageIoAgree) {
    // Written: the same codes either way (every code 0..255 through the sRGB encoding).
    Image ramp = make_image(256, 2);
    for (int x = 0; x < 256; ++x)
        for (int c = 0; c < 3; ++c) {
            ramp.at(x, 0, c) = srgb_decode(float(x) / 255);
            ramp.at(x, 1, c) = float(x * 3 + c) / 700;
        }
    write_image(path("direct.png"), ramp);
    through_openimageio([&] { write_image(path("oiio.png"), ramp); return 0; });
    const Image a = read_both_ways(path("direct.png"));
    const Image b = read_both_ways(path("oiio.png"));
    expect_same_bits(a, b);
    for (int x = 0; x < 256; ++x) EXPECT_EQ(a.at(x, 0, 1), float(x) * (1.0f / 255.0f)) << x;

    // Read: every layout the direct reader takes, and some it leaves to OpenImageIO.
    std::vector<int> rgb8, grey16, rgb16, grey4, pal;
    for (int i = 0; i < 5 * 3 * 3; ++i) rgb8.push_back((i * 37) % 256);
    for (int i = 0; i < 5 * 3; ++i) grey16.push_back((i * 4999) % 65536);
    for (int i = 0; i < 5 * 3 * 3; ++i) rgb16.push_back((i * 1777 + 3) % 65536);
    for (int i = 0; i < 5 * 3; ++i) grey4.push_back(i % 16);
    for (int i = 0; i < 5 * 3; ++i) pal.push_back(i % 3);
    std::vector<png_color> palette = {{1, 2, 3}, {250, 128, 0}, {17, 255, 99}};
    write_test_png(path("rgb8.png"), 5, 3, PNG_COLOR_TYPE_RGB, 8, rgb8);
    write_test_png(path("rgb8-gamma1.png"), 5, 3, PNG_COLOR_TYPE_RGB, 8, rgb8, true);
    write_test_png(path("rgb8-adam7.png"), 5, 3, PNG_COLOR_TYPE_RGB, 8, rgb8, false, true);
    write_test_png(path("grey16.png"), 5, 3, PNG_COLOR_TYPE_GRAY, 16, grey16);
    write_test_png(path("rgb16.png"), 5, 3, PNG_COLOR_TYPE_RGB, 16, rgb16);
    write_test_png(path("grey4.png"), 5, 3, PNG_COLOR_TYPE_GRAY, 4, grey4);
    write_test_png(path("grey1.png"), 5, 3, PNG_COLOR_TYPE_GRAY, 1,
                   std::vector<int>(grey4.size(), 1));
    write_test_png(path("pal.png"), 5, 3, PNG_COLOR_TYPE_PALETTE, 8, pal, false, false, palette);
    write_test_png(path("pal2.png"), 5, 3, PNG_COLOR_TYPE_PALETTE, 2, pal, false, false, palette);
    write_test_png(path("grey-alpha.png"), 5, 3, PNG_COLOR_TYPE_GRAY_ALPHA, 8,
                   std::vector<int>(30, 77));
    for (const char* name : {"rgb8", "rgb8-gamma1", "rgb8-adam7", "grey16", "rgb16", "grey4",
                             "grey1", "pal", "pal2", "grey-alpha"}) {
        SCOPED_TRACE(name);
        read_both_ways(path(std::string(name) + ".png"));
    }
    // The values: code / 255 and code / 65535; grey of 4 bits scaled to 8 (code * 17).
    Image r = read_image(path("rgb8.png"), false);
    EXPECT_EQ(r.at(1, 0, 0), 111 * (1.0f / 255));
    Image g = read_image(path("grey16.png"), false);
    EXPECT_EQ(g.channels, 1);
    EXPECT_EQ(g.at(1, 0, 0), 4999 * (1.0f / 65535));
    Image g4 = read_image(path("grey4.png"), false);
    EXPECT_EQ(g4.at(3, 0, 0), 51 * (1.0f / 255));
    Image p = read_image(path("pal.png"), false);
    ASSERT_EQ(p.channels, 3);
    EXPECT_EQ(p.at(1, 0, 1), 128 * (1.0f / 255));
}

/// Writes a JPEG with libjpeg: `components` 1 (grey), 3 (RGB, stored as YCbCr with 2x2
/// chroma subsampling) or 4 (CMYK), baseline or progressive, a smooth pattern.
void write_test_jpeg(const std::string& p, int w, int h, int components, bool progressive) {
    std::FILE* f = std::fopen(p.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    jpeg_compress_struct cinfo;
    jpeg_error_mgr err;
    cinfo.err = jpeg_std_error(&err);
    jpeg_create_compress(&cinfo);
    jpeg_stdio_dest(&cinfo, f);
    cinfo.image_width = JDIMENSION(w);
    cinfo.image_height = JDIMENSION(h);
    cinfo.input_components = components;
    cinfo.in_color_space = components == 1 ? JCS_GRAYSCALE : components == 3 ? JCS_RGB : JCS_CMYK;
    jpeg_set_defaults(&cinfo);
    jpeg_set_quality(&cinfo, 90, TRUE);
    if (progressive) jpeg_simple_progression(&cinfo);
    jpeg_start_compress(&cinfo, TRUE);
    std::vector<JSAMPLE> row(size_t(w) * size_t(components));
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < components; ++c)
                row[size_t(x) * components + c] = JSAMPLE((x * 13 + y * 7 + c * 50 + (x * y) % 17) % 256);
        JSAMPROW r = row.data();
        jpeg_write_scanlines(&cinfo, &r, 1);
    }
    jpeg_finish_compress(&cinfo);
    jpeg_destroy_compress(&cinfo);
    ASSERT_EQ(std::fclose(f), 0);
}

TEST_F(ImageIo, JpegDirectAndOpenImageIoAgree) {
    // JPEG is read with libjpeg and written through OpenImageIO: the decoded codes must be
    // those OpenImageIO decoded, for every kind of file (CMYK is left to OpenImageIO).
    Image img = make_image(37, 21);
    for (int y = 0; y < 21; ++y)
        for (int x = 0; x < 37; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = float((x * 7 + y * 3 + c * 40) % 100) / 100;
    write_image(path("oiio.jpg"), img);
    write_test_jpeg(path("rgb.jpg"), 37, 21, 3, false);
    write_test_jpeg(path("rgb-progressive.jpg"), 37, 21, 3, true);
    write_test_jpeg(path("grey.jpg"), 37, 21, 1, false);
    write_test_jpeg(path("cmyk.jpg"), 37, 21, 4, false);
    for (const char* name : {"oiio", "rgb", "rgb-progressive", "grey", "cmyk"}) {
        SCOPED_TRACE(name);
        Image r = read_both_ways(path(std::string(name) + ".jpg"));
        EXPECT_EQ(r.width, 37);
        EXPECT_EQ(r.channels, std::string(name) == "grey" ? 1 : 3);
    }
    // A JPEG cut short is an error naming the file (libjpeg's complaint), not a crash.
    {
        std::ifstream in(path("rgb.jpg"), std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::ofstream out(path("cut.jpg"), std::ios::binary);
        out.write(bytes.data(), 100);
    }
    try {
        Image cut = read_image(path("cut.jpg"));
        // libjpeg pads a truncated entropy-coded segment with grey (with a warning); the
        // header must be complete for that, which 100 bytes of this file are not.
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("cut.jpg"), std::string::npos) << e.what();
    }
}

TEST_F(ImageIo, PngErrorsNameTheFile) {
    // A PNG cut short: libpng's complaint, with the file name.
    Image img = make_image(64, 64);
    for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(i % 97) / 97;
    write_image(path("full.png"), img);
    {
        std::ifstream in(path("full.png"), std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::ofstream out(path("cut.png"), std::ios::binary);
        out.write(bytes.data(), std::streamsize(bytes.size() / 2));
    }
    try {
        read_image(path("cut.png"));
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("cut.png"), std::string::npos) << e.what();
    }
}

TEST_F(ImageIo, OtherFormatsGoThroughOpenImageIo) {
    // TIFF (8-bit sRGB codes, as PNG), JPEG (lossy: near) and Radiance HDR (float, 8-bit
    // shared-exponent mantissas: within 1 %) through the OpenImageIO module.
    Image img = make_image(8, 4);
    for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(i % 11) / 10;
    write_image(path("a.png"), img);
    write_image(path("a.tif"), img);
    expect_same_bits(read_image(path("a.tif"), false), read_image(path("a.png"), false));
    expect_same_bits(read_image(path("a.tif")), read_image(path("a.png")));
    write_image(path("a.jpg"), img);
    Image j = read_image(path("a.jpg"));
    ASSERT_EQ(j.channels, 3);
    write_image(path("a.hdr"), img);
    Image h = read_image(path("a.hdr"));
    ASSERT_EQ(h.data.size(), img.data.size());
    for (size_t i = 0; i < img.data.size(); ++i) EXPECT_NEAR(h.data[i], img.data[i], 0.01);
    // A PNG under another extension is read as before (by its content).
    std::filesystem::copy_file(path("a.png"), path("png-named.jpg"));
    expect_same_bits(read_image(path("png-named.jpg")), read_image(path("a.png")));
    EXPECT_THROW(check_image_output(path("a.nosuchformat")), Error);
}

}  // namespace
}  // namespace sr
