#include "steradian/spectrum/spectrum.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "steradian/core/error.h"

namespace sr {
namespace {

Vec2d chromaticity(Xyz c) {
    double s = double(c.x) + double(c.y) + double(c.z);
    return {c.x / s, c.y / s};
}

// ---- CIE colour matching functions ----------------------------------------------------------

TEST(CieCmf, YIntegralMatchesConstant) {
    double sum = 0;
    for (int l = 360; l <= 830; ++l) sum += cie_y()(Float(l));
    EXPECT_NEAR(sum / kCieYIntegral, 1.0, 1e-4);
}

TEST(CieCmf, YPeaksAtOneAt555nm) {
    EXPECT_NEAR(cie_y()(555), 1.0, 1e-3);
    for (int l = 360; l <= 830; ++l) EXPECT_LE(cie_y()(Float(l)), 1.0f + 1e-6f) << l;
}

TEST(CieCmf, XAndZIntegralsCloseToY) {
    // The 1931 functions are scaled to equal areas (equal-energy white is x = y = 1/3).
    double sx = 0, sz = 0;
    for (int l = 360; l <= 830; ++l) {
        sx += cie_x()(Float(l));
        sz += cie_z()(Float(l));
    }
    EXPECT_NEAR(sx / kCieYIntegral, 1.0, 1e-3);
    EXPECT_NEAR(sz / kCieYIntegral, 1.0, 1e-3);
}

TEST(CieCmf, EqualEnergyWhiteIsAchromatic) {
    Vec2d xy = chromaticity(spectrum_to_xyz(Spectrum(ConstantSpectrum{1})));
    EXPECT_NEAR(xy.x, 1.0 / 3, 1e-3);
    EXPECT_NEAR(xy.y, 1.0 / 3, 1e-3);
}

TEST(CieCmf, NonNegativeAndZeroOutsideRange) {
    for (Float l = 360; l <= 830; l += 0.37f) {
        EXPECT_GE(cie_x()(l), 0);
        EXPECT_GE(cie_y()(l), 0);
        EXPECT_GE(cie_z()(l), 0);
    }
    EXPECT_EQ(cie_y()(359.5f), 0);
    EXPECT_EQ(cie_y()(830.5f), 0);
}

// ---- CIE 1951 scotopic luminous efficiency function and luminous efficacies ---------------

TEST(CieScotopic, PeaksAtOneAt507nm) {
    // CIE 1951: V'(lambda) is normalised to 1 at its maximum, 507 nm.
    const DenselySampledSpectrum& v = cie_scotopic_v();
    EXPECT_NEAR(v(507), 1.0, 1e-6);
    EXPECT_NEAR(v.max_value(), 1.0, 1e-6);
    for (int l = 360; l <= 830; ++l) EXPECT_LE(v(Float(l)), 1.0f) << l;
}

TEST(CieScotopic, MatchesCie1951Table) {
    // The CIE 1951 table at 5 nm (Wyszecki & Stiles, "Color Science", 2nd ed., Table
    // I(4.3.2); ISO 23539:2005 / CIE S 010:2004).
    struct Case {
        Float nm;
        double v;
    };
    const Case cases[] = {
        {380, 0.000589}, {400, 0.00929}, {420, 0.0966},   {450, 0.455},   {480, 0.793},
        {500, 0.982},    {505, 0.998},   {510, 0.997},    {530, 0.811},   {555, 0.402},
        {560, 0.3288},   {600, 0.03315}, {650, 0.000677}, {700, 1.78e-5}, {780, 1.39e-7},
    };
    for (const Case& c : cases) EXPECT_NEAR(cie_scotopic_v()(c.nm), c.v, 1e-6 * c.v) << c.nm;
    // Monochromatic light at 555 nm: V'(555) = 0.402, i.e. 40% of the scotopic peak.
    EXPECT_NEAR(cie_scotopic_v()(555), 0.402, 1e-6);
}

TEST(CieScotopic, ZeroOutsideTable) {
    const DenselySampledSpectrum& v = cie_scotopic_v();
    for (Float l : {350.0f, 360.0f, 370.0f, 379.0f, 781.0f, 800.0f, 830.0f, 900.0f})
        EXPECT_EQ(v(l), 0) << l;
    EXPECT_GT(v(380), 0);
    EXPECT_GT(v(780), 0);
}

TEST(CieScotopic, MaximumLuminousEfficaciesFollowFromTheCandela) {
    // SI: K_cd = 683 lm/W at 540e12 Hz, 555.016 nm in standard air (CIE 018:2019). Hence
    // K_m = 683 / V(555.016 nm) = 683.002 lm/W and K'_m = 683 / V'(555.016 nm) = 1700 lm/W.
    EXPECT_EQ(kKmPhotopic, 683.0);
    EXPECT_EQ(kKmScotopic, 1700.0);
    EXPECT_NEAR(kKmPhotopic / cie_y()(555.016f), 683.002, 1e-3);
    EXPECT_NEAR(683.0 / cie_scotopic_v()(555), kKmScotopic, 1e-3 * kKmScotopic);
    EXPECT_NEAR(683.0 / cie_scotopic_v()(555.016f), kKmScotopic, 1e-4 * kKmScotopic);
}

// ---- spectrum types and dispatch --------------------------------------------------------------

TEST(Spectrum, DefaultIsZero) {
    Spectrum s;
    EXPECT_EQ(s(500), 0);
    EXPECT_EQ(s.max_value(), 0);
}

TEST(Spectrum, DenselySampledInterpolatesLinearly) {
    auto v = std::make_shared<std::vector<Float>>(471);
    for (int i = 0; i < 471; ++i) (*v)[i] = Float(i % 2);
    DenselySampledSpectrum d{v};
    EXPECT_FLOAT_EQ(d(360), 0);
    EXPECT_FLOAT_EQ(d(361), 1);
    EXPECT_FLOAT_EQ(d(360.25f), 0.25f);
    EXPECT_FLOAT_EQ(d(830), 0);
    EXPECT_FLOAT_EQ(d(829.5f), 0.5f);
    EXPECT_EQ(d(359.9f), 0);
    EXPECT_EQ(d(830.1f), 0);
    EXPECT_EQ(d.max_value(), 1);
    EXPECT_EQ(DenselySampledSpectrum{}(500), 0);
}

TEST(Spectrum, PiecewiseLinear) {
    PiecewiseLinearSpectrum p = piecewise_linear_from_interleaved({400, 1, 500, 3, 600, 2}, false);
    EXPECT_FLOAT_EQ(p(400), 1);
    EXPECT_FLOAT_EQ(p(450), 2);
    EXPECT_FLOAT_EQ(p(500), 3);
    EXPECT_FLOAT_EQ(p(575), 2.25f);
    EXPECT_FLOAT_EQ(p(600), 2);
    EXPECT_EQ(p(399), 0);
    EXPECT_EQ(p(601), 0);
    EXPECT_EQ(p.max_value(), 3);
}

TEST(Spectrum, PiecewiseLinearRejectsBadInput) {
    EXPECT_THROW(piecewise_linear_from_interleaved({400, 1, 500}, false), Error);
    EXPECT_THROW(piecewise_linear_from_interleaved({}, false), Error);
    EXPECT_THROW(piecewise_linear_from_interleaved({500, 1, 400, 2}, false), Error);
    EXPECT_THROW(piecewise_linear_from_interleaved({400, 1, 400, 2}, false), Error);
}

TEST(Spectrum, PiecewiseLinearNormalizeGivesUnitY) {
    PiecewiseLinearSpectrum p =
        piecewise_linear_from_interleaved({300, 5, 500, 20, 700, 10, 900, 3}, true);
    EXPECT_NEAR(spectrum_to_xyz(Spectrum(p)).y, 1.0, 1e-5);
}

TEST(Spectrum, SampleMatchesPointEvaluationForEveryAlternative) {
    std::vector<Spectrum> all = {
        Spectrum(ConstantSpectrum{0.3f}),
        Spectrum(cie_y()),
        Spectrum(piecewise_linear_from_interleaved({350, 1, 600, 4, 850, 2}, false)),
        Spectrum(BlackbodySpectrum(4000)),
        Spectrum(RgbAlbedoSpectrum{1e-4f, -0.1f, 20}),
        Spectrum(RgbUnboundedSpectrum{2, -1e-4f, 0.1f, -25}),
        Spectrum(RgbIlluminantSpectrum{1.5f, 0, 0, 0.5f, cie_x()}),
    };
    for (Float u : {0.0f, 0.13f, 0.5f, 0.77f, 0.999f}) {
        SampledWavelengths w = SampledWavelengths::sample_visible(u);
        for (const Spectrum& s : all) {
            SampledSpectrum v = s.sample(w);
            for (int i = 0; i < kSpectrumSamples; ++i) EXPECT_EQ(v[i], s(w[i]));
        }
    }
}

TEST(Spectrum, DenseSampleMatchesPointEvaluationAtTheEndsAndOutside) {
    // The four-wavelength table lookup: the table's ends, just outside them, far outside and
    // NaN (0 outside the table, as the point evaluation).
    Spectrum y(cie_y());
    ASSERT_NE(y.get_if<DenselySampledSpectrum>(), nullptr);
    const Float nan = std::numeric_limits<Float>::quiet_NaN();
    for (std::array<Float, 4> l : {std::array<Float, 4>{kLambdaMin, kLambdaMax, 555.5f, 829.99f},
                                   std::array<Float, 4>{359.99f, 830.01f, 100, 2000},
                                   std::array<Float, 4>{nan, 360.5f, -1e30f, 1e30f}}) {
        SampledWavelengths w;
        w.lambda = l;
        SampledSpectrum v = y.sample(w);
        for (int i = 0; i < kSpectrumSamples; ++i) EXPECT_FLOAT_EQ(v[i], y(l[i])) << l[i];
    }
    EXPECT_GT(y.sample(SampledWavelengths::sample_visible(0.5f)).max_value(), 0);
}

TEST(Spectrum, MaxValueBoundsEveryAlternative) {
    std::vector<Spectrum> all = {
        Spectrum(cie_z()),
        Spectrum(BlackbodySpectrum(5000)),                // peak at 580 nm: the bound is tight
        Spectrum(RgbAlbedoSpectrum{-2e-4f, 0.23f, -64}),  // peak inside the range
        Spectrum(RgbUnboundedSpectrum{3, 1e-4f, -0.1f, 20}),
        Spectrum(RgbIlluminantSpectrum{1.5f, 0, 0, 0.5f, cie_y()}),
    };
    for (const Spectrum& s : all) {
        Float m = s.max_value(), seen = 0;
        for (Float l = kLambdaMin; l <= kLambdaMax; l += 0.5f) seen = std::max(seen, s(l));
        EXPECT_GE(m * (1 + 1e-5f), seen);
        EXPECT_NEAR(m, seen, 1e-3f * m);
    }
    // A 2700 K peak lies beyond 830 nm: 1 is then an upper bound, not the maximum.
    BlackbodySpectrum warm(2700);
    for (Float l = kLambdaMin; l <= kLambdaMax; l += 0.5f) EXPECT_LE(warm(l), warm.max_value());
}

TEST(Spectrum, DenselySampledOfPiecewiseAgreesAtIntegerWavelengths) {
    PiecewiseLinearSpectrum p = piecewise_linear_from_interleaved({380, 0, 500, 2, 780, 1}, false);
    DenselySampledSpectrum d = densely_sampled(Spectrum(p));
    for (int l = 360; l <= 830; ++l) EXPECT_FLOAT_EQ(d(Float(l)), p(Float(l)));
    // Re-densifying shares the values.
    EXPECT_EQ(densely_sampled(Spectrum(d)).values, d.values);
}

TEST(Spectrum, InnerProductSumsIntegerWavelengths) {
    EXPECT_NEAR(inner_product(Spectrum(ConstantSpectrum{1}), Spectrum(ConstantSpectrum{2})), 942,
                1e-3);
    EXPECT_NEAR(inner_product(Spectrum(cie_y()), Spectrum(ConstantSpectrum{1})), kCieYIntegral,
                1e-2);
}

TEST(Spectrum, PhotometricUsesIlluminantOfRgbIlluminant) {
    const DenselySampledSpectrum& d65 = srgb_illuminant();
    Float expected = inner_product(Spectrum(d65), Spectrum(cie_y()));
    EXPECT_NEAR(expected, kCieYIntegral, 1e-3 * kCieYIntegral);  // D65 normalised to Y = 1
    RgbIlluminantSpectrum rs{7, 1e-4f, -0.1f, 3, d65};
    EXPECT_FLOAT_EQ(spectrum_to_photometric(Spectrum(rs)), expected);
    EXPECT_NEAR(spectrum_to_photometric(Spectrum(ConstantSpectrum{2})), 2 * kCieYIntegral,
                1e-5 * kCieYIntegral);
}

// ---- blackbody ----------------------------------------------------------------------------------

TEST(Blackbody, PeakFollowsWiensLaw) {
    for (double t : {2000.0, 3000.0, 5778.0, 10000.0}) {
        double expected_nm = kWienDisplacement / t * 1e9;
        double best = 0, best_l = 0;
        for (double l = 0.5 * expected_nm; l <= 1.5 * expected_nm; l += 0.005) {
            double b = planck(l, t);
            if (b > best) best = b, best_l = l;
        }
        EXPECT_NEAR(best_l, expected_nm, 0.01 + 1e-6 * expected_nm) << t;
    }
}

TEST(Blackbody, IntegratesToStefanBoltzmann) {
    // Radiance integrated over wavelength equals sigma T^4 / pi; Simpson's rule in ln(l).
    constexpr double sigma = 5.670374e-8;  // W m^-2 K^-4 (CODATA)
    for (double t : {3000.0, 5778.0}) {
        const double a = std::log(10.0), b = std::log(1e5);  // 10 nm .. 100 um
        const int n = 20000;
        double h = (b - a) / n, sum = 0;
        for (int i = 0; i <= n; ++i) {
            double l_nm = std::exp(a + i * h);
            double f = planck(l_nm, t) * l_nm * 1e-9;  // B dl = B l d(ln l), l in m
            sum += f * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
        }
        double integral = sum * h / 3;
        EXPECT_NEAR(integral / (sigma * t * t * t * t / std::numbers::pi), 1.0, 1e-4) << t;
    }
}

TEST(Blackbody, NormalizedToUnitPeak) {
    for (Float t : {1500.0f, 2856.0f, 6500.0f, 12000.0f}) {
        BlackbodySpectrum bb(t);
        Float peak_nm = Float(kWienDisplacement / t * 1e9);
        EXPECT_NEAR(bb(peak_nm), 1.0f, 1e-5f);
        for (Float l = 200; l <= 3000; l += 1) EXPECT_LE(bb(l), 1.0f + 1e-5f);
        EXPECT_EQ(bb.max_value(), 1);
    }
    EXPECT_EQ(BlackbodySpectrum(0)(500), 0);
    EXPECT_EQ(planck(500, -1), 0);
}

TEST(Blackbody, KnownRadianceValue) {
    // Planck's law evaluated by hand at 500 nm, 5778 K: 2hc^2 / l^5 = 3.8113e15 W m^-3 sr^-1,
    // hc / (l kb T) = 4.98019, so B = 3.8113e15 / (e^4.98019 - 1) = 2.6376e13.
    EXPECT_NEAR(planck(500, 5778) / 2.6376e13, 1.0, 1e-4);
}

// ---- colorimetry of the standard illuminants ----------------------------------------------------

TEST(Illuminants, D65IsTheSrgbWhite) {
    const DenselySampledSpectrum& d65 = srgb_illuminant();
    Xyz xyz = spectrum_to_xyz(Spectrum(d65));
    EXPECT_NEAR(xyz.y, 1.0, 1e-5);
    Rgb rgb = xyz_to_linear_srgb(xyz);
    EXPECT_NEAR(rgb.r, 1.0, 1e-2);
    EXPECT_NEAR(rgb.g, 1.0, 1e-2);
    EXPECT_NEAR(rgb.b, 1.0, 1e-2);
    // CIE 015: D65 white point x = 0.31272, y = 0.32903 (2 degree observer).
    Vec2d xy = chromaticity(xyz);
    EXPECT_NEAR(xy.x, 0.3127, 2e-3);
    EXPECT_NEAR(xy.y, 0.3290, 2e-3);
    EXPECT_NEAR(xy.x, 0.31272, 2e-4);
    EXPECT_NEAR(xy.y, 0.32903, 2e-4);
}

TEST(Illuminants, ChromaticitiesMatchCie015) {
    struct Case {
        const char* name;
        double x, y, tol;
    };
    // CIE 015 chromaticity coordinates of the CIE illuminants (2 degree observer).
    const Case cases[] = {
        {"stdillum-A", 0.44757, 0.40745, 2e-4},
        {"stdillum-D50", 0.34567, 0.35850, 2e-4},
        {"stdillum-D65", 0.31272, 0.32903, 2e-4},
        {"stdillum-F1", 0.3131, 0.3373, 5e-4},
        {"stdillum-F2", 0.3721, 0.3751, 5e-4},
        {"stdillum-F3", 0.4091, 0.3941, 5e-4},
        {"stdillum-F4", 0.4402, 0.4031, 5e-4},
        {"stdillum-F5", 0.3138, 0.3452, 5e-4},
        {"stdillum-F6", 0.3779, 0.3882, 5e-4},
        {"stdillum-F7", 0.3129, 0.3292, 5e-4},
        {"stdillum-F8", 0.3458, 0.3586, 5e-4},
        {"stdillum-F9", 0.3741, 0.3727, 5e-4},
        {"stdillum-F10", 0.3458, 0.3588, 5e-4},
        {"stdillum-F11", 0.3805, 0.3769, 5e-4},
        {"stdillum-F12", 0.4370, 0.4042, 5e-4},
        // ACES white point (Academy S-2014-004).
        {"illum-acesD60", 0.32168, 0.33767, 1e-4},
    };
    for (const Case& c : cases) {
        std::optional<Spectrum> s = named_spectrum(c.name);
        ASSERT_TRUE(s) << c.name;
        Xyz xyz = spectrum_to_xyz(*s);
        EXPECT_NEAR(xyz.y, 1.0, 1e-4) << c.name;  // normalised like pbrt-v4
        Vec2d xy = chromaticity(xyz);
        EXPECT_NEAR(xy.x, c.x, c.tol) << c.name;
        EXPECT_NEAR(xy.y, c.y, c.tol) << c.name;
    }
}

TEST(Illuminants, DaylightBasisReproducesTabulatedD65) {
    // CIE 015: D65 is daylight at 6500 * 1.4388 / 1.4380 K; with M1, M2 rounded to three
    // decimals the S-basis gives the official table.
    PiecewiseLinearSpectrum d = cie_daylight(Float(6500 * 1.4388 / 1.4380));
    EXPECT_NEAR(d(560), 100, 1e-4);
    EXPECT_NEAR(d(380), 49.9755, 1e-3);
    EXPECT_NEAR(d(400), 82.7549, 1e-3);
    EXPECT_NEAR(d(555), 102.023, 1e-3);
    EXPECT_NEAR(d(700), 71.6091, 1e-3);
    EXPECT_NEAR(d(830), 60.3125, 1e-3);
    EXPECT_THROW(cie_daylight(3000), Error);
}

TEST(Illuminants, PbrtStyleDIlluminant) {
    // Nominal 6500 K is D65 and 5000 K is D50 (CIE 015 white points).
    Vec2d d65 = chromaticity(spectrum_to_xyz(cie_d_illuminant(6500)));
    EXPECT_NEAR(d65.x, 0.31272, 2e-4);
    EXPECT_NEAR(d65.y, 0.32903, 2e-4);
    Vec2d d50 = chromaticity(spectrum_to_xyz(cie_d_illuminant(5000)));
    EXPECT_NEAR(d50.x, 0.34567, 5e-4);
    EXPECT_NEAR(d50.y, 0.35850, 5e-4);
    // Below 4000 K: a Planckian radiator. Illuminant A is Planckian at 2848 K with
    // c2 = 1.435e-2 m K, i.e. at 2848 * 1.4388 / 1.435 K with today's c2 (Planck's constants
    // here give c2 = hc / kb = 1.43878e-2 m K).
    Spectrum a = cie_d_illuminant(Float(2848 * 1.4388 / 1.435 * 1.4380 / 1.4388));
    ASSERT_TRUE(a.get_if<BlackbodySpectrum>());
    Vec2d xa = chromaticity(spectrum_to_xyz(a));
    EXPECT_NEAR(xa.x, 0.44757, 2e-4);
    EXPECT_NEAR(xa.y, 0.40745, 2e-4);
    EXPECT_EQ(cie_d_illuminant(0)(500), 0);
}

TEST(Illuminants, DaylightChromaticityFollowsCct) {
    // CIE 015: x_D for 5000 K (on the old c2 scale, i.e. D50) is 0.3457.
    Vec2d xy = chromaticity(spectrum_to_xyz(Spectrum(cie_daylight(Float(5000 * 1.4388 / 1.438)))));
    EXPECT_NEAR(xy.x, 0.3457, 1e-3);
    EXPECT_NEAR(xy.y, 0.3585, 1e-3);
}

}  // namespace
}  // namespace sr
