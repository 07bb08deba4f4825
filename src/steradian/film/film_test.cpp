#include "steradian/film/film.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "steradian/spectrum/color.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {
namespace {

using Matrix3 = std::array<std::array<Float, 3>, 3>;

Matrix3 identity3() {
    Matrix3 m{};
    for (int i = 0; i < 3; ++i) m[i][i] = 1;
    return m;
}

FilmParams small_params(int w, int h) {
    FilmParams p;
    p.resolution = {w, h};
    p.x0 = 0;
    p.x1 = w;
    p.y0 = 0;
    p.y1 = h;
    p.rgb_from_sensor = identity3();
    return p;
}

/// Integral of a CIE matching function (piecewise linear through the 1 nm table) over
/// [360, 830] nm by the trapezoid rule at 1 nm, which is exact for a piecewise-linear function.
double cmf_integral(const DenselySampledSpectrum& cmf) {
    double s = 0;
    for (int l = 360; l <= 830; ++l) s += (l == 360 || l == 830 ? 0.5 : 1.0) * cmf(Float(l));
    return s;
}

/// Mean of to_sensor over n stratified wavelength samples (stratum midpoints): a midpoint
/// rule for the wavelength integral.
std::array<double, 3> mean_sensor(const Film& film, const Spectrum& s, int n, bool visible,
                                  bool terminate = false) {
    std::array<double, 3> sum{0, 0, 0};
    for (int k = 0; k < n; ++k) {
        Float u = (Float(k) + 0.5f) / Float(n);
        SampledWavelengths lambda =
            visible ? SampledWavelengths::sample_visible(u) : SampledWavelengths::sample_uniform(u);
        if (terminate) lambda.terminate_secondary();
        auto xyz = film.to_sensor(s.sample(lambda), lambda);
        for (int c = 0; c < 3; ++c) sum[c] += xyz[c];
    }
    for (auto& v : sum) v /= n;
    return sum;
}

TEST(Film, CmfIntegralsAreThoseOfTheCie1931Tables) {
    // The 1 nm sum of ybar is pbrt-v4's CIE_Y_integral. The equal-energy stimulus E has
    // chromaticity (1/3, 1/3) by the construction of the CIE 1931 system, so the xbar and zbar
    // integrals equal ybar's to the tables' rounding (well under 0.1%).
    double x = cmf_integral(cie_x()), y = cmf_integral(cie_y()), z = cmf_integral(cie_z());
    EXPECT_NEAR(y, kCieYIntegral, 1e-3);
    EXPECT_NEAR(x / y, 1, 1e-3);
    EXPECT_NEAR(z / y, 1, 1e-3);
}

TEST(Film, ToSensorOfUnitRadianceConvergesToTheCmfIntegrals) {
    Film film(small_params(1, 1));
    const double ix = cmf_integral(cie_x()), iz = cmf_integral(cie_z());
    const double iy = kCieYIntegral;
    // Uniform wavelengths: the estimator is 470 nm times the average of the CMF, and the
    // stratified mean is a midpoint rule with 4 * 8192 nodes.
    auto u = mean_sensor(film, ConstantSpectrum{1}, 8192, false);
    EXPECT_NEAR(u[0] / ix, 1, 1e-4);
    EXPECT_NEAR(u[1] / iy, 1, 1e-4);
    EXPECT_NEAR(u[2] / iz, 1, 1e-4);
    // Importance-sampled visible wavelengths: the same integral (cmf / pdf is smooth).
    auto v = mean_sensor(film, ConstantSpectrum{1}, 8192, true);
    EXPECT_NEAR(v[0] / ix, 1, 2e-4);
    EXPECT_NEAR(v[1] / iy, 1, 2e-4);
    EXPECT_NEAR(v[2] / iz, 1, 2e-4);
    // After a dispersive event only the hero wavelength remains, its pdf divided by N: still
    // an unbiased estimate of the same integral.
    auto t = mean_sensor(film, ConstantSpectrum{1}, 8192, false, true);
    EXPECT_NEAR(t[0] / ix, 1, 2e-4);
    EXPECT_NEAR(t[1] / iy, 1, 2e-4);
    EXPECT_NEAR(t[2] / iz, 1, 2e-4);
}

TEST(Film, ToSensorScalesWithImagingRatioAndRadiance) {
    FilmParams p = small_params(1, 1);
    Film film1(p);
    p.imaging_ratio = 2.5f;
    Film film2(p);
    SampledWavelengths lambda = SampledWavelengths::sample_uniform(0.3f);
    auto a = film1.to_sensor(SampledSpectrum(1), lambda);
    auto b = film2.to_sensor(SampledSpectrum(3), lambda);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(b[c], 7.5 * a[c], 1e-6 * std::abs(b[c]));
}

TEST(Film, MaxComponentClampsAndKeepsChromaticity) {
    FilmParams p = small_params(1, 1);
    Film free_film(p);
    SampledWavelengths lambda = SampledWavelengths::sample_uniform(0.37f);
    SampledSpectrum L;
    L[0] = 5;
    L[1] = 1;
    L[2] = 0.5f;
    L[3] = 2;
    auto r = free_film.to_sensor(L, lambda);
    double m = std::max({r[0], r[1], r[2]});
    ASSERT_GT(m, 0);
    p.max_component = Float(0.25 * m);
    Film clamped_film(p);
    auto c = clamped_film.to_sensor(L, lambda);
    EXPECT_NEAR(std::max({c[0], c[1], c[2]}), 0.25 * m, 1e-6 * m);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(c[i], 0.25 * r[i], 1e-6 * m);  // same direction
    // Below the limit nothing changes.
    p.max_component = Float(2 * m);
    Film loose_film(p);
    auto d = loose_film.to_sensor(L, lambda);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(d[i], r[i]);
}

TEST(Film, PixelValueIsTheWeightedMeanOverAllPasses) {
    // A 4 x 3 image with the crop window [1, 3) x [1, 3): pixel (2, 1) is crop pixel (1, 0).
    FilmParams p = small_params(4, 3);
    p.x0 = 1;
    p.x1 = 3;
    p.y0 = 1;
    p.y1 = 3;
    Film film(p);
    auto pass1 = film.make_buffer();
    ASSERT_EQ(pass1.size(), 4u);
    film.add(pass1, 2, 1, {1, 2, 3}, 0.5);
    film.add(pass1, 2, 1, {4, 0, -1}, 2.0);
    auto pass2 = film.make_buffer();
    film.add(pass2, 2, 1, {2, 2, 2}, 1.5);
    film.add(pass2, 1, 2, {7, 8, 9}, 0.25);  // crop pixel (0, 1)
    film.merge(pass1);
    film.merge(pass2);
    // sum(w xyz) / sum(w) with sum(w) = 4: x = (0.5 + 8 + 3) / 4, y = (1 + 0 + 3) / 4,
    // z = (1.5 - 2 + 3) / 4.
    Image img = film.rgb_image();
    ASSERT_EQ(img.width, 2);
    ASSERT_EQ(img.height, 2);
    ASSERT_EQ(img.channels, 3);
    EXPECT_NEAR(img.at(1, 0, 0), 11.5 / 4, 1e-6);
    EXPECT_NEAR(img.at(1, 0, 1), 1.0, 1e-6);
    EXPECT_NEAR(img.at(1, 0, 2), 2.5 / 4, 1e-6);
    // A single sample's value is independent of its weight.
    EXPECT_NEAR(img.at(0, 1, 0), 7, 1e-6);
    EXPECT_NEAR(img.at(0, 1, 2), 9, 1e-6);
    // Pixels without samples are black.
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(img.at(0, 0, c), 0);
        EXPECT_EQ(img.at(1, 1, c), 0);
    }
    auto y = film.luminance();
    ASSERT_EQ(y.size(), 4u);
    EXPECT_NEAR(y[1], 1.0, 1e-12);
    EXPECT_NEAR(y[2], 8, 1e-12);
    EXPECT_EQ(y[0], 0);
}

