// DiffuseTransmissionLobe (and LambertLobe): chi-square of sample() against pdf() for several
// reflectance/transmittance splits and incident sides, consistency of sample() with f() and
// pdf(), reciprocity, and the directional albedo r + t.
#include "steradian/bsdf/diffuse_transmission.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "stat/chi2.h"
#include "stat/lobe_util.h"
#include "steradian/bsdf/lambert.h"
#include "steradian/sampling/stats.h"
#include "steradian/sampling/warp.h"

namespace sr {
namespace {

using testing::direction_deg;

SampledSpectrum spectrum(Float a, Float b, Float c, Float d) {
    SampledSpectrum s;
    s.v = Float4{a, b, c, d};
    return s;
}

struct Split {
    SampledSpectrum r, t;
};
const Split kSplits[] = {
    {SampledSpectrum(0.5f), SampledSpectrum(0.5f)},
    {spectrum(0.8f, 0.1f, 0.3f, 0.5f), spectrum(0.1f, 0.6f, 0.2f, 0.05f)},
    {SampledSpectrum(0.9f), SampledSpectrum(0)},
    {SampledSpectrum(0), SampledSpectrum(0.7f)},
};
const double kThetas[] = {20, 89, 150};

// Diffuse transmission for every split and angle, plus Lambert at three angles.
constexpr int kNumChi2Tests = int(std::size(kSplits) * std::size(kThetas)) + 3;

TEST(DiffuseTransmission, SamplingMatchesPdfChi2) {
    const double alpha = sidak_alpha(0.01, kNumChi2Tests);
    double p_min = 1, p_max = 0;
    uint64_t seed = 500;
    auto check = [&](const testing::SphereChi2Outcome& r, const std::string& what) {
        std::printf("[chi2] %s: %s\n", what.c_str(), r.summary().c_str());
        p_min = std::min(p_min, r.chi2.p_value);
        p_max = std::max(p_max, r.chi2.p_value);
        EXPECT_GT(r.chi2.p_value, alpha) << what << "\n" << r.tables();
    };
    for (std::size_t k = 0; k < std::size(kSplits); ++k) {
        DiffuseTransmissionLobe lobe{kSplits[k].r, kSplits[k].t};
        for (double t : kThetas) {
            testing::SphereChi2Config cfg;
            cfg.seed = ++seed;
            check(testing::lobe_chi2(lobe, direction_deg(t), TransportMode::Radiance, cfg),
                  "diffuse transmission split " + std::to_string(k) + " theta_o " +
                      std::to_string(int(t)));
        }
    }
    LambertLobe lambert{SampledSpectrum(0.6f)};
    for (double t : kThetas) {
        testing::SphereChi2Config cfg;
        cfg.seed = ++seed;
        check(testing::lobe_chi2(lambert, direction_deg(t), TransportMode::Radiance, cfg),
              "lambert theta_o " + std::to_string(int(t)));
    }
    std::printf("[chi2] diffuse: %d tests, p in [%.3g, %.3g], per-test alpha %.3g\n", kNumChi2Tests,
                p_min, p_max, alpha);
}

TEST(DiffuseTransmission, SampleAgreesWithFAndPdf) {
    for (const Split& sp : kSplits) {
        DiffuseTransmissionLobe lobe{sp.r, sp.t};
        for (double t : kThetas) {
            testing::ConsistencyResult c = testing::check_sample_consistency(
                lobe, direction_deg(t), TransportMode::Radiance, 20000);
            EXPECT_GT(c.samples, 19000);
            EXPECT_LT(c.max_rel_f, 1e-6) << c.worst;
            EXPECT_LT(c.max_rel_pdf, 1e-6) << c.worst;
        }
    }
}

TEST(DiffuseTransmission, Reciprocity) {
    Pcg32 rng(9);
    DiffuseTransmissionLobe lobe{kSplits[1].r, kSplits[1].t};
    for (int k = 0; k < 1000; ++k) {
        Vec3 wo = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        Vec3 wi = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        SampledSpectrum a = lobe.f(wo, wi, TransportMode::Radiance);
        SampledSpectrum b = lobe.f(wi, wo, TransportMode::Radiance);
        SampledSpectrum c = lobe.f(wo, wi, TransportMode::Importance);
        for (int i = 0; i < kSpectrumSamples; ++i) {
            EXPECT_EQ(a[i], b[i]);
            EXPECT_EQ(a[i], c[i]);
        }
    }
}

TEST(DiffuseTransmission, AlbedoIsRPlusT) {
    for (const Split& sp : kSplits) {
        DiffuseTransmissionLobe lobe{sp.r, sp.t};
        for (double t : kThetas) {
            testing::Albedo a = testing::directional_albedo(lobe, direction_deg(t),
                                                            TransportMode::Radiance, 100000);
            for (int i = 0; i < kSpectrumSamples; ++i) {
                double expected = sp.r[i] + sp.t[i];
                EXPECT_NEAR(a.mean[i], expected, 4 * a.std_error[i] + 1e-6) << i << " " << t;
                EXPECT_LE(a.mean[i], 1 + 4 * a.std_error[i]);
            }
        }
    }
}

TEST(DiffuseTransmission, FlagsAndDegenerateCases) {
    EXPECT_EQ((DiffuseTransmissionLobe{SampledSpectrum(0.5f), SampledSpectrum(0.5f)}.flags()),
              kLobeReflection | kLobeTransmission | kLobeDiffuse);
    EXPECT_EQ((DiffuseTransmissionLobe{SampledSpectrum(0), SampledSpectrum(0.5f)}.flags()),
              kLobeTransmission | kLobeDiffuse);
    DiffuseTransmissionLobe black{SampledSpectrum(0), SampledSpectrum(0)};
    EXPECT_EQ(black.flags(), kLobeNone);
    EXPECT_FALSE(black.sample(Vec3(0, 0, 1), 0.5f, {0.5f, 0.5f}, TransportMode::Radiance));
    EXPECT_EQ(black.pdf(Vec3(0, 0, 1), Vec3(0, 0, -1), TransportMode::Radiance), 0);
}

}  // namespace
}  // namespace sr
