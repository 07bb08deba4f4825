#include "steradian/film/image_io.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "steradian/core/error.h"
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

}  // namespace
}  // namespace sr