TEST(Film, SrgbMatrixIsTheInverseOfTheSrgbPrimaries) {
    // IEC 61966-2-1: XYZ -> linear sRGB is the inverse of the primaries' matrix (color.h).
    auto m = srgb_from_xyz_matrix();
    for (int j = 0; j < 3; ++j) {
        Rgb e{j == 0 ? 1.f : 0.f, j == 1 ? 1.f : 0.f, j == 2 ? 1.f : 0.f};
        Xyz xyz = linear_srgb_to_xyz(e);
        for (int i = 0; i < 3; ++i) {
            double v = m[i][0] * xyz.x + m[i][1] * xyz.y + m[i][2] * xyz.z;
            EXPECT_NEAR(v, i == j ? 1 : 0, 2e-6) << i << j;
        }
    }
}

TEST(Film, D65MapsToSrgbWhite) {
    Xyz d65 = spectrum_to_xyz(Spectrum(srgb_illuminant()));
    EXPECT_NEAR(d65.y, 1, 1e-5);
    // Chromaticity of D65 with the CIE 1931 observer: (0.3127, 0.3290).
    double sum = double(d65.x) + d65.y + d65.z;
    EXPECT_NEAR(d65.x / sum, 0.3127, 2e-4);
    EXPECT_NEAR(d65.y / sum, 0.3290, 2e-4);

    FilmParams p = small_params(1, 1);
    p.rgb_from_sensor = srgb_from_xyz_matrix();
    Film film(p);
    auto buf = film.make_buffer();
    film.add(buf, 0, 0, {d65.x, d65.y, d65.z}, 1);
    film.merge(buf);
    Image img = film.rgb_image();
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(img.at(0, 0, c), 1, 2e-3) << "channel " << c;

    // End to end: the film's own spectral estimate of the D65 illuminant, normalised by the
    // Y integral, gives the same white.
    Film film2(p);
    auto s = mean_sensor(film2, Spectrum(srgb_illuminant()), 4096, true);
    auto buf2 = film2.make_buffer();
    film2.add(buf2, 0, 0, {s[0] / kCieYIntegral, s[1] / kCieYIntegral, s[2] / kCieYIntegral}, 1);
    film2.merge(buf2);
    Image img2 = film2.rgb_image();
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(img2.at(0, 0, c), 1, 3e-3) << "channel " << c;
}

