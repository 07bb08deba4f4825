// Texture filtering over a pixel's footprint: the MIP pyramid (exact area averages), pbrt-v4's
// level choice, EWA, the filtered checkerboard and band-limited noise, each against a value
// from its definition (an area average, a closed-form integral, a symmetry).
#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "steradian/core/noise.h"
#include "steradian/material/texture.h"

namespace sr {
namespace {

Image make_image(int w, int h, const std::function<float(int, int)>& f) {
    Image im;
    im.width = w;
    im.height = h;
    im.channels = 1;
    im.data.resize(size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) im.at(x, y, 0) = f(x, y);
    return im;
}

double mean(const Image& im) {
    double s = 0;
    for (float v : im.data) s += v;
    return s / double(im.data.size());
}

TEST(TexturePyramid, EveryLevelIsAnExactAreaAverageDownToOneTexel) {
    // Odd sizes: each texel of the next level covers 1.5 to 2 texels per axis, weighted by
    // the area it covers; the mean over the image is then the same at every level.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0, 1);
    TextureImage t;
    t.image = make_image(37, 23, [&](int, int) { return u(rng); });
    t.build_pyramid();
    // ceil-halving 37 -> 19 -> 10 -> 5 -> 3 -> 2 -> 1: 7 levels (1 + ceil(log2 37)).
    ASSERT_EQ(t.levels(), 7);
    const double m0 = mean(t.image);
    for (int l = 1; l < t.levels(); ++l) {
        // The mean of a level weighs its texels equally, and each covers the same area.
        EXPECT_NEAR(mean(t.level(l)), m0, 1e-5) << "level " << l;
    }
    EXPECT_EQ(t.level(t.levels() - 1).width, 1);
    EXPECT_EQ(t.level(t.levels() - 1).height, 1);
    // Level 1 of 37: texel 0 covers source [0, 37/19) = texel 0 fully and 18/19 of texel 1.
    const double w = 37.0 / 19;
    const double want = (t.image.at(0, 0, 0) + (w - 1) * t.image.at(1, 0, 0)) / w;
    // ... in x; in y, 23 -> 12: texel 0 covers [0, 23/12) rows.
    const double wy = 23.0 / 12;
    const double want_row1 = (t.image.at(0, 1, 0) + (w - 1) * t.image.at(1, 1, 0)) / w;
    EXPECT_NEAR(t.level(1).at(0, 0, 0), (want + (wy - 1) * want_row1) / wy, 1e-5);
}

/// A 256 x 256 image of 2 x 2-texel blocks, black and white alternating: level 0 and 1 hold
/// only 0 and 1, level 2 and above only 0.5.
TextureImage blocks() {
    TextureImage t;
    t.image = make_image(256, 256, [](int x, int y) { return float(((x / 2) + (y / 2)) & 1); });
    t.build_pyramid();
    return t;
}

TEST(TextureFilter, ThePixelFootprintChoosesTheLevelAsPbrtV4) {
    const TextureImage t = blocks();
    ASSERT_EQ(t.levels(), 9);
    // A point inside a white block at level 0 (texel (2, 0) - (3, 1); s, t of its centre).
    TexCoord2 c;
    c.st = Point2(3.0f / 256, 1 - 1.0f / 256);
    EXPECT_NEAR(t.filter(c, TextureFilter::Bilinear, 8).r, 1, 1e-6);  // zero footprint
    // pbrt-v4: level = L - 1 + log2(2 max|d|). A derivative of 1 texel -> width 2 texels
    // -> level 1 (still blocks of 0 and 1); of 2 texels -> level 2 (all 0.5).
    c.dsdx = 1.0f / 256;
    EXPECT_NEAR(t.filter(c, TextureFilter::Bilinear, 8).r, 1, 1e-6);
    c.dsdx = 2.0f / 256;
    EXPECT_NEAR(t.filter(c, TextureFilter::Bilinear, 8).r, 0.5, 1e-6);
    EXPECT_NEAR(t.filter(c, TextureFilter::Point, 8).r, 0.5, 1e-6);
    // A footprint wider than the image: the one texel of the top level, the image's mean.
    c.dsdx = 4;
    EXPECT_NEAR(t.filter(c, TextureFilter::Bilinear, 8).r, mean(t.image), 1e-6);
    // Trilinear between level 1 (value 1 here) and 2 (0.5) at level 1.5: 0.75.
    c.dsdx = std::sqrt(2.0f) / 256;  // width 2 sqrt 2 texels: log2 = 1.5
    EXPECT_NEAR(t.filter(c, TextureFilter::Trilinear, 8).r, 0.75, 1e-4);
}

TEST(TextureFilter, EwaOfALinearRampIsTheRampAtTheCentre) {
    // Symmetric weights about the ellipse's centre average a linear function to its value
    // there, whatever the ellipse (away from the edges).
    TextureImage t;
    t.image = make_image(512, 512, [](int x, int y) { return float(0.25 + 0.001 * x + 0.0005 * y); });
    t.wrap = WrapMode::Clamp;
    t.build_pyramid();
    TexCoord2 c;
    c.st = Point2(0.5f, 0.5f);
    c.dsdx = 6.0f / 512;
    c.dtdx = 2.0f / 512;
    c.dsdy = -1.0f / 512;
    c.dtdy = 3.0f / 512;
    // Texel centres at half-integers: s = 0.5 is x = 255.5; t = 0.5 is y = 255.5.
    const double want = 0.25 + 0.001 * 255.5 + 0.0005 * 255.5;
    EXPECT_NEAR(t.filter(c, TextureFilter::Ewa, 8).r, want, 2e-4);
    // On a black-and-white pattern finer than the footprint, EWA gives the average.
    const TextureImage b = blocks();
    TexCoord2 w;
    w.st = Point2(0.3f, 0.6f);
    w.dsdx = 8.0f / 256;
    w.dtdy = 3.0f / 256;
    EXPECT_NEAR(b.filter(w, TextureFilter::Ewa, 8).r, 0.5, 0.02);
}

TEST(TextureFilter, CheckerboardIsFilteredByItsClosedFormTriangleIntegral) {
    UvMapping m;  // s = u, t = v
    SurfaceHit h;
    h.uv = Point2(0.5f, 0.5f);  // the middle of the even square [0,1)^2: tex1
    EXPECT_EQ(checkerboard_weight(m, h), 0);
    h.uv = Point2(1.5f, 0.5f);
    EXPECT_EQ(checkerboard_weight(m, h), 1);
    // pbrt-v4 filters with a triangle of half-width r = 1.5 |ds/dx|. With r = 1 at s = 0.5
    // the triangle (1 - |x|) covers +1 on [0, 1) (integral 0.75) and -1 on the two outer
    // quarters (0.125 each): the filtered checker in s is 0.5; in t (no footprint) +1.
    // Weight of tex2 = 1/2 - q_s q_t / 2 = 0.25.
    h.uv = Point2(0.5f, 0.5f);
    h.dudx = 1 / 1.5f;
    EXPECT_NEAR(checkerboard_weight(m, h), 0.25, 1e-6);
    // A footprint of many squares in both directions averages to 1/2.
    h.dudx = 40;
    h.dvdy = 33;
    EXPECT_NEAR(checkerboard_weight(m, h), 0.5, 1e-3);
}

TEST(NoiseFootprint, OctavesFinerThanTheFootprintAreLeftOut) {
    const Point3 p(0.37f, 1.21f, 2.53f);
    const Vec3 zero(0, 0, 0);
    // pbrt-v4: n = clamp(-1 - log2(|dp|^2) / 2, 0, octaves). |dp| = 1: n = 0, nothing.
    EXPECT_EQ(fbm(p, Vec3(1, 0, 0), zero, 0.5f, 8), 0);
    // |dp|^2 = 2^-4: n = 1 exactly, the first octave alone.
    EXPECT_NEAR(fbm(p, Vec3(0.25f, 0, 0), zero, 0.5f, 8), perlin_noise(p), 1e-6);
    // A zero footprint keeps all octaves (the unfiltered sum).
    Float sum = 0, o = 1, f = 1;
    for (int i = 0; i < 5; ++i, o *= 0.5f, f *= 1.99f) sum += o * perlin_noise(p * f);
    EXPECT_NEAR(fbm(p, zero, zero, 0.5f, 5), sum, 1e-6);
    // Turbulence with every octave left out is the 0.2-per-octave mean: sum 0.2 omega^i
    // (pbrt-v4 counts the first one twice: the faded partial octave and the loop's).
    EXPECT_NEAR(turbulence(p, Vec3(1, 0, 0), zero, 0.5f, 3), 0.2 + 0.2 + 0.1 + 0.05, 1e-6);
}

}  // namespace
}  // namespace sr
