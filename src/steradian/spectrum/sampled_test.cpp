#include "steradian/spectrum/sampled.h"
#include "steradian/spectrum/spectrum.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sr {
namespace {

/// Integral of visible_wavelengths_pdf over [kLambdaMin, upper] by Simpson's rule.
double visible_cdf(double upper) {
    const int n = 4000;
    double a = kLambdaMin, h = (upper - a) / n, sum = 0;
    for (int i = 0; i <= n; ++i) {
        double f = visible_wavelengths_pdf(Float(a + i * h));
        sum += f * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
    }
    return sum * h / 3;
}

TEST(SampledWavelengths, VisiblePdfIntegratesToOne) {
    EXPECT_NEAR(visible_cdf(kLambdaMax), 1.0, 1e-5);
    EXPECT_EQ(visible_wavelengths_pdf(359), 0);
    EXPECT_EQ(visible_wavelengths_pdf(831), 0);
}

TEST(SampledWavelengths, InverseCdfSampling) {
    // F(sample(u)) = u: the sampler inverts the CDF of the pdf it reports.
    for (double u = 0; u < 1; u += 1.0 / 64) {
        Float l = sample_visible_wavelengths(Float(u));
        EXPECT_GE(l, kLambdaMin - 1e-3f);
        EXPECT_LE(l, kLambdaMax + 1e-3f);
        EXPECT_NEAR(visible_cdf(l), u, 2e-5) << u;
    }
}

TEST(SampledWavelengths, SampleVisibleRotatesHeroWavelength) {
    // The wavelengths are the hero's primary sample rotated by multiples of 1/N.
    for (Float u : {0.0f, 0.3f, 0.61f, 0.999f}) {
        SampledWavelengths w = SampledWavelengths::sample_visible(u);
        uint32_t bits = uint32_t(u * Float(1 << 24));
        uint32_t high = bits >> 2;
        Float hero = Float(high) / Float(1 << 22) / kSpectrumSamples +
                     Float((high * 0x9E3779B1u) >> 30) / kSpectrumSamples;
        for (int i = 0; i < kSpectrumSamples; ++i) {
            Float up = hero + Float(i) / kSpectrumSamples;
            if (up >= 1) up -= 1;
            EXPECT_NEAR(w.lambda[i], sample_visible_wavelengths(up), 1e-3f);
            EXPECT_NEAR(w.pdf[i], visible_wavelengths_pdf(w.lambda[i]), 1e-5f * w.pdf[i]);
            EXPECT_GT(w.pdf[i], 0);
        }
    }
}

TEST(SampledWavelengths, SampleVisibleInvertsTheCdfAtEveryRotation) {
    // Dense in u: each rotation's wavelength is the inverse CDF of its primary sample (double
    // precision oracle), within 1e-3 nm.
    for (int k = 0; k < 4096; ++k) {
        Float u = (Float(k) + 0.37f) / 4096;
        SampledWavelengths w = SampledWavelengths::sample_visible(u);
        uint32_t high = uint32_t(u * Float(1 << 24)) >> 2;
        double hero = double(high) / double(1 << 22) / kSpectrumSamples +
                      double((high * 0x9E3779B1u) >> 30) / kSpectrumSamples;
        for (int i = 0; i < kSpectrumSamples; ++i) {
            double up = hero + double(i) / kSpectrumSamples;
            if (up >= 1) up -= 1;
            // From the definition: p proportional to 1/cosh^2(r (l - 538)) on [360, 830].
            const double r = 0.0072, lo = std::tanh(r * (538 - 360)), hi = std::tanh(r * (830 - 538));
            double y = lo - (lo + hi) * up;
            double lambda = 538 - std::atanh(y) / r;
            EXPECT_NEAR(w.lambda[i], lambda, 1e-3) << u << " " << i;
            // y carries float rounding of about 1.2e-7; 1 - y^2 >= 0.058 then has relative
            // error up to 2 |y| 1.2e-7 / 0.058 < 5e-6.
            EXPECT_NEAR(w.pdf[i], r / (lo + hi) * (1 - y * y), 5e-6 * w.pdf[i]);
        }
    }
}

#if defined(__SSE4_1__)
TEST(SampledWavelengths, VectorLogWithinFourUlps) {
    double worst = 0;
    for (int k = -2000; k <= 2000; ++k) {
        Float x[4];
        for (int j = 0; j < 4; ++j) x[j] = Float(std::exp(0.01 * k + 0.0025 * j));
        Float l[4];
        _mm_storeu_ps(l, log_ps(_mm_loadu_ps(x)));
        for (int j = 0; j < 4; ++j) {
            double ref = std::log(double(x[j]));
            worst = std::max(worst, std::abs(double(l[j]) - ref) / std::max(std::abs(ref), 1.0));
        }
    }
    EXPECT_LT(worst, 4 * 6e-8);
}
#endif

// Stratified over u in [0, 1), the average over all wavelengths and the hero alone (after
// terminate_secondary) both estimate an integral over wavelength without bias: here the
// integral of CIE ybar, kCieYIntegral (CIE 015 table sum at 1 nm).
TEST(SampledWavelengths, SampleVisibleEstimatesIntegralsWithoutBias) {
    const auto& ybar = cie_y();
    const int n = 1 << 16;
    double all = 0, hero = 0, hero2 = 0;
    for (int k = 0; k < n; ++k) {
        Float u = (Float(k) + 0.5f) / Float(n);
        SampledWavelengths w = SampledWavelengths::sample_visible(u);
        double s = 0;
        for (int i = 0; i < kSpectrumSamples; ++i) s += ybar(w.lambda[i]) / w.pdf[i];
        all += s / kSpectrumSamples;
        w.terminate_secondary();
        double h = ybar(w.lambda[0]) / w.pdf[0] / kSpectrumSamples;
        hero += h;
        hero2 += h * h;
    }
    all /= n;
    hero /= n;
    double se = std::sqrt(std::max(0.0, hero2 / n - hero * hero) / n);
    EXPECT_NEAR(all, kCieYIntegral, 1e-3 * kCieYIntegral);
    EXPECT_NEAR(hero, kCieYIntegral, std::max(4.5 * se, 1e-3 * kCieYIntegral));
}

TEST(SampledWavelengths, TerminateSecondaryKeepsEstimatorUnbiased) {
    SampledWavelengths w = SampledWavelengths::sample_uniform(0.6f);
    Float hero_pdf = w.pdf[0];
    EXPECT_FALSE(w.secondary_terminated());
    w.terminate_secondary();
    EXPECT_TRUE(w.secondary_terminated());
    EXPECT_FLOAT_EQ(w.pdf[0], hero_pdf / kSpectrumSamples);
    w.terminate_secondary();  // idempotent
    EXPECT_FLOAT_EQ(w.pdf[0], hero_pdf / kSpectrumSamples);
}

TEST(SampledSpectrum, Arithmetic) {
    SampledSpectrum a(2), b;
    b.v = Float4{1, 0, 4, -1};
    SampledSpectrum q = a.safe_div(b);
    EXPECT_EQ(q[0], 2);
    EXPECT_EQ(q[1], 0);
    EXPECT_EQ(q[2], 0.5f);
    EXPECT_EQ((a * b).max_value(), 8);
    EXPECT_EQ((a + b).min_value(), 1);
    EXPECT_FLOAT_EQ(b.average(), 1);
    EXPECT_FALSE(SampledSpectrum(0));
    EXPECT_TRUE(a);
}

}  // namespace
}  // namespace sr