TEST(Film, WhiteBalanceAtD65IsTheIdentity) {
    auto a = srgb_from_xyz_white_balanced(0.3127f, 0.3290f);
    auto b = srgb_from_xyz_matrix();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(a[i][j], b[i][j], 1e-4) << i << j;
}

TEST(Film, WhiteBalanceMapsTheSourceWhiteToSrgbWhite) {
    // Von Kries adaptation (Bradford cone space) maps the source white (Y = 1) to D65, which
    // the sRGB matrix maps to (1, 1, 1). CIE chromaticities: D50 (0.3457, 0.3585),
    // A (0.44757, 0.40745), F2 (0.37208, 0.37529), D75 (0.29902, 0.31485).
    const double whites[][2] = {{0.3457, 0.3585}, {0.44757, 0.40745}, {0.37208, 0.37529},
                                {0.29902, 0.31485}};
    for (const auto& w : whites) {
        auto m = srgb_from_xyz_white_balanced(Float(w[0]), Float(w[1]));
        double xyz[3] = {w[0] / w[1], 1, (1 - w[0] - w[1]) / w[1]};
        for (int i = 0; i < 3; ++i) {
            double v = m[i][0] * xyz[0] + m[i][1] * xyz[1] + m[i][2] * xyz[2];
            EXPECT_NEAR(v, 1, 1e-3) << "white (" << w[0] << ", " << w[1] << ") channel " << i;
        }
        // Luminance is preserved by Bradford adaptation of the white (Y stays 1): checked
        // through sRGB's luminance row, Y = 0.2126 R + 0.7152 G + 0.0722 B.
        double y = 0;
        const double lum[3] = {0.2126729, 0.7151522, 0.0721750};
        for (int i = 0; i < 3; ++i)
            y += lum[i] * (m[i][0] * xyz[0] + m[i][1] * xyz[1] + m[i][2] * xyz[2]);
        EXPECT_NEAR(y, 1, 1e-3);
    }
}

}  // namespace
}  // namespace sr
