// ConductorLobe: chi-square of sample() against pdf() (rough, isotropic and anisotropic,
// incident directions from normal to grazing and from below), consistency of sample() with
// f() and pdf(), Helmholtz reciprocity, directional albedo <= 1, and the smooth mirror's
// weight equal to the conductor Fresnel reflectance.
#include "steradian/bsdf/conductor.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "stat/chi2.h"
#include "stat/lobe_util.h"
#include "steradian/bsdf/fresnel.h"
#include "steradian/sampling/stats.h"
#include "steradian/sampling/warp.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {
namespace {

using testing::direction_deg;

/// Gold's n and k at four visible wavelengths.
ConductorLobe gold(TrowbridgeReitz mf) {
    Spectrum n = *named_spectrum("metal-Au-eta"), k = *named_spectrum("metal-Au-k");
    SampledWavelengths lambda = SampledWavelengths::sample_uniform(0.1f, 400, 700);
    return ConductorLobe{n.sample(lambda), k.sample(lambda), mf};
}

const TrowbridgeReitz kRough[] = {
    {0.05f, 0.05f}, {0.2f, 0.2f}, {0.5f, 0.5f}, {1.0f, 1.0f}, {0.05f, 0.4f}, {0.6f, 0.15f},
};
const double kThetas[] = {0, 35, 70, 88, 125};  // 125: wo below the surface

constexpr int kNumChi2Tests = int(std::size(kRough) * std::size(kThetas));

TEST(Conductor, SamplingMatchesPdfChi2) {
    const double alpha = sidak_alpha(0.01, kNumChi2Tests);
    double p_min = 1, p_max = 0;
    for (const TrowbridgeReitz& mf : kRough) {
        ConductorLobe lobe = gold(mf);
        for (double t : kThetas) {
            Vec3 wo = direction_deg(t);
            testing::SphereChi2Config cfg;
            cfg.seed = uint64_t(t * 1000 + mf.alpha_x * 100 + mf.alpha_y * 10);
            testing::SphereChi2Outcome r =
                testing::lobe_chi2(lobe, wo, TransportMode::Radiance, cfg);
            std::printf("[chi2] conductor alpha (%g, %g) theta_o %g: %s\n", mf.alpha_x, mf.alpha_y,
                        t, r.summary().c_str());
            p_min = std::min(p_min, r.chi2.p_value);
            p_max = std::max(p_max, r.chi2.p_value);
            EXPECT_GT(r.chi2.p_value, alpha)
                << "alpha (" << mf.alpha_x << ", " << mf.alpha_y << "), theta_o " << t << "\n"
                << r.tables();
        }
    }
    std::printf("[chi2] conductor: %d tests, p in [%.3g, %.3g], per-test alpha %.3g\n",
                kNumChi2Tests, p_min, p_max, alpha);
}

TEST(Conductor, SampleAgreesWithFAndPdf) {
    for (const TrowbridgeReitz& mf : kRough) {
        ConductorLobe lobe = gold(mf);
        for (double t : kThetas) {
            Vec3 wo = direction_deg(t);
            testing::ConsistencyResult c =
                testing::check_sample_consistency(lobe, wo, TransportMode::Radiance, 20000);
            EXPECT_GT(c.samples, 5000);
            EXPECT_LT(c.max_rel_f, 1e-3)
                << mf.alpha_x << " " << mf.alpha_y << " " << t << ": " << c.worst;
            EXPECT_LT(c.max_rel_pdf, 1e-3)
                << mf.alpha_x << " " << mf.alpha_y << " " << t << ": " << c.worst;
        }
    }
}

TEST(Conductor, HelmholtzReciprocity) {
    Pcg32 rng(11);
    for (const TrowbridgeReitz& mf : kRough) {
        ConductorLobe lobe = gold(mf);
        for (int k = 0; k < 2000; ++k) {
            Vec3 wo = sample_uniform_sphere({rng.next_float(), rng.next_float()});
            Vec3 wi = sample_uniform_sphere({rng.next_float(), rng.next_float()});
            SampledSpectrum a = lobe.f(wo, wi, TransportMode::Radiance);
            SampledSpectrum b = lobe.f(wi, wo, TransportMode::Radiance);
            if (!same_hemisphere(wo, wi)) {
                EXPECT_TRUE(a.is_zero() && b.is_zero());
                continue;
            }
            for (int i = 0; i < kSpectrumSamples; ++i)
                EXPECT_LT(testing::rel_diff(a[i], b[i]), 1e-4) << a[i] << " " << b[i];
        }
    }
}

TEST(Conductor, AlbedoAtMostOne) {
    for (const TrowbridgeReitz& mf : kRough) {
        // A nearly perfect reflector (F close to 1 everywhere) isolates the microfacet loss.
        SampledSpectrum eta(1), k(1000);
        ConductorLobe white{eta, k, mf};
        ConductorLobe au = gold(mf);
        for (double t : kThetas) {
            Vec3 wo = direction_deg(t);
            for (const ConductorLobe* lobe : {&white, &au}) {
                testing::Albedo a =
                    testing::directional_albedo(*lobe, wo, TransportMode::Radiance, 50000);
                for (int i = 0; i < kSpectrumSamples; ++i) {
                    EXPECT_LE(a.mean[i], 1 + 4 * a.std_error[i] + 1e-6)
                        << mf.alpha_x << " " << mf.alpha_y << " " << t;
                    EXPECT_GT(a.mean[i], 0);
                }
            }
        }
    }
    // Low roughness at normal incidence: hardly any masking, the albedo is the Fresnel
    // reflectance at normal incidence (within the spread of F over the lobe).
    ConductorLobe au = gold({0.05f, 0.05f});
    testing::Albedo a =
        testing::directional_albedo(au, Vec3(0, 0, 1), TransportMode::Radiance, 50000);
    SampledSpectrum f0 = fr_complex(1, au.eta, au.k);
    for (int i = 0; i < kSpectrumSamples; ++i) EXPECT_NEAR(a.mean[i], f0[i], 0.01 * f0[i]);
}

TEST(Conductor, SmoothMirrorWeightIsFresnel) {
    ConductorLobe lobe = gold({});
    EXPECT_EQ(lobe.flags(), kLobeReflection | kLobeSpecular);
    EXPECT_EQ(gold({0.3f, 0.3f}).flags(), kLobeReflection | kLobeGlossy);
    for (double t : {0.0, 30.0, 60.0, 89.0, 110.0}) {
        Vec3 wo = direction_deg(t);
        std::optional<BsdfSample> s = lobe.sample(wo, 0.5f, {0.3f, 0.7f}, TransportMode::Radiance);
        ASSERT_TRUE(s);
        EXPECT_TRUE(s->is_specular() && s->is_reflection());
        EXPECT_EQ(s->pdf_sa, 1);
        EXPECT_NEAR(s->wi.x, -wo.x, 1e-7);
        EXPECT_NEAR(s->wi.y, -wo.y, 1e-7);
        EXPECT_EQ(s->wi.z, wo.z);
        SampledSpectrum fr = fr_complex(std::abs(wo.z), lobe.eta, lobe.k);
        for (int i = 0; i < kSpectrumSamples; ++i)
            EXPECT_NEAR(s->f[i] * std::abs(s->wi.z) / s->pdf_sa, fr[i], 1e-6);
        EXPECT_TRUE(lobe.f(wo, s->wi, TransportMode::Radiance).is_zero());
        EXPECT_EQ(lobe.pdf(wo, s->wi, TransportMode::Radiance), 0);
    }
}

}  // namespace
}  // namespace sr
