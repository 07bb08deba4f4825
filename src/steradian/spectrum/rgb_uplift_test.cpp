#include <fmt/format.h>
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "steradian/core/error.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {
namespace {

/// Linear sRGB of a reflectance viewed under the sRGB white (D65).
Rgb reflectance_rgb(const Spectrum& s) {
    return xyz_to_linear_srgb(reflectance_to_xyz(s, Spectrum(srgb_illuminant())));
}

void expect_rgb_near(Rgb a, Rgb b, double tol, const std::string& what) {
    EXPECT_NEAR(a.r, b.r, tol) << what;
    EXPECT_NEAR(a.g, b.g, tol) << what;
    EXPECT_NEAR(a.b, b.b, tol) << what;
}

// fmt rather than std::string concatenation: GCC 12 at -O3 reports a false -Wrestrict in
// char_traits for the latter (GCC bug 105329).
std::string str(Rgb c) { return fmt::format("({}, {}, {})", c.r, c.g, c.b); }

TEST(RgbUplift, ReflectanceRoundTrip) {
    std::vector<Rgb> colours = {
        {0.78f, 0.78f, 0.78f}, {0.8f, 0.2f, 0.1f},    {0.05f, 0.9f, 0.3f},   {0.01f, 0.01f, 0.9f},
        {0.5f, 0.5f, 0.5f},    {0.18f, 0.18f, 0.18f}, {0.9f, 0.9f, 0.1f},    {0.1f, 0.6f, 0.9f},
        {0.3f, 0.1f, 0.6f},    {0.95f, 0.5f, 0.6f},   {0.02f, 0.03f, 0.02f}, {0.99f, 0.98f, 0.97f},
    };
    // A coarse grid over the cube as well.
    for (Float r : {0.03f, 0.35f, 0.7f, 0.97f})
        for (Float g : {0.03f, 0.35f, 0.7f, 0.97f})
            for (Float b : {0.03f, 0.35f, 0.7f, 0.97f}) colours.push_back({r, g, b});
    for (Rgb c : colours) {
        RgbAlbedoSpectrum s = rgb_albedo_spectrum(c);
        expect_rgb_near(reflectance_rgb(Spectrum(s)), c, 1e-3, str(c));
    }
}

TEST(RgbUplift, ReflectanceStaysInUnitInterval) {
    for (Rgb c : {Rgb{0.8f, 0.2f, 0.1f}, Rgb{0.05f, 0.9f, 0.3f}, Rgb{0.01f, 0.01f, 0.9f},
                  Rgb{1, 0, 0}, Rgb{0, 1, 0}, Rgb{0, 0, 1}, Rgb{1, 1, 0}, Rgb{0, 1, 1}}) {
        RgbAlbedoSpectrum s = rgb_albedo_spectrum(c);
        for (Float l = kLambdaMin; l <= kLambdaMax; l += 0.5f) {
            Float v = s(l);
            ASSERT_GE(v, 0) << str(c);
            ASSERT_LE(v, 1) << str(c);
        }
        EXPECT_LE(s.max_value(), 1);
    }
}

TEST(RgbUplift, ExtremeColoursRoundTrip) {
    // The primaries and secondaries lie on the edge of the cube; the sigmoid space still
    // reaches them (with large coefficients).
    for (Rgb c : {Rgb{1, 0, 0}, Rgb{0, 1, 0}, Rgb{0, 0, 1}, Rgb{1, 1, 0}, Rgb{0, 1, 1},
                  Rgb{1, 0, 1}, Rgb{1, 0.5f, 0}, Rgb{0.999f, 0.001f, 0.001f}}) {
        Rgb back = reflectance_rgb(Spectrum(rgb_albedo_spectrum(c)));
        expect_rgb_near(back, c, 1e-3, str(c));
    }
}

TEST(RgbUplift, GreyIsConstantExactly) {
    for (Float v : {0.0f, 0.18f, 0.5f, 0.78f, 1.0f}) {
        RgbAlbedoSpectrum s = rgb_albedo_spectrum({v, v, v});
        EXPECT_EQ(s.c0, 0);
        EXPECT_EQ(s.c1, 0);
        for (Float l : {360.0f, 555.0f, 830.0f}) EXPECT_NEAR(s(l), v, 1e-6f) << v;
    }
    EXPECT_EQ(rgb_albedo_spectrum({1, 1, 1}).c2, kInfinity);
    EXPECT_EQ(rgb_albedo_spectrum({0, 0, 0}).c2, -kInfinity);
    EXPECT_EQ(rgb_albedo_spectrum({1, 1, 1})(500), 1);
    EXPECT_EQ(rgb_albedo_spectrum({0, 0, 0})(500), 0);
}

TEST(RgbUplift, RejectsOutOfRange) {
    EXPECT_THROW(rgb_albedo_spectrum({1.1f, 0.5f, 0.5f}), Error);
    EXPECT_THROW(rgb_albedo_spectrum({-0.1f, 0.5f, 0.5f}), Error);
    EXPECT_THROW(rgb_albedo_spectrum({kInfinity, 0.5f, 0.5f}), Error);
    EXPECT_THROW(rgb_unbounded_spectrum({-1, 0, 0}), Error);
    EXPECT_THROW(rgb_illuminant_spectrum({std::nanf(""), 0, 0}), Error);
}

TEST(RgbUplift, UnboundedScalesByTwiceTheMaximum) {
    Rgb c{3.0f, 1.5f, 0.6f};
    RgbUnboundedSpectrum s = rgb_unbounded_spectrum(c);
    EXPECT_FLOAT_EQ(s.scale, 6.0f);
    expect_rgb_near(reflectance_rgb(Spectrum(s)), c, 3e-3, str(c));
    RgbUnboundedSpectrum zero = rgb_unbounded_spectrum({0, 0, 0});
    EXPECT_EQ(zero.scale, 0);
    EXPECT_EQ(zero(500), 0);
    EXPECT_EQ(zero.max_value(), 0);
    // Grey: half of the scale everywhere.
    RgbUnboundedSpectrum g = rgb_unbounded_spectrum({2, 2, 2});
    EXPECT_NEAR(g(400), 2, 1e-5);
    EXPECT_NEAR(g(700), 2, 1e-5);
}

TEST(RgbUplift, IlluminantEmitsTheRequestedColour) {
    for (Rgb c : {Rgb{1, 1, 1}, Rgb{10, 4, 1}, Rgb{0.2f, 0.5f, 0.9f}}) {
        RgbIlluminantSpectrum s = rgb_illuminant_spectrum(c);
        Rgb emitted = xyz_to_linear_srgb(spectrum_to_xyz(Spectrum(s)));
        Float m = std::max({c.r, c.g, c.b});
        expect_rgb_near(emitted, c, 2e-3 * m, str(c));
    }
    // White light is the illuminant itself, with Y = 1.
    RgbIlluminantSpectrum w = rgb_illuminant_spectrum({1, 1, 1});
    EXPECT_NEAR(spectrum_to_xyz(Spectrum(w)).y, 1.0, 1e-4);
    EXPECT_EQ(w.illuminant.values, srgb_illuminant().values);
}

TEST(RgbUplift, CachedAndThreadSafe) {
    Rgb c{0.42f, 0.17f, 0.66f};
    RgbAlbedoSpectrum first = rgb_albedo_spectrum(c);
    std::vector<std::thread> threads;
    std::vector<RgbAlbedoSpectrum> results(8);
    for (int i = 0; i < 8; ++i)
        threads.emplace_back([&results, i] {
            results[i] = rgb_albedo_spectrum({0.1f + 0.1f * Float(i % 4), 0.3f, 0.5f});
        });
    for (std::thread& t : threads) t.join();
    for (int i = 0; i < 8; ++i) {
        RgbAlbedoSpectrum again = rgb_albedo_spectrum({0.1f + 0.1f * Float(i % 4), 0.3f, 0.5f});
        EXPECT_EQ(results[i].c0, again.c0);
        EXPECT_EQ(results[i].c1, again.c1);
        EXPECT_EQ(results[i].c2, again.c2);
    }
    RgbAlbedoSpectrum second = rgb_albedo_spectrum(c);
    EXPECT_EQ(first.c0, second.c0);
    EXPECT_EQ(first.c1, second.c1);
    EXPECT_EQ(first.c2, second.c2);
}

TEST(RgbUpliftInterpolated, RoundTripCloseToTarget) {
    build_rgb_uplift_table();
    double sum = 0, worst = 0;
    int n = 0;
    for (Float r = 0.02f; r <= 1; r += 0.07f)
        for (Float g = 0.01f; g <= 1; g += 0.09f)
            for (Float b = 0.03f; b <= 1; b += 0.08f) {
                Rgb c{r, g, b};
                RgbAlbedoSpectrum s = rgb_albedo_spectrum_interpolated(c);
                Rgb back = reflectance_rgb(Spectrum(s));
                double e = std::max(
                    {std::abs(back.r - c.r), std::abs(back.g - c.g), std::abs(back.b - c.b)});
                sum += e;
                worst = std::max(worst, e);
                ++n;
                ASSERT_LE(s.max_value(), 1) << str(c);
            }
    EXPECT_LT(sum / n, 1e-3);
    EXPECT_LT(worst, 5e-3);
}

TEST(RgbUpliftInterpolated, AgreesWithExactPath) {
    for (Rgb c : {Rgb{0.8f, 0.2f, 0.1f}, Rgb{0.05f, 0.9f, 0.3f}, Rgb{0.01f, 0.01f, 0.9f}}) {
        RgbAlbedoSpectrum exact = rgb_albedo_spectrum(c);
        RgbAlbedoSpectrum table = rgb_albedo_spectrum_interpolated(c);
        for (Float l = 380; l <= 780; l += 20) EXPECT_NEAR(table(l), exact(l), 0.02) << str(c);
    }
}

TEST(RgbUpliftInterpolated, GreyClampAndNaN) {
    RgbAlbedoSpectrum g = rgb_albedo_spectrum_interpolated({0.3f, 0.3f, 0.3f});
    EXPECT_EQ(g.c0, 0);
    EXPECT_EQ(g.c1, 0);
    EXPECT_NEAR(g(600), 0.3f, 1e-6f);
    EXPECT_EQ(rgb_albedo_spectrum_interpolated({1.2f, 1.5f, 1.1f})(500), 1);  // clamped to white
    EXPECT_EQ(rgb_albedo_spectrum_interpolated({-0.1f, -1, 0})(500), 0);      // clamped to black
    EXPECT_EQ(rgb_albedo_spectrum_interpolated({std::nanf(""), 0.5f, 0.5f})(500), 0);
    EXPECT_EQ(rgb_unbounded_spectrum_interpolated({std::nanf(""), 0.5f, 0.5f})(500), 0);
    RgbUnboundedSpectrum u = rgb_unbounded_spectrum_interpolated({4, 2, 1});
    EXPECT_FLOAT_EQ(u.scale, 8);
    expect_rgb_near(reflectance_rgb(Spectrum(u)), {4, 2, 1}, 2e-2, "unbounded (4, 2, 1)");
    RgbIlluminantSpectrum e = rgb_illuminant_spectrum_interpolated({1, 1, 1});
    EXPECT_NEAR(spectrum_to_xyz(Spectrum(e)).y, 1.0, 1e-4);
}

}  // namespace
}  // namespace sr
